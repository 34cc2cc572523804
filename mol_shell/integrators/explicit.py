"""Explicit embedded Runge-Kutta pairs stepped in generated C: ``dop853-c`` and ``rk45-c``.

SciPy's ``DOP853`` (Dormand-Prince 8(5,3)) and ``RK45`` (Dormand-Prince 5(4)): their tableaus, error norms
and step-size control (safety 0.9, factors 0.2 to 10, SciPy's minimum step), with the loop in C
(:mod:`mol_shell.discretization.rk_driver`) on the compiled right-hand side, so that no Python runs per step. The model's
limits are checked after every accepted step in C (as leap-frog does), the energy and progress between
calls. Steps are shortened to land on each saved time instead of interpolating (no dense output); on a
run with one saved interval the step sequence is SciPy's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ModelLimitError
from mol_shell.integrators import loop
from mol_shell.integrators.base import StepBudget
from mol_shell.integrators.loop import integers, option
from mol_shell.integrators.tolerances import Tolerances


def failed(message, t):
    """A :class:`ModelLimitError` with status ``"failed"`` (the integrator, not the model, gave up)."""
    err = ModelLimitError(message, t, "whole shell")
    err.status = "failed"
    return err


def initial_step(f, y0, f0, order, rtol, atol, t_end, max_step):
    """Hairer, Norsett and Wanner's starting step (Solving ODEs I, II.4), as SciPy chooses it."""
    scale = atol + np.abs(y0) * rtol
    d0, d1 = (float(np.sqrt(np.mean((v / scale) ** 2))) for v in (y0, f0))
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, t_end)
    f1 = f(y0 + h0 * f0, h0)
    d2 = float(np.sqrt(np.mean(((f1 - f0) / scale) ** 2))) / h0
    h1 = max(1e-6, h0 * 1e-3) if d1 <= 1e-15 and d2 <= 1e-15 else (0.01 / max(d1, d2)) ** (1 / (order + 1))
    h = min(100 * h0, h1, t_end)
    return min(h, max_step) if max_step > 0 else h


@dataclass(frozen=True)
class RungeKuttaC(Tolerances):
    """SciPy's ``DOP853`` in generated C (tolerances as for CVODE: ``rtol``, ``atol`` per field, momenta scaled).

    ``max_steps`` bounds the accepted steps of the run; ``chunk`` steps run in C between two checks of the
    energy and progress updates.
    """

    max_steps: int = option(1_000_000, integers(1))
    chunk: int = option(2000, integers(1))

    name = "dop853-c"
    #: the scipy.integrate class whose tableau and step control this runs (imported when used: scipy.integrate
    #: takes 0.35 s to import, a third of a study worker's start)
    solver = "DOP853"
    order = 8
    #: the energy and finiteness are checked at the end of every chunk (and so at every saved time)
    checks_every_chunk = True

    @classmethod
    def scipy_method(cls):
        """The scipy.integrate class (``DOP853``, ``RK45``)."""
        import scipy.integrate

        return getattr(scipy.integrate, cls.solver)

    @classmethod
    def tableau(cls):
        m = cls.scipy_method()
        B, C = (np.ascontiguousarray(x, dtype=float) for x in (m.B, m.C))
        A = np.zeros((len(B), len(B)))  # RK45's A is 6 x 5: square, row-major for the driver
        A[:, : m.A.shape[1]] = m.A[: len(B)]
        if hasattr(m, "E3"):
            return A, B, C, np.ascontiguousarray(m.E5, dtype=float), np.ascontiguousarray(m.E3, dtype=float), \
                -1.0 / (m.error_estimator_order + 1)
        return A, B, C, np.ascontiguousarray(m.E, dtype=float), None, -1.0 / (m.error_estimator_order + 1)

    def integrate(self, system, compiled, y0, times, *, progress=None):
        """Run from ``times[0]`` (must be 0) through ``times``; returns a :class:`Trajectory`."""
        return loop.run(self, system, compiled, y0, times, progress=progress)

    def start(self, system, compiled, y0, times, monitor):
        return _RungeKuttaStepper(self, system, compiled, y0, times, monitor)


