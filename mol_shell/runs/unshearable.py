"""Section 4: the azimuthally unshearable shell, a DAE with Lagrange multipliers, solved by IDA.

The constraints (4.1), ``chi_s = 0`` and ``psi = 0``, are imposed on the same discrete
Lagrangian as :class:`~mol_shell.discretization.system.ShellSystem` (its cell kernel for the stored
energy, the model's kinetic energy density lumped at nodes):

    L_h = sum_i T_i(q_i, v_i) - sum_cells V_c - 2 pi r0 [ sum_cells Lc (chi_{i+1} - chi_i)
                                                          + sum_i w_i Lp_i psi_i ],

so ``Lc`` (``lambda_chi``) is conjugate to ``chi_s`` and ``Lp`` (``lambda_psi``) to ``psi``, per
unit reference area: ``2 pi r0 lambda_chi`` is the axial torque carried across a section
by the constraint (the combination ``r n . a3`` of (3.11), (4.11)), ``-lambda_psi`` the couple
per unit area that keeps the director in the meridional plane (the multiplier of (4.13),
entering (3.12)). Lagrange's equations in residual form,

    q_t - v = 0,
    d/dt dT/dv - dT/dq + dV/dq + dD/dv + G^T (Lc, Lp) = 0,
    G v_t = 0   (the constraints differentiated twice: chi_s,tt = 0, psi_tt = 0),

form a DAE of index 1 in ``(q, v, Lc, Lp)``. The constraints are linear (``G`` is constant),
so BDF keeps ``G v = 0`` and ``G q = 0`` to the accuracy of its Newton iteration: no drift.

Physics (sections 4-5). Each section of a spinning shell whose radius varies along ``s``
carries the angular momentum ``rhoA r^2 chi_t`` (plus the director's); as sections breathe by
different amounts, conservation alone would spin them at different rates (4.7), so a free
shell twists (``chi_s`` grows) and, through the Coriolis terms ``2 r_t chi_t`` and
``2 chi_t theta_t sin(theta)`` of (4.6), shears out of the meridional plane (``psi`` grows).
The unshearable shell keeps ``chi_s = psi = 0``; its multipliers supply exactly those
Coriolis torques and couples and vanish without spin.
"""

from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.discretization.compiled import buffered
from mol_shell.integrators import Leapfrog
from mol_shell.integrators.base import StepBudget
from mol_shell.integrators.loop import run
from mol_shell.results.dataset import build_dataset
from mol_shell.runs import resources
from mol_shell.runs.building import build, observe, parse_times, resolve
from mol_shell.runs.checks import check_system, checked_spectrum
from mol_shell.scenes.unshearable import Unshearable

#: DAE unknowns per node: q (5), v (5), lambda_chi of the cell to the right (a dummy at the last node), lambda_psi
NODE = 12
#: IDA steps after which a constrained run is given up (as max_steps of the shell's SUNDIALS integrators)
STEP_LIMIT = 1_000_000


