"""The paper's Figure 1 from a run: a section perpendicular to the axis with its material fibres.

``mol-shell plot run.nc --figure fibres -o fig1.png``: (a) the section at ``s`` in the reference
configuration, its fibres through the thickness radial; (b) the images of the same fibres at a
chosen time, projected onto the plane of the section. A fibre is the segment ``r + zeta d``,
``zeta1 <= zeta <= zeta1 + 2h`` (a graded wall: ``-h(s) <= zeta <= h(s)`` at the section), of the material
line at reference azimuth ``phi``; its projection starts at ``r a2(phi + chi)``
and runs along ``cos(psi) cos(theta) a2 + sin(psi) a3``: ``chi`` turns
the section, ``psi`` tilts its fibres out of the radial direction (the rotationally symmetric, not
axisymmetric, deformation of the paper's Figure 1c). The thickness is drawn magnified (the
magnification is in the title); magnifying ``zeta`` keeps each fibre's direction, so the tilt is
drawn at its true angle.

A run with fibre reinforcement (``fibre_E > 0``, :mod:`mol_shell.model.fibres`; in a layered wall, any layer's)
gets a third panel: (c) the reinforcing fibres on the base surface seen from the side (the half facing the
viewer), in the reference configuration (grey, dashed) and deformed at the same time (one colour per family, and
per layer: :func:`fibre_sets`). A fibre at angle ``alpha``
from the meridian towards ``+phi`` follows ``dphi/ds = tan(alpha) / r0(s)`` on the reference surface; its image
is ``z(s) k + r(s) a2(phi(s) + chi(s))``, drawn as ``(z, r sin(phi + chi))``: the helices of a twisting shell
turn with ``chi``.
"""

from __future__ import annotations

import itertools

import numpy as np
import xarray as xr

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.model.layers import parse_layers
from mol_shell.views.fields import face_depths, run_of
from mol_shell.views.figures import equal_aspect, figure_path, incomplete_note, save_figure, wrapped_title

#: the drawn thickness 2h M is about this fraction of the radius when no magnification is given
DRAWN_THICKNESS = 0.2
#: fibres drawn at most: a fibre every degree, denser than a section shows apart (``--fibres 1e8`` ran for minutes)
MAX_FIBRES = 360


def _nearest(values, value, name, unit):
    lo, hi = float(values[0]), float(values[-1])
    if not (np.isfinite(value) and lo - 1e-12 * max(1.0, abs(hi)) <= value <= hi + 1e-12 * max(1.0, abs(hi))):
        allowed = f"[{lo:g}, {hi:g}] {unit} (the run's range)"
        raise ParameterError(name, value, allowed, message=f"{name} = {value:g} is outside {allowed}")
    return int(np.argmin(np.abs(np.asarray(values) - value)))


#: colours of the reinforcing fibre families in panel (c), in the order of :func:`fibre_sets` and their families
FAMILY_COLOURS = ("tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown", "tab:pink")


def fibre_sets(ds):
    """``[(label, angle, families)]`` of a run's reinforcing fibres: the scene's (label ``""``) when ``fibre_E > 0``;
    for a layered wall each layer's whose ``fibre_E > 0`` (label ``"layer k"``, counted from the lower face; a key
    the layer leaves out is the scene's, as the run takes it)."""
    attrs = ds.attrs
    layers = str(attrs.get("layers", "") or "").strip()
    if layers in ("", "none"):
        if float(attrs.get("fibre_E", 0.0)) > 0:
            return [("", float(attrs.get("fibre_angle", 0.0)), int(attrs.get("fibre_families", 1)))]
        return []
    out = []
    for number, (_, _, changes) in enumerate(parse_layers(layers), start=1):
        def value(key, default, changes=changes):
            return float(changes.get(key, attrs.get(key, default)))
        if value("fibre_E", 0.0) > 0:
            out.append((f"layer {number}", value("fibre_angle", 0.0), int(value("fibre_families", 1))))
    return out


#: what :func:`fibres_figure` reads of a run at its section (and its faces' depths: ``faces``); :func:`fibre_reads`
SECTION = ("r", "chi", "theta", "psi")


def fibre_reads(ds):
    """The variables :func:`fibres_figure` reads of ``ds`` (a Dataset, or the path of a run file: its section's,
    :data:`SECTION`; ``z`` too, for the reinforcing fibres of a run that has them)."""
    return SECTION + (("z",) if isinstance(ds, xr.Dataset) and fibre_sets(ds) else ())


