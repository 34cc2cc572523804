"""Static equilibria under load: Newton's method on the exact sparse Jacobian, with continuation in the load.

At rest (``p = 0``) Hamilton's equations reduce to ``0 = F(q) = -dV/dq + f_loads(q, t = 0)`` on the free
coordinates (``dT/dq`` vanishes with ``p``; drag and viscosity with the rates). The tangent stiffness is
the block ``dp_t/dq`` of :attr:`ShellSystem.jac <mol_shell.discretization.system.ShellSystem.jac>`. Rigid motions
the edges allow (axial translation of a closed sphere, spin about the axis) make it singular: one ``z`` (one
``chi``) is held while Newton iterates and the result is shifted back to the starting mean (what minimum-norm steps
give). Every free field is solved for, ``chi`` included: an end torque, or one helical family of fibres under
pressure, twists the shell at rest (until December 2026 ``chi`` was held as given, and such a state was reported as
an equilibrium with its torque unbalanced). Sparse LU throughout: memory and time per iteration grow like ``n``.

When Newton does not converge from the given state, the loads are applied in increments (continuation:
each load times ``lambda`` from 0 to 1, each increment's solution the next one's start); when even that
fails, a ParameterError names the scene and the residual reached.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.discretization.compiled import buffered
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.loads import history
from mol_shell.runs.building import build

#: Newton stops when the residual is below this fraction of a unit strain's force (``max diag K`` x scale)
TOL = 1e-11
MAX_ITER = 30


def sparse_evaluator(f):
    """``(*inputs) -> [outputs]`` of the CasADi Function ``f`` in NumPy: a column as a 1-D array, a matrix as SciPy
    CSC on its structural pattern (read once). Evaluated through a preallocated buffer
    (:func:`~mol_shell.discretization.compiled.buffered`; dense inputs): no DM is made per call, where the DM of a
    48,000-entry Jacobian took 4.5 ms to convert to SciPy and its evaluation 15 % longer. The outputs are
    copies, safe to keep."""
    import scipy.sparse  # optional heavy dependency: loaded where statics needs it

    call = buffered(f)
    patterns = [f.sparsity_out(i) for i in range(f.n_out())]
    rows = [np.array(sp.row(), dtype=np.int32) for sp in patterns]
    columns = [np.array(sp.colind(), dtype=np.int32) for sp in patterns]

    def output(values, sp, row, colind):
        if sp.size2() > 1:  # a matrix, whatever its pattern (a tiny system's Jacobian may be structurally dense)
            return scipy.sparse.csc_matrix((values.copy(), row.copy(), colind.copy()), shape=sp.shape)
        if sp.is_dense():
            return values.copy()
        vector = np.zeros(sp.size1())  # a column with structural zeros: dense, its zeros filled in
        vector[row] = values
        return vector

    def evaluate(*args):
        call(*args)
        return [output(*parts) for parts in zip(call.outputs, patterns, rows, columns)]

    return evaluate


def _free_entries(system, hold):
    fixed = system.fixed[:, list(system.active)]
    return np.array([system.ny * i + j for i in range(system.n) for j, k in enumerate(system.active)
                     if not fixed[i, j] and k not in hold])


def rigid_motions(system):
    """``{what: field}`` of the rigid motions no edge stops, by the field each moves: axial translation (``z``,
    field 0) when no edge imposes or drives ``z``, spin about the axis (``chi``, field 2) when none imposes or
    drives ``chi`` (a pole's ``chi``, tied to its neighbour's, imposes nothing). They make the tangent stiffness
    singular; the statics, the paths and the modes take them out (one definition for all three)."""
    driven = {k for _, k in system.drives}
    return {what: field for what, field in (("axial translation", 0), ("spin about the axis", 2))
            if field in system.active and not system.imposed[:, field].any() and field not in driven}


def _gauge(system, hold, field):
    """Positions in the state of the free entries of ``field`` (0: ``z``, 2: ``chi``) when it is solved for and
    moves rigidly (:func:`rigid_motions`: the Jacobian is singular), else ``None``. A pole's tied ``chi`` is not
    among them."""
    if field in hold or field not in rigid_motions(system).values():
        return None
    column = system.active.index(field)
    return np.flatnonzero(~system.fixed[:, column]) * system.ny + column


def _tied(system, y):
    """``y`` (at rest) with a pole's ``chi`` set to its neighbour's: a tied entry is no unknown of Newton's, and
    once ``chi`` is solved for it kept its starting value beside a neighbour that moved."""
    body = system.ny * system.n
    Q = system.tie(system.unpack(y))
    out = system.pack(Q, np.zeros_like(Q))
    out[body:] = y[body:]
    return out


def newton(system, y0, hold=(), tol=TOL, max_iter=MAX_ITER):
    """``(y, iterations, residual)``: Newton from ``y0`` at rest, ``hold`` fields (indices; none by default) kept
    as given.

    Each step solves with the exact sparse Jacobian (SuperLU, ``scipy.sparse.linalg.splu``; the node-major
    ordering keeps it banded): time and memory grow like ``n``, never a dense matrix. A step is halved until the
    trial state is inside the model's limits (a full step may cross ``delta = 0`` far from the solution) and passes
    the natural monotonicity test (Deuflhard): the next Newton correction, solved with this iteration's LU, is
    smaller than this one (positions in units of the meridian's size, angles in radians). The test is affine
    invariant: a residual's norm is not, and with fibres a thousand times stiffer than the matrix it halved
    converging full steps four to six times over dozens of iterations. A shell that no edge holds
    axially (a closed sphere) can translate along the axis, which makes the Jacobian singular at every state: the
    ``z`` of the first node is held during the iteration (its equation is the sum of the others' for loads
    self-equilibrated axially) and the converged state is shifted along the axis so that the mean ``z`` is the
    starting one's: the solution of minimum-norm steps, which leave the rigid translation where it was. So for
    ``chi`` when it is solved for (``hold`` without 2) and no edge imposes it: the spin about the axis. Once the
    residual is below ``tol``, one more full step (:func:`_polished`) takes it to round-off where it can.

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
    # the corrections' norm: positions (z, r) in units of the meridian's size, angles in radians
    length = max(float(np.abs(system.reference[:2]).max()), 1e-300)
    weight = np.where(np.isin(np.array(system.active)[solve % system.ny], (0, 1)), 1.0 / length, 1.0)
    jacobian = sparse_evaluator(system.jac)

    def reduced(y):  # the Jacobian on the unknowns, evaluated where a step needs it (and for the scale, once)
        return jacobian(0.0, y)[0].tocsr()[p_solve][:, solve].tocsc()

    for it in range(max_iter + 1):
        f = np.array(system.rhs_newton(0, y)).ravel()
        Jr = None
        if scale is None:
            Jr = reduced(y)
            scale = float(np.abs(Jr.diagonal()).max()) * max(1.0, float(np.abs(system.reference[:2]).max()))
        res = float(np.abs(f[p]).max()) / scale
        if not np.isfinite(res):
            raise RuntimeError(f"non-finite residual after {it} iterations")
        if res <= tol:
            y, res = _polished(system, y, f, reduced(y) if Jr is None else Jr, p, solve, scale, res)
            for g in gauges:
                y[g] += float(np.mean(np.asarray(y0, dtype=float)[g] - y[g]))
            return _tied(system, y), it, res
        if it == max_iter:  # (until December 7 its Jacobian was evaluated here too, and never used)
            break
        Jr = reduced(y) if Jr is None else Jr
        try:
            lu = scipy.sparse.linalg.splu(Jr)
        except RuntimeError as exc:  # exactly singular
            raise RuntimeError(f"singular tangent stiffness after {it} iterations ({exc})") from None
        step = lu.solve(-f[p_solve])
        size = np.linalg.norm(step * weight)
        for _ in range(20):
            trial = y.copy()
            trial[solve] += step
            ft = np.array(system.rhs_newton(0, trial)).ravel()
            limits = np.array(system.limits(trial)).ravel()
            # natural monotonicity: the next Newton correction (with this iteration's LU) is smaller than this one
            if (np.all(np.isfinite(ft[p])) and np.all(limits > 0)
                    and np.linalg.norm(lu.solve(-ft[p_solve]) * weight) < size):
                break
            step /= 2
        else:
            break
        y = trial
    raise RuntimeError(f"Newton did not converge (residual {res:.3g} of a unit strain's force)")


def _polished(system, y, f, Jr, p, solve, scale, res):
    """``(y, res)`` after one more full Newton step from a converged ``y`` when it lowers the residual: the
    tolerance is where Newton may stop, the step after it (quadratic convergence) reaches round-off for one more
    factorisation. Kept only when the residual falls: at round-off already, the step is noise."""
    import scipy.sparse.linalg  # optional heavy dependency: only statics needs it

    try:
        step = scipy.sparse.linalg.splu(Jr).solve(-f[solve + system.nf])
    except RuntimeError:  # exactly singular at the solution (a critical point): the converged state stands
        return y, res
    trial = y.copy()
    trial[solve] += step
    after = float(np.abs(np.array(system.rhs_newton(0, trial)).ravel()[p]).max()) / scale
    return (trial, after) if after < res and np.all(np.array(system.limits(trial)).ravel() > 0) else (y, res)


#: the widest band (node-major, in entries off the diagonal) for which a state's stability is checked: a band
#: matrix's eigenvalues below zero cost ``O(N band^2)`` (LAPACK's ``dsbevx``); a meridian's couplings give about 10
BAND_MAX = 200
#: an eigenvalue of the tangent stiffness scaled to a unit diagonal counts as negative below minus this: round-off
#: there is about 1e-15; a shell's softest stable direction about ``1 / n^2`` (2e-6 at n = 80)
NEGATIVE = 1e-12


def unstable_directions(system, y, hold=()):
    """How many independent directions lower the energy of the state ``y`` at rest: the negative eigenvalues of the
    tangent stiffness ``K = -dp_t/dq`` (its symmetric part) on the free coordinates with the gauges of
    :func:`newton` held; ``None`` where its band is wider than :data:`BAND_MAX`.

    ``K phi = omega^2 M phi`` has as many negative ``omega^2`` as ``K`` has negative eigenvalues (Sylvester's law
    of inertia, ``M`` positive definite), and so has ``D K D`` for any diagonal ``D``: ``K`` is scaled to a unit
    diagonal (its entries mix forces and moments) and only its eigenvalues below ``-NEGATIVE`` are computed.
    """
    import scipy.linalg  # optional heavy dependency: only statics needs it
    import scipy.sparse

    q = _free_entries(system, hold)
    gauges = [g[0] for g in (_gauge(system, hold, 0), _gauge(system, hold, 2)) if g is not None]
    solve = q[~np.isin(q, gauges)]
    J = sparse_evaluator(system.jac)(0.0, y)[0].tocsr()
    K = -J[solve + system.nf][:, solve]
    K = ((K + K.T) / 2).tocoo()
    d = 1.0 / np.sqrt(np.maximum(np.abs(K.diagonal()), 1e-300))
    K = (scipy.sparse.diags(d) @ K @ scipy.sparse.diags(d)).tocoo()
    band = int(np.abs(K.row - K.col).max()) if K.nnz else 0
    if band > BAND_MAX or not np.all(np.isfinite(K.data)):
        return None
    upper = K.row <= K.col
    packed = np.zeros((band + 1, K.shape[0]))
    packed[band + K.row[upper] - K.col[upper], K.col[upper]] = K.data[upper]
    lowest = -1.0 - float(abs(K).sum(axis=1).max())  # below every eigenvalue (Gershgorin: the largest row sum)
    return len(scipy.linalg.eigvals_banded(packed, select="v", select_range=(lowest, -NEGATIVE)))


def scaled_loads(scene, factor):
    """``scene`` with every load times ``factor``."""
    return dataclasses.replace(scene, **{k: getattr(scene, k) * factor for k in scene.loads_on()})


#: continuation in the load: the first increment (a fraction of the full load), and the smallest one tried before
#: the loads are refused; an increment that fails is halved, one that converges in few iterations doubled
FIRST_INCREMENT = 0.25
SMALLEST_INCREMENT = 2.0**-6
#: Newton iterations below which the next increment is doubled (up to the first one)
EASY = 8


#: the loads whose net force (or moment) along a rigid motion is never zero, by the field the motion moves
UNBALANCED = {0: ("gravity", "end1_force", "end2_force"), 2: ("end1_torque", "end2_torque")}
#: a net force along a free rigid motion counts as zero below this share of the forces' sum of magnitudes (the
#: elastic forces of any state sum to round-off there: the energy does not change under the rigid motion)
BALANCED = 1e-9


def check_balanced(scene, system, y0, hold=()):
    """Refuse, naming the load, loads with a net force along a rigid motion no edge stops (a closed sphere under
    gravity: it falls, and has no equilibrium); the net is the sum of the generalised forces on that field."""
    y = np.array(y0, dtype=float)
    y[: system.ny * system.n].reshape(system.n, system.ny)[:, system.nf:] = 0.0  # at rest
    f = np.array(system.rhs_newton(0, y)).ravel()
    for field, what in ((0, "axial translation"), (2, "spin about the axis")):
        entries = _gauge(system, hold, field)
        if entries is None:
            continue
        forces = f[entries + system.nf]
        if abs(float(forces.sum())) > BALANCED * max(float(np.abs(forces).sum()), 1e-300):
            loads = scene.loads_on()
            name = next((k for k in UNBALANCED[field] if k in loads), loads[0] if loads else "scene")
            raise ParameterError(name, getattr(scene, name, scene.name), "loads whose net "
                                 f"{'force along' if field == 0 else 'moment about'} the axis is zero on a shell "
                                 f"no edge holds in {('z', 'chi')[field == 2]}", hint=f"its edges ({system.edges[0]} "
                                 f"and {system.edges[1]}) leave the {what} free, so there is no equilibrium under "
                                 "the loads; hold an edge, or start from a state of one's own (R or dilation)")


def check_law_domain(scene, system, y):
    """Raise :class:`~mol_shell._core.errors.ModelLimitError` (a limit of the law: exit 3 on the command line) when the
    law's stored energy is not finite at the static equilibrium ``y``
    (:meth:`~mol_shell.discretization.limits.ModelLimits.energy_not_finite`), naming the loads, the law, the first
    such cell and its stretches. A plane-stress law of one's own past the edge of its domain (St Venant-Kirchhoff's
    beyond an equibiaxial stretch of 1.472 at ``nu = 0.3``: no root ``C_22 > 0``) keeps finite forces there, its
    thickness held where its solve stopped, and Newton converges to such a state: until December 7 the run then
    started there and stopped at ``t = 0``, its message saying nothing of the static start."""
    if np.isfinite(float(system.observables(y, 0.0)[2])):  # the stored energy (the cells' only where it is not)
        return
    found = getattr(system, "energy_not_finite", lambda y: None)(y)
    if found is None:
        return
    law, where, detail = found
    loads = ", ".join(f"{k} = {getattr(scene, k):g}" for k in scene.loads_on())
    raise ModelLimitError(f"the static equilibrium under the loads at t = 0 ({loads}) lies outside the domain of "
                          f"{law}: its energy is not finite at {where}: {detail}; no run was started from it (smaller "
                          "loads, or a law whose domain holds the equilibrium)", 0.0, where)


def resting(scene, n):
    """The system of ``scene``'s static equilibrium at ``t = 0``: its driven edges held where they are at rate 0
    (:class:`~mol_shell.discretization.system.ShellSystem`'s ``at_rest``); the run's own (cached) one where no edge
    is driven. A spin or a drive is set on the equilibrium afterwards: until December 7 2026 the driven rate entered
    the equilibrium equations, whose driven edge node then carried the centrifugal force of its own lumped mass
    (``m_i r omega^2``, ``m_i ~ 1/n``) and the start moved with the grid (r - r0 = 0.134, 0.077, 0.036 m at
    n = 21, 41, 81 for a cone's end2_spin = 50 rad/s without loads)."""
    drives = scene.drives() if hasattr(scene, "drives") else {}
    return ShellSystem(scene, n, at_rest=True) if drives else build(scene, n)[0]


def static_equilibrium(scene, n, y0, hold=()):
    """The equilibrium state at rest under the scene's loads at ``t = 0``, starting from ``y0``.

    Returns ``(y, info)``; ``info`` says how it was found (for the run's attrs); :func:`check_law_domain` refuses an
    equilibrium outside the law's domain, a limit of the law. Direct Newton first; on failure,
    continuation in the load (every load times ``lambda`` from 0 to 1, each increment's solution the next one's
    start) with increments of :data:`FIRST_INCREMENT`, halved where Newton fails (down to
    :data:`SMALLEST_INCREMENT`, then the loads are refused), doubled again after an easy one. The intermediate
    loads need only the graphs (:class:`~mol_shell.discretization.system.ShellSystem`), no compiled kernels. The
    equations are those at rest (:func:`resting`): a driven edge is held where it is at ``t = 0``, at rate 0.
    """
    system = resting(scene, n)
    check_balanced(scene, system, y0, hold)
    try:
        y, it, res = newton(system, y0, hold)
        how = f"static equilibrium under the loads at t = 0 (Newton, {it} iterations, residual {res:.2g})"
    except RuntimeError as direct:
        y, done, increment, total, steps = np.array(y0, dtype=float), 0.0, FIRST_INCREMENT, 0, 0
        while done < 1.0:
            factor = min(1.0, done + increment)
            sub = system if factor == 1.0 else ShellSystem(scaled_loads(scene, factor), n, at_rest=True)
            try:
                y_next, it, res = newton(sub, y, hold)
            except RuntimeError as exc:
                increment /= 2
                if increment >= SMALLEST_INCREMENT:
                    continue
                loads = scene.loads_on()
                name, value = (loads[0], getattr(scene, loads[0])) if loads else ("scene", scene.name)
                others = " (with the other loads as given)" if len(loads) > 1 else ""
                allowed = f"loads under which the shell has a static equilibrium inside the model's limits{others}"
                histories = scene.load_histories()
                if not any(history(histories[load], 0.0) for load in loads) and getattr(scene, "gamma", 0):
                    # every load starts from 0 (a ramp): not theirs, but the twist held as initial data
                    name, value = "gamma", scene.gamma
                    allowed = ("twists that the shell, its loads 0 at t = 0, holds at a static equilibrium inside the "
                               "model's limits")
                raise ParameterError(name, value, allowed, hint=f"Newton failed ({direct}); continuation "
                                     f"stopped at {done:g} of the loads, no increment down to "
                                     f"{SMALLEST_INCREMENT:g} of them converging ({exc}); to start from a state "
                                     "of one's own, set R or dilation") from None
            y, done, total, steps = y_next, factor, total + it, steps + 1
            if it < EASY:
                increment = min(FIRST_INCREMENT, 2 * increment)
        how = (f"static equilibrium under the loads at t = 0 (continuation in {steps} steps, {total} Newton "
               f"iterations, residual {res:.2g})")
    check_law_domain(scene, system, y)  # a law whose forces stay finite past its domain: Newton may end there
    return y, how