class UnshearableDAE:
    """Residual, Jacobians and consistent initial values of the constrained system.

    Parameters
    ----------
    shell : ShellSystem
        The unconstrained discretisation of the same scene (all five fields): its cell
        (and viscous) kernels, weights, inertias and end conditions are reused.
    """

    def __init__(self, shell):
        if shell.nf != NF:
            raise ValueError("the unshearable DAE needs a ShellSystem with all five fields")
        self.shell, self.n = shell, shell.n
        self.size = NODE * self.n
        n, c = self.n, 2 * math.pi * shell.r0
        y, yp = ca.SX.sym("y", self.size), ca.SX.sym("yp", self.size)
        Y, YP = ca.reshape(y, NODE, n), ca.reshape(yp, NODE, n)
        Q, V, Lc, Lp = Y[:5, :], Y[5:10, :], Y[10, : n - 1], Y[11, :]
        Qp, Vp = YP[:5, :], YP[5:10, :]
        inertial = self._node_kernel().map(n)(Q, V, Qp, Vp, shell.inertia)
        gl, gr = shell.cell_forces_kernel().map(n - 1)(Q[:, :-1], Q[:, 1:], shell.cell_data)
        pad = ca.SX.zeros(NF, 1)
        generalized = inertial + ca.horzcat(gl, pad) + ca.horzcat(pad, gr)
        if shell.viscous:
            fl, fr = shell.viscous_forces_kernel().map(n - 1)(Q[:, :-1], Q[:, 1:], V[:, :-1], V[:, 1:], shell.cell_data)
            generalized += ca.horzcat(fl, pad) + ca.horzcat(pad, fr)
        zero = ca.SX.zeros(1, 1)
        constraint = ca.SX.zeros(NF, n)
        constraint[2, :] = c * (ca.horzcat(zero, Lc) - ca.horzcat(Lc, zero))
        constraint[4, :] = c * shell.weights[None, :] * Lp
        fixed = ca.DM(shell.fixed.T.astype(float))
        balance = (1 - fixed) * (generalized + constraint) + fixed * Vp
        accel = ca.horzcat((Vp[2, 1:] - Vp[2, :-1]) / shell.ds, Y[10, n - 1])
        res = ca.vec(ca.vertcat(Qp - V, balance, accel, Vp[4, :]))
        self.residual = ca.Function("residual", [y, yp], [res], ["y", "yp"], ["res"])
        Jy, Jyp = ca.jacobian(res, y), ca.jacobian(res, yp)
        self.jacobians = ca.Function("jacobians", [y, yp], [ca.densify(Jy), ca.densify(Jyp)])
        cj = ca.SX.sym("cj")
        iteration = Jy + cj * Jyp  # IDA's iteration matrix dF/dy + cj dF/dyp, sparse
        self.iteration_matrix = ca.Function("iteration_matrix", [y, yp, cj], [iteration])
        pattern = iteration.sparsity()
        self.pattern = (np.array(pattern.row()), np.repeat(np.arange(self.size), np.diff(pattern.colind())))
        self.bandwidth = (int(pattern.bw_lower()), int(pattern.bw_upper()))
        self.algebraic = np.array([NODE * i + k for i in range(n) for k in (10, 11)])

    def _node_kernel(self):
        """``(q, v, q_t, v_t, m) -> d/dt dT/dv - dT/dq`` for the lumped kinetic energy of one node (inertias ``m``)."""
        sh = self.shell
        q, v, qp, vp, m = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("qp", NF), ca.SX.sym("vp", NF), ca.SX.sym("m", 3)
        T = sh.kinetic_energy(ca.vertsplit(q), ca.vertsplit(v), ca.vertsplit(m))
        gv = ca.gradient(T, v)
        rate = ca.jtimes(gv, ca.vertcat(q, v), ca.vertcat(qp, vp))
        return ca.Function("lagrange", [q, v, qp, vp, m], [rate - ca.gradient(T, q)])

    def pack(self, Q, V, Lc=None, Lp=None):
        """DAE vector from fields ``Q``, rates ``V`` (``5 x n``) and multipliers (``n - 1``, ``n``)."""
        n = self.n
        Y = np.zeros((NODE, n))
        Y[:5], Y[5:10] = Q, V
        if Lc is not None:
            Y[10, : n - 1] = Lc
        if Lp is not None:
            Y[11] = Lp
        return Y.T.reshape(-1)

    def unpack(self, y):
        """``(Q, V, lambda_chi, lambda_psi)`` of a stack of DAE vectors ``(..., size)``."""
        Y = np.swapaxes(np.asarray(y).reshape(*np.shape(y)[:-1], self.n, NODE), -1, -2)
        return Y[..., :5, :], Y[..., 5:10, :], Y[..., 10, : self.n - 1], Y[..., 11, :]

    def consistent(self, Q, V):
        """``(y0, yp0)``: accelerations and multipliers solved from the residual (affine in them)."""
        y0, yp0 = self.pack(Q, V), self.pack(V, np.zeros_like(V))
        per_node = np.zeros(NODE, dtype=bool)
        rates, mult = per_node.copy(), per_node.copy()
        rates[5:10], mult[10:] = True, True
        rates, mult = np.tile(rates, self.n), np.tile(mult, self.n)
        rows = rates | mult  # the balance and constraint rows (the q_t - v rows hold already)
        F = np.array(self.residual(y0, yp0)).ravel()
        Jy, Jyp = (np.array(J) for J in self.jacobians(y0, yp0))
        J = np.hstack([Jyp[:, rates], Jy[:, mult]])[rows]
        u = np.linalg.solve(J, -F[rows])
        yp0[rates] = u[: rates.sum()]
        y0[mult] = u[rates.sum():]
        return y0, yp0

    def solver(self, rtol, atol, max_step=0.0):
        """An ``sksundae`` IDA solver with the CasADi residual and its exact band Jacobian."""
        from sksundae.ida import IDA

        res_buf = buffered(self.residual)
        jac_buf = buffered(self.iteration_matrix)
        rows, cols = self.pattern
        self.n_res = self.n_jac = 0

        def resfn(t, y, yp, res):
            self.n_res += 1
            if not np.isfinite(t):  # IDA's step underflowed: motions too fast for double precision
                raise RuntimeError(f"IDA asked for the residual at t = {t} (its step size underflowed)")
            res[:] = res_buf(y, yp)

        def jacfn(t, y, yp, res, cj, JJ):
            self.n_jac += 1
            JJ.fill(0.0)
            JJ[rows, cols] = jac_buf(y, yp, cj)  # the nonzeros, in CCS order

        lb, ub = self.bandwidth
        return IDA(
            resfn, jacfn=jacfn, rtol=rtol, atol=atol, linsolver="band", lband=lb, uband=ub,
            algebraic_idx=self.algebraic, max_num_steps=100000, max_step=max_step,
        )


