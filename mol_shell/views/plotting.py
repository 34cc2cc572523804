"""Figures: the paper's figures 4-8 (r, theta, chi against s, one panel per saved time)."""

from __future__ import annotations

import math

import numpy as np

from mol_shell._core.errors import ParameterError, show
from mol_shell.views.fields import REFERENCE, run_of
from mol_shell.views.figures import figure_path, incomplete_note, save_figure, wrapped_title
from mol_shell.views.history import HISTORY, draw_balance, draw_radius, radius_node

# Axis ranges of the paper's figures 4-8; used when the data fit inside them and fill enough of them (PAPER_SHARE).
PAPER_LIMITS = {"r": (0.985, 1.005), "theta": (-0.02, 0.02), "chi": (-0.2, 0.2)}
#: the least share of a paper's range the data span for it to be used: smaller motions get limits of their own,
#: else they are drawn as flat lines (gamma = 0.001 rad/m twists chi over 1 % of the paper's -0.2 to 0.2 rad)
PAPER_SHARE = 0.2
LABELS = {"r": "r [m]", "theta": r"$\theta$ [rad]", "chi": r"$\chi$ [rad]"}
#: what :func:`meridian_figure` reads of a run: the meridian and its reference, the angles, and the figures over time's
MERIDIAN = ("z", "chi", "psi", *HISTORY, *REFERENCE)
#: saved times per row of panels
COLUMNS = 6
#: saved times drawn at most (evenly picked beyond that, and the figure says so)
MAX_TIMES = 24
#: the figure title's distance below the figure's top edge at most (inches): the default, 2 % of the height, grew
#: with the rows of panels until the title overprinted the top panels' titles (tight_layout counts no such gap)
TITLE_GAP = 0.14


def _limits(values, name):
    """The axis range of field ``name``: the paper's where the data fit inside it and span at least
    :data:`PAPER_SHARE` of it, or are constant (a flat line at any scale); else the data's own with a 5 % margin
    (a constant outside the paper's range: centred in a range as wide as the paper's)."""
    lo, hi = PAPER_LIMITS[name]
    vmin, vmax = float(np.nanmin(values)), float(np.nanmax(values))
    span = vmax - vmin
    flat = span <= 64 * np.finfo(float).eps * max(abs(vmin), abs(vmax))
    if lo <= vmin and vmax <= hi and (flat or span >= PAPER_SHARE * (hi - lo)):
        return lo, hi
    if flat:
        middle = 0.5 * (vmin + vmax)
        return middle - 0.5 * (hi - lo), middle + 0.5 * (hi - lo)
    pad = 0.05 * span
    return vmin - pad, vmax + pad


def shown_times(count, max_times=MAX_TIMES):
    """Indices of the saved times drawn: all of them up to ``max_times``, else ``max_times`` evenly picked."""
    if count <= max_times:
        return np.arange(count)
    return np.unique(np.linspace(0, count - 1, max_times).round().astype(int))


def number(attrs, name):
    """``attrs[name]`` as a float, or ``None`` when it is absent or not a number (files of 0.5.0 stored
    ``"none"`` for a radius left to the code)."""
    value = attrs.get(name)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        return None
    return float(value)


def title_of(attrs, shown, count):
    """The figure's title: scene, the parameters it has, grid, integrator, and which times are drawn."""
    parts = [str(attrs.get("scene", "run"))]
    if number(attrs, "gamma") is not None:
        parts.append(f"gamma = {number(attrs, 'gamma'):g} rad/m")
    for name, unit in (("omega", "rad/s"), ("psi0", "rad")):
        if number(attrs, name):
            parts.append(f"{name} = {number(attrs, name):g} {unit}")
    if number(attrs, "R") is not None:
        auto = " (auto)" if attrs.get("R_requested") == "auto" else ""
        parts.append(f"R = {number(attrs, 'R'):.6f} m{auto}")
    if "n" in attrs:
        parts.append(f"n = {attrs['n']}")
    if "integrator" in attrs:
        parts.append(str(attrs["integrator"]))
    title = ", ".join(parts[1:])
    title = f"{parts[0]}: {title}" if title else parts[0]
    if shown < count:
        title += f"\n{shown} of {count} saved times shown (evenly picked)"
    if incomplete_note(attrs):
        title += f"\n[{incomplete_note(attrs)}]"
    return title


