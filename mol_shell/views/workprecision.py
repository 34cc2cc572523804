"""Figure and tables of a work-precision Dataset: error against wall time, one line per integrator."""

from __future__ import annotations

import numpy as np

from mol_shell._core.atomic import write_text
from mol_shell._core.paths import beside
from mol_shell.analysis.workprecision import full_table, markdown_table
from mol_shell.results.dataset import write_netcdf
from mol_shell.views.figures import save_figure

#: the wall-time labels tried, richest first: ``k x 10^e`` for each ``k`` of a set, then every decade, every second ...
LABELLED_MANTISSAS = ((1, 2, 3, 4, 5, 6, 7, 8, 9), (1, 2, 5), (1, 3), (1,))
DECADE_STRIDES = (2, 3, 5, 10, 20, 50, 100)
#: the least free space between two neighbouring labels, as a share of their mean width
LABEL_SPACE = 0.3


def _label_sets(lo, hi):
    """Candidate wall-time ticks in ``[lo, hi]``, richest first (:data:`LABELLED_MANTISSAS`, decades by
    :data:`DECADE_STRIDES`), then, for a span too short for two of them, evenly spaced values with 1, 2, 2.5 or 5 as
    their last digit (4 to 2 of them)."""
    from matplotlib.ticker import MaxNLocator

    decades = range(int(np.floor(np.log10(lo))), int(np.ceil(np.log10(hi))) + 1)
    for mantissas in LABELLED_MANTISSAS:
        yield np.array([k * 10.0**e for e in decades for k in mantissas])
    for stride in DECADE_STRIDES:
        yield np.array([10.0**e for e in decades if e % stride == 0])
    for bins in (4, 3, 2):
        yield MaxNLocator(bins, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi)


def uncrowded_log_ticks(ax, fig):
    """Label the log x-axis at the richest of :func:`_label_sets` that has two labels or more in view whose
    neighbours leave :data:`LABEL_SPACE` between them, measured with the figure's renderer; the minor ticks stay
    unlabelled. Matplotlib labels the minor ticks of an axis spanning up to about a decade and a half (2, 3, 4, 6 x
    10^e) and crowded them: "3x10^-3 4x10^-3" overlapped."""
    from matplotlib.ticker import FixedLocator, LogFormatterSciNotation, LogLocator, NullFormatter

    lo, hi = sorted(ax.get_xlim())
    if not (0 < lo < hi < np.inf):
        return
    formatter = LogFormatterSciNotation(labelOnlyBase=False, minor_thresholds=(np.inf, np.inf))  # every tick given
    renderer = fig.canvas.get_renderer()
    size = ax.xaxis.get_ticklabels()[0].get_fontsize() if ax.xaxis.get_ticklabels() else None
    for ticks in _label_sets(lo, hi):
        ticks = ticks[(ticks >= lo) & (ticks <= hi)]
        if ticks.size < 2:
            continue
        formatter.set_locs(ticks)
        probes = [ax.text(0, 0, formatter(t), fontsize=size) for t in ticks]
        widths = np.array([p.get_window_extent(renderer).width for p in probes])
        for p in probes:
            p.remove()
        centres = ax.transData.transform(np.c_[ticks, np.ones_like(ticks)])[:, 0]
        halves = (widths[1:] + widths[:-1]) / 2
        if np.all(np.diff(centres) >= (1 + LABEL_SPACE) * halves):
            ax.xaxis.set_major_locator(FixedLocator(ticks))
            ax.xaxis.set_major_formatter(formatter)
            ax.xaxis.set_minor_locator(LogLocator(base=10, subs=np.arange(2, 10), numticks=100))
            ax.xaxis.set_minor_formatter(NullFormatter())
            return


#: each integrator's colour (an index into matplotlib's ``tab20``: a family's members share a hue, dark and light)
#: and marker, distinct, the same in every figure; a name not here takes a colour no line has, while tab20 has one
STYLES = {
    "leapfrog": (6, "o"), "cvode-bdf": (1, "s"), "cvode-adams": (0, "D"), "ida": (18, "^"),
    "casadi-cvodes-c": (19, "v"), "dop853-c": (4, "P"), "rk45-c": (5, "X"), "scipy-rk45": (2, "<"),
    "scipy-dop853": (3, ">"), "scipy-radau": (10, "h"), "scipy-bdf": (11, "p"), "casadi-cvodes": (8, "*"),
    "casadi-idas": (9, "d"), "sksundae-cvode-adams": (12, "8"), "sksundae-cvode-bdf": (13, "H"), "sksundae-ida": (16, "o"),
}
MARKERS = "osD^v<>phH8*dPX"