def simulate_unshearable(scene, *, n=40, times=None, t_end=None, constrained=True, rtol=1e-8, atol=1e-10,
                         dt=1e-6, max_step=0.0, progress=None):
    """Run an :class:`Unshearable` scene, constrained (DAE, IDA) or free (the PDE, leap-frog).

    Parameters
    ----------
    scene : Unshearable
    n : int
        Nodes in ``s``.
    times, t_end : optional
        Saved times as for :func:`mol_shell.simulate`.
    constrained : bool
        ``True``: ``chi_s = 0`` and ``psi = 0`` imposed (the DAE, solved by IDA, BDF with an
        exact band Jacobian). ``False``: the ordinary shell from the same initial state
        (leap-frog, step ``dt``).
    rtol, atol : float
        IDA tolerances (``atol`` for lengths and angles; scaled for rates and multipliers).
    dt : float
        Leap-frog step of the free run, s.
    max_step : float
        Largest IDA step (0: unbounded).
    progress : bool, optional
        Unused; accepted for the study runner's sake.

    Returns
    -------
    xarray.Dataset
        The variables of :func:`mol_shell.simulate`, plus ``chi_s_max`` and ``psi_max`` (the
        constraint defects, per time) and, constrained, ``lambda_chi`` on cells ``(time,
        s_cell)`` and ``lambda_psi`` on nodes ``(time, s)``.
    """
    scene = resolve(scene)
    if not isinstance(scene, Unshearable):
        raise ParameterError("scene", getattr(scene, "name", scene), "{unshearable}")
    times = parse_times(times, t_end)
    resources.check_before_build(n, times, "ida" if constrained else "leapfrog", dt=None if constrained else dt)
    shell, compiled = build(scene, n)
    Q0, V0 = scene.initial_fields(shell.s)
    check_system(scene, shell, shell.pack(Q0, shell.momenta(Q0, V0)))  # numbers finite in double precision
    start = time.perf_counter()
    if constrained:
        traj, V, multipliers, stats = _integrate_dae(shell, Q0, V0, times, rtol, atol, max_step)
        attrs = {"integrator": "ida", "rtol": rtol, "atol": atol, "constrained": 1, **stats}
    else:
        y0 = shell.pack(Q0, shell.momenta(Q0, V0))
        omega_max, _ = checked_spectrum(scene, shell, y0)
        if dt * omega_max >= 1.0:
            raise ParameterError("dt", dt, f"(0, {1.0 / omega_max:.4g}) s", hint="leap-frog stability bound")
        method = Leapfrog(dt=dt)
        traj = method.integrate(shell, compiled, y0, method.step_counts(times) * dt)
        multipliers = None
        attrs = {"integrator": "leapfrog", "dt": dt, "constrained": 0, "leapfrog_dt_bound_s": 1.0 / omega_max}
    attrs["build_and_run_time_s"] = time.perf_counter() - start
    velocities, totals = observe(shell, traj.y)

    ds = build_dataset(shell, scene, traj, velocities, totals, attrs)
    ds.attrs["title"] = f"mol_shell run of scene unshearable ({'constrained DAE' if constrained else 'free shell'})"
    return _add_defects(ds, shell, multipliers)


def _integrate_dae(shell, Q0, V0, times, rtol, atol, max_step):
    """The constrained run on the one run loop (:func:`mol_shell.integrators.loop.run`): ``(traj, V, (Lc, Lp), stats)``."""
    dae = UnshearableDAE(shell)
    y0, yp0 = dae.consistent(Q0, V0)
    ida = ConstrainedIDA(dae, y0, yp0, dae.solver(rtol, atol * _atol_scale(dae, y0, yp0), max_step))
    traj = run(ida, shell, None, shell.pack(Q0, shell.momenta(Q0, V0)), times)
    raw = np.array((ida.stepper.saved if ida.stepper is not None else [y0])[: len(traj.t)])
    _, V, Lc, Lp = dae.unpack(raw)
    return traj, V, (Lc, Lp), traj.stats