def reinforcing_fibres(ds, k, count=12, angle=None, families=None):
    """Per family, ``(reference, deformed)`` arrays ``(fibre, node, 2)`` of the side view ``(z, y)`` at time index
    ``k``, NaN where a point faces away (``cos(phi + chi) < 0``) or where ``r0`` is under 2 % of its largest value
    (near a pole the helix winds without end). ``angle`` (rad) and ``families``: the run's scene-level ones unless
    given (a layer's)."""
    nodes = ds["s"].values
    fine = np.linspace(nodes[0], nodes[-1], 8 * len(nodes))  # the nodal values interpolated linearly

    def at(values):
        return np.interp(fine, nodes, values)

    r0 = at(ds["r0"].values) if "r0" in ds else np.ones_like(fine)
    z0 = at(ds["z0"].values) if "z0" in ds else fine
    alpha = float(ds.attrs.get("fibre_angle", 0.0)) if angle is None else angle
    families = int(ds.attrs.get("fibre_families", 1)) if families is None else families
    keep = r0 > 0.02 * np.max(r0)
    inv = np.where(keep, 1.0 / np.where(keep, r0, 1.0), 0.0)
    turn = np.concatenate([[0.0], np.cumsum(np.diff(fine) * (inv[1:] + inv[:-1]) / 2)])  # int ds / r0
    z, r, chi = (at(ds[f].values[k]) for f in ("z", "r", "chi"))
    start = 2 * np.pi * np.arange(count) / count
    out = []
    for sign in (1, -1)[:families]:
        phi = start[:, None] + sign * np.tan(alpha) * turn[None, :]
        ref = np.stack([np.broadcast_to(z0, phi.shape), r0 * np.sin(phi)], axis=-1)
        ref[(np.cos(phi) < 0) | ~keep] = np.nan
        angle = phi + chi
        cur = np.stack([np.broadcast_to(z, phi.shape), r * np.sin(angle)], axis=-1)
        cur[(np.cos(angle) < 0) | ~keep] = np.nan
        out.append((ref, cur))
    return out


def _fibre_panel(ax, ds, k, sets):
    colour = itertools.cycle(FAMILY_COLOURS)  # up to 20 layers of 2 families: the colours come round again
    for label, alpha, families in sets:
        for j, (ref, cur) in enumerate(reinforcing_fibres(ds, k, angle=alpha, families=families)):
            for line in ref:
                ax.plot(line[:, 0], line[:, 1], color="0.65", lw=0.8, ls=(0, (2, 1.5)))
            c = next(colour)
            for number, line in enumerate(cur):
                ax.plot(line[:, 0], line[:, 1], color=c, lw=1.3, label=None if number or not label else
                        f"{label}: {'-' if j else '+'}{np.degrees(alpha):.3g} deg")
    ax.set_xlabel("z [m] (along the axis)")
    ax.set_ylabel("y [m]")
    if len(sets) == 1 and not sets[0][0]:
        _, alpha, families = sets[0]
        what = f"{'+-' if families == 2 else ''}{np.degrees(alpha):.3g} deg"
    else:
        what = "of each layer"
        ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"(c) reinforcing fibres {what}, side view:\n"
                 "dashed the reference, solid at the time of (b)", fontsize=10)


