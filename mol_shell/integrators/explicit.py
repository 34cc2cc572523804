"""Explicit embedded Runge-Kutta pairs stepped in generated C: ``dop853-c`` and ``rk45-c``.

SciPy's ``DOP853`` (Dormand-Prince 8(5,3)) and ``RK45`` (Dormand-Prince 5(4)): their tableaus, error norms
and step-size control (safety 0.9, factors 0.2 to 10, SciPy's minimum step), with the loop in C
(:mod:`mol_shell.discretization.rk_driver`) on the compiled right-hand side, so that no Python runs per step. The model's
limits are checked after every accepted step in C (as leap-frog does), the energy and progress between
calls. A step whose end left a limit is searched for the crossing on its dense output, once
(:mod:`mol_shell.integrators.rk_dense`): the run stops there, as CVODE's and IDA's at a root (a non-finite state and
the energy's growth stop at the step's end). Steps are shortened to land on each saved time instead of interpolating (no dense output); on a
run with one saved interval the step sequence is SciPy's.

A driven edge's rate that follows a ramp or a table has kinks (:func:`~mol_shell.discretization.loading.drive_kinks`):
there the right-hand side jumps (the driven node's acceleration, and the driver's power in ``work``). A step also
lands on each kink: it ends one ulp short of it, so that all its stages (the last at the step's end) take the old
segment's rate, its left limit (the history's rate at the corner itself is the new segment's); its state is the
state at the kink (one ulp of time apart: a change of the order of round-off), and ``f`` there, the next step's first
stage (first same as last), is evaluated again on the new segment. Without kinks nothing changes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ModelLimitError
from mol_shell.discretization.loading import drive_kinks
from mol_shell.integrators import loop
from mol_shell.integrators.base import StepBudget
from mol_shell.integrators.loop import integers, option
from mol_shell.integrators.rk_dense import DenseStep, first_crossing
from mol_shell.integrators.tolerances import Tolerances


def failed(message, t):
    """A :class:`ModelLimitError` with status ``"failed"`` (the integrator, not the model, gave up)."""
    err = ModelLimitError(message, t, "whole shell")
    err.status = "failed"
    return err


#: SciPy's minimum step at ``t = 0`` (10 ulp(0), 4.9e-323 s): a starting step below it underflows
MIN_STEP_AT_ZERO = 10 * float(np.nextafter(0.0, 1.0))


def _log_rms(v, scale):
    """``log10 sqrt(mean((v / scale)^2))``, finite where that norm is beyond doubles (``-inf`` for ``v = 0``).

    ``v / scale`` is formed as ``(v / m) / scale`` with ``m = max |v|`` and squared after another division by its
    largest entry, so that a right-hand side of 1e300 (``E = 1e300``) in a tolerance of 1e-9 is ``1e309``, not ``inf``.
    """
    m = float(np.max(np.abs(v)))
    if m == 0 or not np.isfinite(m):
        return -math.inf if m == 0 else math.inf
    with np.errstate(over="ignore"):
        u = np.abs(v / m) / scale
    mu = float(np.max(u))
    if not np.isfinite(mu):
        return math.inf
    return math.log10(m) + math.log10(mu) + 0.5 * math.log10(float(np.mean((u / mu) ** 2)))


def initial_step(f, y0, f0, order, rtol, atol, t_end, max_step):
    """Hairer, Norsett and Wanner's starting step (Solving ODEs I, II.4), as SciPy chooses it.

    Where its norms or their ratios leave double precision (``|f| / atol`` beyond 1e154, whose square overflows:
    ``E = 1e150`` or ``rho = 1e-150``), the same estimate is formed from their logarithms; the step returned is 0 when
    the estimate itself is below :data:`MIN_STEP_AT_ZERO` (it underflows: ``h0 = 0.01 |y| / |f|`` with ``|f| ~ 1e309``).
    """
    scale = atol + np.abs(y0) * rtol
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        d0, d1 = (float(np.sqrt(np.mean((v / scale) ** 2))) for v in (y0, f0))
        h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        if np.isfinite(d1) and h0 > 0:  # SciPy's formula, in the arithmetic this function always had
            h0 = min(h0, t_end)
            f1 = f(y0 + h0 * f0, h0)
            d2 = float(np.sqrt(np.mean(((f1 - f0) / scale) ** 2))) / h0
            if np.isfinite(d2):
                h1 = max(1e-6, h0 * 1e-3) if d1 <= 1e-15 and d2 <= 1e-15 else (0.01 / max(d1, d2)) ** (1 / (order + 1))
                h = min(100 * h0, h1, t_end)
                return min(h, max_step) if max_step > 0 else h
    # beyond double precision somewhere: the same estimate in log10
    l0, l1 = _log_rms(y0, scale), _log_rms(f0, scale)
    h0 = 1e-6 if l0 < -5 or l1 < -5 else 10.0 ** min(l0 - l1 - 2, math.log10(t_end))
    h0 = min(h0, t_end)
    if not h0 >= MIN_STEP_AT_ZERO:
        return 0.0
    l2 = _log_rms(f(y0 + h0 * f0, h0) - f0, scale) - math.log10(h0)
    if math.isnan(l2):  # f is not finite a step away: the estimate from d1 alone
        l2 = l1
    h1 = max(1e-6, h0 * 1e-3) if l1 <= -15 and l2 <= -15 else 10.0 ** ((-2 - max(l1, l2)) / (order + 1))
    h = min(100 * h0, h1, t_end)
    h = min(h, max_step) if max_step > 0 else h
    return h if h >= MIN_STEP_AT_ZERO else 0.0


def _magnitude(v, scale):
    """``|v / scale|``'s largest entry as ``1e+309`` (its power of ten: it may be beyond doubles)."""
    with np.errstate(divide="ignore"):
        logs = np.log10(np.abs(v)) - np.log10(scale)
    top = float(np.max(logs))
    return f"1e{math.floor(top):+d}" if np.isfinite(top) else "not finite"


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

    kinks = ()  # the drive's kinks still ahead (a list from __init__)
    work = None  # the driver's stages and scratch, kept for the search of a crossing (an array from __init__)

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
        if h0 == 0:  # the starting step underflows: the motion is too fast for double precision at this state
            scale = self.atol + np.abs(self.y) * method.rtol
            raise failed(f"{method.name} failed at t = 0 s: its initial step underflows (below {MIN_STEP_AT_ZERO:.2g} s, "
                         f"10 ulp(0)): the right-hand side at the start is {_magnitude(self.f, scale)} times its "
                         f"tolerance ({method.tolerance_text()}) per second, and h0 ~ 0.01 |y| / |f| is beyond double "
                         "precision (a stiffness or density near the edge of doubles: E / rho ~ 1e300?)", 0.0)
        self.time, self.h = np.zeros(1), np.array([h0])
        self.budget = StepBudget(method.name, self.t_end, method.max_steps, method.tolerance_text())
        self.evaluate = evaluate
        self.work = np.empty((len(self.tableau[1]) + 4) * self.y.size)  # the driver's stages and scratch
        self.names = system.limit_names()
        # the drive's kinks still ahead (increasing, up to the last saved time): a step lands on each
        self.kinks = [k for k in drive_kinks(system) if k <= self.t_end]

    @property
    def t(self):
        return float(self.time[0])

    def advance(self, target):
        m, counts, t = self.method, self.counts, self.time
        budget = min(m.chunk, m.max_steps - int(counts[0]))
        kink = self.kinks[0] if self.kinks and self.kinks[0] <= target else None
        # the step that ends on a kink ends one ulp short of it: its stages all take the old segment's rate
        stop = float(np.nextafter(kink, -math.inf)) if kink is not None else target
        code = self.compiled.runge_kutta((t, self.y, self.f, self.h), stop, m.rtol, self.atol, m.max_step,
                                         self.tableau, budget, counts, work=self.work)
        if code == 1:
            raise self._crossed()
        if code == -2:  # the step fell below 10 ulp(t), round-off at t: the tolerance asks more than doubles hold
            raise failed(f"{m.name} failed at t = {t[0]:.9g} s: its step fell below round-off at t ({self.h[0]:.3g} s, "
                         f"SciPy's minimum): {self.tolerance()} cannot be met there in double precision (a looser "
                         "tolerance goes on), or the right-hand side is not finite near this state", t[0])
        if code == -1:
            raise failed(f"{m.name}: the right-hand side failed at t = {t[0]:.9g} s", t[0])
        if counts[0] >= m.max_steps:
            raise failed(f"{m.name} took max_steps = {m.max_steps} steps by t = {t[0]:.9g} s", t[0])
        self.budget.project(int(counts[0]), t[0])  # the steps still needed, from the mean of the last ones
        self.monitor.check(self.y, t[0])  # the energy (instability) and finiteness, once a chunk
        if kink is not None and t[0] == stop:
            self._past(kink)

    def _crossed(self):
        """The :class:`ModelLimitError` of the step that left a limit (the driver kept it: ``(t, y, f)`` its start,
        ``h`` the time at its end, the work its stages and end), at the crossing inside it: the end of the last bracket
        of :func:`~mol_shell.integrators.rk_dense.first_crossing` on the step's dense output, where (t, y, f) are
        left, as CVODE's state at a root. A non-finite state and the energy's growth stop at the step's end."""
        N, s = self.y.size, len(self.tableau[1])
        t0, t1, work = float(self.time[0]), float(self.h[0]), self.work
        y1, f1 = work[s * N:(s + 1) * N].copy(), work[(s + 1) * N:(s + 2) * N].copy()
        self.monitor.check_balance(y1, t1)  # raises at the step's end: these are not located inside it
        step = DenseStep(self.method.scipy_method(), t0, self.y, t1, work[: s * N].reshape(s, N), y1, f1,
                         lambda y, t: self.evaluate(y, t).copy())
        limits = self.compiled.limits
        t, g = first_crossing(lambda t: limits(step(t)), t0, t1, limits(self.y), limits(y1))
        self.y[:] = step(t)
        self.f[:] = self.evaluate(self.y, t)
        self.time[0] = t
        self.counts[2] += step.n_rhs + 1
        what, where = self.names[int(np.flatnonzero(~(g > 0))[0])]
        return ModelLimitError(f"{what} at t = {t:.9g} s, {where}: a limit of the model (crossing located by "
                               f"{self.method.name} in its last step)", t, where)

    def _past(self, kink):
        """At a kink (reached one ulp short of it): the state is the kink's, and ``f`` there, the next step's first
        stage, the new segment's (a step whose first stage took the old rate would span the jump)."""
        self.kinks.pop(0)
        self.time[0] = kink
        if kink < self.t_end:
            self.f[:] = self.evaluate(self.y, kink)
            self.counts[2] += 1

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
