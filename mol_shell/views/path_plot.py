"""Figure of an equilibrium path: the load against a chosen response, critical points marked, and each critical
mode drawn on the meridian.

Left: the continued load against the response, solid where the state is stable (no negative eigenvalue of the
tangent stiffness), dashed where it is not; limit points as triangles, bifurcations as circles, each numbered as
in the file (``--point K``). Right: the meridian ``(r, z)`` in its reference state (grey), and for each critical
point its equilibrium (thin) with the critical mode added (bold), the mode scaled to a tenth of the meridian's size.
"""

from __future__ import annotations

import math
import os

import numpy as np

from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.path_start import checked_path, read_path
from mol_shell.views.figures import path_note, save_figure, wrapped_title

#: the critical mode as drawn: its largest displacement this fraction of the meridian's size
MODE_SCALE = 0.1
MARKERS = {"limit": "^", "bifurcation": "o"}
#: what ``load_conjugate`` is for each continued parameter (mol_shell.analysis.equilibria), for the axis label
CONJUGATE_MEANING = {"pressure": "enclosed volume", "gravity": "minus the mass-weighted height",
                     "end1_force": "z of edge 1", "end2_force": "z of edge 2", "end1_torque": "chi of edge 1",
                     "end2_torque": "chi of edge 2", "end1_dz": "reaction force at edge 1",
                     "end2_dz": "reaction force at edge 2", "end1_dchi": "reaction torque at edge 1",
                     "end2_dchi": "reaction torque at edge 2"}
#: critical points nearer than this share of the axes' ranges (in both directions) share one label
CLOSE = 0.04


def responses(ds):
    """The responses a path can be drawn against: its scalar variables along ``step`` (the load aside) and
    ``FIELD@S`` (a field at the node nearest ``s``)."""
    return tuple(name for name, var in ds.data_vars.items() if var.dims == ("step",) and name != "parameter")


def check_response(ds, response):
    """Refuse, naming ``response``, anything but one of :func:`responses` or ``FIELD@S``."""
    form = "{" + ", ".join(responses(ds)) + "} or FIELD@S with FIELD in {" + ", ".join(FIELDS) + "} and S in m"
    if not isinstance(response, str):
        raise ParameterError.not_a("response", response, "a string", form)
    if "@" in response:
        field, _, at = response.partition("@")
        try:
            ok = field in FIELDS and math.isfinite(float(at))
        except ValueError:
            ok = False
    else:
        ok = response in responses(ds)
    if not ok:
        raise ParameterError("response", response, form)


def path_of(ds):
    """The path a figure draws: ``ds`` (checked: an equilibrium path whose critical points lie on its steps), or the
    path file at ``ds``; named ``ds``."""
    shown = str(ds) if isinstance(ds, (str, os.PathLike)) else None
    ds = read_path(ds, "ds") if shown is not None else checked_path(ds, "ds")
    _check_points_on_steps(ds, shown)
    return ds


def _check_points_on_steps(ds, shown):
    """Refuse a path whose critical points do not lie on its steps: point ``m`` lies between the states at positions
    ``point_step`` and ``point_step + 1``, its load within (a bifurcation) or next to (a limit point: the load turns
    there) theirs. A path cut after it was written (``ds.isel(step=slice(0, 30))``, or its stable steps selected)
    keeps every point with the step it had: the figure failed with an IndexError, or drew the points on other
    steps."""
    lam = ds.parameter.values
    count = len(lam)
    for m, (k, at) in enumerate(zip(ds.point_step.values if "point_step" in ds else (), ds.point_parameter.values
                                    if "point_parameter" in ds else ())):
        k = int(k)
        fits = 0 <= k < count
        if fits and k + 1 < count:  # the load within the step's, give or take the steps beside it (a limit's turn)
            near = np.abs(np.diff(lam[max(k - 1, 0):k + 3]))
            pad = 2.0 * float(near.max()) + 1e-12 * max(abs(lam[k]), abs(lam[k + 1]), 1.0)
            fits = min(lam[k], lam[k + 1]) - pad <= at <= max(lam[k], lam[k + 1]) + pad
        if not fits:
            raise ParameterError.invalid(
                "ds", shown if shown is not None else ds.encoding.get("source", "<xarray.Dataset>"),
                f"holds {count} states, and its critical point {m} (at {ds.attrs.get('parameter')} = {float(at):.6g}) "
                f"is not between its states {k} and {k + 1}", "an equilibrium path as mol-shell path wrote it",
                hint="a path cut or thinned after it was written: keep the points of the steps kept (ds.isel(point=...)) "
                "or draw the whole file")


