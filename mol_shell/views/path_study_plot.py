"""Figure of a study of paths (``mol-shell study ... --path``): each case's critical loads against a varied parameter.

The x axis is the first varied parameter; a further varied parameter gives one line per value. Every critical
point a case's path met is drawn (limit points as triangles, bifurcations as circles); the first critical point of
each case, the buckling or snap-through load when the path starts unloaded, is joined by a line. Cases whose path
ended without one are left out of the line (and said in the legend).
"""

from __future__ import annotations

import itertools

import numpy as np

from mol_shell._core.errors import is_number
from mol_shell.views.figures import save_figure, wrapped_title
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
    short = _ended_short(ax, ds, x_dim, xs)
    if not numeric:
        ax.set_xticks(xs, [str(v) for v in x], rotation=30, ha="right")
    x_units = ds[x_dim].attrs.get("units", "") if x_dim in ds.coords else ""
    ax.set_xlabel(f"{x_dim} [{x_units}]" if x_units else x_dim)
    ax.set_ylabel(f"critical {parameter} [{units}]" if units else f"critical {parameter}")
    title = ds.attrs.get("title", f"critical points of {parameter}")
    if short:
        stop = ds.attrs.get("path_stop")
        units = ds.attrs.get("units_path_stop", "")
        end = f" of {parameter} = {stop:g} {units}".rstrip() if isinstance(stop, (int, float, np.number)) else ""
        title += f"\n[ENDED SHORT{end}: " + "; ".join(short) + "]"
    ax.set_title(wrapped_title(fig.get_figwidth(), title, fontsize=10), fontsize="medium")
    if np.all(np.isnan(ds.first_critical.values)):  # axes of NaN alone are empty: say why, and how far each got
        stop = ds.attrs.get("path_stop", "")
        whole = f" up to {stop:g} {ds.attrs.get('units_path_stop', '')}".rstrip() if is_number(stop) else ""
        each = ("\n" + "\n".join(f"{_case_label(ds, index)}: {said}{whole if said == 'none' else ''}" for index, said
                                  in zip(np.ndindex(ds.first_critical.shape), first_critical_said(ds))) if short
                else f"\n(each traced up to {parameter} = {stop})" if stop != "" else "")
        ax.text(0.5, 0.5, f"no path met a critical point of {parameter}{each}", transform=ax.transAxes, ha="center",
                va="center", fontsize="small" if short else None)
        if numeric and len(xs):
            ax.set_xlim(float(np.min(xs)) - 0.5 * (np.ptp(xs) or 1.0), float(np.max(xs)) + 0.5 * (np.ptp(xs) or 1.0))
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return fig


def _ended_short(ax, ds, x_dim, xs):
    """Mark on ``ax`` each case whose path stopped before the end of its range (``status`` not ``complete``:
    ``max_steps``, a limit, a failure, a case that did not run) with a dotted line at its x and its status; returns
    ``["nu = 0.45 (max_steps)", ...]``. Its critical points were drawn as any case's: those it met before it stopped."""
    if "status" not in ds:
        return []
    status = ds["status"]
    said = []
    for index in np.ndindex(status.shape):
        word = str(status.values[index])
        if word in ("complete", ""):
            continue
        where = dict(zip(status.dims, index))
        at = xs[where[x_dim]]
        ax.vlines(at, 0, 1, transform=ax.get_xaxis_transform(), colors="0.4", linestyles=":", lw=1.2, zorder=0,
                  gid="ended short")
        ax.annotate(word, (at, 1.0), xycoords=("data", "axes fraction"), xytext=(3, -4), textcoords="offset points",
                    rotation=90, va="top", ha="left", fontsize=7, color="0.3")
        got = reached(ds, index)
        said.append(_case_label(ds, index) + f" ({word}{' at ' + got if got else ''})")
    if said:
        ax.plot([], [], ":", color="0.4", lw=1.2, label="path ended short (its status)")
    return said


def _case_label(ds, index):
    """``"nu = 0.45, h = 0.003"``: case ``index`` (a tuple on the study's dims)."""
    return ", ".join(f"{d} = {ds[d].values[k]!s}" if d in ds.coords else f"{d} {k}"
                     for d, k in zip(ds["first_critical"].dims, index))


def reached(ds, index):
    """``"1965.48 Pa"``: the load the path of case ``index`` (a tuple on the study's dims) of a study of paths ``ds``
    reached, when it ended short of its range's stop (``status`` not ``complete``); ``""`` for a complete one, or
    one with no state (a refused case), or a file written before the variable ``reached``."""
    status = str(ds["status"].values[index]) if "status" in ds else ""
    value = float(ds["reached"].values[index]) if "reached" in ds else np.nan
    if status in ("complete", "") or not np.isfinite(value):
        return ""
    return f"{value:.6g} {ds['reached'].attrs.get('units', '')}".rstrip()


def first_critical_said(ds):
    """Each case's first critical load (in the order of ``ds.first_critical.values.ravel()``): ``"-69.4898"``,
    ``"none"`` without one up to the range's stop, ``"none up to 1965.48 Pa (max_steps)"`` for a path that ended
    short of it without one (``"none (refused)"`` for a case with no path)."""
    out = []
    for index in np.ndindex(ds.first_critical.shape):
        value = float(ds.first_critical.values[index])
        status = str(ds["status"].values[index]) if "status" in ds else "complete"
        at = reached(ds, index)
        out.append(f"{value:.6g}" if np.isfinite(value) else "none" if status in ("complete", "") else
                   f"none up to {at} ({status})" if at else f"none ({status})")
    return out


def plot_path_study(ds, path):
    """Write :func:`path_study_figure` to ``path`` (atomically)."""
    save_figure(path_study_figure(ds), path)


__all__ = ["first_critical_said", "is_path_study", "path_study_figure", "plot_path_study", "reached"]