def snapshot_fields(fields):
    """``fields`` as a tuple of names the snapshots draw (:data:`LABELS`: ``r``, ``theta``, ``chi``; one name alone
    as a string too), else refused naming ``fields``."""
    fields = (fields,) if isinstance(fields, str) else fields
    allowed = "one or more of {" + ", ".join(LABELS) + "}"
    try:
        fields = tuple(fields)
    except TypeError:
        raise ParameterError.not_a("fields", fields, "a tuple of names", allowed) from None
    unknown = [name for name in fields if not isinstance(name, str) or name not in LABELS]
    if unknown or not fields:
        problem = f"names {show(unknown[0])}, not a field the snapshots draw" if unknown else "is empty"
        raise ParameterError.invalid("fields", fields, problem, allowed)
    return fields


def plot_snapshots(ds, path, fields=("r", "theta", "chi"), max_times=MAX_TIMES, columns=COLUMNS):
    """Plot ``fields`` against ``s``, one panel per saved time (up to ``max_times``; beyond, evenly picked).

    Panels are laid out ``columns`` times to a row, one row per field, with the paper's axis
    ranges where the data fit them and span a fair share of them (:data:`PAPER_SHARE`), else the data's own.
    The title says when not every saved time is drawn, and when the run is incomplete. ``ds``: a run's Dataset or
    the path of its netCDF file; ``path``: an image (:func:`mol_shell.views.figures.figure_path`), checked before
    anything is drawn.
    """
    fields = snapshot_fields(fields)
    ds = run_of(ds, "plot", fields)
    path = figure_path(path)
    fig = snapshot_figure(ds, fields, max_times, columns)
    save_figure(fig, path, dpi=120)
    return path


def snapshot_figure(ds, fields=("r", "theta", "chi"), max_times=MAX_TIMES, columns=COLUMNS):
    """The figure of :func:`plot_snapshots` (a matplotlib ``Figure``, not saved)."""
    import matplotlib.pyplot as plt

    fields = snapshot_fields(fields)
    ds = run_of(ds, "plot", fields)
    idx = shown_times(ds.sizes["time"], max_times)
    ncols = min(columns, len(idx))
    blocks = math.ceil(len(idx) / ncols)
    nrows = blocks * len(fields)
    width = 2.6 * ncols + 0.8
    title = wrapped_title(width, title_of(ds.attrs, len(idx), ds.sizes["time"]))
    lines = title.count("\n") + 1
    fig, axes = plt.subplots(nrows, ncols, figsize=(width, 1.9 * nrows + 0.8 + 0.2 * lines), squeeze=False)
    s, times = ds["s"].values, ds["time"].values
    for row, name in enumerate(fields):
        values = ds[name].values
        limits = _limits(values, name)
        for k, i in enumerate(idx):
            block, col = divmod(k, ncols)
            ax = axes[block * len(fields) + row, col]
            ax.plot(s, values[i], "k.-", lw=1, ms=3)
            ax.set_xlim(s[0], s[-1])
            ax.set_ylim(*limits)
            ax.axhline(0.0 if name != "r" else 1.0, color="0.8", lw=0.6, zorder=0)
            if row == 0:
                ax.set_title(f"t = {float(times[i]):.4g} s", fontsize=10)
            if col == 0:
                ax.set_ylabel(LABELS[name])
            else:
                ax.tick_params(labelleft=False)
            if row == len(fields) - 1:
                ax.set_xlabel("s [m]")
            else:
                ax.tick_params(labelbottom=False)
    for k in range(len(idx), blocks * ncols):  # the empty places of the last row of panels
        block, col = divmod(k, ncols)
        for row in range(len(fields)):
            axes[block * len(fields) + row, col].set_visible(False)
    height = fig.get_figheight()
    fig.suptitle(title, fontsize=10, y=max(0.98, 1.0 - TITLE_GAP / height))  # 0.98: matplotlib's default
    fig.tight_layout()  # which leaves room for the title's lines, counting them from the top edge
    return fig