def response_values(ds, response):
    """``(values along step, label)``; ``response``: one of :func:`responses` or ``FIELD@S``."""
    if "@" in response:
        field, _, at = response.partition("@")
        first, last = float(ds.s[0]), float(ds.s[-1])
        low, high = f"{first:.6g}", f"{last:.6g}"  # the ends as said: a value typed as shown is taken
        if not min(first, float(low)) <= float(at) <= max(last, float(high)):
            raise ParameterError("response", response, f"FIELD@S with S in [{low}, {high}] m (the meridian's arc "
                                 "length; S is drawn at the node nearest it)")
        node = int(np.argmin(np.abs(ds.s.values - float(at))))
        var = ds[field]
        return var.values[:, node], f"{field} at s = {float(ds.s[node]):.4g} m [{var.attrs.get('units', '')}]"
    var = ds[response]
    meaning = CONJUGATE_MEANING.get(str(ds.attrs.get("parameter"))) if response == "load_conjugate" else None
    return var.values, (f"{meaning} ({response})" if meaning else response) + f" [{var.attrs.get('units', '')}]"


def critical_response(ds, x, m):
    """The response at critical point ``m``, which lies between steps ``k = point_step`` and ``k + 1``: by linear
    interpolation in the load (limit points, whose load turns there: the nearer step's)."""
    lam, kind, k, at = ds.parameter.values, str(ds.point_kind.values[m]), int(ds.point_step.values[m]), \
        float(ds.point_parameter.values[m])
    if kind == "limit" or k + 1 >= len(lam) or lam[k + 1] == lam[k]:
        return x[k] if k + 1 >= len(lam) or abs(lam[k] - at) <= abs(lam[k + 1] - at) else x[k + 1]
    return x[k] + (at - lam[k]) / (lam[k + 1] - lam[k]) * (x[k + 1] - x[k])


def _pieces(ds, x, marks):
    """The path as ``(xs, loads, stable)`` pieces: each step's segment split at its critical points (in the order
    found), the piece before the first as stable as the step it leaves, after the last as the step it reaches,
    between two unstable."""
    lam, stable = ds.parameter.values, ds.negative_eigenvalues.values == 0
    steps = ds.point_step.values if "point_step" in ds else np.zeros(0, int)
    out = []
    for k in range(len(lam) - 1):
        ends = [(x[k], lam[k])] + [marks[m] for m in np.flatnonzero(steps == k)] + [(x[k + 1], lam[k + 1])]
        for j in range(len(ends) - 1):
            ok = stable[k] if j == 0 else stable[k + 1] if j == len(ends) - 2 else False
            if len(ends) == 2:
                ok = stable[k] and stable[k + 1]
            out.append(([ends[j][0], ends[j + 1][0]], [ends[j][1], ends[j + 1][1]], ok))
    return out


def _label_groups(points, spans):
    """Indices of ``points`` grouped so that each is within :data:`CLOSE` of its group's first point."""
    groups = []
    for m, (px, py) in enumerate(points):
        for group in groups:
            gx, gy = points[group[0]]
            if abs(px - gx) <= CLOSE * spans[0] and abs(py - gy) <= CLOSE * spans[1]:
                group.append(m)
                break
        else:
            groups.append([m])
    return groups