class _RungeKuttaStepper:
    """The driver's state between chunks: ``t``, ``y``, ``f(y)`` and the next step ``h`` (in place)."""

    def __init__(self, method, system, compiled, y0, times, monitor):
        self.method, self.compiled, self.monitor = method, compiled, monitor
        self.t_end = float(times[-1])
        evaluate = compiled.evaluator()
        self.atol = np.ascontiguousarray(method.atol_vector(system, y0, momenta=True))
        self.tableau = method.tableau()
        self.y = np.array(y0, dtype=float)
        self.counts = np.zeros(3, dtype=np.int64)  # accepted, rejected steps, RHS evaluations in C
        self.f = evaluate(self.y, 0.0).copy()
        h0 = initial_step(lambda v, t: evaluate(v, t).copy(), self.y, self.f, method.scipy_method().error_estimator_order,
                          method.rtol, self.atol, self.t_end, float(method.max_step))
        self.time, self.h = np.zeros(1), np.array([h0])

    @property
    def t(self):
        return float(self.time[0])

    def advance(self, target):
        m, counts, t = self.method, self.counts, self.time
        budget = min(m.chunk, m.max_steps - int(counts[0]))
        code = self.compiled.runge_kutta((t, self.y, self.f, self.h), target, m.rtol, self.atol, m.max_step,
                                         self.tableau, budget, counts)
        if code == 1:
            self.monitor.check(self.y, t[0])  # raises, naming the limit and the place
            raise ModelLimitError(f"a limit of the model was reached at t = {t[0]:.9g} s", t[0], "whole shell")
        if code == -2:  # the step fell below 10 ulp(t), round-off at t: the tolerance asks more than doubles hold
            raise failed(f"{m.name} failed at t = {t[0]:.9g} s: its step fell below round-off at t ({self.h[0]:.3g} s, "
                         f"SciPy's minimum): {self.tolerance()} cannot be met there in double precision (a looser "
                         "tolerance goes on), or the right-hand side is not finite near this state", t[0])
        if code == -1:
            raise failed(f"{m.name}: the right-hand side failed at t = {t[0]:.9g} s", t[0])
        if counts[0] >= m.max_steps:
            raise failed(f"{m.name} took max_steps = {m.max_steps} steps by t = {t[0]:.9g} s", t[0])
        needed = counts[0] * self.t_end / t[0] if t[0] > 0 else float("inf")
        if counts[0] >= StepBudget.EVERY and needed > StepBudget.MARGIN * m.max_steps:
            raise failed(f"{m.name} would need about {needed:.3g} steps to reach t = {self.t_end:.6g} s "
                         f"at its mean step so far, more than max_steps = {m.max_steps}: the motion is "
                         f"too fast for this horizon at {self.tolerance()} (a looser tolerance or a larger "
                         f"max_steps goes on; stopped at t = {t[0]:.9g} s)", t[0])
        self.monitor.check(self.y, t[0])  # the energy (instability) and finiteness, once a chunk

    def tolerance(self):
        """The method's tolerances as failures name them (:meth:`Tolerances.tolerance_text`)."""
        return self.method.tolerance_text()

    def state(self, target):
        return self.y.copy()

    def stats(self):
        c = self.counts
        return {"n_steps": int(c[0]), "n_rejected": int(c[1]), "n_rhs": int(c[2]) + 2}


@dataclass(frozen=True)
class RungeKutta45C(RungeKuttaC):
    """SciPy's ``RK45`` (Dormand-Prince 5(4)) in generated C."""

    name = "rk45-c"
    solver = "RK45"
    order = 5


EXPLICIT = {cls.name: cls for cls in (RungeKuttaC, RungeKutta45C)}
