"""Writing a figure: atomically, in the format its file name asks for."""

from __future__ import annotations

import os
import shutil
import textwrap
from pathlib import Path

from mol_shell._core.atomic import atomic_path
from mol_shell._core.paths import writable_path


def image_formats():
    """File suffixes matplotlib can write (``png``, ``pdf``, ``svg``, ...); ``pgf`` only where its TeX system
    (``xelatex`` by default) is installed: matplotlib lists it everywhere and fails at the save without one."""
    import matplotlib
    from matplotlib.backend_bases import FigureCanvasBase

    formats = set(FigureCanvasBase.get_supported_filetypes())
    if shutil.which(str(matplotlib.rcParams["pgf.texsystem"])) is None:
        formats.discard("pgf")
    return formats


def figure_path(path):
    """``path`` checked before a figure is drawn (:func:`mol_shell._core.paths.writable_path`, named ``path``): a
    suffix matplotlib writes (:func:`image_formats`; none at all is a PNG), a writable place; missing directories
    are created.

    Raises
    ------
    ParameterError
        ``path = 's.xyz' ends in .xyz, a kind of file this command does not write; allowed: a file ending in one of
        .eps, .pdf, .png, ...``
    """
    has_suffix = isinstance(path, (str, os.PathLike)) and Path(os.fspath(path)).suffix
    return writable_path(path, "path", suffixes=image_formats() if has_suffix else None)


def save_figure(fig, path, dpi=120):
    """Save ``fig`` to ``path`` (its suffix names the format; none: PNG) and close it.

    ``path`` is checked by :func:`figure_path` (its missing directories created); drawing functions check it before
    they draw. Written under a temporary name and renamed onto ``path``: an interrupted plot leaves the previous
    figure intact.
    """
    import matplotlib.pyplot as plt  # optional heavy dependency: only commands that draw load it

    try:
        path = figure_path(path)
    except Exception:
        plt.close(fig)
        raise
    suffix = path.suffix.lstrip(".").lower() or "png"
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
