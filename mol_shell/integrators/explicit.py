"""Explicit embedded Runge-Kutta pairs stepped in generated C: ``dop853-c`` and ``rk45-c``.

SciPy's ``DOP853`` (Dormand-Prince 8(5,3)) and ``RK45`` (Dormand-Prince 5(4)): their tableaus, error norms
and step-size control (safety 0.9, factors 0.2 to 10, SciPy's minimum step), with the loop in C
(:mod:`mol_shell.rk_driver`) on the compiled right-hand side, so that no Python runs per step. The model's
limits are checked after every accepted step in C (as leap-frog does), the energy and progress between
calls. Steps are shortened to land on each saved time instead of interpolating (no dense output); on a
run with one saved interval the step sequence is SciPy's.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.integrators.base import Monitor, StepBudget, Trajectory
from mol_shell.integrators.sundials import _Sundials


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
class RungeKuttaC(_Sundials):
    """SciPy's ``DOP853`` in generated C (tolerances as for CVODE: ``rtol``, ``atol`` per field, momenta scaled).

    ``max_steps`` bounds the accepted steps of the run; ``chunk`` steps run in C between two checks of the
    energy and progress updates.
    """

    chunk: int = 2000

    name = "dop853-c"
    #: the scipy.integrate class whose tableau and step control this runs (imported when used: scipy.integrate
    #: takes 0.35 s to import, a third of a study worker's start)
    solver = "DOP853"
    order = 8

    def __post_init__(self):
        super().__post_init__()
        if not (isinstance(self.chunk, (int, np.integer)) and not isinstance(self.chunk, bool) and self.chunk >= 1):
            raise ParameterError("chunk", self.chunk, "integers >= 1")

    def settings(self):
        return self.tolerances()

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
        times = np.asarray(times, dtype=float)
        if times[0] != 0:
            raise ParameterError("times", float(times[0]), "first saved time must be 0")
        evaluate = compiled.evaluator()
        atol = np.ascontiguousarray(self.atol_vector(system, y0, momenta=True))
        tableau = self.tableau()
        monitor = Monitor(system, y0)
        y = np.array(y0, dtype=float)
        saved, reached = [y.copy()], [0.0]
        status, message, failure = "complete", "completed", float("nan")
        stats = np.zeros(3, dtype=np.int64)
        start = time.perf_counter()
        f = evaluate(y, 0.0).copy()
        h0 = initial_step(lambda v, t: evaluate(v, t).copy(), y, f, self.scipy_method().error_estimator_order, self.rtol,
                          atol, float(times[-1]), float(self.max_step))
        t, h = np.zeros(1), np.array([h0])
        evaluations = 2
        try:
            for target in times[1:]:
                while t[0] < target:
                    t_before = t[0]
                    budget = min(self.chunk, self.max_steps - int(stats[0]))
                    code = compiled.runge_kutta((t, y, f, h), target, self.rtol, atol, self.max_step, tableau,
                                                budget, stats)
                    if progress is not None:
                        progress.update(t[0] - t_before)
                    if code == 1:
                        monitor.check(y, t[0])  # raises, naming the limit and the place
                        raise ModelLimitError(f"a limit of the model was reached at t = {t[0]:.9g} s", t[0],
                                              "whole shell")
                    if code == -2:
                        raise failed(f"{self.name} failed at t = {t[0]:.9g} s: the step fell below SciPy's minimum "
                                     f"({h[0]:.3g} s): not finite, or stiff?", t[0])
                    if code == -1:
                        raise failed(f"{self.name}: the right-hand side failed at t = {t[0]:.9g} s", t[0])
                    if stats[0] >= self.max_steps:
                        raise failed(f"{self.name} took max_steps = {self.max_steps} steps by t = {t[0]:.9g} s", t[0])
                    needed = stats[0] * times[-1] / t[0] if t[0] > 0 else float("inf")
                    if stats[0] >= StepBudget.EVERY and needed > StepBudget.MARGIN * self.max_steps:
                        raise failed(f"{self.name} would need about {needed:.3g} steps to reach t = {times[-1]:.6g} s "
                                     f"at its mean step so far, more than max_steps = {self.max_steps}: the motion is "
                                     f"too fast for this horizon (stopped at t = {t[0]:.9g} s)", t[0])
                    monitor.check(y, t[0])  # the energy (instability) and finiteness, once a chunk
                saved.append(y.copy())
                reached.append(float(target))
        except ModelLimitError as exc:
            status, message, failure = exc.status, str(exc), exc.time
        except KeyboardInterrupt:
            status, message, failure = "interrupted", f"interrupted by the user at t = {t[0]:.9g} s", t[0]
        wall = time.perf_counter() - start
        run_stats = {"n_steps": int(stats[0]), "n_rejected": int(stats[1]), "n_rhs": int(stats[2]) + evaluations,
                     "wall_time_s": wall}
        return Trajectory(np.array(reached), np.array(saved), status=status, message=message, stats=run_stats,
                          failure_time=failure)


@dataclass(frozen=True)
class RungeKutta45C(RungeKuttaC):
    """SciPy's ``RK45`` (Dormand-Prince 5(4)) in generated C."""

    name = "rk45-c"
    solver = "RK45"
    order = 5


EXPLICIT = {cls.name: cls for cls in (RungeKuttaC, RungeKutta45C)}