def is_cylinder(ds):
    """Whether a run's reference meridian is a cylinder (constant ``r0``, ``theta0 = 0``); runs without it are."""
    if "r0" not in ds:
        return True
    r0, th0 = ds.r0.values, ds.theta0.values
    return bool(np.ptp(r0) <= 1e-12 * np.abs(r0).max() and np.abs(th0).max() == 0)


def shows_history(ds):
    """Whether the default figure of a run is :func:`meridian_figure` (with the radius and the energy-work balance
    over time): every shell but the paper's cylinder without pressure, whose figure is the paper's snapshots."""
    pressure = ds.attrs.get("pressure", 0.0)
    pressurised = isinstance(pressure, (int, float, np.integer, np.floating)) and float(pressure) != 0.0
    return pressurised or not is_cylinder(ds)


def meridian_figure(ds, max_times=8, s=None):
    """The deformed meridian ``(r, z)`` at saved times over the reference one, ``chi`` and ``psi`` against ``s``;
    below, the radius at the equator (or at ``s``) against time and the energy-work balance
    (:mod:`mol_shell.views.history`). A matplotlib ``Figure``, not saved.

    For shells that are not cylinders, where r, theta, chi against s say less than the shape does, and for
    pressurised ones. Displacements are drawn to scale (the title gives the largest one).
    """
    import matplotlib.pyplot as plt

    ds = run_of(ds, "plot", MERIDIAN)
    idx = shown_times(ds.sizes["time"], max_times)
    fig = plt.figure(figsize=(13, 8.6))
    grid = fig.add_gridspec(2, 6, height_ratios=[1.15, 1])
    ax, bx, cx = (fig.add_subplot(grid[0, 2 * k : 2 * k + 2]) for k in range(3))
    ax.plot(ds.r0, ds.z0, color="0.6", lw=3, label="reference")
    cmap = plt.get_cmap("viridis")
    for j, i in enumerate(idx):
        c = cmap(j / max(1, len(idx) - 1))
        t = float(ds.time[i])
        ax.plot(ds.r.isel(time=i), ds.z.isel(time=i), color=c, lw=1, label=f"t = {t:.4g} s")
        bx.plot(ds.s, ds.chi.isel(time=i), color=c, lw=1)
        cx.plot(ds.s, ds.psi.isel(time=i), color=c, lw=1)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("r [m]")
    ax.set_ylabel("z [m]")
    ax.legend(fontsize=7)
    bx.set_xlabel("s [m]")
    bx.set_ylabel(r"$\chi$ [rad]")
    cx.set_xlabel("s [m]")
    cx.set_ylabel(r"$\psi$ [rad]")
    draw_radius(fig.add_subplot(grid[1, :3]), ds, radius_node(ds, s))
    draw_balance(fig.add_subplot(grid[1, 3:]), ds)
    move = float(np.hypot(ds.r - ds.r0, ds.z - ds.z0).max())
    title = title_of(ds.attrs, len(idx), ds.sizes["time"]) + f"\nmeridian to scale; largest displacement {move:.3g} m"
    fig.suptitle(wrapped_title(fig.get_figwidth(), title, fontsize=9), fontsize=9)
    fig.tight_layout()
    return fig


def plot_meridian(ds, path, max_times=8, s=None):
    """Write :func:`meridian_figure` to ``path`` (checked first, as by :func:`plot_snapshots`)."""
    ds = run_of(ds, "plot", MERIDIAN)
    path = figure_path(path)
    save_figure(meridian_figure(ds, max_times, s), path, dpi=120)
    return path
