"""IDA on the unshearable shell's constrained DAE (:class:`~mol_shell.discretization.unshearable_dae.UnshearableDAE`)
as an integrator of the one run loop: the scene's own formulation, not a registered integrator name.

The model's limits (``delta > 0``, ``r > 0``, SVK's turning point: :attr:`~mol_shell.discretization.limits.ModelLimits.
limits` of the shell) are IDA's root functions, as on the shell's own ``ida`` and ``cvode-*``: a run stops where one is
crossed, found to IDA's tolerance, whatever the saved times (checked only at saved times, a run went through one between
two of them and finished).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from mol_shell._core.errors import ModelLimitError
from mol_shell.discretization.compiled import buffered
from mol_shell.discretization.unshearable_dae import NODE
from mol_shell.integrators.base import StepBudget

#: IDA steps after which a constrained run is given up (as max_steps of the shell's SUNDIALS integrators)
STEP_LIMIT = 1_000_000
#: the status of an IDA step that stopped at a root of its events (SUNDIALS' IDA_ROOT_RETURN)
ROOT_RETURN = 2


def dae_limits(dae):
    """``x -> g``: the shell's limits (:attr:`~mol_shell.discretization.limits.ModelLimits.limits`, positive inside)
    at the DAE's unknowns ``x``: they depend on the fields alone, the first five of each node's unknowns."""
    shell = dae.shell
    x = ca.MX.sym("x", dae.size)
    X = ca.reshape(x, NODE, dae.n)
    y = ca.vertcat(ca.vec(X[: shell.ny, :]), ca.MX.zeros(shell.size - shell.ny * dae.n, 1))
    return ca.Function("dae_limits", [x], [shell.limits(y)], ["x"], ["g"])


def ida_solver(dae, rtol, atol, max_step=0.0):
    """An ``sksundae`` IDA solver with the CasADi residual and its exact band Jacobian."""
    from sksundae.ida import IDA

    res_buf = buffered(dae.residual)
    jac_buf = buffered(dae.iteration_matrix)
    rows, cols = dae.pattern
    dae.n_res = dae.n_jac = 0

    def resfn(t, y, yp, res):
        dae.n_res += 1
        if not np.isfinite(t):  # IDA's step underflowed: motions too fast for double precision
            raise RuntimeError(f"IDA asked for the residual at t = {t} (its step size underflowed)")
        res[:] = res_buf(y, yp)

    def jacfn(t, y, yp, res, cj, JJ):
        dae.n_jac += 1
        JJ.fill(0.0)
        JJ[rows, cols] = jac_buf(y, yp, cj)  # the nonzeros, in CCS order

    limits = buffered(dae_limits(dae))
    count = len(dae.shell.limit_names())

    def eventsfn(t, y, yp, g):  # the model's limits: a root ends the run there (ConstrainedIDA)
        g[:] = limits(y)

    eventsfn.terminal = [True] * count
    eventsfn.direction = [-1] * count
    lb, ub = dae.bandwidth
    return IDA(
        resfn, jacfn=jacfn, rtol=rtol, atol=atol, linsolver="band", lband=lb, uband=ub,
        algebraic_idx=dae.algebraic, max_num_steps=100000, max_step=max_step, eventsfn=eventsfn, num_events=count,
    )


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
        if result.status == ROOT_RETURN:
            raise self._limit(result)
        if not result.success:
            error = ModelLimitError(f"IDA failed at t = {t:.9g} s: {result.message}", t, "whole shell")
            error.status = "failed"
            raise error
        self.steps += 1
        self.budget.step(t)  # stops a run that cannot reach its end
        self.t, self.y = t, np.array(result.y).ravel()

    def _limit(self, result):
        """The :class:`ModelLimitError` of a root of the limits (:func:`dae_limits`): what, where and when."""
        t = float(np.ravel(result.t_events)[-1]) if result.t_events is not None else float(np.ravel(result.t)[0])
        which = np.flatnonzero(np.atleast_2d(result.i_events)[-1])
        limit, where = self.dae.shell.limit_names()[int(which[0])]
        return ModelLimitError(f"{limit} at t = {t:.9g} s, {where}: a limit of the model (root found by IDA on the "
                               "constrained DAE)", t, where)

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


__all__ = ["STEP_LIMIT", "ConstrainedIDA", "dae_limits", "ida_solver"]
