"""Figure of a study of paths (``mol-shell study ... --path``): each case's critical loads against a varied parameter.

The x axis is the first varied parameter; a further varied parameter gives one line per value. Every critical
point a case's path met is drawn (limit points as triangles, bifurcations as circles); the first critical point of
each case, the buckling or snap-through load when the path starts unloaded, is joined by a line. Cases whose path
ended without one are left out of the line (and said in the legend).
"""

from __future__ import annotations

import itertools

import numpy as np

from mol_shell.views.figures import save_figure
from mol_shell.views.path_plot import MARKERS


def is_path_study(ds):
    """Whether Dataset ``ds`` is a study of paths."""
    return "first_critical" in ds and "path_parameter" in ds.attrs and "point" in ds.dims


def path_study_figure(ds):
    """The figure (a matplotlib ``Figure``, not saved)."""
    import matplotlib.pyplot as plt

    dims = [d for d in ds.first_critical.dims]
    x_dim, others = dims[0], dims[1:]
    x = ds[x_dim].values if x_dim in ds.coords else np.arange(ds.sizes[x_dim])
    numeric = np.issubdtype(np.asarray(x).dtype, np.number)
    xs = x if numeric else np.arange(len(x))
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    parameter = ds.attrs["path_parameter"]
    units = ds.first_critical.attrs.get("units", "")
    for combo in itertools.product(*(range(ds.sizes[d]) for d in others)):
        sel = dict(zip(others, combo))
        first = ds.first_critical.isel(sel).values
        label = ", ".join(f"{d} = {ds[d].values[k]!s}" for d, k in sel.items()) or "first critical point"
        missing = int(np.isnan(first).sum())
        if missing:
            label += f" ({missing} without one)"
        (line,) = ax.plot(xs, first, "-", label=label)
        kinds, values = ds.point_kind.isel(sel).values, ds.point_parameter.isel(sel).values
        for kind, marker in MARKERS.items():
            rows, cols = np.nonzero(kinds == kind)
            if len(rows):
                ax.plot(np.asarray(xs)[rows], values[rows, cols], marker, color=line.get_color(), fillstyle="none",
                        linestyle="none")
    for kind, marker in MARKERS.items():
        ax.plot([], [], marker, color="k", fillstyle="none", linestyle="none", label=kind)
    if not numeric:
        ax.set_xticks(xs, [str(v) for v in x], rotation=30, ha="right")
    x_units = ds[x_dim].attrs.get("units", "") if x_dim in ds.coords else ""
    ax.set_xlabel(f"{x_dim} [{x_units}]" if x_units else x_dim)
    ax.set_ylabel(f"critical {parameter} [{units}]" if units else f"critical {parameter}")
    ax.set_title(ds.attrs.get("title", f"critical points of {parameter}"), fontsize="medium")
    if np.all(np.isnan(ds.first_critical.values)):  # axes of NaN alone are empty: say why
        stop = ds.attrs.get("path_stop", "")
        ax.text(0.5, 0.5, f"no path met a critical point of {parameter}"
                + (f"\n(each traced up to {parameter} = {stop})" if stop != "" else ""),
                transform=ax.transAxes, ha="center", va="center")
        if numeric and len(xs):
            ax.set_xlim(float(np.min(xs)) - 0.5 * (np.ptp(xs) or 1.0), float(np.max(xs)) + 0.5 * (np.ptp(xs) or 1.0))
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return fig


def plot_path_study(ds, path):
    """Write :func:`path_study_figure` to ``path`` (atomically)."""
    save_figure(path_study_figure(ds), path)


__all__ = ["is_path_study", "path_study_figure", "plot_path_study"]