class ConstrainedIDA:
    """IDA on the constrained DAE as an integrator of the run loop (not a registered integrator: the
    unshearable scene's own formulation). ``stepper`` keeps the DAE's unknowns at the saved times."""

    name = "ida"

    def __init__(self, dae, y0, yp0, solver):
        self.dae, self.y0, self.yp0, self.solver = dae, y0, yp0, solver
        self.stepper = None

    def start(self, system, compiled, y0, times, monitor):
        self.stepper = _ConstrainedStepper(self.dae, self.solver, self.y0, self.yp0, times[-1])
        return self.stepper


class _ConstrainedStepper:
    """One IDA step at a time (``onestep``, stopping at each saved time); the loop's :class:`Stepper`."""

    def __init__(self, dae, solver, y0, yp0, t_end):
        self.dae, self.solver = dae, solver
        self.t, self.y, self.steps = 0.0, y0, 0
        self.saved = [y0]
        self.budget = StepBudget("ida", t_end, STEP_LIMIT)
        solver.init_step(0.0, y0, yp0)

    def advance(self, target):
        result = self.solver.step(target, method="onestep", tstop=target)
        t = float(np.ravel(result.t)[0])
        if not result.success:
            error = ModelLimitError(f"IDA failed at t = {t:.9g} s: {result.message}", t, "whole shell")
            error.status = "failed"
            raise error
        self.steps += 1
        self.budget.step(t)  # stops a run that cannot reach its end
        self.t, self.y = t, np.array(result.y).ravel()

    def state(self, target):
        """The shell's state (for the loop's checks and the Dataset); the DAE's unknowns are kept in ``saved``."""
        self.saved.append(self.y)
        Q, V, _, _ = self.dae.unpack(self.y)
        shell = self.dae.shell
        return shell.pack(Q, shell.momenta(Q, V))

    def stats(self):
        dae = self.dae
        return {"n_steps": self.steps, "n_rhs": dae.n_res, "n_jac": dae.n_jac,
                "jacobian_bw_lower": dae.bandwidth[0], "jacobian_bw_upper": dae.bandwidth[1], "dae_size": dae.size}


def _atol_scale(dae, y0, yp0):
    """Absolute-tolerance weights: 1 for lengths and angles, a time scale for rates, force scales for multipliers."""
    sh = dae.shell
    speed = math.sqrt((sh.lam + 2 * sh.mu) / sh.scene.rho)  # fastest wave, m/s
    scale = np.ones((dae.n, NODE))
    scale[:, 5:10] = speed / sh.scene.L  # rates: lengths per time scale L / c
    stiffness = (sh.lam + 2 * sh.mu) * 2 * sh.scene.h  # membrane stiffness per unit length, N/m
    scale[:, 10] = stiffness * sh.scene.L
    scale[:, 11] = stiffness
    return scale.reshape(-1)


def _add_defects(ds, shell, multipliers):
    """Constraint defects per time; multipliers with their units when given."""
    chi_s = np.diff(ds.chi.values, axis=1) / shell.ds
    ds["chi_s_max"] = (("time",), np.abs(chi_s).max(axis=1),
                       {"units": "rad m-1", "long_name": "max over cells of |chi_s| (0 for an axisymmetric motion)"})
    ds["psi_max"] = (("time",), np.abs(ds.psi.values).max(axis=1),
                     {"units": "rad", "long_name": "max over s of |psi| (0 for an axisymmetric motion)"})
    if multipliers is not None:
        Lc, Lp = multipliers
        cells = (shell.s[:-1] + shell.s[1:]) / 2
        ds = ds.assign_coords(s_cell=("s_cell", cells, {"units": "m", "long_name": "arc length at cell midpoints"}))
        ds["lambda_chi"] = (("time", "s_cell"), Lc, {
            "units": "N", "long_name": "Lagrange multiplier of chi_s = 0: axial moment per unit reference "
            "circumferential length (2 pi r0 lambda_chi = torque across the section)"})
        ds["lambda_psi"] = (("time", "s"), Lp, {
            "units": "N m-1", "long_name": "Lagrange multiplier of psi = 0 per unit reference area "
            "(minus the couple keeping the director in the meridional plane)"})
    return ds


def defects(ds):
    """``(max |chi_s|, max |psi|)`` over a whole run Dataset (any scene)."""
    chi_s = ds.chi.diff("s") / ds.s.diff("s")
    return float(abs(chi_s).max()), float(abs(ds.psi).max())


__all__ = ["UnshearableDAE", "defects", "simulate_unshearable"]

