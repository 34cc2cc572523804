"""Figure of an equilibrium path: the load against a chosen response, critical points marked, and each critical
mode drawn on the meridian.

Left: the continued load against the response, solid where the state is stable (no negative eigenvalue of the
tangent stiffness), dashed where it is not; limit points as triangles, bifurcations as circles, each numbered as
in the file (``--point K``). Right: the meridian ``(r, z)`` in its reference state (grey), and for each critical
point its equilibrium (thin) with the critical mode added (bold), the mode scaled to a tenth of the meridian's size.
"""

from __future__ import annotations

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.views.figures import save_figure

#: the critical mode as drawn: its largest displacement this fraction of the meridian's size
MODE_SCALE = 0.1
MARKERS = {"limit": "^", "bifurcation": "o"}


def responses(ds):
    """The responses a path can be drawn against: its scalar variables along ``step`` (the load aside) and
    ``FIELD@S`` (a field at the node nearest ``s``)."""
    return tuple(name for name, var in ds.data_vars.items() if var.dims == ("step",) and name != "parameter")


def response_values(ds, response):
    """``(values along step, label)``; ``response``: one of :func:`responses` or ``FIELD@S``."""
    if "@" in response:
        field, _, at = response.partition("@")
        first, last = float(ds.s[0]), float(ds.s[-1])
        low, high = f"{first:.6g}", f"{last:.6g}"  # the ends as said: a value typed as shown is taken
        if not min(first, float(low)) <= float(at) <= max(last, float(high)):
            raise ParameterError("--response", response, f"FIELD@S with S in [{low}, {high}] m (the meridian's arc "
                                 "length; S is drawn at the node nearest it)")
        node = int(np.argmin(np.abs(ds.s.values - float(at))))
        var = ds[field]
        return var.values[:, node], f"{field} at s = {float(ds.s[node]):.4g} m [{var.attrs.get('units', '')}]"
    var = ds[response]
    return var.values, f"{response} [{var.attrs.get('units', '')}]"


def path_figure(ds, response="load_conjugate"):
    """The figure (a matplotlib ``Figure``, not saved)."""
    import matplotlib.pyplot as plt

    x, xlabel = response_values(ds, response)
    lam = ds.parameter.values
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6))
    stable = ds.negative_eigenvalues.values == 0
    # each segment drawn in the style of its less stable end
    for k in range(len(lam) - 1):
        ok = stable[k] and stable[k + 1]
        left.plot(x[k:k + 2], lam[k:k + 2], "-" if ok else "--", color="tab:blue" if ok else "tab:red", lw=1.5)
    left.plot(x, lam, ".", color="0.3", ms=3)
    npoints = ds.sizes.get("point", 0)
    for m in range(npoints):
        kind = str(ds.point_kind.values[m])
        k = int(ds.point_step.values[m])
        # the point lies between steps k and k + 1: the response there by linear interpolation in the load (limit
        # points: the nearer step's)
        if kind == "limit" or k + 1 >= len(lam) or lam[k + 1] == lam[k]:
            xm = x[k] if k + 1 >= len(lam) or abs(lam[k] - ds.point_parameter.values[m]) <= abs(
                lam[k + 1] - ds.point_parameter.values[m]) else x[k + 1]
        else:
            w = (ds.point_parameter.values[m] - lam[k]) / (lam[k + 1] - lam[k])
            xm = x[k] + w * (x[k + 1] - x[k])
        left.plot(xm, ds.point_parameter.values[m], MARKERS.get(kind, "s"), color="k", mfc="none", ms=9)
        left.annotate(str(m), (xm, ds.point_parameter.values[m]), textcoords="offset points", xytext=(6, 4),
                      fontsize=8)
    units = ds.parameter.attrs.get("units", "")
    left.set_xlabel(xlabel)
    left.set_ylabel(f"{ds.attrs['parameter']} [{units}]")
    left.set_title(f"{ds.attrs.get('scene', '')}: {ds.attrs['parameter']} against {response}\n"
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
    right.legend(fontsize=7, loc="best")
    fig.tight_layout()
    return fig


def plot_path(ds, path, response="load_conjugate"):
    """Draw :func:`path_figure` into ``path``."""
    save_figure(path_figure(ds, response), path)
    return path