def path_figure(ds, response="load_conjugate"):
    """The figure (a matplotlib ``Figure``, not saved) of path ``ds`` (or its file)."""
    import matplotlib.pyplot as plt

    ds = path_of(ds)
    check_response(ds, response)
    x, xlabel = response_values(ds, response)
    lam = ds.parameter.values
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6))
    npoints = ds.sizes.get("point", 0)
    marks = [(critical_response(ds, x, m), float(ds.point_parameter.values[m])) for m in range(npoints)]
    for xs, loads, ok in _pieces(ds, x, marks):
        left.plot(xs, loads, "-" if ok else "--", color="tab:blue" if ok else "tab:red", lw=1.5)
    left.plot(x, lam, ".", color="0.3", ms=3)
    if not ds.attrs.get("complete", 1):  # where the path stopped, short of its range
        left.plot(x[-1], lam[-1], "x", color="k", ms=9, mew=1.5)
        left.annotate(f"ended: {ds.attrs.get('status', 'stopped')}", (x[-1], lam[-1]), textcoords="offset points",
                      xytext=(7, -12), fontsize=8)
    for m, (xm, lm) in enumerate(marks):
        left.plot(xm, lm, MARKERS.get(str(ds.point_kind.values[m]), "s"), color="k", mfc="none", ms=9)
    spans = [max(float(np.ptp(np.r_[values, [p[i] for p in marks]])), 1e-300) for i, values in enumerate((x, lam))]
    units = ds.parameter.attrs.get("units", "")
    left.set_xlabel(xlabel)
    left.set_ylabel(f"{ds.attrs['parameter']} [{units}]")
    left.set_title(f"{ds.attrs.get('scene', '')}: {ds.attrs['parameter']} against {xlabel.rpartition(' [')[0]}\n"
                   "solid stable, dashed unstable; ^ limit, o bifurcation", fontsize=9)
    r0, z0 = ds.r0.values, ds.z0.values
    right.plot(r0, z0, color="0.7", lw=1, label="reference")
    size = max(float(np.ptp(r0)), float(np.ptp(z0)), 1e-300)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for m in range(npoints):
        c = colors[m % len(colors)]
        r, z = ds.point_r.values[m], ds.point_z.values[m]
        dr, dz = ds.point_mode_r.values[m], ds.point_mode_z.values[m]
        amp = max(float(np.abs(np.r_[dr, dz]).max()), 1e-300)
        right.plot(r, z, color=c, lw=0.8, alpha=0.6)
        right.plot(r + MODE_SCALE * size * dr / amp, z + MODE_SCALE * size * dz / amp, color=c, lw=1.8,
                   label=f"{m}: {ds.point_kind.values[m]} at {float(ds.point_parameter.values[m]):.4g} {units} "
                   f"({ds.point_family.values[m]})")
    right.set_aspect("equal", adjustable="datalim")
    right.set_xlabel("r [m]")
    right.set_ylabel("z [m]")
    right.set_title("critical modes on the meridian (bold; thin: the equilibrium there)" if npoints else
                    "no critical points on this path", fontsize=9)
    if npoints:  # below the meridian: inside, it covers the modes
        right.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=1 if npoints < 4 else 2,
                     frameon=False)
    note = path_note(ds.attrs, float(lam[-1]))
    if note:  # a path cut short (max_steps, a limit, Ctrl-C) looked like a whole one
        fig.suptitle(wrapped_title(fig.get_figwidth(), f"[{note}]", fontsize=9), fontsize=9)
    fig.tight_layout()
    groups = _label_groups(marks, spans)  # points at nearly one place: one label, "0-2" or "0, 2"
    _label_points(left, [marks[group[0]] for group in groups],
                  [f"{group[0]}-{group[-1]}" if len(group) > 2 and group == list(range(group[0], group[-1] + 1))
                   else ", ".join(map(str, group)) for group in groups])
    return fig


#: a critical point's label: its font size (points), and its place beside the point (points right of it and above)
LABEL_FONT, LABEL_OFFSET = 8, (7.0, 5.0)


def _label_points(ax, anchors, texts):
    """Label each of ``anchors`` (data coordinates) with its text of ``texts``, none over another: in the order of
    their points' heights on the page, each label stands at least a line above the one before it (its point's own
    place, :data:`LABEL_OFFSET`, where that is free), a thin line joining a label moved off its place to its point.
    Placed once the axes are laid out (their transform is final): points close together (bifurcations 2 % of the
    load apart) had their labels on one another."""
    if not anchors:
        return
    points = ax.transData.transform(np.asarray(anchors, dtype=float)) * 72.0 / ax.figure.dpi  # page, in points
    line = 1.3 * LABEL_FONT
    floor = -np.inf
    for k in np.argsort(points[:, 1], kind="stable"):
        dx, dy = LABEL_OFFSET
        y = max(points[k, 1] + dy, floor)
        floor = y + line
        moved = y - points[k, 1] - dy > 0.5
        ax.annotate(texts[k], anchors[k], textcoords="offset points", xytext=(dx, y - points[k, 1]), fontsize=LABEL_FONT,
                    va="bottom", arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.4", "shrinkA": 0, "shrinkB": 5}
                    if moved else None)


def plot_path(ds, path, response="load_conjugate"):
    """Draw :func:`path_figure` into ``path``."""
    save_figure(path_figure(ds, response), path)
    return path
