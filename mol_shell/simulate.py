"""One entry point: run a scene with an integrator and get a labelled xarray Dataset."""

from __future__ import annotations

import cmath
import dataclasses
import functools
import math
import sys
import time
import warnings

import numpy as np

from . import resources
from .compiled import CompiledRHS
from .degenerate import check_system, checked_spectrum, equilibrium_radius, initial_state
from .discretization import ShellSystem
from .errors import ParameterError, is_number
from .integrators import INTEGRATORS
from .output import build_dataset
from .scenes import SCENES, CylinderScene, ShellScene, check_radius, get_scene


#: leap-frog is refused when damped modes could grow by more than exp(this) (1e6) over the run
LEAPFROG_MAX_LOG_GROWTH = float(np.log(1e6))
#: leap-frog's step when none is given (the paper's), s
DEFAULT_DT = 1e-6
#: relative tolerances accepted: below 1e-14 is under round-off, 1 and above controls nothing
RTOL_RANGE = (1e-14, 1.0)


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


def _graph_key(scene):
    """The parameters the equations depend on (initial data at their defaults), so graphs are shared."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    initial = {k: fields[k].default for k in getattr(scene, "initial", ()) if k in fields}
    if isinstance(scene, CylinderScene):
        initial["R"] = scene.a  # the natural radius: a finite initial state for the checks of the graph
    return dataclasses.replace(scene, **initial)


#: from this many nodes the compiled RHS runs its cell and node kernels on threads (OpenMP maps); below,
#: a parallel region costs more than it saves (measured: see README, Performance)
PARALLEL_MIN_NODES = 1000


@functools.lru_cache(maxsize=16)
def _built(key, n):
    start = time.perf_counter()
    system = ShellSystem(key, n)
    check_system(key, system)  # values whose numbers are not finite are refused before anything is compiled
    rhs = system.rhs_parallel if n >= PARALLEL_MIN_NODES else system.rhs_mapped
    compiled = CompiledRHS(rhs, system.limits)
    return system, compiled, time.perf_counter() - start


def build(scene, n=40):
    """The discretised system and its compiled RHS for ``scene`` on ``n`` nodes (cached in-process)."""
    system, compiled, _ = _built(_graph_key(scene), int(n) if isinstance(n, (int, np.integer)) else n)
    return system, compiled


def resolve(scene):
    """The scene with ``R`` computed when it was left to the code."""
    if isinstance(scene, CylinderScene) and scene.R is None:
        R = equilibrium_radius(scene)
        check_radius(R, scene.h, scene.zeta1, hint="the computed equilibrium radius; set R", a=scene.a)
        return dataclasses.replace(scene, R=R)
    return scene


def as_scene(scene):
    """A scene object from an object or a registered name; anything else is refused by name."""
    if isinstance(scene, str):
        return get_scene(scene)
    if not isinstance(scene, ShellScene):
        raise ParameterError.not_a("scene", scene, "a scene",
                                   "a scene object such as mol_shell.TwistedCylinder(), or one of {"
                                   + ", ".join(sorted(SCENES)) + "}")
    return scene


def integrator_options(scene, integrator):
    """Names of the options ``integrator`` takes for ``scene`` (keyword arguments of :func:`simulate`)."""
    if hasattr(scene, "run"):  # the unshearable scene: its own formulation
        return {"dt"} if integrator == "leapfrog" else {"rtol", "atol", "max_step"}
    if integrator not in INTEGRATORS:
        raise ParameterError("integrator", integrator, "{" + ", ".join(INTEGRATORS) + "}")
    return {f.name for f in dataclasses.fields(INTEGRATORS[integrator])}


def check_options(scene, integrator, options, offered=None):
    """Refuse options ``integrator`` does not take, and an ``rtol`` outside :data:`RTOL_RANGE`.

    ``offered`` (a set of names) limits the options listed in the message to those a caller
    offers (the command line offers ``dt, rtol, atol, max_step``).
    """
    allowed = integrator_options(scene, integrator)
    for name in options:
        if name not in allowed:
            raise ParameterError.not_an_option(name, integrator, allowed & offered if offered else allowed)
    if hasattr(scene, "run") and "atol" in options:  # the unshearable DAE takes one number
        atol = options["atol"]
        if not is_number(atol):
            raise ParameterError.not_a("atol", atol, "a number", f"(0, inf), one value for the {scene.name} scene")
        if not (np.isfinite(atol) and atol > 0):
            raise ParameterError("atol", atol, "(0, inf)")
    if "rtol" in options:
        lo, hi = RTOL_RANGE
        value = options["rtol"]
        if not is_number(value):
            raise ParameterError.not_a("rtol", value, "a number", f"[{lo:g}, {hi:g})")
        if not (lo <= value < hi):
            raise ParameterError("rtol", value, f"[{lo:g}, {hi:g})")


def parse_times(times=None, t_end=None):
    """Saved times as an array starting at 0; ``t_end`` alone gives 11 evenly spaced times."""
    if t_end is not None:
        if not is_number(t_end):
            raise ParameterError.not_a("t_end", t_end, "a number", "(0, inf) s")
        if not (np.isfinite(t_end) and t_end > 0):
            raise ParameterError("t_end", t_end, "(0, inf) s")
    if times is None:
        if t_end is None:
            raise ParameterError.missing("t_end", "give t_end in (0, inf) s, or times")
        return np.linspace(0.0, float(t_end), 11)
    allowed = "increasing finite times starting at 0, at least two"
    try:
        if isinstance(times, str):
            raise TypeError
        times = np.asarray(times, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ParameterError.not_a("times", times, "a list of numbers", allowed) from None
    if times.size < 2 or not np.all(np.isfinite(times)) or times[0] != 0 or np.any(np.diff(times) <= 0):
        raise ParameterError("times", times, allowed)
    if t_end is not None and not np.isclose(times[-1], t_end):
        raise ParameterError("t_end", t_end, f"the last saved time {times[-1]:g} s (or leave t_end out)")
    return times


def leapfrog_times(t_end, dt, count=10):
    """Default saved times of a fixed-step run: ``count`` intervals to ``t_end``, each a whole number of steps.

    ``t_end`` must be a multiple of ``dt``. The times are as even as the step grid allows and are
    rounded to 12 significant digits, so ``ds.sel(time=...)`` finds the values a user would type.
    """
    parse_times(None, t_end)  # validates t_end
    if not t_end / dt <= INTEGRATORS["leapfrog"].MAX_STEPS:  # beyond it steps cannot be counted in double precision
        raise ParameterError("t_end", t_end, f"(0, {INTEGRATORS['leapfrog'].MAX_STEPS * dt:.4g}] s at dt = {dt:g} s")
    steps = round(t_end / dt)
    if steps < 1 or abs(steps * dt - t_end) > 1e-9 * t_end:
        raise ParameterError("t_end", t_end, f"positive multiples of dt = {dt:g} s (leap-frog has a fixed step)")
    marks = np.unique(np.rint(np.linspace(0, steps, min(count, steps) + 1)).astype(np.int64))
    return np.array([float(f"{k * dt:.12g}") for k in marks])


def simulate(scene, integrator="leapfrog", *, n=40, t_end=None, times=None, dt=None, progress=None, stresses=None,
             threads=None, **options):
    """Run ``scene`` and return its motion as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scene : TwistedCylinder or str
        A scene object, or the name of a registered scene with default parameters.
    integrator : str
        One of :data:`mol_shell.integrators.INTEGRATORS`.
    n : int
        Nodes in ``s`` (paper: 40).
    t_end : float, optional
        Final time (s); with ``times`` omitted, 11 evenly spaced saved times.
    times : array_like, optional
        Saved times (s), starting at 0.
    dt : float, optional
        Leap-frog step (s), default :data:`DEFAULT_DT` (1e-6, the paper's); refused beyond the
        stability bound ``1 / max |eig J(y0)|``. Adaptive integrators choose their own steps and
        refuse ``dt`` (bound them with ``max_step``).
    progress : bool, optional
        Progress bar over simulated time; default: only when stderr is a terminal.
    stresses : bool, optional
        Resultants and face stresses after the run (:func:`mol_shell.stresses.add_stresses`): ``None``
        (default) up to :data:`mol_shell.stresses.MAX_SAMPLES` cell samples x saved times, ``True``
        always, ``False`` never.
    threads : int, optional
        Threads for the compiled right-hand side's cell and node kernels (every integrator uses it);
        default ``$MOL_SHELL_THREADS`` or all cores. Grids below :data:`PARALLEL_MIN_NODES` nodes run
        serially whatever it says. Results do not depend on it (each cell is one thread's work).
    **options
        Passed to the integrator's dataclass (e.g. ``rtol`` in [1e-14, 1), ``atol``, ``max_step``);
        an option the integrator does not take is refused by name.

    Returns
    -------
    xarray.Dataset
        Dims ``time`` and ``s``; fields, rates, energies, angular momentum and
        ``delta_min``; every scene parameter (``R`` as computed) and the run's
        statistics in attrs. If the run hit a model limit or was interrupted, the
        Dataset holds what was computed and ``attrs["complete"] == 0``.
    """
    scene = as_scene(scene)
    if dt is not None:
        options["dt"] = dt
    check_options(scene, integrator, options)
    if integrator == "leapfrog":
        options.setdefault("dt", DEFAULT_DT)
    if stresses is not None and not isinstance(stresses, (bool, np.bool_)):
        raise ParameterError.not_a("stresses", stresses, "a bool", "True, False or None (cheap runs only)")
    if hasattr(scene, "run"):  # a scene with its own formulation (the unshearable DAE)
        return scene.run(integrator, n=n, times=times, t_end=t_end, progress=progress, **options)
    method = INTEGRATORS[integrator](**options)
    if times is None and integrator == "leapfrog":
        times = leapfrog_times(t_end, method.dt)
    times = parse_times(times, t_end)
    est = resources.check_before_build(n, times, integrator, fields=len(scene.fields), dt=getattr(method, "dt", None))
    scene = resolve(scene)
    system, compiled = build(scene, n)
    _, _, build_time = _built(_graph_key(scene), int(n))
    compiled.set_threads(threads)
    y0, start_info = starting_state(scene, system, n)  # refused by name if it cannot be formed in double precision
    omega_max, damping = checked_spectrum(scene, system, y0)
    if integrator == "leapfrog":
        dt = method.dt
        if dt * omega_max >= 1.0:
            raise ParameterError("dt", dt, f"(0, {1.0 / omega_max:.4g}) s", hint="leap-frog stability bound 1/max|eig J(y0)|")
        growth = parasitic_growth_rate(damping, omega_max, dt)
        if growth * times[-1] > LEAPFROG_MAX_LOG_GROWTH:
            raise ParameterError(
                "integrator", integrator, "{cvode-bdf, ida} for this case",
                hint=f"leap-frog's parasitic root grows damped modes like exp({growth:.4g}/s * t) at dt = {dt:g} s; "
                f"up to t = {times[-1]:g} s that is exp({growth * times[-1]:.3g}); viscosity makes the system stiff",
            )
    resources.check_before_run(n, times, integrator, fields=len(scene.fields), dt=getattr(method, "dt", None),
                               omega_max=omega_max, compiled=compiled, y0=y0, warned=est.seconds > resources.LONG_RUN_S)
    if progress is None:
        progress = sys.stderr.isatty()
    bar = _progress_bar(times[-1]) if progress else None
    try:
        traj = method.integrate(system, compiled, y0, times, progress=bar)
    finally:
        if bar is not None:
            bar.close()
    if traj.status != "complete":
        warnings.warn(f"run incomplete: {traj.message}; keeping {len(traj.t)} saved times", RuntimeWarning, stacklevel=2)
    velocities, totals = observe(system, traj.y, traj.t)
    attrs = {"integrator": integrator, **method.settings(), **system.graph_stats()}
    attrs.update({
        "build_time_s": build_time,
        "omega_max_rad_s": omega_max,
        "max_damping_rate": damping,
        "units_max_damping_rate": "s-1",
        "leapfrog_dt_bound_s": 1.0 / omega_max,
        "initial_state": start_info,
    })
    ds = build_dataset(system, scene, traj, velocities, totals, attrs)
    if stresses is not False:
        from .stresses import MAX_SAMPLES, add_stresses

        ds = add_stresses(ds, limit=None if stresses else MAX_SAMPLES)
    return ds


def starting_state(scene, system, n):
    """``(y0, how)``: the scene's initial state, or the static equilibrium under its loads when it asks for one."""
    y0 = initial_state(scene, system)
    if scene.at_equilibrium() and getattr(scene, "loaded", False):
        from .analysis.statics import static_equilibrium

        return static_equilibrium(scene, n, y0)
    return y0, "as given by the scene's parameters"


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
    return velocities, totals


def _progress_bar(t_end):
    from tqdm import tqdm

    return tqdm(total=float(t_end), unit="s", unit_scale=False, desc="simulating", bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]")
