"""Equilibrium paths: Keller's pseudo-arclength continuation in a load, with stability and critical points.

:func:`path` follows the solutions of ``F(q, lambda) = 0`` (:class:`~mol_shell.analysis.equilibria.
EquilibriumEquations`: the equations at rest on the free coordinates, rigid motions gauged away) from
``lambda = start`` towards ``stop``. Each step predicts along the unit tangent ``t`` and corrects with Newton's
method on the bordered system

    [ F_q          F_lambda        ] [dq      ]     [ F                                  ]
    [ t_q / c_q    t_lambda / c_l  ] [dlambda ] = - [ t . (u - u_0) / c - ds             ]

factorised by sparse LU (``scipy.sparse.linalg.splu``; the node-major ordering keeps ``F_q`` banded and the
border adds one row and one column), which stays regular through limit points where ``F_q`` is singular. The
scales ``c`` make the arclength dimensionless: lengths over the meridian's size, angles as they are, and
``lambda`` over ``|stop - start|``, with the displacement part weighted so that the first tangent is half load
and half displacement. The step grows after quick Newton convergence (<= 3 iterations), to at most ``MAX_GROWTH``
times the first (stability is sampled at the steps only), and shrinks after slow convergence; a failed or limit-crossing step is halved down to ``ds / 2^10``, where the path ends (status
``failed`` or ``limit``, the steps so far kept). The last step lands on ``lambda = stop`` exactly. A first step that
fails so is taken again as a secant (:mod:`mol_shell.analysis.path_secant`: the start's tangent is not the path's
where the stiffness jumps there, as at the natural state of tension-only fibres).

Stability at each step: the eigenvalues ``omega^2`` of ``K phi = omega^2 M phi`` nearest zero (``K = -F_q``,
``M`` the lumped mass matrix; sparse shift-invert, ``scipy.sparse.linalg.eigsh`` about a small negative shift),
their count below zero, and the sign of ``det K`` from its LU. Between two steps where the count changes, each
crossing is located by the secant method on the crossing eigenvalue to ``LOCATE_RTOL`` of the range
(:mod:`mol_shell.analysis.path_stability`): a bifurcation in ``lambda``, each trial state by Newton at fixed
``lambda`` from the chord of the bracket; a limit point (``t_lambda`` changes sign over the interval) in the
arclength, each trial a corrector solve from the earlier step. Its mode is the eigenvector there, its family ``torsional`` when
``chi`` carries most of its kinetic energy, else ``axisymmetric``. With ``branch = K`` the path switches, once
bifurcation point ``K`` is located, onto the branch leaving it (:mod:`mol_shell.analysis.path_branch`) and follows
that branch to the end; the variable ``branch`` says which steps lie on it.

The model is rotationally symmetric: its critical points are those of rotationally symmetric modes only, upper
bounds where a real shell buckles into circumferential waves.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.errors import MaterialWarning, MolShellWarning, by_interrupt, scalar
from mol_shell._core.progress import progress_meter, progress_mode
from mol_shell.analysis.equilibria import EquilibriumEquations
from mol_shell.analysis.path_branch import BranchFailed, closed, no_branch_reason, switch
from mol_shell.analysis.path_dataset import interrupted_at_end, path_dataset
from mol_shell.analysis.path_first import first_state
from mol_shell.analysis.path_inputs import check_inputs, check_start
from mol_shell.analysis.path_modes import near_critical
from mol_shell.analysis.path_record import PathRecord
from mol_shell.analysis.path_secant import secant_start
from mol_shell.analysis.path_stability import LOCATE_NEWTON, LOCATE_TOL
from mol_shell.runs.building import as_scene
from mol_shell.scenes.scene_warnings import say_scene_warnings

#: Newton's convergence: ``|F|`` below this fraction of the forces of a unit strain (``max diag K`` times the
#: meridian's size), then one step more
TOL = 1e-10
MAX_ITER = 8
#: step control: the ratio of steps to the first one stays in ``[2^-MIN_HALVINGS, MAX_GROWTH]`` (to the default
#: first step when a smaller ``ds`` was asked for)
MIN_HALVINGS = 10
MAX_GROWTH = 2.0
#: a corrector that ends farther than this many steps from its predictor has jumped to another branch
STRAY = 0.5
#: the least weight of the displacements in the arclength, as a share of the shell's size (:meth:`_Path.weigh`)
WEIGHT_FLOOR = 1e-10


class PathFailed(Exception):
    """The corrector did not converge at the smallest step, or a model limit was reached (``kind``, ``where``)."""

    def __init__(self, kind, message):
        self.kind = kind
        super().__init__(message)


class _Path:
    """The continuation of one :class:`EquilibriumEquations` (scales, tangents, correctors).

    Vectors ``q`` hold every free coordinate; solves act on ``eq.keep`` (the gauge's coordinates stay put).
    """

    def __init__(self, eq, start, stop):
        self.eq, self.start, self.stop = eq, float(start), float(stop)
        system = eq.system
        self.length = max(float(np.abs(system.reference[:2]).max()), system.L / math.pi)
        local = eq.q_idx % eq.ny
        field = np.array(system.active)[local]
        self.q_scale = np.where(field <= 1, self.length, 1.0)[eq.keep]
        self.l_scale = abs(self.stop - self.start)
        self.direction = math.copysign(1.0, self.stop - self.start)
        self.f_scale = None

    def _full(self, dq):
        out = np.zeros(self.eq.size)
        out[self.eq.keep] = dq
        return out

    # -- linear algebra ------------------------------------------------------------------------
    @staticmethod
    def bordered(Fq, g, row_q, row_l):
        """Sparse LU of ``[[F_q, F_lambda], [row_q, row_l]]``."""
        import scipy.sparse
        import scipy.sparse.linalg

        A = scipy.sparse.bmat([[Fq, scipy.sparse.csc_matrix(g[:, None])],
                               [scipy.sparse.csc_matrix(row_q[None, :]), scipy.sparse.csc_matrix([[row_l]])]],
                              format="csc")
        return scipy.sparse.linalg.splu(A)

    def tangent(self, q, lam, previous=None):
        """Unit tangent ``(t_q, t_lambda)`` in scaled coordinates (``t_q`` on the unknowns), oriented along
        ``previous`` (or towards ``stop``)."""
        _, Fq, g = self.eq.reduced(q, lam)
        if previous is None:
            import scipy.sparse.linalg

            try:
                dq = scipy.sparse.linalg.splu(Fq).solve(-g)
            except RuntimeError:  # exactly singular
                raise PathFailed("newton", f"singular tangent stiffness at {self.eq.parameter} = {lam:g}") from None
            v = np.concatenate([dq / self.q_scale, [1.0 / self.l_scale]]) * self.direction
        else:
            tq, tl = previous
            rhs = np.zeros(len(tq) + 1)
            rhs[-1] = 1.0
            x = self.bordered(Fq, g, tq / self.q_scale, tl / self.l_scale).solve(rhs)
            v = np.concatenate([x[:-1] / self.q_scale, [x[-1] / self.l_scale]])
        v = v / np.abs(v).max()  # first to O(1): 1 / l_scale squared overflows for a range below 1e-154
        v = v / np.linalg.norm(v)
        return v[:-1], float(v[-1])

    def weigh(self, q, lam, scales=None):
        """Weigh the displacements so that the first tangent is half load, half displacement (or as ``scales``, an
        earlier path's :attr:`scales`: its metric, so that a continuation steps as that path did, and a start at a
        fold, where the first tangent is nearly all displacement, does not weigh them to nothing).

        Not below :data:`WEIGHT_FLOOR` of the shell's size: a response smaller than that over the whole range is
        linear to that share, and weighed more its round-off (the solves' ``eps`` times the stiffness's condition,
        1e-12 of the size on a director-constrained sphere) strayed the corrector from the predictor."""
        if scales is None:
            tq, tl = self.tangent(q, lam)
            factor = max(np.linalg.norm(tq) / max(abs(tl), 1e-300), WEIGHT_FLOOR)
        else:
            factor, self.l_scale = float(scales[0]), float(scales[1])
        self.q_scale = self.q_scale * factor
        #: the displacements' factor over the shell's lengths and the load's scale (attrs ``arclength_displacement_scale``, ``arclength_load_scale``)
        self.scales = (factor, self.l_scale)

    def distance(self, q0, l0, q1, l1):
        """The scaled length of the chord between two states."""
        d = np.concatenate([(q1 - q0)[self.eq.keep] / self.q_scale, [(l1 - l0) / self.l_scale]])
        return float(np.linalg.norm(d))

    def along(self, t, q0, l0, q1, l1):
        """The scaled distance from ``(q0, l0)`` to ``(q1, l1)`` along the tangent ``t``."""
        return float(np.dot(t[0], (q1 - q0)[self.eq.keep] / self.q_scale) + t[1] * (l1 - l0) / self.l_scale)

    # -- correctors -------------------------------------------------------------------------------
    def correct(self, q0, lam0, t, ds, fixed_lambda=None, max_iter=MAX_ITER, tol=TOL):
        """Newton on ``F = 0`` and the arclength equation (or ``lambda = fixed_lambda``) from the predictor.

        Returns ``(q, lam, iterations)``; raises :class:`PathFailed` (kind ``newton``) when it does not converge
        in :data:`MAX_ITER` iterations or strays from the predictor by more than the step (onto another branch).
        """
        tq, tl = t
        if fixed_lambda is None:
            q = q0 + self._full(ds * tq * self.q_scale)
            lam = lam0 + ds * tl * self.l_scale
        else:
            ds = (fixed_lambda - lam0) / (tl * self.l_scale) if tl != 0 else 0.0
            q = q0 + self._full(ds * tq * self.q_scale)
            lam = fixed_lambda
        q_pred, l_pred = q.copy(), lam
        polished, F = False, None  # one step more after the tolerance (see at_load)
        for it in range(1, max_iter + 1):
            polished = polished or (F is not None and np.abs(F).max() <= tol * self.f_scale)
            F, Fq, g = self.eq.reduced(q, lam)
            if not (np.all(np.isfinite(F)) and np.all(np.isfinite(Fq.data))):
                break
            if fixed_lambda is None:
                N = self.along(t, q0, lam0, q, lam) - ds
                row_q, row_l = tq / self.q_scale, tl / self.l_scale
            else:
                N, row_q, row_l = lam - fixed_lambda, np.zeros(len(tq)), 1.0
            try:
                x = self.bordered(Fq, g, row_q, row_l).solve(-np.concatenate([F, [N]]))
            except RuntimeError:  # exactly singular
                break
            q, lam = q + self._full(x[:-1]), lam + x[-1]
            if not (np.all(np.isfinite(q)) and np.isfinite(lam)):
                break
            F = self.eq.residual(q, lam)
            if np.abs(F).max() <= tol * self.f_scale and (polished or it == max_iter):
                if self.distance(q_pred, l_pred, q, lam) > max(abs(ds), 1e-12) * STRAY:
                    raise PathFailed("newton", "the corrector left the predictor's neighbourhood")
                return q, lam, it
        raise PathFailed("newton", f"Newton did not converge in {max_iter} iterations")

    def at_load(self, q, lam, along=None, max_iter=LOCATE_NEWTON, tol=LOCATE_TOL):
        """Newton at fixed ``lambda`` from ``q`` (no damping): ``q``; :class:`PathFailed` when it does not converge.

        At least one step is taken: a residual below the tolerance is no converged state where the shell is soft
        (the chord between two states of a sphere under pressure, a/t = 40 at n = 60, had a residual of 2e-10 of a
        unit strain's force and lay 4e-4 rad off the path; taken for a trial state, its lowest eigenvalue was 1 s-2
        off, and the secant located a crossing of the chord's, 6e-4 p_cl before the path's). Past the tolerance, one
        more step, kept only when it lowers the residual (:meth:`_polished`). ``along = (v, w)``
        (:func:`~mol_shell.analysis.path_stability.deflation`): every step's component along the critical mode is
        taken out. Near a bifurcation ``K`` is nearly singular along that mode, and a solve amplifies the round-off
        there: at the crossing it moved a cylinder's converged trial 1e-2 m onto a state whose residual was 2e-7."""
        import scipy.sparse.linalg

        for it in range(max_iter):
            F, Fq, _ = self.eq.reduced(q, lam)
            if not np.all(np.isfinite(F)):
                break
            if it and np.abs(F).max() <= tol * self.f_scale:
                return self._polished(q, lam, F, Fq, steps=1, along=along)
            try:
                q = q + self._full(self._deflated(scipy.sparse.linalg.splu(Fq).solve(-F), along))
            except RuntimeError:  # exactly singular
                break
        raise PathFailed("newton", f"Newton at {self.eq.parameter} = {lam:.6g} did not converge")

    @staticmethod
    def _deflated(dq, along):
        """``dq`` less its component along ``along = (v, w)``: ``v (w . dq) / (w . v)`` (``dq`` when ``None``)."""
        if along is None:
            return dq
        v, w = along
        return dq - v * (np.dot(w, dq) / np.dot(w, v))

    def _polished(self, q, lam, F, Fq, steps=2, along=None):
        """``q`` after up to ``steps`` more Newton steps, each kept while it lowers the residual: the tolerance leaves
        an error of (residual / stiffness) along the softest modes (a free twisted tube's: 1e-8 rad), which a
        path over a small load range took for its response and left its first predictor by 100 steps."""
        import scipy.sparse.linalg

        for left in range(steps, 0, -1):
            try:
                trial = q + self._full(self._deflated(scipy.sparse.linalg.splu(Fq).solve(-F), along))
            except RuntimeError:
                break
            if left == 1:  # the last step's Jacobian would not be used: its residual alone decides
                F_trial, Fq_trial = self.eq.residual(trial, lam), None
            else:
                F_trial, Fq_trial, _ = self.eq.reduced(trial, lam)
            if not (np.all(np.isfinite(F_trial)) and np.abs(F_trial).max() < np.abs(F).max()):
                break
            q, F, Fq = trial, F_trial, Fq_trial
        return q

    def slope(self, q, lam):
        """``dq/dlambda`` along the path at fixed load (``-F_q^-1 F_lambda`` on the unknowns)."""
        import scipy.sparse.linalg

        _, Fq, g = self.eq.reduced(q, lam)
        return self._full(scipy.sparse.linalg.splu(Fq).solve(-g))

    def equilibrium(self, q, lam):
        """Newton at fixed ``lambda`` from ``q`` (the path's first state), halving its steps when the residual grows."""
        import scipy.sparse.linalg

        for it in range(MAX_ITER * 4):
            F, Fq, _ = self.eq.reduced(q, lam)
            if self.f_scale is None:
                self.f_scale = float(np.abs(Fq.diagonal()).max()) * self.length
            if np.abs(F).max() <= TOL * self.f_scale:
                return self._polished(q, lam, F, Fq), it
            try:
                step = self._full(scipy.sparse.linalg.splu(Fq).solve(-F))
            except RuntimeError:  # exactly singular (a load so large the state's numbers overflow)
                break
            norm = np.abs(F).max()
            for _ in range(30):
                trial = q + step
                Ft = self.eq.residual(trial, lam)
                if np.all(np.isfinite(Ft)) and self.eq.limits_ok(trial, lam) is None and np.abs(Ft).max() < norm:
                    break
                step = step / 2
            else:
                break
            q = trial
        raise PathFailed("newton", f"no equilibrium found at {self.eq.parameter} = {lam:g} {self.eq.units} "
                         f"(Newton from the scene's initial state, residual {np.abs(F).max() / self.f_scale:.2g} "
                         "of a unit strain's force)")

    def start_equilibrium(self, q, lam):
        """:meth:`equilibrium` at ``lam``; where Newton from ``q`` fails, continuation in the parameter from 0 to
        ``lam`` (increments of a quarter, halved on failure down to 1/64, doubled after a success), as a run's
        ``R = auto`` does: a start the load reaches from rest is found (a sphere at 1e6 Pa was refused)."""
        try:
            return self.equilibrium(q, lam)
        except PathFailed as direct:
            if lam == 0.0:
                raise
            done, increment, total = 0.0, 0.25, 0
            while done < 1.0:
                factor = min(1.0, done + increment)
                try:
                    q, its = self.equilibrium(q, factor * lam)
                except PathFailed:
                    increment /= 2
                    if increment < 1.0 / 64:
                        raise PathFailed("newton", f"{direct}; continuation from {self.eq.parameter} = 0 stopped at "
                                         f"{done * lam:g} {self.eq.units}") from None
                    continue
                done, total, increment = factor, total + its, 2 * increment
            return q, total


def _steps_done(n, total):
    """A path's progress line's count (a path has no total)."""
    return f"{n:.0f} step{'s' * (n != 1)}"


def path(scene, parameter, start, stop, n=40, *, steps=20, max_steps=200, ds=None, branch=None, initial=None,
         heading=None, scales=None, progress=None):
    """Follow the equilibria of ``scene`` at rest as the load ``parameter`` goes from ``start`` to ``stop``.

    Parameters
    ----------
    scene : ShellScene or str
        A scene object or a registered name; its other loads stay as given, its initial state is where
        Newton starts at ``lambda = start``.
    parameter : str
        The continued load: ``pressure``, ``gravity``, ``end1_force``, ``end2_force``, ``end1_torque`` or
        ``end2_torque``; or an edge displacement (displacement control): ``end1_dz``, ``end2_dz`` (m),
        ``end1_dchi`` or ``end2_dchi`` (rad), on an edge that holds ``z`` or ``chi`` (units as the scene's
        parameter).
    start, stop : float
        The load's range; ``stop`` may be below ``start``.
    n : int
        Nodes in ``s``.
    steps : int
        The first step covers ``1/steps`` of the range (the later ones adapt).
    max_steps : int
        The path ends after this many steps.
    ds : float, optional
        The first step in the scaled arclength (default ``sqrt(2)/steps``; at most ``sqrt(2)``, the whole range
        along the first tangent: a larger one is taken as that).
    branch : int, optional
        Switch onto the branch leaving critical point ``branch`` (numbered as found, from 0) once it is located,
        and follow it; at a limit point, where no branch leaves, the path goes on without a switch and its message
        says why. A path that ends
        before it finds that point says so in ``attrs["message"]``.
    initial : array_like, optional
        Fields ``z, r, chi, theta, psi`` at the nodes, ``(5, n)``, of an equilibrium at ``start``: where Newton
        starts in place of the scene's initial state (a step of an earlier path, to go on from it:
        :func:`~mol_shell.analysis.path_start.path_start` gives its scene, ``n`` and fields;
        :func:`~mol_shell.analysis.path_continue.continue_path` does it all). The path leaves it towards ``stop``,
        or along ``heading``.
    heading : array_like, optional
        With ``initial``: the fields ``(5, n)`` of the state before it on its path; the path leaves ``initial`` the
        way its displacements went from that state (past a limit point the load may at first move away from
        ``stop``). A path so continued is not ended for coming back past ``start``.
    scales : tuple, optional
        ``(displacements' factor over the shell's lengths, load's scale)``: an earlier path's arclength scales
        (attrs ``arclength_displacement_scale``, ``arclength_load_scale``), so that its continuation steps as it did;
        default: the load's range, and the displacements weighed at the start so that the first tangent is half
        load, half displacement.
    progress : bool, optional
        Progress on stderr: the steps taken, the load reached, the critical points found. ``True`` a bar (tqdm),
        ``False`` nothing; default (``None``) a bar when stderr is a terminal, else a line every
        :data:`mol_shell._core.progress.LOG_INTERVAL_S` s of a longer path and a last one at its end.

    Returns
    -------
    xarray.Dataset
        Along ``step``: ``parameter``, the fields, ``arclength``, ``negative_eigenvalues``,
        ``smallest_eigenvalues``, ``stiffness_det_sign``, ``stored_energy``, ``load_work``, ``volume`` (a closed
        shell's);
        along ``point``: the critical points. ``attrs["status"]`` is ``complete`` (``stop`` reached),
        ``max_steps``, ``returned`` (back past ``start``, or a branch back at the point it left: a loop),
        ``failed``, ``limit`` or ``interrupted`` (Ctrl-C: the steps so far; ``attrs["message"]`` says where; a
        Ctrl-C before the first step, in the set-up, raises ``KeyboardInterrupt``).
    """
    scene = as_scene(scene)
    start, stop, n, steps, max_steps, ds, branch = map(scalar, (start, stop, n, steps, max_steps, ds, branch))
    check_inputs(scene, parameter, start, stop, n, steps, max_steps, ds, branch)
    check_start(initial, heading, scales)
    mode = progress_mode(progress)  # refused (not a bool) before the set-up's work
    clock = time.perf_counter()
    no_switch = None  # why --branch could not switch at the point it names (a limit point)
    origin = None  # on a branch: the critical point it left (state, load, the step after which it did)
    eq = EquilibriumEquations(scene, parameter, n)
    tracer = _Path(eq, start, stop)
    q, iterations, t = first_state(tracer, float(start), initial, heading, scales, PathFailed)
    noted = say_scene_warnings(scene, {}, parameter=parameter, stacklevel=2)  # once refusals are past: before the trace
    ds0 = math.sqrt(2.0) / steps if ds is None else min(float(ds), math.sqrt(2.0))  # at most the whole range
    bar = progress_meter(mode, f"path in {parameter} ({eq.units})", count=_steps_done, unit=" steps")  # no total
    record = PathRecord(eq, tracer, bar, PathFailed)
    record.add(q, float(start), t, 0.0, iterations)
    lam, h, secant = float(start), ds0, None  # secant: the first step's chord, when it had to take one
    status, message = "max_steps", f"stopped after max_steps = {max_steps} step{'s' * (max_steps != 1)}"
    try:  # Ctrl-C: the steps so far are the path, said interrupted (as a run keeps its saved times)
        while len(record.lams) <= max_steps:
            try:
                q_new, lam_new, its = tracer.correct(q, lam, t, h)
                where = eq.limits_ok(q_new, lam_new)
                if where is not None:
                    raise PathFailed("limit", f"{where[0]} at {where[1]}")
            except PathFailed as exc:
                if h <= ds0 * 2.0 ** -MIN_HALVINGS:
                    if exc.kind == "newton" and len(record.lams) == 1 and secant is None:  # the start's tangent failed
                        try:
                            q_new, lam_new, t_new, secant, its = secant_start(tracer, q, lam, steps, MIN_HALVINGS,
                                                                             PathFailed)
                        except PathFailed as again:
                            secant = exc = PathFailed("newton", f"{exc}; nor did Newton at a fixed load past it "
                                                      f"find an equilibrium ({again}): the tangent may not be "
                                                      f"defined there, or the range is too wide for a first step "
                                                      f"(a nearer stop or more steps, --steps, shorten it)")
                        else:
                            record.add(q_new, lam_new, t_new, tracer.distance(q, lam, q_new, lam_new), its)
                            record.locate_between(-2, -1, (q, lam, secant))
                            q, lam, t, h = q_new, lam_new, t_new, ds0
                            if (lam - tracer.stop) * tracer.direction >= 0:
                                status, message = "complete", f"reached {parameter} = {lam:.6g} {eq.units}"
                                break
                            continue
                    status = "limit" if exc.kind == "limit" else "failed"
                    message = (f"the path cannot continue from {parameter} = {lam:.6g} {eq.units}: {exc} "
                               f"(at the smallest step, {h:.3g})")
                    break
                h /= 2
                continue
            beyond = (lam_new - tracer.stop) * tracer.direction >= 0
            if beyond:
                try:
                    q_new, lam_new, its = tracer.correct(q, lam, t, h, fixed_lambda=tracer.stop)
                except PathFailed:
                    h /= 2
                    continue
            t_new = tracer.tangent(q_new, lam_new, previous=t)
            arc = tracer.along(t, q, lam, q_new, lam_new)
            record.add(q_new, lam_new, t_new, record.arcs[-1] + arc, its)
            record.locate_between(-2, -1, (q, lam, t))
            q, lam, t = q_new, lam_new, t_new
            if branch is not None and record.branch == 0 and len(record.points) > branch:
                no_switch = no_branch_reason(record, branch)
                if no_switch is None:
                    try:
                        q, lam, t, its = switch(tracer, record.points[branch], t, h, ds0 * 2.0 ** -MIN_HALVINGS,
                                                PathFailed)
                    except BranchFailed as exc:
                        status, message = "failed", f"no switch onto the branch at critical point {branch}: {exc}"
                        break
                    record.branch, record.branch_point = 1, branch
                    origin = (record.points[branch]["q"], record.points[branch]["parameter"], len(record.lams))
                    t = tracer.tangent(q, lam, previous=t)
                    record.add(q, lam, t, record.arcs[-1] + h, its)
                    continue
                branch = None  # a limit point: the path goes on without the switch, said in its message
            if beyond:
                status, message = "complete", f"reached {parameter} = {lam:.6g} {eq.units}"
                break
            if origin is not None and closed(tracer, origin, q, lam, arc, record):
                status, message = "returned", (
                    f"the branch closed: it came back to critical point {record.branch_point} ({parameter} = "
                    f"{origin[1]:.6g} {eq.units}) {len(record.lams) - origin[2]} steps after it left it, round a loop")
                break
            if (lam - tracer.start) * tracer.direction < 0 and len(record.lams) > 2 and heading is None:
                status, message = "returned", (f"the path came back past start = {start:g} {eq.units}, away "
                                               f"from stop = {stop:g} {eq.units}")
                break
            # the cap: twice the first step, or twice the default first step when a smaller one was asked for
            h = min(h * (1.6 if its <= 3 else 1.0 if its <= 5 else 0.5), max(ds0, math.sqrt(2.0) / steps) * MAX_GROWTH)
    except BaseException as exc:  # a Ctrl-C, or an error of a C call that wraps one (by_interrupt)
        if not by_interrupt(exc):
            raise
        record.truncate()
        status, message = "interrupted", (f"interrupted by the user at {parameter} = {record.lams[-1]:.6g} "
                                          f"{eq.units}")
    with interrupts.watched() as watch:  # the steps are the path from here: a Ctrl-C is noted, the path kept
        if branch is not None and record.branch == 0:
            message += f"; no switch: critical point {branch} was not reached ({len(record.points)} found)"
        if no_switch is not None:
            message += f"; no switch: {no_switch}"
        if record.bar is not None:
            record.bar.close()
        near = near_critical(record)  # its search between the steps is part of the path's time
        ds = path_dataset(eq, scene, record, status, message, time.perf_counter() - clock, start, stop, near, noted)
    if initial is not None:
        ds.attrs["initial_state"] = "the fields given (initial), at rest"
    ds.attrs["arclength_displacement_scale"], ds.attrs["arclength_load_scale"] = tracer.scales
    ds.attrs["units_arclength_displacement_scale"], ds.attrs["units_arclength_load_scale"] = "1", eq.units
    if watch.caught:  # as it was assembled: written, said interrupted (exit 130)
        ds = interrupted_at_end(ds)
    if "ellipticity_warning" in ds.attrs:
        warnings.warn(ds.attrs["ellipticity_warning"], MaterialWarning, stacklevel=2)
    for said in ("grid_mode_warning", "near_critical_warning"):  # as modes says its grid modes
        if said in ds.attrs:
            warnings.warn(ds.attrs[said], MolShellWarning, stacklevel=2)
    return ds
