"""The discrete loads of a :class:`~mol_shell.discretization.system.ShellSystem`: generalised forces, their power, drag.

The potentials and the Rayleigh function of :mod:`mol_shell.model.loads`, summed over the grid and
differentiated by CasADi:

* pressure: ``-p h(t) V_h(q)``, ``V_h = sign pi sum_cells r_mid^2 (z_{i+1} - z_i)`` (``sign`` makes the
  natural shell's volume positive);
* gravity: ``g h(t) sum_i (mA_i z_i + mI_i d_i.k)``;
* end force and torque: ``-F h(t) z_end``, ``-M h(t) chi_end``;
* drag: ``R = drag/2 sum_i A_i |r_t,i|^2``, ``A_i`` the reference area of node ``i``'s dual cell.

:func:`load_terms` returns the generalised forces (``5 x n``), the power of the loads on the motion
(``sum F . q_t``) and the drag's dissipation ``2 R``: the run integrates the power into ``work`` and the
dissipation into ``dissipated`` as two extra states, so that ``E(t) - E(0) = work - dissipated`` can be
checked to the integrator's accuracy.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ParameterError
from mol_shell.model.loads import cell_volume, drag_rayleigh, gravity_potential, history

#: per end load: the field it acts on, the field's letter, the drive that would prescribe the field's rate, and the
#: edges that leave the field free (for messages)
END_LOADS = (("force", 0, "z", "axial_speed", "free, or a set without z"),
             ("torque", 2, "chi", "spin", "magnet, free, or a set without chi"))


def drive_key(scene, end, field):
    """The parameter that drives ``field`` (0 = z, 2 = chi) at ``end``: ``end1_spin``, ..., or a scene's own
    (the twisted cylinder's ``end_omega``, which spins both ends where ``end*_spin`` is 0)."""
    name = f"{end}_{ {f: d for _, f, _, d, _ in END_LOADS}[field]}"
    return name if getattr(scene, name, 0.0) or field != 2 or not getattr(scene, "end_omega", 0.0) else "end_omega"


def check_end_loads(system, scene):
    """Refuse an end load on a field a drive holds (its rate prescribed: the load would do no work on the motion and
    only enter the reaction), an end force where the edge's ``z`` is imposed, a torque where its ``chi`` is (or at a
    pole, or on a scene without chi)."""
    for end, e, node in (("end1", 0, 0), ("end2", 1, system.n - 1)):
        kind = system.edges[e]
        for load, field, letter, _, takers in END_LOADS:
            name, needs = f"{end}_{load}", f"a {load} needs an edge that leaves {letter} free: {takers}"
            value = getattr(scene, name, 0.0)
            if not value:
                continue
            if field not in system.active:  # as an end's spin is refused there (ShellSystem's drives)
                why = f"this scene has no {letter}"
            elif (e, field) in system.drives:  # before the edge's kind: a drive holds a free edge's field too
                key = drive_key(scene, end, field)
                why = (f"{key} = {getattr(scene, key)!r} holds {end}'s {letter} (it prescribes its rate), so a {load} "
                       f"there does no work on the motion and would only enter reaction_{load}; {needs}, and {key} = 0")
            elif field == 2 and kind == "pole":
                why = f"{end} is a pole: its chi is tied to its neighbour's; {needs}"
            elif system.fixed[node, field]:
                why = f"{end} = {kind!r} imposes its {letter}; {needs}"
            else:
                continue
            raise ParameterError(name, value, "0 for this edge", hint=why)


def edge_displacements(system, scene):
    """``[(node, field, value)]`` of the scene's static edge displacements (``end1_dz`` ...) that are not 0. The
    scene has refused one at an edge that does not impose its field (:func:`mol_shell.model.edges.check_displacements`,
    before anything is built)."""
    out = []
    for end, node in (("end1", 0), ("end2", system.n - 1)):
        for kind, field in (("dz", 0), ("dchi", 2)):
            value = getattr(scene, f"{end}_{kind}", 0.0)
            if value:
                out.append((node, field, float(value)))
    return out


def dual_areas(system):
    """``A_i = 2 pi int r0 ds`` over each node's dual cell (the reference area the drag acts on)."""
    x, w = np.polynomial.legendre.leggauss(6)
    s = system.s
    mids = (s[:-1] + s[1:]) / 2
    left, right = np.concatenate([[s[0]], mids]), np.concatenate([mids, [s[-1]]])
    out = np.zeros(system.n)
    for lo, hi in ((left, s), (s, right)):
        half = (hi - lo) / 2
        pts = ((lo + hi) / 2)[:, None] + half[:, None] * x[None, :]
        r0 = system.meridian.at(pts.ravel())[0].reshape(pts.shape)
        out += 2 * math.pi * np.sum(half[:, None] * w[None, :] * r0, axis=1)
    return out


def volume_sign(system):
    """``+1`` if the natural shell's ``pi sum r^2 dz`` is positive (z increasing along s), else ``-1``."""
    z0, r0, _ = system.reference
    r = (r0[1:] + r0[:-1]) / 2
    return 1.0 if np.sum(r * r * np.diff(z0)) >= 0 else -1.0


def load_terms(system, scene, t, Q, V):
    """``(forces 5 x n, power, drag dissipation 2R)`` of the scene's loads at time ``t`` (MX).

    The forces are not masked: the caller removes those on imposed and driven fields from the equations
    (a driven field's share goes into its reaction).
    """
    n = system.n
    hist = scene.load_histories()
    forces = ca.MX.zeros(NF, n)
    power = 0
    dissipation = 0
    if "pressure" in hist:
        zl, zr, rl, rr = (ca.MX.sym(name) for name in ("zl", "zr", "rl", "rr"))
        vol = cell_volume(zl, zr, rl, rr)
        grad = ca.Function("dV", [zl, zr, rl, rr], [ca.gradient(vol, ca.vertcat(zl, zr, rl, rr))]).expand()
        g = grad.map(n - 1)(Q[0, :-1], Q[0, 1:], Q[1, :-1], Q[1, 1:])  # 4 x (n - 1)
        pad = ca.MX.zeros(1, 1)
        dz = ca.horzcat(g[0, :], pad) + ca.horzcat(pad, g[1, :])
        dr = ca.horzcat(g[2, :], pad) + ca.horzcat(pad, g[3, :])
        p = volume_sign(system) * scene.pressure * history(hist["pressure"], t)
        forces = forces + ca.vertcat(p * dz, p * dr, ca.MX.zeros(3, n))
    if "gravity" in hist:
        q, m = ca.SX.sym("q", NF), ca.SX.sym("m", 3)
        m_i = m[1] if system.has_rho_i else 0
        pot = gravity_potential(ca.vertsplit(q), m[0], m_i, 1.0)
        grad = ca.Function("dG", [q, m], [ca.gradient(pot, q)])
        g = scene.gravity * history(hist["gravity"], t)
        forces = forces - g * grad.map(n)(system.tie(Q), system.inertia)
    for end, node in (("end1", 0), ("end2", n - 1)):
        for kind, row in (("force", 0), ("torque", 2)):
            name = f"{end}_{kind}"
            if name in hist:
                value = getattr(scene, name) * history(hist[name], t)
                unit = np.zeros((NF, n))
                unit[row, node] = 1.0
                forces = forces + value * ca.DM(unit)
    power = ca.sum1(ca.sum2(forces * V))  # imposed fields do not move; driven ones do, and loads work on them
    if "drag" in hist:
        q, v, a = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("a")
        R = drag_rayleigh(ca.vertsplit(q), ca.vertsplit(v), a, scene.drag)
        f = ca.Function("drag", [q, v, a], [ca.gradient(R, v), 2 * R])
        dRdv, twice = f.map(n)(system.tie(Q), V, dual_areas(system)[None, :])
        forces = forces - dRdv
        dissipation = ca.sum2(twice)
    return forces, power, dissipation


def history_kinks(parsed):
    """The times after the start where a parsed history (:func:`mol_shell.model.loads.parse_history`) is not smooth:
    the end of a ramp, every point of a table (held before its first and after its last), a step's time; none for a
    constant or a sine (a step at 0 is the start)."""
    kind, data = parsed
    if kind in ("ramp", "step"):
        return tuple(t for t in data[:1] if t > 0)
    if kind == "table":
        return tuple(t for t in data[0] if t > 0)
    return ()


def drive_kinks(system):
    """The times after the start where a driven edge's prescribed rate has a kink, increasing (empty without
    drives): there the driven node's acceleration, and with it the driver's power, jumps. A multistep solver that
    steps across such a time, or carries its history over it, misses the driver's work by far more than its
    tolerance; the compiled SUNDIALS loop stops and restarts at each (docs/loads.md)."""
    times = {t for _, parsed in getattr(system, "drives", {}).values() for t in history_kinks(parsed)}
    return tuple(sorted(times))
