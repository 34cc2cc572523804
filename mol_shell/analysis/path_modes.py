"""Checks of a path's critical modes: the grid's modes among them, and the near-critical points a path passes.

**Grid modes.** A critical point's mode is measured as :mod:`mol_shell.modes <mol_shell.analysis.modes>` measures a
natural mode (:func:`~mol_shell.analysis.grid_modes.grid_mode_share`: the share of its amplitude, fields weighted by
their kinetic energy, in the node-to-node ``(-1)^i`` pattern). For a wave of ``k`` the share is
``(1 - cos k ds) / 2``: 0.5 at a half-wavelength of two cells, the shortest the grid can hold. A mode from
:data:`~mol_shell.analysis.grid_modes.GRID_MODE_SHARE` on is the grid's, and so is its critical load (a cylinder of
``L = 4`` m, wall ``t = 0.01`` m, under an end force at n = 21: its ring buckling's classical half-wavelength,
``pi sqrt(a t) / (12 (1 - nu^2))^(1/4) = 0.173`` m, is under one cell of 0.2 m, and the path's first bifurcation had
a mode of share 0.79, the equivalent of 1.4 cells a half-wavelength). :func:`grid_warning` says so.

**Near-critical points.** An imperfect bifurcation is no crossing: the eigenvalue that would cross zero falls
towards it and rises again (the discrete sphere departs from a sphere by ``O(ds^2)``, which makes it imperfect for
the even Legendre degrees: at a/t = 50, n = 80 the lowest eigenvalue fell from 540 to 4.6 s-2 at 0.977 of the
classical load and rose again, and the path reported only a later fold). :func:`near_critical` finds, among the
steps a path recorded, those where the lowest non-negative eigenvalue has a local minimum below :data:`NEAR_SHARE`
of its value at the path's start with no change in the count of negative eigenvalues: each is a near-critical point,
its load an estimate of the perfect shell's critical load (one eigen-solve there, for its mode).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from mol_shell.analysis.grid_modes import GRID_MODE_SHARE, grid_mode_share
from mol_shell.analysis.path_stability import EIGENVALUES, LOCATE_ITER, LOCATE_RTOL, family, stability
from mol_shell.model.kinematics import FIELDS

#: a local minimum of the lowest non-negative eigenvalue ``omega^2`` below this share of its value at the path's
#: start is a near-critical point. Near a bifurcation the crossing eigenvalue falls about linearly in the load
#: (``omega^2 ~ omega_0^2 (1 - lambda / lambda_cr)`` from an unloaded start), so a minimum under 1 % of the start's
#: lies within about 1 % of the load at which the perfect shell would cross (the sphere above: 0.84 % at 0.977 of
#: the classical load, a fold at 0.983); an eigenvalue that only softens (a pressurised shell's stiffening and
#: softening modes, a plate's bending) stays well above it
NEAR_SHARE = 1e-2


def mode_shape(eq, vector):
    """A vector on the free coordinates as fields ``(5, n)`` (held and imposed entries 0, a pole's chi tied)."""
    out = np.zeros((5, eq.n))
    node, local = np.divmod(eq.q_idx, eq.ny)
    out[np.array(eq.system.active)[local], node] = vector
    return eq.system.tie(out)


def grid_shares(eq, pairs):
    """Each mode's :func:`~mol_shell.analysis.grid_modes.grid_mode_share`, ``pairs`` ``[(q, mode), ...]`` (a state
    and a mode on the free coordinates there): an array as long as ``pairs``."""
    if not pairs:
        return np.zeros(0)
    local = eq.q_idx % eq.ny
    field = np.array(eq.system.active)[local]
    shapes = np.zeros((len(pairs), 5, eq.n))
    fractions = np.zeros((len(pairs), 5))
    for m, (q, mode) in enumerate(pairs):
        shapes[m] = mode_shape(eq, mode)
        Mphi = eq.mass(q) @ mode
        kinetic = float(np.dot(mode, Mphi))
        for k in range(5):
            fractions[m, k] = float(np.sum(mode[field == k] * Mphi[field == k]) / kinetic) if kinetic > 0 else 0.0
    data = {name: (("mode", "s"), shapes[:, k]) for k, name in enumerate(FIELDS)}
    data["energy_fraction"] = (("mode", "field"), fractions)
    ds = xr.Dataset(data, coords={"field": list(FIELDS)})
    return np.asarray(grid_mode_share(ds).values, dtype=float)


def half_wavelength_cells(share):
    """The half-wavelength, in cells, of the wave whose grid-mode share is ``share`` (``pi / arccos(1 - 2 share)``:
    2 at 0.5, 1 at 1)."""
    return math.pi / math.acos(min(max(1.0 - 2.0 * float(share), -1.0), 1.0)) if share > 0 else math.inf


def near_critical(record):
    """The near-critical points of the steps ``record`` (a :class:`~mol_shell.analysis.path_record.PathRecord`)
    holds: dicts ``step``, ``parameter``, ``eigenvalue``, ``share`` (of the start's), ``family``, ``chi_share``,
    ``mode``, ``q``, ``located``: each the minimum of the eigenvalue between the steps around it
    (:func:`least_eigenvalue`), the step's where that search fails (``located`` false)."""
    eigen = np.asarray(record.eigen)
    near = []
    for k in range(1, len(record.lams) - 1):
        around = slice(k - 1, k + 2)
        m = record.negative[k]
        if (len(set(record.negative[around])) != 1 or len(set(record.det_sign[around])) != 1
                or len(set(record.branches[around])) != 1 or m >= EIGENVALUES):
            continue
        before, here, after, start = eigen[k - 1, m], eigen[k, m], eigen[k + 1, m], eigen[0, m]
        if not (np.isfinite([before, here, after, start]).all() and start > 0 and 0 < here < before
                and here <= after and here < NEAR_SHARE * start):
            continue
        lam, q, w2, vectors, located = least_eigenvalue(record, k, m)
        mode = vectors[:, m]
        name, chi = family(record.eq, q, mode)
        near.append({"step": k, "parameter": lam, "eigenvalue": float(w2[m]), "share": float(w2[m] / start),
                     "family": name, "chi_share": chi, "mode": mode, "q": q, "located": located})
    return near


def least_eigenvalue(record, k, m):
    """``(load, q, w2, vectors, located)``: where eigenvalue ``m`` (ascending) is least between steps ``k - 1`` and
    ``k + 1`` of ``record``, step ``k``'s the least of the three; the spectrum there (:func:`stability`).

    The load is searched, not the step taken: successive parabolas through the three best states (golden sections
    where a parabola's vertex leaves the bracket or the bracket stops shrinking), to :data:`LOCATE_RTOL` of
    ``|stop - start|``, in at most :data:`LOCATE_ITER` trials; each trial's state by Newton at its fixed load from
    the chord of its neighbours, as a bifurcation's trials
    (:meth:`~mol_shell.analysis.path_record.PathRecord.state_at`). A minimum is a smooth extremum of the load (no
    crossing, no fold), so the eigenvalue is smooth in it there, and a parabola's vertex converges superlinearly.
    Step ``k``'s own state and load, with ``located`` false, where the load does not go one way over the three steps,
    a trial fails, its count of negative eigenvalues or sign of ``det K`` differs from the steps' (a crossing
    between them: no near-critical point), or the bracket does not close."""
    eq, lams = record.eq, record.lams
    step = stability(eq, record.qs[k], lams[k])
    here = (lams[k], record.qs[k], step[0], step[1])
    way = math.copysign(1.0, lams[k + 1] - lams[k - 1])
    a, x, b = (way * lams[j] for j in (k - 1, k, k + 1))
    if not (a < x < b and record.tls[k - 1] * record.tls[k] > 0 and record.tls[k] * record.tls[k + 1] > 0):
        return (*here, False)
    states = {a: record.qs[k - 1], x: record.qs[k], b: record.qs[k + 1]}
    fa, fx, fb = (float(record.eigen[j][m]) for j in (k - 1, k, k + 1))
    best, tol = here, LOCATE_RTOL * record.tracer.l_scale
    moves = [math.inf, math.inf]  # the distances of the trials from the best state before them
    if b - a <= 1.01 * tol:
        return (*best, True)
    for _ in range(LOCATE_ITER):
        u = _vertex(a, x, b, fa, fx, fb)
        if not a < u < b or abs(u - x) >= moves[-2] / 2:  # as Brent: a vertex that does not close in, a golden section
            u = x + GOLDEN * (b - x) if b - x > x - a else x - GOLDEN * (x - a)
        if abs(u - x) < tol / 2:  # half the tolerance off the best at least: the bracket closes on it
            u = x + math.copysign(tol / 2, (b - x) - (x - a))
        moves.append(abs(u - x))
        other = a if u < x else b
        try:
            q = record.state_at(way * u, (states[x], way * x), (states[other], way * other))
        except record.failed:
            return (*here, False)
        w2, vectors, negative, sign = stability(eq, q, way * u)
        if negative != m or sign != record.det_sign[k]:
            return (*here, False)
        states[u], fu = q, float(w2[m])
        if fu < fx:
            if u < x:
                b, fb = x, fx
            else:
                a, fa = x, fx
            x, fx, best = u, fu, (way * u, q, w2, vectors)
        elif u < x:
            a, fa = u, fu
        else:
            b, fb = u, fu
        if b - a <= 1.01 * tol:  # closed by this trial (the last one's too)
            return (*best, True)
    return (*here, False)


#: the golden section's share of the larger side of a bracket
GOLDEN = (3.0 - math.sqrt(5.0)) / 2.0


def _vertex(a, x, b, fa, fx, fb):
    """The abscissa of the vertex of the parabola through ``(a, fa), (x, fx), (b, fb)`` (NaN where they are on a
    line)."""
    p = (x - a) ** 2 * (fx - fb) - (x - b) ** 2 * (fx - fa)
    d = (x - a) * (fx - fb) - (x - b) * (fx - fa)
    return x - 0.5 * p / d if d != 0 else math.nan


def near_message(eq, near):
    """The one line that says a path passed near-critical points (``""`` without)."""
    if not near:
        return ""
    unlocated = ", not located: the step's load"
    said = "; ".join(f"{eq.parameter} = {p['parameter']:.6g} {eq.units} (near step {p['step']}"
                     f"{'' if p.get('located') else unlocated}, {p['family']}; "
                     f"lowest eigenvalue {p['eigenvalue']:.3g} s-2, {p['share']:.2%} of the start's)" for p in near)
    return (f"the path passed {'a near-critical point' if len(near) == 1 else f'{len(near)} near-critical points'} "
            f"at {said}: a local minimum of the lowest eigenvalue without a crossing, an imperfect bifurcation (the "
            f"grid's departure from the perfect shell, or the scene's own imperfection); its load is an estimate of "
            f"the perfect shell's critical load (near_parameter)")


def grid_warning(eq, kinds, loads, shares):
    """The one line that says which critical modes are the grid's (``""`` when none): ``kinds`` (``bifurcation``,
    ``limit`` or ``near-critical``), ``loads`` and ``shares`` per point."""
    flagged = [(kind, load, share) for kind, load, share in zip(kinds, loads, shares) if share >= GRID_MODE_SHARE]
    if not flagged:
        return ""
    said = ", ".join(f"{kind} at {eq.parameter} = {load:.6g} {eq.units} (share {share:.2f}: a half-wavelength of "
                     f"{half_wavelength_cells(share):.2g} cells)" for kind, load, share in flagged)
    return (f"critical mode{'s' * (len(flagged) != 1)} of the grid at n = {eq.n}: {said}; {GRID_MODE_SHARE:g} or more "
            f"of the amplitude in the node-to-node (-1)^i pattern (point_grid_mode_share, near_grid_mode_share), under "
            f"two cells a half-wavelength: the load is the grid's, not the shell's; refine n")


__all__ = ["GOLDEN", "NEAR_SHARE", "grid_shares", "grid_warning", "half_wavelength_cells", "least_eigenvalue", "mode_shape",
           "near_critical", "near_message"]