def styles(names):
    """``{name: (colour, marker, linestyle)}``: :data:`STYLES`' pairs, distinct for any set of names; dashed for the
    scipy and CasADi routes, dotted for scikit-sundae's."""
    import matplotlib

    cmap = matplotlib.colormaps["tab20"]
    pairs = {name: STYLES[name] for name in names if name in STYLES}
    for name in names:  # a colour no line has first, then a marker no line of that colour has
        if name not in pairs:
            used = {c for c, _ in pairs.values()}
            pairs[name] = min(((c, m) for m in MARKERS for c in range(20) if (c, m) not in pairs.values()),
                              key=lambda pair: (pair[0] in used, MARKERS.index(pair[1])))
    return {name: (matplotlib.colors.to_hex(cmap(c)), m, "--" if name.startswith(("scipy", "casadi")) else
                   ":" if name.startswith("sksundae") else "-") for name, (c, m) in pairs.items()}


def figure(ds, target=1e-6):
    """Log-log error against wall time, one line per integrator, each its own colour and marker (:func:`styles`):
    the open figure (:func:`plot` saves it). A point whose error is at or below the reference's own
    (``attrs["reference_error"]``) is drawn hollow: the reference cannot measure it (its error may be less)."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, ax = plt.subplots(figsize=(9, 5))
    level = float(ds.attrs["reference_error"])
    names = [str(name) for name in ds.integrator.values]
    handles, labels, hollow_drawn = [], [], False
    for name, (colour, marker, ls) in styles(names).items():
        row = ds.sel(integrator=name)
        ok = np.isfinite(row.error.values) & (row.status.values == "complete")
        wall, error = row.wall_time_s.values[ok], np.maximum(row.error.values[ok], 1e-16)
        below = error <= level  # False where the level is NaN (not estimated)
        ax.loglog(wall, error, color=colour, ls=ls, lw=1.2, gid=f"{name}:line")
        ax.loglog(wall[~below], error[~below], ls="none", marker=marker, color=colour, gid=f"{name}:measured")
        if below.any():
            ax.loglog(wall[below], error[below], ls="none", marker=marker, mfc="none", mec=colour, gid=f"{name}:below")
            hollow_drawn = True
        handles.append(Line2D([], [], color=colour, ls=ls, lw=1.2, marker=marker))
        labels.append(name)
    ax.axhline(target, color="grey", lw=0.8, ls=":")
    ax.axhline(level, color="k", lw=0.6, ls="-.")
    handles.append(Line2D([], [], color="k", lw=0.6, ls="-."))
    labels.append(f"reference's error, {level:.2g}" if np.isfinite(level) else "reference's error: not estimated")
    if hollow_drawn:
        handles.append(Line2D([], [], ls="none", marker="o", mfc="none", mec="k"))
        labels.append("hollow: error at or below the\nreference's (not resolved)")
    ax.set_xlabel("wall time [s] (median of repeats)")
    ax.set_ylabel("max relative error of r, theta, chi")
    ax.set_title(f"work-precision, {ds.attrs['scene']}, n = {ds.attrs['n']}, t = 0..{ds.attrs['times'].split(',')[-1]} s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    uncrowded_log_ticks(ax, fig)
    fig.tight_layout()
    return fig


def plot(ds, path, target=1e-6):
    """Log-log error against wall time, one line per integrator, saved to ``path``."""
    save_figure(figure(ds, target), path, dpi=120)


def companion_files(path):
    """``(png, md)``: the figure and the tables written beside ``path`` (its stem; a symbolic link's own folder:
    :func:`~mol_shell._core.paths.beside`)."""
    return str(beside(path, ".png")), str(beside(path, ".md"))


def write_outputs(ds, path, target=1e-6):
    """``path`` (netCDF), and beside it :func:`companion_files`: ``.png`` and ``.md`` with the same stem."""
    write_netcdf(ds, path)
    png, md = companion_files(path)
    plot(ds, png, target)
    write_text(md, markdown_table(ds, target) + "\n\nAll runs:\n\n" + full_table(ds) + "\n")
    return png, md
