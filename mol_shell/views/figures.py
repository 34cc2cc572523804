"""Writing a figure: atomically, in the format its file name asks for."""

from __future__ import annotations

import textwrap
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


def wrapped_title(width, title, fontsize=10):
    """``title`` with each line wrapped to ``width`` inches of figure (about 0.6 em a character, a margin of 0.3
    in), never inside ``name = value``: a one-column figure is 3.4 in wide, and a title with a stopped run's
    message was cut off at both ends."""
    chars = max(20, int((width - 0.3) * 72 / (0.6 * fontsize)))
    lines = (textwrap.fill(line.replace(" = ", "\u00a0=\u00a0"), chars) if line else line for line in title.split("\n"))
    return "\n".join(lines)
