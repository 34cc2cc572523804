"""Writing a figure: atomically, in the format its file name asks for."""

from __future__ import annotations

from pathlib import Path

from mol_shell._core.atomic import atomic_path


def save_figure(fig, path, dpi=120):
    """Save ``fig`` to ``path`` (its suffix names the format) and close it.

    Written under a temporary name and renamed onto ``path``: an interrupted plot leaves the previous
    figure intact.
    """
    import matplotlib.pyplot as plt  # optional heavy dependency: only commands that draw load it

    suffix = Path(path).suffix.lstrip(".").lower() or "png"
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=suffix)
    finally:
        plt.close(fig)
