"""One entry point: run a scene with an integrator and get a labelled xarray Dataset."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.constants import DEFAULT_INTERVALS, RTOL_RANGE, stated_down, stated_up
from mol_shell._core.errors import MolShellWarning, ParameterError, SceneWarning, is_number, scalar
from mol_shell._core.progress import progress_mode, time_meter
from mol_shell.discretization.kernel_cache import CacheFull
from mol_shell.discretization.threads import checked_threads
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.leapfrog import (
    grid_steps,
    off_grid_hint,
)
from mol_shell.integrators.loop import declared, real
from mol_shell.integrators.tolerances import ATOL_RANGE, MAX_STEP_MARGIN, atol_ok, least_max_steps, smallest_max_step
from mol_shell.model.kinematics import FIELDS
from mol_shell.model.loads import check_leapfrog_history
from mol_shell.results.dataset import build_dataset
from mol_shell.results.stresses import MAX_SAMPLES, add_stresses
from mol_shell.runs import asked_times, resources, step_limits
from mol_shell.runs.building import (  # noqa: F401
    PARALLEL_MIN_NODES,
    _built,
    _graph_key,
    as_scene,
    build,
    observe,
    parse_times,
    resolve,
)
from mol_shell.runs.checks import check_start_inside_limits, checked_spectrum, initial_state
from mol_shell.runs.ellipticity import check_ellipticity
from mol_shell.runs.leapfrog_guard import check_parasitic, check_step
from mol_shell.runs.post_run import cut_short, kept
from mol_shell.runs.statics import static_equilibrium, unstable_directions
from mol_shell.runs.unshearable import DAE_OPTIONS, FREE_OPTIONS, simulate_unshearable
from mol_shell.scenes import UNSHEARABLE_INTEGRATORS, CylinderScene, Unshearable
from mol_shell.scenes.base import DRIVES, LOADS
from mol_shell.scenes.scene_warnings import say_scene_warnings

#: leap-frog's step when none is given (the paper's), s
DEFAULT_DT = 1e-6


def integrator_options(scene, integrator):
    """Names of the options ``integrator`` takes for ``scene`` (keyword arguments of :func:`simulate`)."""
    if isinstance(scene, Unshearable):  # its own formulation
        if integrator not in UNSHEARABLE_INTEGRATORS:
            raise ParameterError("integrator", integrator, "{" + ", ".join(UNSHEARABLE_INTEGRATORS) + "}",
                                 hint="ida solves the unshearable DAE, leapfrog the free shell from the same state")
        return set(FREE_OPTIONS if integrator == "leapfrog" else DAE_OPTIONS)
    if integrator not in INTEGRATORS:
        raise ParameterError("integrator", integrator, "{" + ", ".join(INTEGRATORS) + "}")
    return {f.name for f in dataclasses.fields(INTEGRATORS[integrator])}


def check_loads(scene, integrator):
    """Refuse an integrator that cannot run ``scene``'s loads or driven edges (its class says why in
    ``refuses_loads``), listing the registered integrators that can."""
    why = getattr(INTEGRATORS.get(integrator), "refuses_loads", "")
    if why and getattr(scene, "loaded", False):
        can = [name for name, cls in INTEGRATORS.items() if not getattr(cls, "refuses_loads", "")]
        raise ParameterError("integrator", integrator, "{" + ", ".join(can) + "} for a scene with loads or driven edges",
                             hint=why)


def check_options(scene, integrator, options, offered=None):
    """Refuse options ``integrator`` does not take, an integrator that cannot take ``scene``'s loads
    (:func:`check_loads`), and an ``rtol`` outside :data:`RTOL_RANGE`.

    ``offered`` (a set of names) limits the options listed in the message to those a caller
    offers (the command line offers ``dt, rtol, atol, max_step``).
    """
    allowed = integrator_options(scene, integrator)
    check_loads(scene, integrator)
    for name in options:
        if name not in allowed:
            raise ParameterError.not_an_option(name, integrator, allowed & offered if offered else allowed,
                                               more=allowed if offered else ())
    if isinstance(scene, Unshearable) and "atol" in options:  # the unshearable DAE takes one number
        atol = options["atol"]
        if not is_number(atol):
            raise ParameterError.not_a("atol", atol, "a number", f"{ATOL_RANGE}, one value for the {scene.name} scene")
        if not atol_ok(atol):
            raise ParameterError("atol", atol, ATOL_RANGE)
    if "rtol" in options:
        lo, hi = RTOL_RANGE
        value = options["rtol"]
        # an integrator's own range where it declares a narrower one (the scipy-* peers: SciPy's floor)
        own = declared(INTEGRATORS[integrator]).get("rtol") if integrator in INTEGRATORS else None
        allowed = own.allowed if own is not None else f"[{lo:g}, {hi:g})"
        if not is_number(value):
            raise ParameterError.not_a("rtol", value, "a number", allowed)
        if not (lo <= value < hi) or (own is not None and not own.check(value)):
            raise ParameterError("rtol", value, allowed)


def steps_to(t_end, dt):
    """The whole number of steps ``dt`` that make ``t_end``, or 0 if there is none: on the step grid as saved times
    are (:data:`mol_shell.integrators.leapfrog.GRID_TOLERANCE`, at the double-precision value of ``t_end``)."""
    if not (is_number(t_end) and is_number(dt) and t_end > 0 and dt > 0):
        return 0
    t_end, dt = real(t_end), real(dt)
    if not t_end / dt <= INTEGRATORS["leapfrog"].MAX_STEPS:  # NaN, inf, or more steps than can be counted
        return 0
    steps, off = grid_steps([t_end], dt)
    return int(steps[0]) if steps[0] >= 1 and not off[0] else 0


def leapfrog_times(t_end, dt, count=DEFAULT_INTERVALS, dt_given=False):
    """Default saved times of a fixed-step run: ``count`` intervals to ``t_end``, each a whole number of steps.

    ``t_end`` must be a multiple of ``dt``. The times are as even as the step grid allows and are
    rounded to 12 significant digits, so ``ds.sel(time=...)`` finds the values a user would type. Too many steps
    name ``dt`` where it was given (``dt_given``: ``--dt 1e-300`` was said as ``t_end = 0.0001`` out of range).
    """
    parse_times(None, t_end)  # validates t_end
    most = INTEGRATORS["leapfrog"].MAX_STEPS
    low, high = stated_up(t_end / most), stated_down(most * dt)  # the bounds as stated to 4 digits, and applied
    if not t_end / dt <= most or (dt < low if dt_given else t_end > high):  # beyond: steps cannot be counted
        if dt_given:
            raise ParameterError("dt", dt, f"[{low:.4g}, inf) s at t_end = {t_end:g} s",
                                 hint=f"leap-frog counts at most 2^53 = {most:.3g} steps")
        raise ParameterError("t_end", t_end, f"(0, {high:.4g}] s at dt = {dt:g} s")
    steps = steps_to(t_end, dt)
    if not steps:
        raise ParameterError("t_end", t_end, f"positive multiples of dt = {dt:g} s (leap-frog has a fixed step)",
                             hint=off_grid_hint(real(t_end), dt) if t_end / dt >= 0.5 else "")
    marks = np.unique(np.rint(np.linspace(0, steps, min(count, steps) + 1)).astype(np.int64))
    return np.array([float(f"{k * dt:.12g}") for k in marks])


def simulate(scene, integrator="leapfrog", *, n=40, t_end=None, times=None, dt=None, progress=None, stresses=None,
             threads=None, initial=None, **options):
    """Run ``scene`` and return its motion as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scene : ShellScene or str
        A scene object (any of :data:`mol_shell.SCENES`' classes, e.g. ``mol_shell.Sphere()``), or the name
        of a registered scene with default parameters.
    integrator : str
        One of :data:`mol_shell.integrators.INTEGRATORS`.
    n : int
        Nodes in ``s`` (paper: 40).
    t_end : float, optional
        Final time (s); with ``times`` omitted, 11 evenly spaced saved times, for leap-frog snapped to its step
        ``dt`` (as even as that grid allows: ``t_end = 13 dt`` saves steps 0, 1, 3, 4, 5, 6, 8, 9, 10, 12, 13; fewer
        times where ``t_end`` is fewer than 10 steps).
    times : array_like, optional
        Saved times (s), starting at 0: numbers (a bool or a string is refused, as in ``t_end``). For leap-frog,
        each of them and ``t_end`` a whole number of steps ``dt``, to ``1e-6 dt + 1e-12 t``
        (:data:`mol_shell.integrators.leapfrog.GRID_TOLERANCE`) at its double-precision value (a float32 ``1e-4``
        is 2.5e-6 steps off, and refused).
    dt : float, optional
        Leap-frog step (s), default :data:`DEFAULT_DT` (1e-6, the paper's); refused beyond the
        stability bound ``1 / max |eig J(y0)|``. Adaptive integrators choose their own steps and
        refuse ``dt`` (bound them with ``max_step``).
    progress : bool, optional
        Progress over simulated time on stderr: ``True`` a bar (tqdm), ``False`` nothing; default (``None``) a bar
        when stderr is a terminal, else a line every :data:`mol_shell._core.progress.LOG_INTERVAL_S` s of a longer
        run and a last one at its end.
    stresses : bool, optional
        Resultants and face stresses after the run (:func:`mol_shell.results.stresses.add_stresses`):
        ``None`` (default) up to :data:`mol_shell.results.stresses.MAX_SAMPLES` cell samples x saved times,
        ``True`` always, ``False`` never. The unshearable scene's constrained run (``"ida"``) has the torque of its
        constraint ``chi_s = 0`` in ``axial_torque`` (:mod:`mol_shell.results.constraint_stresses`).
    threads : int, optional
        Threads for the compiled right-hand side's cell and node kernels (every integrator uses it);
        default ``$MOL_SHELL_THREADS`` or all cores. Grids below :data:`PARALLEL_MIN_NODES` nodes run
        serially whatever it says. Results do not depend on it (each cell is one thread's work).
    initial : array_like, optional
        Fields ``z, r, chi, theta, psi`` at the nodes, ``(5, n)``: the run starts from them at rest in place of the
        scene's initial data (e.g. a path's step, :func:`mol_shell.analysis.path_start.path_start`); the file
        records that data as the start has it (``omega = 0``, ``gamma`` its twist, ...), the scene's value in
        ``NAME_requested`` beside it where they differ, and ``initial_data_note`` says so.
    **options
        Passed to the integrator's dataclass (e.g. ``rtol`` in ``RTOL_RANGE``, ``atol``, ``max_step``);
        an option the integrator does not take is refused by name.

    Returns
    -------
    xarray.Dataset
        Dims ``time`` and ``s``; fields, rates, energies, angular momentum and
        ``delta_min``; every scene parameter as used (``R``, ``dilation``, ``zeta1`` as numbers, ``end1``,
        ``end2`` as the edge kinds chosen; ``R`` the start's radius, ``r(t = 0)`` of a uniform cylinder, the static
        equilibrium under loads included; ``NAME_requested = "auto"`` beside one left to the code) and the
        run's statistics in attrs. If the run hit a model limit or was interrupted, the
        Dataset holds what was computed and ``attrs["complete"] == 0``.

    Raises
    ------
    ParameterError
        Input out of range, named (before the build where it can be).
    KeyboardInterrupt
        A Ctrl-C before the run steps (its graphs, their compilation, the start's static equilibrium, the checks):
        there is nothing to keep. Once it steps, a Ctrl-C does not raise: the run stops at the end of its current
        chunk and its Dataset is returned with the saved times reached, ``attrs["status"] == "interrupted"`` (and a
        ``RuntimeWarning``). A loop of runs stops on either: ``if ds.attrs["status"] == "interrupted": break``.

    Warns
    -----
    MaterialWarning
        ``material = "svk"`` with ``nu >= 0.45`` (:func:`mol_shell.model.material.locking_warning`); the
        text is also in ``attrs["material_warning"]``. Saved states where the shell's equations are no longer
        elliptic in ``s`` (:func:`~mol_shell.runs.ellipticity.check_ellipticity`; the Dataset's
        ``ellipticity_margin``): the first one's time and place, also in ``attrs["ellipticity_warning"]``.
    """
    scene = as_scene(scene)
    n, t_end, dt = scalar(n), scalar(t_end), scalar(dt)
    options = {k: scalar(v) for k, v in options.items()}
    if dt is not None:
        options["dt"] = dt
    check_options(scene, integrator, options)
    dt_given = "dt" in options
    if integrator == "leapfrog":
        options.setdefault("dt", DEFAULT_DT)
    mode = progress_mode(progress)  # refused here if not a bool or None; the unshearable route takes it as given
    if stresses is not None and not isinstance(stresses, (bool, np.bool_)):
        raise ParameterError.not_a("stresses", stresses, "a bool", "True, False or None (cheap runs only)")
    if threads is not None:  # before any graph is built and compiled (a bad count was refused after the build)
        checked_threads("threads", scalar(threads))
    if isinstance(scene, Unshearable):  # its own formulation: the constrained DAE, or the free shell
        if initial is not None:
            raise ParameterError("initial", "given", "None for the unshearable scene (its own formulation)")
        ds = simulate_unshearable(scene, n=n, times=times, t_end=t_end, constrained=integrator == "ida",
                                  progress=progress, **options)
        with interrupts.watched() as watch:  # a Ctrl-C from here on keeps the run (mol_shell.runs.post_run)
            # the scene's warnings after the run, as a quick run's (its refusals stay one line); its stresses as any
            # run's (the constraint's torque in axial_torque)
            ds.attrs.update(say_scene_warnings(scene, {}, stacklevel=2))
            if stresses is not False:
                with cut_short(watch):
                    ds = _with_stresses(ds, limit=None if stresses else MAX_SAMPLES)
        return kept(ds, watch, stresses is not False, ellipticity=False)
    method = INTEGRATORS[integrator](**options)
    deferred = None  # a t_end that is no multiple of a dt given: said once dt is within its stability bound
    times_given = times is not None
    if times is None and integrator == "leapfrog":
        try:
            times = leapfrog_times(t_end, method.dt, dt_given=dt_given)
        except ParameterError as exc:
            if not (dt_given and exc.name == "t_end"):
                raise
            deferred, times = exc, None
    times = parse_times(times, t_end)
    _check_max_step(method, times)
    with warnings.catch_warnings():
        if deferred is not None:  # no run follows: nothing to announce
            warnings.simplefilter("ignore", resources.LongRunWarning)
        est = resources.check_before_build(n, times, integrator, fields=len(scene.fields),
                                           dt=getattr(method, "dt", None), method=method, times_given=times_given)
    requested, requested_scene = scene.params(), scene
    scene = resolve(scene)
    # the scene's warnings (the material's locking, unused keys), recorded after the run: said before a long build or
    # run (a law to switch), else after the run (a refusal of a quick run stays one line, whenever it comes)
    noted, early = {}, max(est.build_seconds, est.seconds) > resources.LONG_BUILD_S
    if early:
        say_scene_warnings(scene, noted, stacklevel=2)
    system, compiled = build(scene, n)
    _, _, build_time = _built(_graph_key(scene), int(n))
    compiled.set_threads(threads)
    # refused by name if it cannot be formed in double precision
    y0, start_info = starting_state(scene, system, n, initial, asked=requested_scene)
    check_start_inside_limits(scene, requested, system, y0, start_info)
    _check_radius_atol(method, system, y0)
    stability_note = _start_stability(scene, system, y0, start_info)
    omega_max, damping = checked_spectrum(scene, system, y0)
    if integrator == "leapfrog":
        dt = method.dt
        check_step(dt, omega_max, "" if dt_given else "; the default dt: the scene's stiffness, mass and grid set "
                   "the bound; give a smaller dt or an implicit integrator")  # the default named as the default
        for key in [k for k in LOADS + DRIVES if k != "drag" and getattr(scene, k, 0)]:  # each history within dt's reach
            note = check_leapfrog_history(f"{key}_history", getattr(scene, f"{key}_history"), dt, rate=key in DRIVES)
            if note:
                warnings.warn(note, SceneWarning, stacklevel=2)
        if deferred is not None:  # dt is within its bound: t_end is what to change
            raise deferred
        check_parasitic(integrator, method, damping, omega_max, times[-1])
    step_limits.before_run(method, times[-1], damping)  # a fixed-point cvode-adams that stiffness will hold short
    resources.check_before_run(n, times, integrator, fields=len(scene.fields), dt=getattr(method, "dt", None),
                               omega_max=omega_max, compiled=compiled, y0=y0, warned=est.seconds > resources.LONG_RUN_S)
    bar = time_meter(mode, times[-1])
    # a Ctrl-C raised as ever until the run has its states, noted from there on: what follows keeps them, cut short
    # (mol_shell.runs.post_run)
    with interrupts.watched(raising=True) as watch:
        try:
            traj = method.integrate(system, compiled, y0, times, progress=bar)
        finally:
            watch.raising = False
            if bar is not None:
                bar.close()
        if traj.status == "interrupted":  # by any signal so far (one lost in the set-up too): what follows as ever
            watch.caught = False
        if traj.status != "complete":
            warnings.warn(f"run incomplete: {traj.message}; keeping {len(traj.t)} saved times", RuntimeWarning,
                          stacklevel=2)
        velocities, totals = observe(system, traj.y, traj.t)
        attrs = {"integrator": integrator, **method.settings(), **system.graph_stats()}
        for name in declared(type(method)):  # every option, so that the file says how to run it again
            if name not in attrs and f"{name}_option" not in attrs:
                attrs[name] = getattr(method, name)
        attrs.update({
            "build_time_s": build_time,
            "omega_max_rad_s": omega_max,
            "max_damping_rate": damping,
            "units_max_damping_rate": "s-1",
            "leapfrog_dt_bound_s": 1.0 / omega_max,
            "initial_state": start_info,
            "threads": compiled.threads,  # wall_time_s depends on them
            "t_end_requested": float(times[-1]),  # the end asked for: a run that stops early holds only what it
            # reached
        })
        if len(traj.t) < len(times):  # stopped short: the times it asked for, as a scene file asks for them again
            attrs[asked_times.ATTR] = asked_times.times_text(times)
        if stability_note:
            attrs["stability_warning"] = stability_note
        ds = build_dataset(system, scene, traj, velocities, totals, attrs, requested, given=initial is not None)
        ds.attrs.update(noted if early else say_scene_warnings(scene, noted, stacklevel=2))
        ds = step_limits.after_run(method, ds, omega_max, damping)  # steps held, not by rtol
        if not watch.caught:
            with cut_short(watch):
                ds = check_ellipticity(system, ds)
        if stresses is not False and not watch.caught:
            with cut_short(watch):
                ds = _with_stresses(ds, limit=None if stresses else MAX_SAMPLES)
    return kept(ds, watch, stresses is not False)


#: how ``attrs["stresses"]`` of a run begins whose stresses' kernel found no space in ``MOL_SHELL_CACHE``
NO_SPACE_FOR_STRESSES = "skipped: no space for the stresses' kernel in MOL_SHELL_CACHE"


def _with_stresses(ds, limit):
    """``ds`` with its stresses (:func:`add_stresses`); where ``MOL_SHELL_CACHE`` has no space left to build their
    kernel (:class:`CacheFull`), ``ds`` without them, ``attrs["stresses"]`` and one warning saying why: the run's data
    are kept (they were lost with the error), and ``mol_shell.add_stresses`` adds the stresses once there is space."""
    try:
        return add_stresses(ds, limit=limit)
    except CacheFull as exc:
        where = f"{NO_SPACE_FOR_STRESSES} = {exc.value!r} (no space left on device)"
        out = ds.copy()
        out.attrs["stresses"] = f"{where}; mol_shell.add_stresses(ds) adds them once there is space"
        warnings.warn(f"stresses not computed: {where.removeprefix('skipped: ')}; the run is kept without them "
                      "(mol_shell.add_stresses adds them once there is space)", MolShellWarning, stacklevel=3)
        return out


def _check_max_step(method, times):
    """Refuse a ``max_step`` with which ``max_steps`` steps cannot reach the last of ``times``
    (:func:`~mol_shell.integrators.tolerances.smallest_max_step`: ``--max-step 1e-12`` to 1 ms ran, then stopped as "the
    motion is too fast for this horizon"); each saved interval's end for a route whose ``max_steps`` counts per
    interval (``max_steps_per_interval``: casadi-cvodes, casadi-idas); ``max_steps`` where no ``max_step`` can."""
    max_step, max_steps = getattr(method, "max_step", 0.0) or 0.0, getattr(method, "max_steps", None)
    t_end, intervals = float(times[-1]), len(times) - 1
    per_interval = getattr(method, "max_steps_per_interval", False)
    longest = float(np.max(np.diff(times), initial=0.0)) if per_interval else None
    low = smallest_max_step(t_end, intervals, max_steps, longest) if max_steps else 0.0
    if max_step > 0 and max_step < (stated_up(low) if math.isfinite(low) else low):  # the bound stated is applied
        start = f"{MAX_STEP_MARGIN:.0%} of them for the start"
        hint = (f"{method.name} counts max_steps per saved interval: steps of at most max_step, one more to land on "
                f"the saved time and {start}, must cross the longest ({longest:g} s)" if per_interval else
                f"max_steps = {max_steps} steps of at most max_step, one more per saved interval ({intervals}) and "
                f"{start}, must reach t = {t_end:g} s")
        if not math.isfinite(low):  # no max_step can: max_steps is what is short (the least at this max_step)
            least = least_max_steps(t_end, intervals, max_step, longest)
            why = f"{hint}; no max_step can with max_steps = {max_steps}"
            raise ParameterError("max_steps", max_steps, f"integers >= {least} at max_step = {max_step:g} s", hint=why)
        raise ParameterError("max_step", max_step, f"[{stated_up(low):.4g}, inf) s, or 0 (unbounded)", hint=hint)


def _check_radius_atol(method, system, y0):
    """Refuse an absolute tolerance of ``r`` at or above the smallest radius off the axis at the start, for the
    SUNDIALS integrators, which watch ``r -> 0`` at ``r = atol_r``: ``--atol 1`` stopped a run at t = 3e-9 s as
    "r reached 0" with r = 0.995 m."""
    if getattr(method, "kind", None) not in ("cvode", "ida") or not len(system.radial_nodes):
        return
    r_min = float(np.min(system.unpack(y0)[1][system.radial_nodes]))
    r_atol = float(method.field_atol()[1])
    if r_atol >= r_min:
        raise ParameterError("atol", method.atol, f"absolute tolerances of r below {r_min:.4g} m",
                             hint=f"the smallest radius off the axis at t = 0; {method.name} watches the limit r -> 0 "
                             "at r = atol_r")


def _start_stability(scene, system, y0, how):
    """A warning (said, and returned for the attrs) when the start computed as a static equilibrium (``R`` or
    ``dilation`` auto) is unstable: a load past a critical one, where the run leaves the start as round-off grows.
    Not checked for a start with a twist held as initial data or set moving: neither is an equilibrium."""
    if not how.startswith("static equilibrium") or getattr(scene, "gamma", 0.0) or np.any(system.initial_rates(scene)):
        return None
    count = unstable_directions(system, y0)
    if count is None:  # a band too wide, or a stiffness with a zero diagonal entry: said, not passed over
        return ("the stability of the start computed as a static equilibrium was not checked (its tangent stiffness "
                "is not a band matrix of positive diagonal)")
    if not count:
        return None
    note = (f"the start computed as a static equilibrium (R or dilation auto) is unstable: its tangent stiffness "
            f"has {count} negative eigenvalue{'s' * (count != 1)} (a load past a critical one); the run leaves it as "
            "round-off grows (mol-shell path finds the critical loads, modes the growth rates)")
    warnings.warn(note, MolShellWarning, stacklevel=3)
    return note


def starting_state(scene, system, n, initial=None, asked=None):
    """``(y0, how)``: the scene's initial state, or the static equilibrium under its loads when it asks for one
    (``R`` or ``dilation`` auto; for an untwisted cylinder, ``asked`` the scene before ``R`` was computed, the
    radial equilibrium is the start of the static solve under loads); set moving at the scene's
    initial rates (``omega``, driven edges). With ``initial`` (fields ``z, r, chi, theta, psi`` at the nodes,
    ``(5, n)``), that state at rest."""
    if initial is not None:
        return given_state(system, initial, system.unpack(initial_state(scene, system))), ("the fields given "
                                                                                          "(initial), at rest")
    y0 = initial_state(scene, system)
    # a cylinder's R = auto: the radial equilibrium of its uniform twist (the paper's start, kept with a twist or a
    # tilt psi0 as initial data: released, it moves anyway); untwisted and untilted under loads, the static solve
    # starts from it
    radial = (isinstance(asked, CylinderScene) and asked.R is None and not getattr(asked, "gamma", 0.0)
              and not getattr(asked, "psi0", 0.0))
    # under loads only: a drive or a spin alone is set on the start as without it (until December 7 2026 a driven
    # edge alone started the static solve, and its rate entered it: mol_shell.runs.statics.resting)
    if not ((scene.at_equilibrium() or radial) and getattr(scene, "loads_on", list)()):
        return y0, "as given by the scene's parameters"
    # a twist asked for (gamma) is initial data, kept while the other fields come to rest under the loads
    y, how = static_equilibrium(scene, n, y0, hold=(2,) if getattr(scene, "gamma", 0.0) else ())
    if radial and np.any(system.unpack(y)[1] != scene.R):  # the solve began at the radial equilibrium, and moved
        how += f", found from the radial equilibrium at r = {scene.R:.10g} m"  # (attrs' R: the start's radius)
    if not np.any(system.initial_rates(scene)):
        return y, how
    return system.moving(y, scene), how + "; then set moving at the scene's initial rates (omega, driven edges)"


def given_state(system, fields, imposed=None):
    """The state vector of ``fields`` (``(5, n)``) at rest; a pole's ``chi`` tied; refused by name unless finite
    and of that shape, with zero in the fields the scene does not move, and (``imposed``: the scene's own initial
    fields) with the values a pole imposes (``r = 0``, ``theta = theta0``, ``psi = 0``), to the precision of the
    fields given (``4 eps`` of their dtype, at least 1e-9, of the shell's size), and set to them."""
    try:
        given = np.asarray(fields)
        Q = np.array(given, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError.not_a("initial", fields, "an array of numbers", f"(5, {system.n}) finite") from None
    if Q.shape != (5, system.n) or not np.all(np.isfinite(Q)):
        raise ParameterError("initial", Q, f"finite arrays of shape (5, {system.n}): z, r, chi, theta, psi at the "
                             "nodes")
    off_axis = np.asarray(system.reference[1]) > 0
    if np.any(Q[1][off_axis] <= 0):  # the shell's equations divide by r there
        i = int(np.flatnonzero(off_axis & (Q[1] <= 0))[0])
        raise ParameterError("initial", f"r = {Q[1][i]:g} m at s = {system.s[i]:.6g} m",
                             "fields with r > 0 at every node off the axis (row 1 of initial is r)")
    if imposed is not None:  # a pole's values (r = 0, theta = theta0, psi = 0), which the geometry forces: a state
        # off them broke the pole and ran into a limit (other edges hold what a state has: a path's clamped edges
        # where it started, a driven edge where it went); to the precision of the fields given (a float32 array's
        # theta = pi/2 is 4.4e-8 off, which 1e-9 refused), and set to those values
        scale = max(1.0, float(np.max(np.abs(system.reference))), float(np.max(np.abs(imposed))))
        eps = np.finfo(given.dtype).eps if given.dtype.kind == "f" else np.finfo(float).eps
        tol = max(1e-9, 4.0 * float(eps)) * scale
        poles = np.zeros(system.n, dtype=bool)
        poles[[i for i, edge in ((0, system.edges[0]), (-1, system.edges[1])) if edge == "pole"]] = True
        held = system.imposed.T & poles
        wrong = held & (np.abs(Q - imposed) > tol)
        if np.any(wrong):
            k, i = (int(x[0]) for x in np.nonzero(wrong))
            edge = system.edges[0] if i == 0 else system.edges[1]
            unit = "m" if FIELDS[k] in ("z", "r") else "rad"
            raise ParameterError("initial", f"{FIELDS[k]} = {Q[k][i]:.6g} {unit} at s = {system.s[i]:.6g} m",
                                 f"fields with the values the scene's edges impose: {FIELDS[k]} = {imposed[k][i]:.6g} "
                                 f"{unit} there ({'end1' if i == 0 else 'end2'} is {edge!r})",
                                 hint=f"{abs(Q[k][i] - imposed[k][i]):.3g} {unit} off; fields given in "
                                 f"{given.dtype if given.dtype.kind == 'f' else 'float64'} may be {tol:.2g} {unit} off")
        Q[held] = np.asarray(imposed, dtype=float)[held]
    Q = system.tie(Q)
    try:
        return system.pack(Q, np.zeros_like(Q))
    except ValueError as exc:
        raise ParameterError("initial", Q, "fields the scene moves", hint=str(exc)) from None
