"""Scenes made ready to run: the discretised system and its compiled RHS (cached per process), the scene with
``R`` computed, saved times checked, the starting state (static equilibrium under loads when asked), and the rates
and totals observed at saved states."""

from __future__ import annotations

import dataclasses
import functools
import math
import time

import numpy as np

from mol_shell._core.constants import DEFAULT_INTERVALS, MIN_STEP, stated_up
from mol_shell._core.errors import ParameterError, is_number, kind_of, scalar, show
from mol_shell.discretization.compiled import CompiledRHS
from mol_shell.discretization.scales import unit_strain_energy
from mol_shell.discretization.system import ShellSystem
from mol_shell.integrators.loop import real
from mol_shell.model.laws import ON_REDEFINED
from mol_shell.runs import resources
from mol_shell.runs.checks import check_system, resolve
from mol_shell.scenes import SCENES, CylinderScene, ShellScene, get_scene

#: from this many nodes the compiled RHS runs its cell and node kernels on threads (OpenMP maps); below,
#: a parallel region costs more than it saves (measured: see docs/performance.md)
PARALLEL_MIN_NODES = 1000

__all__ = ["PARALLEL_MIN_NODES", "as_scene", "build", "observe", "parse_times", "resolve"]


def _graph_key(scene):
    """``(scene, meridian)``: the parameters the equations depend on (initial data at their defaults), so graphs
    are shared, and the meridian's description: a points file edited since (same name) is another shell (its
    description carries the points' digest), which a key of the parameters alone handed the old graphs."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    initial = {k: fields[k].default for k in getattr(scene, "initial", ()) if k in fields}
    if isinstance(scene, CylinderScene):
        initial["R"] = scene.a  # the natural radius: a finite initial state for the checks of the graph
    meridian = scene.meridian().describe() if callable(getattr(scene, "meridian", None)) else ""
    return dataclasses.replace(scene, **initial), meridian


@functools.lru_cache(maxsize=16)
def _built(key, n):
    start = time.perf_counter()
    key, _ = key
    system = ShellSystem(key, n)
    check_system(key, system)  # values whose numbers are not finite are refused before anything is compiled
    rhs = system.rhs_parallel if n >= PARALLEL_MIN_NODES else system.rhs_mapped
    compiled = CompiledRHS(rhs, system.limits_mapped)
    return system, compiled, time.perf_counter() - start


ON_REDEFINED.append(_built.cache_clear)  # a mol_shell.Material's name given to another law: build afresh


def build(scene, n=40):
    """The discretised system and its compiled RHS for ``scene`` (an object or a registered name) on ``n`` nodes
    (cached in-process); ``n`` is refused by name when the graphs would not fit in memory."""
    scene = as_scene(scene)
    resources.check_analysis(n, 2, f"building the graphs of n = {n:,} nodes" if isinstance(n, (int, np.integer))
                             else "building the graphs", "states", integrator="leapfrog",
                             fields=len(getattr(scene, "fields", range(5))), announce=False)
    system, compiled, _ = _built(_graph_key(scene), int(n))
    return system, compiled


def as_scene(scene):
    """A scene object from an object or a registered name; anything else is refused by name."""
    if isinstance(scene, str):
        return get_scene(scene)
    if not isinstance(scene, ShellScene):
        raise ParameterError.not_a("scene", scene, "a scene",
                                   "a scene object such as mol_shell.TwistedCylinder(), or one of {"
                                   + ", ".join(sorted(SCENES)) + "}")
    return scene


#: the shortest interval between saved times (s): :data:`~mol_shell._core.constants.MIN_STEP`, sqrt of the smallest
#: normal double, 1.5e-154 s. An adaptive integrator's step-size selection squares the step (h^2 y''); below this it
#: underflows and SUNDIALS refuses to start (CV_ILL_INPUT, measured from 1e-161 s on with IDA)
MIN_INTERVAL = MIN_STEP
#: saved times closer than this many machine epsilons of the later one are the same time to any tolerance
MIN_INTERVAL_ULPS = 1e3
#: the shortest interval as the messages state it, with 5 digits: rounded up, and applied as stated (as is the least
#: t_end, with 2: 1.49e-153 s was accepted outside the range stated for it, [1.5e-153, inf) s); the times a t_end
#: at its least gives, rounded to 12 digits, are 1.5e-154 s apart within their rounding, above it
_SHORTEST = stated_up(MIN_INTERVAL, 5)
_SPACING = (f"at least {_SHORTEST:.5g} s (sqrt of the smallest double: an adaptive step's square underflows "
            f"below it) and {MIN_INTERVAL_ULPS:g} machine epsilons of the later time apart")


def _not_numbers(times):
    """``[value]``, the first value in ``times`` that is not a number as :func:`mol_shell._core.errors.is_number` has
    it (a bool, a string, ``None``), or ``[]``: an array of integers or floats is numbers throughout."""
    if isinstance(times, np.ndarray) and times.dtype.kind in "iuf":
        return []
    values = np.asarray(times, dtype=object).ravel().tolist()  # a list's True stays a bool here
    return [value for value in values if not is_number(scalar(value))][:1]


def parse_times(times=None, t_end=None, intervals=DEFAULT_INTERVALS):
    """Saved times as an array starting at 0; ``t_end`` alone gives ``intervals + 1`` evenly spaced times (to 12
    significant digits, so that ``ds.sel(time=...)`` finds the numbers a user would type).

    Consecutive times are :data:`MIN_INTERVAL` s and :data:`MIN_INTERVAL_ULPS` epsilons of the later one apart, at
    least: closer ones cannot be told apart by an integrator.
    """
    low = stated_up(intervals * MIN_INTERVAL, 2)  # t_end alone: its intervals
    if t_end is not None:
        if not is_number(t_end):
            raise ParameterError.not_a("t_end", t_end, "a number", "(0, inf) s")
        if not (math.isfinite(real(t_end)) and t_end > 0):  # real: 10**400 as inf (np.isfinite raised on it)
            raise ParameterError("t_end", t_end, "(0, inf) s")
    if times is None:
        if t_end is None:
            raise ParameterError.missing("t_end", "give t_end in (0, inf) s, or times")
        if t_end < low:
            raise ParameterError("t_end", t_end, f"[{low:.2g}, inf) s",
                                 hint=f"its {intervals} saved intervals {_SPACING}")
        # as typed: ds.sel finds them
        even = [float(f"{t:.12g}") for t in np.linspace(0.0, float(t_end), intervals + 1)[:-1]]
        return np.array([*even, float(t_end)])
    allowed = "increasing finite times starting at 0, at least two, in one list"
    odd = [] if isinstance(times, str) else _not_numbers(times)  # a number as t_end's is: a bool or a string is none
    if odd:  # (True ran to 1 s, '0' to 0 s)
        raise ParameterError.not_a("times", times, "a list of numbers", allowed,
                                   hint=f"{show(odd[0])} ({kind_of(odd[0])}) is not a number")
    try:
        if isinstance(times, str):
            raise TypeError
        times = np.asarray(times, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError.not_a("times", times, "a list of numbers", allowed) from None
    if times.ndim != 1:
        raise ParameterError.not_a("times", times.tolist(), "a flat list of numbers", allowed,
                                   hint=f"it has {times.ndim} dimensions, shape {times.shape}")
    if times.size < 2 or not np.all(np.isfinite(times)) or times[0] != 0 or np.any(np.diff(times) <= 0):
        raise ParameterError("times", times, allowed)
    gaps = np.diff(times)
    close = gaps < np.maximum(_SHORTEST, MIN_INTERVAL_ULPS * np.finfo(float).eps * times[1:])
    if np.any(close):
        i = int(np.argmax(close))
        raise ParameterError("times", times, f"{allowed}, consecutive ones {_SPACING}",
                             hint=f"{times[i]:.17g} s and {times[i + 1]:.17g} s are {gaps[i]:.3g} s apart")
    if t_end is not None and not np.isclose(times[-1], t_end):
        raise ParameterError("t_end", t_end, f"the last saved time {times[-1]:g} s (or leave t_end out)")
    return times


def observe(system, states, times=None):
    """Rates and per-time totals (energies, angular momentum, min delta, reactions) of saved states."""
    times = np.zeros(len(states)) if times is None else np.asarray(times, dtype=float)
    out = system.observables.map(len(states))(np.asarray(states).T, times[None, :])
    v, kinetic, stored, angular, delta, dissipation, work, dissipated, reactions = (np.array(x) for x in out)
    velocities = np.stack([v[:, i * system.n : (i + 1) * system.n] for i in range(len(states))])
    totals = {
        "kinetic": kinetic.ravel(),
        "stored": stored.ravel(),
        "angular_momentum": angular.ravel(),
        "delta_min": delta.min(axis=0),
        "dissipation": dissipation.ravel(),
        "work": work.ravel(),
        "dissipated": dissipated.ravel(),
        "reactions": reactions.T.reshape(len(states), -1),
    }
    if system.n_extra:
        totals["balance_error"] = energy_balance_error(system, totals)
    return velocities, totals


def energy_balance_error(system, totals):
    """``max |E(t) - E(0) - work + dissipated|`` relative to the energy exchanged.

    The exchange is the largest of the work, the dissipated energy and the change of energy, and at least
    ``1e-12`` of the energy of a unit strain of the whole wall (so a shell at rest, exchanging round-off,
    does not report a balance error of order 1).
    """
    energy = totals["kinetic"] + totals["stored"]
    defect = energy - energy[0] - totals["work"] + totals["dissipated"]
    unit = unit_strain_energy(system)
    exchange = max(float(np.max(np.abs(totals["work"]))), float(np.max(np.abs(totals["dissipated"]))),
                   float(np.max(np.abs(energy - energy[0]))), 1e-12 * unit)
    return float(np.max(np.abs(defect)) / exchange)
