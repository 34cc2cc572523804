"""The paper's explicit, non-dissipative leap-frog scheme (section 6).

``y_{k+1} = y_{k-1} + 2 dt f(y_k)``, started by one explicit midpoint step
``y_1 = y_0 + dt f(y_0 + dt/2 f(y_0))`` so the start is second order too. For the
linear test equation ``y' = i w y`` it is stable for ``|w dt| < 1``; it neither damps
nor amplifies. The loop runs in generated C (the vectorised stencil of :mod:`mol_shell.stencil` for elastic, unloaded
shells without poles; :mod:`mol_shell.compiled`'s driver around the compiled RHS otherwise), which also checks
the model's limits (:attr:`ShellSystem.limits`) after every step and stops at the first step
outside them; Python only sees chunks of steps, where it checks the energy (numerical
instability) and shows progress.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ModelLimitError, ParameterError, is_number
from mol_shell.discretization.stencil import leapfrog_stepper
from mol_shell.integrators.base import Monitor, Trajectory


@dataclass(frozen=True)
class Leapfrog:
    """Leap-frog with a fixed step ``dt`` (s).

    Parameters
    ----------
    dt : float
        Time step (paper: 1e-6 s).
    chunk : int
        Steps run in C between two checks of the energy (and progress updates); the limits are checked every step.
    """

    dt: float = 1e-6
    chunk: int = 2000

    name = "leapfrog"
    order = 2

    def __post_init__(self):
        if not is_number(self.dt):
            raise ParameterError.not_a("dt", self.dt, "a number", "(0, inf) s")
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise ParameterError("dt", self.dt, "(0, inf) s")
        if not (isinstance(self.chunk, (int, np.integer)) and not isinstance(self.chunk, bool) and self.chunk >= 1):
            raise ParameterError("chunk", self.chunk, "integers >= 1")

    def settings(self):
        return {"dt": self.dt}

    #: steps leap-frog can count exactly (the step index k and the time k dt in double precision): 2^53
    MAX_STEPS = 2**53

    def step_counts(self, times):
        """Whole numbers of steps to each saved time; refuses times that are not multiples of ``dt``."""
        last = float(np.max(times)) if len(times) else 0.0
        if not last / self.dt <= self.MAX_STEPS:
            raise ParameterError("times", last, f"[0, {self.MAX_STEPS * self.dt:.4g}] s at dt = {self.dt:g} s",
                                 hint=f"leap-frog counts at most 2^53 = {self.MAX_STEPS:.3g} steps")
        steps = np.rint(np.asarray(times) / self.dt).astype(np.int64)
        bad = np.abs(steps * self.dt - times) > 1e-6 * self.dt + 1e-12 * np.abs(times)
        if bad.any():
            t = np.asarray(times)[bad][0]
            raise ParameterError("times", float(t), f"multiples of dt = {self.dt:g} s (leap-frog has a fixed step)")
        return steps

    def integrate(self, system, compiled, y0, times, *, progress=None):
        """Run from ``times[0]`` (must be 0) through ``times``; returns a :class:`Trajectory`."""
        steps = self.step_counts(times)
        if steps[0] != 0:
            raise ParameterError("times", float(times[0]), "first saved time must be 0")
        monitor = Monitor(system, y0)
        f = compiled.evaluator()
        stepper = leapfrog_stepper(system, compiled)  # the vectorised stencil where it covers the scene
        dt = self.dt
        ya = np.array(y0, dtype=float)
        yb = ya + dt * f(ya + 0.5 * dt * f(ya, 0.0), 0.5 * dt)
        saved = [ya.copy()]
        k, n_rhs = 1, 2
        status, message, failure = "complete", "completed", float("nan")
        start = time.perf_counter()
        try:
            monitor.check(yb, dt)
            for target in steps[1:]:
                while k < target:
                    m = int(min(self.chunk, target - k))
                    chunk_start = (ya.copy(), yb.copy(), k)
                    taken, stopped = stepper.leapfrog(ya, yb, m, dt, k * dt)  # stops at the first step outside the limits
                    k += taken
                    n_rhs += taken
                    if stopped:
                        monitor.check(yb, k * dt)  # raises, naming the limit and the place
                        raise ModelLimitError(f"a limit of the model was reached at t = {k * dt:.9g} s", k * dt,
                                              "whole shell")
                    try:
                        monitor.check(yb, k * dt)  # the energy (instability) and finiteness, once a chunk
                    except ModelLimitError:
                        ya, yb, k = chunk_start
                        self._locate(stepper, monitor, ya, yb, k, m, dt)  # raises at the first bad step
                    if progress is not None:
                        progress.update(m * dt)
                saved.append(yb.copy())
        except ModelLimitError as exc:
            status, message, failure = exc.status, str(exc), exc.time
            k = int(round(exc.time / dt))
        except KeyboardInterrupt:
            status, message, failure = "interrupted", f"interrupted by the user at t = {k * dt:.9g} s", k * dt
        wall = time.perf_counter() - start
        stats = {"n_steps": int(k), "n_rhs": int(n_rhs), "wall_time_s": wall}
        # the saved times as asked for (they are multiples of dt to round-off), so ds.sel(time=...) finds them
        return Trajectory(
            np.asarray(times, dtype=float)[: len(saved)], np.array(saved), status=status, message=message,
            stats=stats, failure_time=failure,
        )

    @staticmethod
    def _locate(stepper, monitor, ya, yb, k, m, dt):
        """Redo a chunk one step at a time; raises at the first step that breaks a limit."""
        for j in range(1, m + 1):
            stepper.leapfrog(ya, yb, 1, dt, (k + j - 1) * dt)
            monitor.check(yb, (k + j) * dt)