def fibres_figure(ds, time=None, s=None, count=24, thickness_scale=None):
    """The figure (a matplotlib ``Figure``, not saved).

    Parameters
    ----------
    ds : xarray.Dataset or str or os.PathLike
        A run, or the path of its netCDF file.
    time : float, optional
        Time of panel (b), s; the nearest saved time is drawn (default the last).
    s : float, optional
        Where the section is, m; the nearest node (default the first, an end of the shell, or on a closed shell,
        whose ends are poles, the widest section).
    count : int
        Fibres drawn (evenly spaced reference azimuths; the one at ``phi = 0`` in red), in [1, :data:`MAX_FIBRES`].
    thickness_scale : float, optional
        Magnification of the thickness, at most the section's reference radius over the wall's thickness there (the
        drawn wall stays off the axis); default: the drawn thickness is 0.2 of the reference radius.
    """
    import matplotlib.pyplot as plt

    if not (isinstance(count, (int, np.integer)) and not isinstance(count, bool) and 1 <= count <= MAX_FIBRES):
        raise ParameterError("count", count, f"integers in [1, {MAX_FIBRES}]")
    ds = run_of(ds, "plot --figure fibres", fibre_reads(ds), faces=True)
    times, nodes = ds["time"].values, ds["s"].values
    k = len(times) - 1 if time is None else _nearest(times, float(time), "time", "s")
    radii = ds["r0"].values if "r0" in ds else np.ones(len(nodes))
    # the first end; on a closed shell (a pole there, r0 = 0: an empty section) the widest section
    i = (0 if radii[0] > 0 else int(np.argmax(radii))) if s is None else _nearest(nodes, float(s), "s", "m")
    if not radii[i] > 0:
        off = nodes[radii > 0]
        raise ParameterError("s", float(s), f"[{off.min():.6g}, {off.max():.6g}] m (sections off the axis: at "
                             "a pole r = 0 and there is no section to draw)")
    r0 = float(radii[i])
    theta0 = float(ds["theta0"].values[i]) if "theta0" in ds else 0.0
    depths = np.array([faces[i] for faces in face_depths(ds)])  # this section's own: a graded wall's h(s)
    wall = float(depths[1] - depths[0])
    if thickness_scale is None:
        thickness_scale = max(1.0, round(DRAWN_THICKNESS * r0 / wall))
    else:
        most = max(1.0, r0 / wall)  # the drawn wall as thick as the section's radius (at least true to scale)
        shown = float(f"{most:.6g}")  # the bound as said: a value typed as shown is taken
        if not (is_number(thickness_scale) and 0 < thickness_scale <= max(most, shown)):
            raise ParameterError("thickness_scale", thickness_scale, f"(0, {shown:g}] (the drawn wall at most as "
                                 f"thick as the section's radius, or true to scale: r0 = {r0:.6g} m, wall "
                                 f"{wall:.6g} m thick at s = {nodes[i]:.6g} m)")
    zeta = thickness_scale * depths
    r, chi, theta, psi = (float(ds[f].values[k, i]) for f in SECTION)
    phi = 2 * np.pi * np.arange(count) / count

    def segments(radius0, along, across, angle):
        """Fibre ends: base point at ``radius0`` along ``j2(angle)``, plus ``zeta (along j2 + across j3)``."""
        j2 = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
        j3 = np.stack([-np.sin(angle), np.cos(angle)], axis=-1)
        return np.stack([radius0 * j2 + z * (along * j2 + across * j3) for z in zeta], axis=1)  # (fibre, end, 2)

    reference = segments(r0, np.cos(theta0), 0.0, phi)
    deformed = segments(r, np.cos(psi) * np.cos(theta), np.sin(psi), phi + chi)
    circle = np.linspace(0, 2 * np.pi, 361)

    sets = fibre_sets(ds)
    reinforced = bool(sets)
    fig, axes = plt.subplots(1, 3 if reinforced else 2, figsize=(13.8 if reinforced else 9.2, 5.4),
                             layout="constrained")
    # room beside each panel for a tick label that grows as equal_aspect settles the limits (one of a pair of
    # layouts that can alternate, "-2" and "-2.0": the y label of (c) stood on the frame of (b))
    fig.get_layout_engine().set(w_pad=0.15)
    panels = [(axes[0], reference, [r0 + z * np.cos(theta0) for z in zeta], r0, "(a) reference configuration"),
              (axes[1], deformed, [np.hypot(r + z * np.cos(psi) * np.cos(theta), z * np.sin(psi)) for z in zeta], r,
               f"(b) t = {times[k]:.4g} s: chi = {chi:+.4g} rad, psi = {psi:+.3g} rad,\nr = {r:.5g} m, "
               f"theta = {theta:+.3g} rad")]
    for ax, fibres, faces, base, label in panels:
        ax.fill_between(faces[1] * np.cos(circle), faces[1] * np.sin(circle), 0, color="#dbe6f3", lw=0)
        ax.fill_between(faces[0] * np.cos(circle), faces[0] * np.sin(circle), 0, color="white", lw=0)
        for radius in faces:
            ax.plot(radius * np.cos(circle), radius * np.sin(circle), color="0.35", lw=0.8)
        ax.plot(base * np.cos(circle), base * np.sin(circle), color="0.35", lw=0.6, ls=":")
        if ax is axes[1]:
            for seg in reference:
                ax.plot(seg[:, 0], seg[:, 1], color="0.65", lw=1.0, ls=(0, (2, 1.5)))
        for j, seg in enumerate(fibres):
            ax.plot(seg[:, 0], seg[:, 1], color="tab:red" if j == 0 else "k", lw=1.8 if j == 0 else 1.2)

        ax.set_xlabel("x [m]")  # the plane of the section, x towards phi = 0
        ax.set_ylabel("y [m]")
        ax.set_title(label, fontsize=10)
    if reinforced:
        _fibre_panel(axes[2], ds, k, sets)
    scene = ds.attrs.get("scene", "run")
    title = (f"{scene}: the section at s = {nodes[i]:.4g} m and its material fibres through the thickness "
             f"(drawn {thickness_scale:g}x thicker)\nin (b) dashed: the fibres of (a); red: the fibre at phi = 0")
    if incomplete_note(ds.attrs):  # (b) is a state of a run that stopped early: as the paper's figures say it
        title += "\n" + wrapped_title(fig.get_figwidth(), f"[{incomplete_note(ds.attrs)}]")
    fig.suptitle(title, fontsize=10)
    equal_aspect(fig)
    return fig


def plot_fibres(ds, path, **options):
    """Write :func:`fibres_figure` to ``path`` (a run's Dataset or file; ``path`` checked before anything is drawn)."""
    ds = run_of(ds, "plot --figure fibres", fibre_reads(ds), faces=True)
    path = figure_path(path)
    fig = fibres_figure(ds, **options)
    save_figure(fig, path, dpi=120)
    return path
