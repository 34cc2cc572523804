"""Static equilibria under load: Newton's method on the exact sparse Jacobian, with continuation in the load.

At rest (``p = 0``) Hamilton's equations reduce to ``0 = F(q) = -dV/dq + f_loads(q, t = 0)`` on the free
coordinates (``dT/dq`` vanishes with ``p``; drag and viscosity with the rates). The tangent stiffness is
the block ``dp_t/dq`` of :attr:`ShellSystem.jac <mol_shell.discretization.system.ShellSystem.jac>`. Rigid motions
the edges allow (axial translation of a closed sphere) make it singular: one ``z`` is held while Newton iterates
and the result is shifted back to the starting mean ``z`` (what minimum-norm steps give); ``chi`` is held
(no spin). Sparse LU throughout: memory and time per iteration grow like ``n``.

When Newton does not converge from the given state, the loads are applied in increments (continuation:
each load times ``lambda`` from 0 to 1, each increment's solution the next one's start); when even that
fails, a ParameterError names the scene and the residual reached.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.runs.building import build

#: Newton stops when the residual is below this fraction of a unit strain's force (``max diag K`` x scale)
TOL = 1e-11
MAX_ITER = 30


def to_csc(dm):
    """A CasADi sparse matrix as SciPy CSC (the same compressed-column layout; nothing dense)."""
    import scipy.sparse  # optional heavy dependency: loaded where statics needs it

    sp = dm.sparsity()
    return scipy.sparse.csc_matrix((np.array(dm.nonzeros()).ravel(), sp.row(), sp.colind()), shape=dm.shape)


def _free_entries(system, hold):
    fixed = system.fixed[:, list(system.active)]
    return np.array([system.ny * i + j for i in range(system.n) for j, k in enumerate(system.active)
                     if not fixed[i, j] and k not in hold])


def _gauge(system, hold, field):
    """Positions in the state of every entry of ``field`` (0: ``z``, 2: ``chi``) when it is solved for and no edge
    imposes it (the shell may translate along the axis, or spin about it: the Jacobian is singular), else ``None``."""
    if field not in system.active or field in hold or system.fixed[:, system.active.index(field)].any():
        return None
    return np.arange(system.n) * system.ny + system.active.index(field)


def newton(system, y0, hold=(2,), tol=TOL, max_iter=MAX_ITER):
    """``(y, iterations, residual)``: Newton from ``y0`` at rest, ``hold`` fields (default ``chi``) kept as given.

    Each step solves with the exact sparse Jacobian (SuperLU, ``scipy.sparse.linalg.splu``; the node-major
    ordering keeps it banded): time and memory grow like ``n``, never a dense matrix. A shell that no edge holds
    axially (a closed sphere) can translate along the axis, which makes the Jacobian singular at every state: the
    ``z`` of the first node is held during the iteration (its equation is the sum of the others' for loads
    self-equilibrated axially) and the converged state is shifted along the axis so that the mean ``z`` is the
    starting one's: the solution of minimum-norm steps, which leave the rigid translation where it was. So for
    ``chi`` when it is solved for (``hold`` without 2) and no edge imposes it: the spin about the axis. Steps are
    halved until the residual falls (a full step may cross ``delta = 0`` far from the solution).

    Raises ``RuntimeError`` when it does not converge (the caller may continue in the load).
    """
    import scipy.sparse.linalg  # optional heavy dependency: only statics needs it

    y = np.array(y0, dtype=float)
    y[: system.ny * system.n].reshape(system.n, system.ny)[:, system.nf:] = 0.0  # at rest
    q = _free_entries(system, hold)
    gauges = [g for g in (_gauge(system, hold, 0), _gauge(system, hold, 2)) if g is not None]
    solve = q[~np.isin(q, [g[0] for g in gauges])]
    p, p_solve = q + system.nf, solve + system.nf
    scale = None
    for it in range(max_iter + 1):
        f = np.array(system.rhs_newton(0, y)).ravel()
        J = to_csc(system.jac(0, y)).tocsr()
        Jr = J[p_solve][:, solve].tocsc()
        if scale is None:
            scale = float(np.abs(Jr.diagonal()).max()) * max(1.0, float(np.abs(system.reference[:2]).max()))
        res = float(np.abs(f[p]).max()) / scale
        if not np.isfinite(res):
            raise RuntimeError(f"non-finite residual after {it} iterations")
        if res <= tol:
            for g in gauges:
                y[g] += float(np.mean(np.asarray(y0, dtype=float)[g] - y[g]))
            return y, it, res
        if it == max_iter:
            break
        try:
            step = scipy.sparse.linalg.splu(Jr).solve(-f[p_solve])
        except RuntimeError as exc:  # exactly singular
            raise RuntimeError(f"singular tangent stiffness after {it} iterations ({exc})") from None
        for _ in range(20):
            trial = y.copy()
            trial[solve] += step
            ft = np.array(system.rhs_newton(0, trial)).ravel()[p]
            limits = np.array(system.limits(trial)).ravel()
            if np.all(np.isfinite(ft)) and np.all(limits > 0) and np.abs(ft).max() < np.abs(f[p]).max():
                break
            step /= 2
        else:
            break
        y = trial
    raise RuntimeError(f"Newton did not converge (residual {res:.3g} of a unit strain's force)")


def scaled_loads(scene, factor):
    """``scene`` with every load times ``factor``."""
    return dataclasses.replace(scene, **{k: getattr(scene, k) * factor for k in scene.loads_on()})


def static_equilibrium(scene, n, y0, steps=(0.25, 0.5, 0.75, 1.0), hold=(2,)):
    """The equilibrium state at rest under the scene's loads at ``t = 0``, starting from ``y0``.

    Returns ``(y, info)``; ``info`` says how it was found (for the run's attrs). Direct Newton first;
    on failure, continuation in the load over ``steps`` (each a fraction of the full load).
    """
    system, _ = build(scene, n)
    try:
        y, it, res = newton(system, y0, hold)
        return y, f"static equilibrium under the loads at t = 0 (Newton, {it} iterations, residual {res:.2g})"
    except RuntimeError as direct:
        y = np.array(y0, dtype=float)
        total = 0
        for factor in steps:
            sub, _ = build(scaled_loads(scene, factor), n)
            try:
                y, it, res = newton(sub, y, hold)
            except RuntimeError as exc:
                loads = scene.loads_on()
                name, value = (loads[0], getattr(scene, loads[0])) if loads else ("scene", scene.name)
                others = " (with the other loads as given)" if len(loads) > 1 else ""
                raise ParameterError(name, value, "loads under which the shell has a static equilibrium inside the "
                                     f"model's limits{others}", hint=f"Newton failed ({direct}); continuation "
                                     f"stopped at {factor:g} of the loads ({exc})") from None
            total += it
        return y, (f"static equilibrium under the loads at t = 0 (continuation in {len(steps)} steps, "
                   f"{total} Newton iterations, residual {res:.2g})")
