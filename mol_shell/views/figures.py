"""Writing a figure: atomically, in the format its file name asks for."""

from __future__ import annotations

import os
import shutil
import textwrap
from pathlib import Path

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.atomic import atomic_path
from mol_shell._core.errors import is_number
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
        if suffix in POSTSCRIPT:
            opaque(fig)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=suffix)
        interrupts.wrote(path)  # an interrupt from here on: said after writing it
    finally:
        plt.close(fig)


#: formats without transparency: matplotlib draws a partly transparent artist opaque there, and said so on stderr in a
#: bare line of its own (its logger's); :func:`opaque` draws them as they look on white first
POSTSCRIPT = ("ps", "eps")


def _on_white(rgba):
    """Opaque colours (``(..., 4)`` RGBA) that look as ``rgba`` do over white; fully transparent ones kept."""
    rgba = np.array(rgba, dtype=float).reshape(-1, 4)
    alpha = rgba[:, 3:]
    seen = (alpha > 0).ravel()
    rgba[seen, :3] = alpha[seen] * rgba[seen, :3] + (1 - alpha[seen])
    rgba[seen, 3] = 1.0
    return rgba


def opaque(fig):
    """Give each partly transparent line, patch and collection of ``fig`` the opaque colours it shows over white (a
    grid of alpha 0.3, a legend's frame, a faded line), for a format that has no transparency (:data:`POSTSCRIPT`):
    drawn so, nothing is rendered darker than it looks, nor said."""
    import matplotlib.colors as mcolors
    from matplotlib.collections import Collection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    for artist in fig.findobj(lambda a: isinstance(a, (Line2D, Patch, Collection))):
        if isinstance(artist, Line2D):
            alpha = artist.get_alpha()
            colours = {name: getattr(artist, f"get_{name}")() for name in ("color", "markerfacecolor", "markeredgecolor")}
            artist.set_alpha(None)
            for name, colour in colours.items():
                if not (isinstance(colour, str) and colour.lower() in ("none", "auto")):
                    getattr(artist, f"set_{name}")(tuple(_on_white(mcolors.to_rgba(colour, alpha))[0]))
        elif isinstance(artist, Collection) and artist.get_array() is not None:
            continue  # colours from a colour map: they are drawn as the map gives them
        else:
            face, edge = artist.get_facecolor(), artist.get_edgecolor()  # RGBA, the artist's alpha applied
            artist.set_alpha(None)
            face, edge = _on_white(face), _on_white(edge)
            single = isinstance(artist, Patch)
            artist.set_facecolor(face[0] if single else face)
            artist.set_edgecolor(edge[0] if single else edge)


def equal_aspect(fig, margin=0.04, rounds=4):
    """Lay out ``fig`` (its layout engine, e.g. constrained) and give each of its axes one scale in x and y (a
    circle drawn round) by its limits, about its data with ``margin`` of their span beside them; the layout is then
    fixed. An axes' box shrunk to an aspect instead (``set_aspect("equal")``) was placed by the layout for the box it
    had before, and the x labels fell off the figure's bottom edge; data limits adjusted to it
    (``adjustable="datalim"``) grew at each pass of the constrained layout. The limits change the tick labels, and
    they the layout: laid out again until the places hold (twice or three times), at most ``rounds`` times."""
    width, height = fig.get_size_inches()
    spans = []
    for ax in fig.axes:
        (x0, y0), (x1, y1) = ax.dataLim.get_points()
        spans.append(((x0 + x1) / 2, (y0 + y1) / 2, (1 + 2 * margin) * (x1 - x0) or 1.0,
                      (1 + 2 * margin) * (y1 - y0) or 1.0))
    places = None
    for _ in range(rounds):
        fig.draw_without_rendering()
        now = np.array([ax.get_position().bounds for ax in fig.axes])
        if places is not None and np.abs(now - places).max() < 1e-6:
            break
        places = now
        for ax, (cx, cy, dx, dy) in zip(fig.axes, spans):
            box = ax.get_position()
            w, h = box.width * width, box.height * height
            per_inch = max(dx / w, dy / h)
            ax.set_xlim(cx - per_inch * w / 2, cx + per_inch * w / 2)
            ax.set_ylim(cy - per_inch * h / 2, cy + per_inch * h / 2)
    fig.set_layout_engine("none")  # the places of the last layout, which the limits were made for


def incomplete_note(attrs):
    """``"INCOMPLETE: MESSAGE (asked: t_end = T s)"`` for a run that stopped or was interrupted (``attrs["complete"] =
    0``), ``""`` for a complete one (or a file that does not say): what every figure, animation and export of a run
    says of it (only the paper's figures said it; the fibres and history figures, the frames and the printed lines did
    not). The end the run was asked to reach (``t_end_requested``) is said where the file has it: the message says
    where the run stopped, and the file's times end there too."""
    if attrs.get("complete", 1):
        return ""
    asked = attrs.get("t_end_requested")
    asked = f" (asked: t_end = {float(asked):g} s)" if is_number(asked) else ""
    return f"INCOMPLETE: {attrs.get('message', '') or attrs.get('status', 'stopped early')}{asked}"


def path_note(attrs, last=None):
    """``"ENDED SHORT: MESSAGE (at PARAMETER = LAST of START to STOP UNITS)"`` for a path that stopped before its
    range's end (``max_steps``, a limit, an interrupt: ``attrs["complete"] = 0``), ``""`` for a complete one; ``last``:
    the parameter at its last state."""
    if attrs.get("complete", 1):
        return ""
    units, name = attrs.get("parameter_units", ""), attrs.get("parameter", "the parameter")
    message = attrs.get("message", "") or attrs.get("status", "stopped early")
    # where the message says it already (an interrupt's "... at pressure = -744.21 Pa"), not said twice
    where = f" at {name} = {last:.6g}" if last is not None and f" {name} = " not in f" {message}" else ""
    span = f" of its range {attrs['start']:g} to {attrs['stop']:g} {units}".rstrip() if "start" in attrs else ""
    return f"ENDED SHORT: {message}{where}{span}"


def wrapped_title(width, title, fontsize=10):
    """``title`` with each line wrapped to ``width`` inches of figure (about 0.6 em a character, a margin of 0.3
    in), never inside ``name = value``: a one-column figure is 3.4 in wide, and a title with a stopped run's
    message was cut off at both ends."""
    chars = max(20, int((width - 0.3) * 72 / (0.6 * fontsize)))
    lines = (textwrap.fill(line.replace(" = ", "\u00a0=\u00a0"), chars) if line else line for line in title.split("\n"))
    return "\n".join(lines)
