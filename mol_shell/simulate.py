"""One entry point: run a scene with an integrator and get a labelled xarray Dataset."""

from __future__ import annotations

import dataclasses
import functools
import sys
import time
import warnings

import numpy as np

from .compiled import CompiledRHS
from .discretization import ShellSystem
from .equilibrium import equilibrium_radius, spectrum_bounds
from .errors import ParameterError
from .integrators import INTEGRATORS
from .output import build_dataset
from .scenes import get_scene


#: leap-frog is refused when damped modes could grow by more than exp(this) (1e6) over the run
LEAPFROG_MAX_LOG_GROWTH = float(np.log(1e6))


def _graph_key(scene):
    """The parameters the equations depend on (initial data left out), so graphs are shared."""
    initial = {"R": 1.0, **{k: 0.0 for k in ("gamma", "omega", "psi0") if k in scene.params()}}
    return dataclasses.replace(scene, **initial)


@functools.lru_cache(maxsize=16)
def _built(key, n):
    start = time.perf_counter()
    system = ShellSystem(key, n)
    compiled = CompiledRHS(system.rhs_mapped, system.limits)
    return system, compiled, time.perf_counter() - start


def build(scene, n=40):
    """The discretised system and its compiled RHS for ``scene`` on ``n`` nodes (cached in-process)."""
    system, compiled, _ = _built(_graph_key(scene), int(n) if isinstance(n, (int, np.integer)) else n)
    return system, compiled


def resolve(scene):
    """The scene with ``R`` computed when it was left to the code."""
    if scene.R is None:
        return dataclasses.replace(scene, R=equilibrium_radius(scene))
    return scene


def parse_times(times=None, t_end=None):
    """Saved times as an array starting at 0; ``t_end`` alone gives 11 evenly spaced times."""
    if times is None:
        if t_end is None:
            raise ParameterError("t_end", None, "(0, inf) s", hint="give t_end or times")
        if not (np.isfinite(t_end) and t_end > 0):
            raise ParameterError("t_end", t_end, "(0, inf) s")
        return np.linspace(0.0, float(t_end), 11)
    times = np.asarray(times, dtype=float).ravel()
    if times.size < 2 or not np.all(np.isfinite(times)) or times[0] != 0 or np.any(np.diff(times) <= 0):
        raise ParameterError("times", times.tolist() if times.size < 8 else "[...]", "increasing finite times starting at 0, at least two")
    if t_end is not None and not np.isclose(times[-1], t_end):
        raise ParameterError("t_end", t_end, f"the last saved time {times[-1]:g} s (or leave t_end out)")
    return times


def leapfrog_times(t_end, dt, count=10):
    """Default saved times of a fixed-step run: ``count`` intervals to ``t_end``, each a whole number of steps.

    ``t_end`` must be a multiple of ``dt``. The times are as even as the step grid allows and are
    rounded to 12 significant digits, so ``ds.sel(time=...)`` finds the values a user would type.
    """
    parse_times(None, t_end)  # validates t_end
    steps = round(t_end / dt)
    if steps < 1 or abs(steps * dt - t_end) > 1e-9 * t_end:
        raise ParameterError("t_end", t_end, f"positive multiples of dt = {dt:g} s (leap-frog has a fixed step)")
    marks = np.unique(np.rint(np.linspace(0, steps, min(count, steps) + 1)).astype(np.int64))
    return np.array([float(f"{k * dt:.12g}") for k in marks])


def simulate(scene, integrator="leapfrog", *, n=40, t_end=None, times=None, dt=1e-6, progress=None, **options):
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
    dt : float
        Leap-frog step (s); refused beyond the stability bound ``1 / max |eig J(y0)|``.
        Ignored by adaptive integrators.
    progress : bool, optional
        Progress bar over simulated time; default: only when stderr is a terminal.
    **options
        Passed to the integrator's dataclass (e.g. ``rtol``, ``atol``, ``max_step``).

    Returns
    -------
    xarray.Dataset
        Dims ``time`` and ``s``; fields, rates, energies, angular momentum and
        ``delta_min``; every scene parameter (``R`` as computed) and the run's
        statistics in attrs. If the run hit a model limit or was interrupted, the
        Dataset holds what was computed and ``attrs["complete"] == 0``.
    """
    if isinstance(scene, str):
        scene = get_scene(scene)
    if hasattr(scene, "run"):  # a scene with its own formulation (the unshearable DAE)
        return scene.run(integrator, n=n, times=times, t_end=t_end, progress=progress, **({"dt": dt} if integrator == "leapfrog" else {}), **options)
    if integrator not in INTEGRATORS:
        raise ParameterError("integrator", integrator, "{" + ", ".join(INTEGRATORS) + "}")
    scene = resolve(scene)
    if integrator == "leapfrog":
        options["dt"] = dt
    cls = INTEGRATORS[integrator]
    allowed = {f.name for f in dataclasses.fields(cls)}
    for name in options:
        if name not in allowed:
            raise ParameterError("option", name, "{" + ", ".join(sorted(allowed)) + "}", hint=f"for integrator {integrator}")
    method = cls(**options)
    if times is None and integrator == "leapfrog":
        times = leapfrog_times(t_end, dt)
    times = parse_times(times, t_end)
    system, compiled = build(scene, n)
    _, _, build_time = _built(_graph_key(scene), int(n))
    y0 = system.initial_state(scene)
    omega_max, damping = spectrum_bounds(system.jac, y0, system.viscous)
    if integrator == "leapfrog":
        if dt * omega_max >= 1.0:
            raise ParameterError("dt", dt, f"(0, {1.0 / omega_max:.4g}) s", hint="leap-frog stability bound 1/max|eig J(y0)|")
        if damping * times[-1] > LEAPFROG_MAX_LOG_GROWTH:
            raise ParameterError(
                "integrator", integrator, "{cvode-bdf, ida} for this case",
                hint=f"leap-frog's parasitic root grows damped modes like exp({damping:.4g}/s * t); "
                f"up to t = {times[-1]:g} s that is exp({damping * times[-1]:.3g}); viscosity makes the system stiff",
            )
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
    velocities, totals = observe(system, traj.y)
    attrs = {"integrator": integrator, **method.settings(), **system.graph_stats()}
    attrs.update({
        "build_time_s": build_time,
        "omega_max_rad_s": omega_max,
        "max_damping_rate_s-1": damping,
        "leapfrog_dt_bound_s": 1.0 / omega_max,
    })
    return build_dataset(system, scene, traj, velocities, totals, attrs)


def observe(system, states):
    """Rates and per-time totals (energies, angular momentum, min delta) of saved states."""
    out = system.observables.map(len(states))(np.asarray(states).T)
    v, kinetic, stored, angular, delta, dissipation = (np.array(x) for x in out)
    velocities = np.stack([v[:, i * system.n : (i + 1) * system.n] for i in range(len(states))])
    totals = {
        "kinetic": kinetic.ravel(),
        "stored": stored.ravel(),
        "angular_momentum": angular.ravel(),
        "delta_min": delta.min(axis=0),
        "dissipation": dissipation.ravel(),
    }
    return velocities, totals


def _progress_bar(t_end):
    from tqdm import tqdm

    return tqdm(total=float(t_end), unit="s", unit_scale=False, desc="simulating", bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]")
