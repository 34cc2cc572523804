"""The paper's explicit, non-dissipative leap-frog scheme (section 6).

``y_{k+1} = y_{k-1} + 2 dt f(y_k)``, started by one explicit midpoint step
``y_1 = y_0 + dt f(y_0 + dt/2 f(y_0))`` so the start is second order too. For the
linear test equation ``y' = i w y`` it is stable for ``|w dt| < 1``; it neither damps
nor amplifies. Its second, parasitic solution (alternating in sign from step to step) is not neutral for a
nonlinear motion: it follows the linearised flow backwards and grows at the motion's own Lyapunov rate, whatever
the step, from the start's round-off to the size of the motion (the paper's twisted cylinder: 2-3 per second, the
energy alternating by 3e-3 from step to step at 9 s and the run stopped near 13 s). Every ``restart`` seconds the
scheme is therefore started again from its last level by the same midpoint step, which sets that solution back to
the start's size. The loop runs in generated C (the vectorised stencil of :mod:`mol_shell.discretization.stencil` for elastic, unloaded
shells without poles; :mod:`mol_shell.discretization.compiled`'s driver around the compiled RHS otherwise), which also checks
the model's limits (:attr:`ShellSystem.limits`) after every step and stops at the first step
outside them; Python only sees chunks of steps, where it checks the energy (numerical
instability) and shows progress.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell._core.ranges import TINY
from mol_shell.discretization.loading import drive_kinks
from mol_shell.discretization.stencil import leapfrog_stepper
from mol_shell.integrators import loop
from mol_shell.integrators.loop import Option, integers, option, real

#: a time ``t`` is on the step grid of ``dt`` when ``|k dt - t| <= GRID_TOLERANCE[0] dt + GRID_TOLERANCE[1] |t|`` for a
#: whole ``k`` (a millionth of a step, and round-off of ``t`` itself): saved times and ``t_end`` alike, taken at their
#: double-precision values (a float32 ``1e-4``, 9.99999975e-05, is 2.5e-6 steps off: refused, saying so)
GRID_TOLERANCE = (1e-6, 1e-12)
#: seconds between two restarts when none is given (:attr:`Leapfrog.restart` None): at least
#: :data:`MIN_RESTART_STEPS` steps (raised to them where ``dt`` is above 10 ms)
DEFAULT_RESTART = 1.0
#: the fewest steps between two restarts: each leaves the compiled loop for two right-hand sides in Python
#: (a restart every 2 steps made a run 30-45 times slower)
MIN_RESTART_STEPS = 100


def grid_steps(times, dt):
    """``(steps, off)``: the whole numbers of steps ``dt`` nearest to ``times`` (an array of seconds, at most
    :attr:`Leapfrog.MAX_STEPS` steps) and where they are off the step grid (:data:`GRID_TOLERANCE`)."""
    times, dt = np.asarray(times, dtype=float), float(dt)
    steps = np.rint(times / dt).astype(np.int64)
    return steps, np.abs(steps * dt - times) > GRID_TOLERANCE[0] * dt + GRID_TOLERANCE[1] * np.abs(times)


def off_grid_hint(t, dt):
    """What a refusal of ``t`` (s) off the grid of ``dt`` adds: how far from its nearest step it is, and where that is
    within single precision of it (a float32 value's rounding), that double precision is needed."""
    k = round(t / dt)
    near = float(f"{k * dt:.12g}")
    single = abs(k * dt - t) <= np.finfo(np.float32).eps * abs(t)
    return (f"{t!r} s is {abs(k * dt - t):.3g} s from step {k} at {near!r} s; "
            + ("a single-precision (float32) value? give it in double precision" if single else
               f"the grid allows {GRID_TOLERANCE[0]:g} dt + {GRID_TOLERANCE[1]:g} t"))


def parasitic_growth_rate(damping, omega_max, dt):
    """Growth rate (1/s) of leap-frog's parasitic root for the worst mode the spectrum's bounds allow.

    For ``y' = lambda y`` the scheme's roots solve ``z^2 - 2 lambda dt z - 1 = 0``; the parasitic one
    has ``|z| > 1`` when ``Re lambda < 0``. With ``lambda = -a + i w`` and ``x = w dt``,
    ``|z|^2 = 1 + 2 a dt / sqrt(1 - x^2) + O((a dt)^2)``: the mode grows at about
    ``a / sqrt(1 - x^2)``, faster than its damping rate near the step bound. Evaluated exactly for
    the eigenvalue with ``a = damping`` (the largest ``-Re lambda``) and ``|lambda| = omega_max``.
    """
    if damping <= 0:
        return 0.0
    lam_dt = complex(-damping, math.sqrt(max(omega_max**2 - damping**2, 0.0))) * dt
    root = cmath.sqrt(1.0 + lam_dt * lam_dt)
    return max(math.log(abs(lam_dt + root)), math.log(abs(lam_dt - root))) / dt


def restart_gain(lam_dt, steps):
    """``|G|``: the factor by which a start (one midpoint step) and ``steps - 1`` leap-frog steps change the mode
    ``y' = lambda y`` (``lam_dt = lambda dt = h``, an array), the state a restart starts again from.

    The levels are ``y_k = c1 z1^k + c2 z2^k`` with ``z^2 - 2 lambda dt z - 1 = 0`` (``z1`` near ``exp(lambda dt)``,
    ``z2`` the parasitic root, near ``-exp(-lambda dt)``) and ``c1 + c2 = y_0``, ``c1 z1 + c2 z2 = y_1 = (1 + h +
    h^2 / 2) y_0``: the start leaves ``c2 = (y_1 / y_0 - z1) / (z2 - z1)``, ``-(lambda dt)^4 / 16``, on the
    parasitic root, and a restart carries what it has grown to (``c2 z2^steps``) into the next start's state: over
    ``m`` restarts a mode changes by ``G^m``. For a damped mode ``|z2| > 1``: ``|G| > 1`` once ``|c2 z2^steps|``
    outgrows the damping, so restarts bound the growth only if they come before that."""
    h = np.asarray(lam_dt, dtype=complex)
    root = np.sqrt(1.0 + h * h)
    z1, z2 = h + root, h - root
    c2 = (1.0 + h + 0.5 * h * h - z1) / (z2 - z1)
    with np.errstate(over="ignore", invalid="ignore"):
        return np.abs((1.0 - c2) * z1**steps + c2 * z2**steps)


def damped_modes(damping, omega_max, dt, count=65):
    """``lambda dt`` of the modes the spectrum's bounds allow with the fastest decay rate ``damping`` (1/s):
    ``lambda = -damping + i w``, ``|lambda| <= omega_max``."""
    w = np.linspace(0.0, math.sqrt(max(omega_max**2 - damping**2, 0.0)), count)
    return (-damping + 1j * w) * dt


def carried_log_growth(damping, omega_max, dt, every, total):
    """``log`` of the growth of the worst damped mode (:func:`damped_modes`) carried through the restarts of a run of
    ``total`` steps restarted every ``every`` steps (0: never): ``(total // every) log max |G|`` (:func:`restart_gain`)
    where ``|G| > 1``; 0 without damping or restarts."""
    if damping <= 0 or not 0 < every < total:
        return 0.0
    gain = float(np.max(restart_gain(damped_modes(damping, omega_max, dt), every)))
    if gain <= 1:
        return 0.0
    return (total // every) * math.log(gain) if math.isfinite(gain) else math.inf  # overflowed (inf or nan): grows


def longest_restart(damping, omega_max, dt, total, rate, limit):
    """The most steps between restarts (at least :attr:`Leapfrog.MIN_RESTART_STEPS`, at most ``total``) with which the
    parasitic root grows by at most ``exp(limit)`` both between two restarts (at ``rate``, 1/s) and carried through
    them over the run's ``total`` steps (:func:`carried_log_growth`); 0 if none."""

    def ok(every):
        return (rate * min(every, total) * dt <= limit
                and carried_log_growth(damping, omega_max, dt, every, total) <= limit)

    lo, hi = Leapfrog.MIN_RESTART_STEPS, max(int(total), Leapfrog.MIN_RESTART_STEPS)
    if not ok(lo):
        return 0
    if ok(hi):
        return hi
    while hi - lo > 1:  # ok(lo), not ok(hi)
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def restart_advice(damping, omega_max, dt, t_end, limit):
    """What a refusal of leap-frog for its parasitic root (``limit``: the log of the growth allowed) offers besides an
    implicit integrator: restarts every so many seconds (9/10 of :func:`longest_restart`, at least 100 steps), or,
    where 100 steps are already too many at ``dt``, a smaller ``dt`` (1, 2 or 5 times a power of ten) with restarts
    every 100 steps or more; "" if neither."""
    for step in [dt] + [m * 10.0**e for e in range(math.floor(math.log10(dt)), math.floor(math.log10(dt)) - 10, -1)
                        for m in (5, 2, 1) if m * 10.0**e < dt * (1 - 1e-9)]:
        total = round(t_end / step)
        every = longest_restart(damping, omega_max, step, total, parasitic_growth_rate(damping, omega_max, step), limit)
        if every:
            low = Leapfrog.MIN_RESTART_STEPS * step
            longest = max(low, int(0.9 * every) * step)
            digit = math.floor(math.log10(longest)) - 1
            restart = float(f"{math.floor(longest / 10.0**digit)}e{digit}")  # 2 digits, rounded down
            restart = restart if longest >= restart >= low else longest
            if step == dt:
                return (f", or restarts of the leap-frog every {restart:g} s or less (option restart; at least 100 dt "
                        f"= {low:g} s)")
            return (f", or a smaller step, dt = {step:g} s, with restarts every {restart:g} s or less (options dt and "
                    f"restart; at least 100 dt = {low:g} s; at dt = {dt:g} s they would have to come within 100 steps)")
    return ""


@dataclass(frozen=True)
class Leapfrog:
    """Leap-frog with a fixed step ``dt`` (s).

    Parameters
    ----------
    dt : float
        Time step (paper: 1e-6 s).
    chunk : int
        Steps run in C between two checks of the energy (and progress updates); the limits are checked every step.
    restart : float or None
        Seconds between two starts of the scheme from its last level by one midpoint step (None, the default: 1 s,
        or 100 steps where dt is above 10 ms; 0 or inf: never, the paper's scheme throughout; at least 100 steps: a
        shorter one given, 1.0 too, is refused), so its parasitic solution cannot grow
        beyond ``restart`` seconds' worth of the motion's Lyapunov rate (module docstring). Runs shorter than
        ``restart`` are unchanged.
    """

    # a normal double: a subnormal step (1e-320) kept a few digits, and was said as a t_end out of range
    dt: float = option(1e-6, Option(f"(0, inf) s, normal doubles (a subnormal step, below {TINY!r}, loses its "
                                    "digits)", lambda v: TINY <= real(v) < math.inf, convert=real))
    chunk: int = option(2000, integers(1))
    # None: the default (DEFAULT_RESTART, at least MIN_RESTART_STEPS steps), told from a restart given
    restart: float | None = option(None, Option("[0, inf] s; 0 or inf: never", lambda v: v is None or real(v) >= 0,
                                                convert=real, words=False))  # "none" is not never: refused

    name = "leapfrog"
    order = 2
    MIN_RESTART_STEPS = MIN_RESTART_STEPS
    #: the energy and finiteness are checked at the end of every chunk (and so at every saved time)
    checks_every_chunk = True

    def __post_init__(self):
        loop.check_declared(self)
        # the default (None) is taken as at least 100 steps (dt above 10 ms); a restart given, 1.0 too, is checked
        given = self.restart is not None
        if given and 0 < self.restart / self.dt < self.MIN_RESTART_STEPS * (1 - 1e-9):  # was held to 100, unsaid
            raise ParameterError("restart", self.restart, f"0 or inf (never), or [{self.MIN_RESTART_STEPS * self.dt:g}, "
                                 f"inf] s at dt = {self.dt:g} s", hint=f"at least {self.MIN_RESTART_STEPS} steps "
                                 "between two restarts: each leaves the compiled loop")

    def settings(self):
        """``dt`` and the ``restart`` taken: a whole number of steps (``restart`` itself where it is never)."""
        every = self.restart_steps()
        return {"dt": self.dt, "restart": float(f"{every * self.dt:.15g}") if every else self.restart_s()}

    def restart_s(self):
        """``restart`` as given, :data:`DEFAULT_RESTART` for the default (``None``)."""
        return DEFAULT_RESTART if self.restart is None else self.restart

    def restart_steps(self):
        """Steps between two restarts (at least :data:`MIN_RESTART_STEPS`); 0 for never: ``restart`` 0, or beyond
        the :data:`MAX_STEPS` steps a run can count (``restart = 1e308`` or inf: ``round`` of its steps overflowed)."""
        steps = self.restart_s() / self.dt
        if not 0 < steps <= self.MAX_STEPS:
            return 0
        return max(self.MIN_RESTART_STEPS, round(steps))

    #: steps leap-frog can count exactly (the step index k and the time k dt in double precision): 2^53
    MAX_STEPS = 2**53

    def step_counts(self, times):
        """Whole numbers of steps to each saved time; refuses times that are not multiples of ``dt``."""
        last = float(np.max(times)) if len(times) else 0.0
        if not last / self.dt <= self.MAX_STEPS:
            raise ParameterError("times", last, f"[0, {self.MAX_STEPS * self.dt:.4g}] s at dt = {self.dt:g} s",
                                 hint=f"leap-frog counts at most 2^53 = {self.MAX_STEPS:.3g} steps")
        steps, bad = grid_steps(times, self.dt)
        if bad.any():
            t = float(np.asarray(times, dtype=float)[bad][0])
            raise ParameterError("times", t, f"multiples of dt = {self.dt:g} s (leap-frog has a fixed step)",
                                 hint=off_grid_hint(t, self.dt))
        same = np.flatnonzero(np.diff(steps) <= 0)  # 1e-300 after 0: no step between two saved times
        if same.size:
            t = float(np.asarray(times)[same[0] + 1])
            raise ParameterError("times", t, f"positive multiples of dt = {self.dt:g} s, at least one step apart "
                                 "(leap-frog has a fixed step)", hint=f"{t:g} s is {steps[same[0] + 1]} steps from "
                                 f"the time before")
        return steps

    def integrate(self, system, compiled, y0, times, *, progress=None):
        """Run from ``times[0]`` (must be 0) through ``times``; returns a :class:`Trajectory`."""
        self.step_counts(times)  # refused before anything runs
        return loop.run(self, system, compiled, y0, times, progress=progress)

    def start(self, system, compiled, y0, times, monitor):
        return _LeapfrogStepper(self, system, compiled, y0, times, monitor)


class _LeapfrogStepper:
    """Leap-frog's state between chunks: the two levels ``ya`` (step ``k - 1``) and ``yb`` (step ``k``)."""

    def __init__(self, method, system, compiled, y0, times, monitor):
        self.method, self.monitor, self.dt = method, monitor, method.dt
        self.steps = dict(zip(np.asarray(times, dtype=float), method.step_counts(times)))
        self.f = compiled.evaluator()
        self.stepper = leapfrog_stepper(system, compiled)  # the vectorised stencil where it covers the scene
        self.every, self.restarts = method.restart_steps(), 0
        self.ya, self.yb = np.array(y0, dtype=float), None
        self.k, self.n_rhs = 0, 0
        self.work = system.ny * system.n if system.n_extra else None  # the index of the work accumulator
        self.kinks = drive_kinks(system) if system.n_extra else ()
        #: the steps k with a drive's kink strictly inside their quadrature interval (t_{k-1}, t_{k+1})
        self.kink_steps = {k for kink in self.kinks for k in (math.floor(kink / self.dt), math.ceil(kink / self.dt))
                           if k >= 1 and (k - 1) * self.dt < kink < (k + 1) * self.dt}
        self._midpoint()
        self.t = 0.0
        monitor.check(self.yb, self.dt)

    def _midpoint(self):
        """One explicit midpoint step from level ``k`` (``yb``, or ``ya`` at the start): the two levels become
        ``k`` and ``k + 1``; the parasitic solution starts again from this step's error."""
        dt, t = self.dt, self.k * self.dt
        y = self.ya if self.yb is None else self.yb
        self.ya = y.copy()
        y_half = y + 0.5 * dt * self.f(y, t)
        self.yb = y + dt * self.f(y_half, t + 0.5 * dt)
        self._correct_work(self.yb, y_half, t + 0.5 * dt, t, t + dt)
        self.k, self.n_rhs = self.k + 1, self.n_rhs + 2

    def _correct_work(self, y_new, y_mid, t_mid, t_lo, t_hi):
        """The work of a step over ``(t_lo, t_hi)`` whose quadrature took the power at ``(y_mid, t_mid)`` only,
        split at each drive's kink inside it: there the driven node's acceleration, and the driver's power with it,
        jumps by ``dP`` (the power at ``y_mid`` on the kink's new segment less that on its old one), and the part of
        the step beyond the kink from ``t_mid`` took the wrong side's power. Adds ``dP (t_hi - kink)`` (``t_mid``
        before the kink) or ``-dP (kink - t_lo)`` to ``y_new``'s work, so that a kink off the step grid leaves the
        quadrature second order (it was first order, ``dP dt``, whatever the step: docs/loads.md)."""
        for kink in self.kinks:
            if t_lo < kink < t_hi:
                jump = self.f(y_mid, kink)[self.work] - self.f(y_mid, np.nextafter(kink, -math.inf))[self.work]
                y_new[self.work] += jump * (t_hi - kink) if t_mid < kink else -jump * (kink - t_lo)
                self.n_rhs += 2

    def advance(self, target):
        if self.every and self.k % self.every == 0 and self.k < self.steps[target]:  # a restart is due
            self._midpoint()
            self.restarts += 1
            try:
                self.monitor.check(self.yb, self.k * self.dt)
            except ModelLimitError as exc:
                self.k = round(exc.time / self.dt)
                raise
            if self.k == self.steps[target]:
                self.t = target
                return
        dt, k = self.dt, self.k
        m = int(min(self.method.chunk, self.steps[target] - k))
        if self.every:
            m = min(m, self.every - k % self.every)  # up to the next restart
        if self.kink_steps:  # a step whose interval holds a drive's kink is taken alone, its work split there
            m = 1 if k in self.kink_steps else min(m, min((j for j in self.kink_steps if j > k), default=k + m) - k)
        chunk_start = (self.ya.copy(), self.yb.copy(), k)
        try:
            _, stopped = self._steps(m)  # stops at the first step outside the limits
            if stopped:
                self.monitor.check(self.yb, self.k * dt)  # raises, naming the limit and the place
                raise ModelLimitError(f"a limit of the model was reached at t = {self.k * dt:.9g} s", self.k * dt,
                                      "whole shell")
            try:
                self.monitor.check(self.yb, self.k * dt)  # the energy (instability) and finiteness, once a chunk
            except ModelLimitError:
                self.ya, self.yb, self.k = chunk_start
                self._locate(m)  # raises at the first bad step
        except ModelLimitError as exc:
            self.k = int(round(exc.time / dt))
            raise
        self.t = target if self.k == self.steps[target] else self.k * dt

    def _steps(self, m):
        """``m`` steps in C (one if a drive's kink lies in its interval: its work is then split there)."""
        k = self.k
        taken, stopped = self.stepper.leapfrog(self.ya, self.yb, m, self.dt, k * self.dt)
        self.k += taken
        self.n_rhs += taken
        if k in self.kink_steps and taken:  # ya is y_k, whose power the step took over (t_{k-1}, t_{k+1})
            self._correct_work(self.yb, self.ya, k * self.dt, (k - 1) * self.dt, (k + 1) * self.dt)
        return taken, stopped

    def _locate(self, m):
        """Redo a chunk one step at a time; raises at the first step that breaks a limit."""
        for _ in range(m):
            self._steps(1)
            self.monitor.check(self.yb, self.k * self.dt)

    def state(self, target):
        return self.yb.copy()

    def stats(self):
        return {"n_steps": int(self.k), "n_rhs": int(self.n_rhs), "n_restarts": int(self.restarts)}
