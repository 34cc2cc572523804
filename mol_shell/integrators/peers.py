"""The alternatives a user would try, for the work-precision comparison: SciPy's solvers (CasADi's SUNDIALS plugins
are :mod:`mol_shell.integrators.casadi_peers`).

* ``scipy-rk45``, ``scipy-dop853``: explicit Runge-Kutta (orders 5(4) and 8(5,3)) of
  :mod:`scipy.integrate`, on the compiled right-hand side.
* ``scipy-radau``, ``scipy-bdf``: implicit, given the exact Jacobian as a scipy CSC matrix
  (the compiled CasADi Jacobian of :mod:`mol_shell.integrators.sundials`).

The scipy solvers are stepped one step at a time (as ``solve_ivp`` does) so that steps are
counted exactly; saved states come from their dense output. At each kink of a driven edge's rate (docs/loads.md) a
scipy solver's run ends one ulp short of it (its ``t_bound``: the last step's stages take the old segment's rate)
and a new one starts from the state there, on the new segment. The model's limits are checked at the saved times only
(:class:`~mol_shell.integrators.Monitor`); none of these has constraints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mol_shell._core.constants import RTOL_RANGE, stated_up
from mol_shell._core.errors import ModelLimitError
from mol_shell.discretization.loading import drive_kinks
from mol_shell.integrators import loop
from mol_shell.integrators.base import StepBudget
from mol_shell.integrators.buildable import JACOBIAN_DEFAULT, resolve_jacobian
from mol_shell.integrators.loop import choice, integers, interval, option
from mol_shell.integrators.sundials import pieces
from mol_shell.integrators.tolerances import Tolerances


@dataclass(frozen=True)
class _Peer(Tolerances):
    """Tolerances as for CVODE (``rtol``, ``atol`` per field, momenta scaled by their mass)."""

    order = None  # variable order (CasADi's CVODES and IDAS); the Runge-Kutta pairs declare theirs

    def integrate(self, system, compiled, y0, times, *, progress=None):
        return loop.run(self, system, compiled, y0, times, progress=progress)


#: the least relative tolerance SciPy's solvers take: ``scipy.integrate`` raises a smaller one to 100 x machine epsilon
#: (2.220446049250313e-14, with a warning) and the run would record a tolerance it did not use; stated to 4 digits,
#: rounded up (2.221e-14), so that the range stated is the one applied
SCIPY_RTOL_MIN = stated_up(100 * np.finfo(float).eps)


@dataclass(frozen=True)
class ScipyRK45(_Peer):
    """``scipy.integrate.RK45`` (Dormand-Prince 5(4)), stepped in Python.

    ``rtol`` in ``[SCIPY_RTOL_MIN, 1)`` (all four peers): SciPy would raise a smaller one to its floor, and the run
    record a tolerance it did not use, so it is refused.
    """

    rtol: float = option(1e-6, interval(SCIPY_RTOL_MIN, RTOL_RANGE[1], " (SciPy's floor: 100 x machine epsilon)"))
    max_steps: int = option(1_000_000, integers(1))

    name = "scipy-rk45"
    solver = "RK45"
    order = 5
    implicit = False

    def start(self, system, compiled, y0, times, monitor):
        return _ScipyStepper(self, system, compiled, y0, times)


class _ScipyStepper:
    """A scipy.integrate solver stepped one step at a time (as ``solve_ivp`` does), so steps are counted exactly;
    saved states come from its dense output."""

    def __init__(self, method, system, compiled, y0, times):
        import scipy.integrate  # here: with the package it was a third of a study worker's start (0.35 s)
        import scipy.sparse as sp

        f = compiled.evaluator()
        options = {"rtol": method.rtol, "atol": method.atol_vector(system, y0, momenta=True)}
        if method.max_step:
            options["max_step"] = method.max_step
        if method.implicit:
            parts = pieces(system, "cvode", resolve_jacobian(method.name, method.jacobian))
            jac, pattern = parts["jac"], parts["pattern"]
            indices, indptr = pattern.indices, pattern.indptr

            def jacobian(t, y):
                return sp.csc_matrix((jac(t, y).copy(), indices, indptr), shape=pattern.shape)

            options["jac"] = jacobian
        self.name, self.t_end = method.name, float(times[-1])
        kind = getattr(scipy.integrate, method.solver)
        self.make = lambda t0, y, bound: kind(lambda t, y: f(y, t).copy(), t0, y, bound, **options)
        #: the drive's kinks still ahead (increasing, up to the last saved time): each solver's run ends at the next
        self.kinks = [k for k in drive_kinks(system) if k <= self.t_end]
        self.before = {"nfev": 0, "njev": 0, "nlu": 0}  # the counts of the solvers before the last kink
        self.solver = self._segment(0.0, np.array(y0, dtype=float))
        self.steps, self.dense = 0, None
        self.budget = StepBudget(method.name, times[-1], method.max_steps, method.tolerance_text())

    def _segment(self, t0, y):
        """A solver from ``(t0, y)`` to the next kink, one ulp short of it (the stages of the step that ends there
        take the old segment's rate; the history's rate at its corner is the new one's), or to the end."""
        return self.make(t0, y, float(np.nextafter(self.kinks[0], -math.inf)) if self.kinks else self.t_end)

    @property
    def t(self):
        solver = self.solver
        # a solver that ended one ulp short of a kink stands at the kink (a change of the state of the order of
        # round-off); the next step starts a new solver there
        return self.kinks[0] if solver.status == "finished" and self.kinks else float(solver.t)

    def advance(self, target):
        solver = self.solver
        if solver.status == "finished" and self.kinks:  # at a kink: a new solver from it, on the new segment
            for key in self.before:
                self.before[key] += int(getattr(solver, key, 0))
            solver = self.solver = self._segment(self.kinks.pop(0), solver.y)
        try:
            message = solver.step()
        except RuntimeError as exc:  # SuperLU's "Factor is exactly singular": raised, not returned as a failure
            if "singular" not in str(exc):
                raise
            raise self._singular(exc) from None
        self.steps += 1
        self.dense = None
        self.budget.step(solver.t)  # max_steps, or a projection far beyond it, ends the run
        if solver.status == "failed":
            raise ModelLimitError(f"{self.name} failed at t = {solver.t:.9g} s: {message}", solver.t, "whole shell")

    def _singular(self, exc):
        """The :class:`ModelLimitError` (``"failed"``) for a Newton matrix that SuperLU found singular: with a step at
        round-off and a Jacobian near the edge of doubles (``E = 1e200``, ``rho = 1e-300``), ``I - c h J`` or
        ``I / (c h) - J`` has entries that overflow (``inf``, ``nan``): not a matrix in double precision."""
        solver = self.solver
        t, h = float(solver.t), float(getattr(solver, "h_abs", math.nan))
        floor = 10 * float(np.nextafter(t, math.inf) - t)  # SciPy steps at least 10 ulp(t), whatever h_abs says
        step = (f"the step h = {h:.3g} s" if h >= floor else
                f"SciPy's minimum step {floor:.3g} s (10 ulp(t); its step estimate, {h:.3g} s, underflowed below it)")
        J = getattr(solver, "J", None)
        values = np.abs(J.data if hasattr(J, "data") else np.asarray(J if J is not None else [math.nan], dtype=float))
        finite = values[np.isfinite(values)]
        entries = (f"{finite.max():.3g} /s" if finite.size else "none finite") + (
            f", {values.size - finite.size} not finite" if finite.size < values.size else "")
        err = ModelLimitError(f"{self.name} failed at t = {t:.9g} s: its Newton matrix is singular in double precision "
                              f"(SuperLU: {exc}) at {step}, with the Jacobian's entries up to {entries}: "
                              "the motion is too fast for double precision at this state (a stiffness or density near "
                              "the edge of doubles)", t, "whole shell")
        err.status = "failed"
        return err

    def state(self, target):
        solver = self.solver
        if target in (solver.t, self.t):
            return solver.y.copy()
        if self.dense is None:
            self.dense = solver.dense_output()
        return self.dense(target)

    def stats(self):
        s, before = self.solver, self.before
        return {"n_steps": self.steps, "n_rhs": before["nfev"] + int(s.nfev),
                "n_jac": before["njev"] + int(getattr(s, "njev", 0)), "n_lu": before["nlu"] + int(getattr(s, "nlu", 0))}


@dataclass(frozen=True)
class ScipyDOP853(ScipyRK45):
    """``scipy.integrate.DOP853`` (Dormand-Prince 8(5,3))."""

    name = "scipy-dop853"
    solver = "DOP853"
    order = 8


@dataclass(frozen=True)
class ScipyRadau(ScipyRK45):
    """``scipy.integrate.Radau`` (implicit Radau IIA, order 5) with the exact sparse Jacobian."""

    jacobian: str = option(JACOBIAN_DEFAULT, choice("compiled", "vm"))

    name = "scipy-radau"
    solver = "Radau"
    implicit = True

    def settings(self):
        """The tolerances, and ``jacobian`` as the run used it (its default follows what gcc can build)."""
        return {**super().settings(), "jacobian": resolve_jacobian(self.name, self.jacobian)}


@dataclass(frozen=True)
class ScipyBDF(ScipyRadau):
    """``scipy.integrate.BDF`` (variable order 1-5, NDF) with the exact sparse Jacobian."""

    name = "scipy-bdf"
    solver = "BDF"
    order = None
    implicit = True


SCIPY_PEERS = {cls.name: cls for cls in (ScipyRK45, ScipyDOP853, ScipyRadau, ScipyBDF)}

__all__ = ["SCIPY_PEERS"]
