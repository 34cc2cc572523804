"""Work-precision: error against run time for every integrator (``mol-shell compare``).

* For each integrator a sweep of tolerances (``rtol``, with ``atol = 1e-3 rtol``), of ``dt`` for leap-frog.
* Error: the largest relative error of ``r``, ``theta`` and ``chi`` over ``s`` and the saved
  times, relative meaning divided by that field's largest ``|value|`` over ``s`` and time:
  ``max_u max_{t,s} |u - u_ref| / max_{t,s} |u_ref|`` for ``u`` in ``(r, theta, chi)``. A field under 1e-6 of the
  largest field's scale is zero but for round-off (theta of a uniform motion): its error is absolute, on the largest
  field's scale (it was on 1e-6 of it, which counted theta's round-off, 1e-14 rad, as 1e-8 and more).
* Reference: CVODE-Adams at ``rtol = 1e-12`` (ODE in momenta), shown converged against IDA at
  ``rtol = 1e-12`` (a different method on a different formulation, the DAE in rates); their
  difference is stored as ``reference_error`` and errors near it are not resolved. Where one of the two does not
  complete (IDA's step budget on a long horizon), the other is the reference, and its error is estimated by the
  check's agreement up to where it stopped and by its own route at a 10x looser tolerance (:func:`reference`).
* Wall time: median of ``repeats`` runs in one process after a warm-up run, graphs and compiled
  code already built; the integrator's own ``wall_time_s`` (solver set-up and stepping, no
  error computation).

Outputs: an :class:`xarray.Dataset` (netCDF), a log-log PNG and a markdown table.
"""

from __future__ import annotations

import dataclasses
import statistics

import numpy as np
import xarray as xr

from mol_shell._core.errors import ModelLimitError, ParameterError, by_interrupt
from mol_shell._core.progress import progress_mode, time_meter
from mol_shell.analysis.workprecision_notes import ATTR as NOTES_ATTR
from mol_shell.analysis.workprecision_notes import SweepNotes
from mol_shell.analysis.workprecision_sweeps import (  # noqa: F401  (RTOLS: importable here)
    DEFAULT_INTEGRATORS,
    RTOLS,
    SWEEPS,
    check_integrators,
    check_sweeps,
    options,
    skip_reason,
    swept,
    unstable_reason,
)
from mol_shell.integrators import INTEGRATORS
from mol_shell.results.cf import attr_value, header
from mol_shell.results.dataset import scene_attrs, with_units
from mol_shell.results.study_dataset import INT_FILL
from mol_shell.runs import resources, step_limits
from mol_shell.runs.checks import checked_spectrum
from mol_shell.runs.simulate import as_scene, build, check_loads, parse_times, resolve, starting_state
from mol_shell.scenes import SCENES, Unshearable

#: the paper's snapshot times (s)
PAPER_TIMES = (0.0, 0.02, 0.07, 0.106, 0.143)
#: timed repeats per sweep point at most (the median is reported; each repeat is a whole run)
MAX_REPEATS = 100
COMPARED = ("r", "theta", "chi")
#: the units of the compared fields: a field at round-off is compared on the largest of its own units (relative_error)
COMPARED_UNITS = {"r": "m", "theta": "rad", "chi": "rad"}
_INDEX = {"r": 1, "chi": 2, "theta": 3}


def settings(ds, name):
    """The swept values of integrator ``name`` along ``level``: its ``rtol``, or leap-frog's ``dt`` (NaN: no point)."""
    return ds[swept(name)].sel(integrator=name).values


def fields_of(system, states):
    """``(field, time, s)`` array of ``r, theta, chi`` from saved states."""
    return system.unpack(np.asarray(states))[:, [_INDEX[f] for f in COMPARED], :].transpose(1, 0, 2)


def relative_error(fields, ref):
    """``max`` over fields of ``max |u - u_ref| / max |u_ref|`` (NaN if the run stopped early); a field whose scale is
    under 1e-6 of the largest in its units (:data:`COMPARED_UNITS`) on that one's (on the largest field's where all of
    its units are under 1e-6 of it)."""
    if fields.shape != ref.shape:
        return float("nan")
    scale = np.abs(ref).max(axis=(1, 2))
    # a field that stays 0 but for round-off (theta of a uniform motion) is compared on the scale of the largest field
    # in its units (theta on chi's: on 1e-6 of it, a uniform drum's theta round-off, 1e-14 rad of 0, was an error of
    # 1e-8); never on another unit's (r's metres would hide a real theta of 1e-4 rad on a shell of R = 100 m)
    units = np.array([COMPARED_UNITS[f] for f in COMPARED])
    largest = np.array([scale[units == u].max() for u in units])
    overall = scale.max()  # where every field of a unit is round-off (theta and chi of a breathing shell): the largest
    largest = np.where(largest < 1e-6 * overall, overall, largest)
    scale = np.where(scale < 1e-6 * largest, largest, scale)
    return float((np.abs(fields - ref).max(axis=(1, 2)) / scale).max())


#: what the compare file's counts of right-hand side evaluations count (a run file's ``n_rhs`` leaves out those of
#: SUNDIALS' difference-quotient Jacobians, which it counts in ``n_rhs_jacobian``)
RHS_LONG_NAMES = {
    "n_rhs": "right-hand side (IDA: residual) evaluations, all of them: the integrator's own and those of its "
             "difference-quotient Jacobians (n_rhs_jacobian), i.e. a run file's n_rhs + n_rhs_jacobian",
    "n_rhs_jacobian": "of n_rhs, the evaluations spent on difference-quotient Jacobians (a run file's n_rhs_jacobian; "
                      "0 where the Jacobian is exact or none is used)"}


def rhs_evaluations(stats):
    """``(all, of them for Jacobians)``: every right-hand side evaluation of a run, its difference-quotient
    Jacobians' (``n_rhs_jacobian``, reported by the compiled SUNDIALS routes; the other routes' Jacobians are exact,
    or they have none) included, and those alone; NaN where the run reports no count."""
    jacobian = stats.get("n_rhs_jacobian", 0)
    return stats.get("n_rhs", np.nan) + jacobian, jacobian


def run_once(system, compiled, y0, times, name, value, progress=None):
    method = INTEGRATORS[name](**options(name, value))
    return method.integrate(system, compiled, y0, np.asarray(times), progress=progress)


#: the reference run and its check: ``(integrator, rtol)`` (:func:`reference`)
REFERENCE, REFERENCE_CHECK = ("cvode-adams", 1e-12), ("ida", 1e-12)
#: where the check does not complete: the reference's route again at this factor of its tolerance (looser), whose
#: difference from the reference is dominated by its own error, an upper estimate of the reference's
SELF_CHECK_FACTOR = 10.0


def _label(route):
    return f"{route[0]} rtol={route[1]:g}"


def _measured(system, compiled, y0, times, route, mode):
    """One reference run of ``route``, its progress shown as a run's (:func:`~mol_shell._core.progress.time_meter`);
    a Ctrl-C is raised (nothing is measured yet)."""
    bar = time_meter(mode, times[-1], f"reference {_label(route)}")
    try:
        run = run_once(system, compiled, y0, times, *route, progress=bar)
    finally:
        if bar is not None:
            bar.close()
    if run.status == "interrupted":  # Ctrl-C, kept by the integrator as the run's end: nothing measured yet
        raise KeyboardInterrupt
    return run


def reference(system, compiled, y0, times, method=REFERENCE, check=REFERENCE_CHECK, progress=None):
    """Reference fields, their estimated error and what was measured: ``(fields, error, info)``.

    The error is the relative difference of two independent runs, ``method`` and ``check`` (a different method on a
    different formulation). Where one of them does not complete (IDA's step budget on a long horizon), the one that
    completed is the reference; the other's agreement with it is measured over the saved times it reached
    (``reference_check_error``, up to ``reference_check_t``), and the reference's route runs again at
    :data:`SELF_CHECK_FACTOR` times its tolerance (``reference_self_check``): the larger of the two differences is
    the error. Neither complete: a :class:`ModelLimitError` naming both (no error can be measured).
    ``progress``: as :func:`mol_shell.runs.simulate.simulate`'s (``None``, a bar on a terminal, else a line a minute).
    """
    mode = progress_mode(progress)
    first, second = (_measured(system, compiled, y0, times, route, mode) for route in (method, check))
    info = {"reference": _label(method), "reference_check": _label(check), "reference_check_status": "complete",
            "reference_check_message": ""}
    if first.status == "complete" and second.status == "complete":
        r = fields_of(system, first.y)
        return r, relative_error(fields_of(system, second.y), r), {**info, "reference_wall_s": first.stats["wall_time_s"]}
    if first.status != "complete" and second.status != "complete":
        when = min(float(getattr(run, "failure_time", float("nan"))) for run in (first, second))
        err = ModelLimitError(f"the reference runs ({method[0]} and {check[0]} at rtol {method[1]:g}) did not "
                              f"complete ({first.message}; {second.message}): no error can be measured against them; "
                              "a shorter t_end, or a scene its integrators can run that tightly", when,
                              "the reference run")
        if all(run.status == "failed" for run in (first, second)):  # the solvers gave up, not the model
            err.status = "failed"
        raise err
    (route, ref), (other_route, other) = ((method, first), (check, second)) if first.status == "complete" else (
        (check, second), (method, first))
    r = fields_of(system, ref.y)
    reached = len(other.t)  # the check's agreement over the saved times it reached (t = 0 alone: nothing measured)
    partial = relative_error(fields_of(system, other.y), r[:, :reached]) if reached > 1 else float("nan")
    looser = (route[0], route[1] * SELF_CHECK_FACTOR)
    again = _measured(system, compiled, y0, times, looser, mode)
    self_error = relative_error(fields_of(system, again.y), r) if again.status == "complete" else float("nan")
    estimates = [e for e in (partial, self_error) if np.isfinite(e)]
    info.update({"reference": _label(route), "reference_check": _label(other_route),
                 "reference_check_status": other.status, "reference_check_message": other.message,
                 "reference_check_error": partial, "units_reference_check_error": "1",
                 "reference_check_t": float(times[reached - 1]) if reached else 0.0, "units_reference_check_t": "s",
                 "reference_self_check": _label(looser), "reference_self_check_status": again.status,
                 "reference_self_error": self_error, "units_reference_self_error": "1",
                 "reference_wall_s": ref.stats["wall_time_s"]})
    return r, max(estimates) if estimates else float("nan"), info


def reference_said(info, error):
    """What the reference is and how well it is known, in one line (the log's, the note's, the table's): ``info``,
    :func:`reference`'s or a compare file's attrs; ``error``, the reference's."""
    said = f"reference {info['reference']}: converged to {error:.2g} (against {info['reference_check']})"
    if info.get("reference_check_status", "complete") == "complete":
        return said
    partial, until = float(info["reference_check_error"]), float(info["reference_check_t"])
    agreed = (f"agreed to {partial:.2g} up to t = {until:g} s" if np.isfinite(partial)
              else "no saved time after t = 0 to compare")
    self_error = float(info["reference_self_error"])
    again = (f"{info['reference_self_check']} (the same route {SELF_CHECK_FACTOR:g}x looser: an upper estimate) "
             + (f"differs by {self_error:.2g}" if np.isfinite(self_error)
                else f"did not complete ({info['reference_self_check_status']})"))
    return (f"reference {info['reference']}: error estimated as {error:.2g}: its check {info['reference_check']} did "
            f"not complete ({info['reference_check_message']}), {agreed}; {again}")


def work_precision(scene, integrators=None, *, n=40, times=PAPER_TIMES, repeats=3, sweeps=None, log=print,
                   progress=None):
    """Measure every sweep point; returns a Dataset with dims ``(integrator, level)``.

    ``integrators``: names; ``None``, :data:`DEFAULT_INTEGRATORS` but those that cannot run the scene's loads
    or driven edges (said by ``log`` and in the attribute ``left_out``; named, such an integrator is refused).
    A lone name (a string) is one integrator.
    ``sweeps``: ``{integrator: {"rtol": [values]}}`` (``{"leapfrog": {"dt": [values in s]}}``), each in place of that
    integrator's default sweep (:data:`~mol_shell.analysis.workprecision_sweeps.SWEEPS`; ``atol = 1e-3 rtol``), e.g.
    ``{"dop853-c": {"rtol": [1e-6, 1e-8]}}``; ``None``: the defaults. Anything else is refused naming ``sweeps``.
    Everything that can be checked is checked before the (expensive) reference runs. A leap-frog
    step whose grid misses a saved time, or past its stability bound ``1/max|eig J(y0)|`` (which
    :func:`~mol_shell.runs.simulate.simulate` refuses), is not run: its point is NaN with status ``skipped`` and
    the reason in ``note`` (simulate's words); where every point would be skipped, the comparison is refused.
    ``progress``: of the reference runs (the long part), as :func:`reference`'s.
    """
    progress_mode(progress)  # refused by name before any work
    sweeps = check_sweeps(sweeps, SWEEPS)  # (this module's SWEEPS: a test may set it)
    asked = as_scene(scene)
    default, left_out = integrators is None, []
    integrators = check_integrators(DEFAULT_INTEGRATORS if default else integrators)
    if default and getattr(asked, "loaded", False):
        left_out = [name for name in integrators if getattr(INTEGRATORS[name], "refuses_loads", "")]
        integrators = [name for name in integrators if name not in left_out]
        for name in left_out:
            log(f"{name:14s} left out: {INTEGRATORS[name].refuses_loads}")
    if not (isinstance(repeats, (int, np.integer)) and not isinstance(repeats, bool) and 1 <= repeats <= MAX_REPEATS):
        raise ParameterError("repeats", repeats, f"integers 1..{MAX_REPEATS}", hint="the median of the repeats is "
                             "timed at every point of every sweep")
    times = parse_times(times)  # as a run's: times closer than an integrator can tell apart failed at t = 0
    for k, name in enumerate(integrators):  # the build is the comparison's: announced once; the matrices of each
        # integrator's linear solver (its default, as the runs use it) counted as a run's check counts them
        resources.check_analysis(n, len(times), f"each {name} run of the comparison", "saved times", integrator=name,
                                 announce=k == 0, method=INTEGRATORS[name]())
    for name, rtol in (REFERENCE, REFERENCE_CHECK):  # the reference runs too, when no sweep runs their integrator
        if name not in integrators:
            resources.check_analysis(n, len(times), f"the reference {name} run of the comparison", "saved times",
                                     integrator=name, announce=False, method=INTEGRATORS[name](**options(name, rtol)))
    plan = {name: [(value, skip_reason(name, value, times)) for value in next(iter(sweeps[name].values()))]
            for name in integrators}
    if all(reason for points in plan.values() for _, reason in points):
        raise ParameterError("times", times.tolist(), "saved times on the step grid of at least one sweep point",
                             hint="every point would be skipped")
    for name in integrators:
        check_loads(asked, name)
    scene = resolve(asked)
    system, compiled = build(scene, n)
    y0, _ = starting_state(scene, system, n, asked=asked)  # where a run starts (R = auto under loads: the statics)
    noted = any(step_limits.may_note(INTEGRATORS[name](**options(name, points[0][0]))) for name, points in plan.items())
    omega_max, damping = checked_spectrum(scene, system, y0) if noted or "dt" in map(swept, integrators) else (None,) * 2
    notes = SweepNotes(system, omega_max if noted else None, damping if noted else None)  # steps held, not by rtol
    if any(swept(name) == "dt" for name in integrators):  # leap-frog's steps past the bound simulate refuses
        plan = {name: [(value, reason or unstable_reason(name, value, omega_max)) for value, reason in points]
                for name, points in plan.items()}
        if all(reason for points in plan.values() for _, reason in points):
            raise ParameterError("sweeps['leapfrog']['dt']", [v for v, _ in plan["leapfrog"]],
                                 f"(0, {1.0 / omega_max:.4g}) s", hint="leap-frog stability bound 1/max|eig J(y0)|, "
                                 "which simulate refuses; every point would be skipped")
    ref, ref_err, ref_info = reference(system, compiled, y0, times, progress=progress)
    log(reference_said(ref_info, ref_err))
    levels = max(len(points) for points in plan.values())
    keys = ("rtol", "dt", "error", "wall_time_s", "n_steps", "n_rhs", "n_rhs_jacobian", "n_jac")
    data = {k: np.full((len(integrators), levels), np.nan) for k in keys}
    status = np.full((len(integrators), levels), "", dtype=object)
    note = np.full((len(integrators), levels), "", dtype=object)
    for i, name in enumerate(integrators):
        for j, (value, _) in enumerate(plan[name]):
            data[swept(name)][i, j] = value
    interrupted = None
    try:  # Ctrl-C: the points measured so far are the comparison, the rest not run (said)
        for i, name in enumerate(integrators):
            notes.start(name, INTEGRATORS[name](**options(name, plan[name][0][0])), times[-1])
            for j, (value, reason) in enumerate(plan[name]):
                if reason:
                    status[i, j], note[i, j] = "skipped", reason
                    log(f"{name:14s} {value:8.1e}  {reason}")
                    continue
                if run_once(system, compiled, y0, times, name, value).status == "interrupted":  # the warm-up
                    raise KeyboardInterrupt  # (compiled pieces, caches)
                runs = []
                for _ in range(repeats):
                    runs.append(run_once(system, compiled, y0, times, name, value))
                    if runs[-1].status == "interrupted":  # Ctrl-C inside a run: its integrator kept it as data
                        raise KeyboardInterrupt
                traj = runs[-1]
                data["error"][i, j] = relative_error(fields_of(system, traj.y), ref)
                data["wall_time_s"][i, j] = statistics.median(r.stats["wall_time_s"] for r in runs)
                for k in ("n_steps", "n_jac"):
                    data[k][i, j] = traj.stats.get(k, np.nan)
                data["n_rhs"][i, j], data["n_rhs_jacobian"][i, j] = rhs_evaluations(traj.stats)
                status[i, j] = traj.status
                if traj.status != "complete":
                    note[i, j] = traj.message
                notes.point(name, swept(name), value, INTEGRATORS[name](**options(name, value)), traj)
                log(f"{name:14s} {value:8.1e}  error {data['error'][i, j]:9.3g}  wall {data['wall_time_s'][i, j]:8.4f} "
                    f"s  steps {traj.stats.get('n_steps', -1):>7}  {traj.status}")
            notes.said(name)
    except BaseException as exc:  # a Ctrl-C, or an error of a C call that wraps one (by_interrupt)
        if not by_interrupt(exc):
            raise
        interrupted = f"interrupted by the user at {name} {value:g}: the points before it measured, the rest not run"
        for i2, j2 in zip(*np.nonzero(status == "")):
            if j2 < len(plan[integrators[i2]]):  # a point of the sweep (the rest of the row is padding)
                reason = plan[integrators[i2]][j2][1]
                status[i2, j2], note[i2, j2] = ("skipped", reason) if reason else (
                    "interrupted", "not run: the comparison was interrupted")
                data["error"][i2, j2] = data["wall_time_s"][i2, j2] = np.nan
    # the swept value in two variables, each with its own units (one variable held rtol and leap-frog's dt in s)
    units = {"rtol": "1", "dt": "s", "error": "1", "wall_time_s": "s", "n_steps": "1", "n_rhs": "1",
             "n_rhs_jacobian": "1", "n_jac": "1"}
    long = {"rtol": "relative tolerance of the point (atol = 1e-3 rtol); NaN for leap-frog, whose sweep is of dt",
            "dt": "time step of the point (leap-frog); NaN for the other integrators, whose sweep is of rtol",
            "error": "max over r, theta, chi of max|u - u_ref| / max|u_ref| over s and saved times (a field under 1e-6 "
                      "of the largest field's max|u_ref|: over the largest's)",
            "wall_time_s": f"median wall time of {repeats} runs", "n_steps": "steps", **RHS_LONG_NAMES,
            "n_jac": "Jacobian evaluations (exact or by difference quotients)"}
    dims = ("integrator", "level")
    coords = {"integrator": ("integrator", list(integrators), {"long_name": "integrator (mol-shell run --integrator)"}),
              "level": ("level", np.arange(levels), {"units": "1", "long_name": "index of the point in the integrator's sweep"})}
    ds = xr.Dataset({k: (dims, v, {"units": units[k], "long_name": long[k]}) for k, v in data.items()}, coords=coords)
    for k in COUNTS:  # counts, written as 32-bit integers (CF 1.8 has none wider); -1 where a point has none, declared
        # whether or not one has none: floats without a _FillValue written as integers made xarray warn (a
        # SerializationWarning per count on a clean comparison), and the file reads back as the floats returned here
        ds[k].encoding = {"dtype": "int32", "_FillValue": INT_FILL}
    ds["status"] = (dims, status.astype(str), {"long_name": "how the run ended: complete, limit, unstable, failed, "
                                                            "interrupted, or skipped (not run; see note); empty: no point"})
    ds["note"] = (dims, note.astype(str), {"long_name": "why a point was skipped or did not complete"})
    for name in integrators:  # a comparison cut short: what its runs so far said
        notes.said(name)
    routes = [notes.route(name) for name in integrators]
    ds["route"] = ("integrator", [r for r, _ in routes], {"long_name": "the route the integrator's name ran, as a run "
                   "file's route: compiled C (the SUNDIALS driver) or scikit-sundae (its Python loop, the sksundae-* names' "
                   "own); empty: a name without SUNDIALS, or no point run"})
    ds["route_reason"] = ("integrator", [why for _, why in routes], {"long_name": "why the integrator's name ran "
                          "scikit-sundae's Python loop in place of the compiled SUNDIALS driver; empty: it did not"})
    ds.attrs.update({**header(f"work-precision of mol_shell integrators, scene {scene.name}"), "scene": scene.name,
                     "n": n, "times": ",".join(f"{t:g}" for t in times), "units_times": "s", "repeats": repeats,
                     "reference_error": ref_err, "units_reference_error": "1", **ref_info,
                     "status": "interrupted" if interrupted else "complete", "message": interrupted or "",
                     "left_out": "; ".join(f"{name}: {INTEGRATORS[name].refuses_loads}" for name in left_out),
                     **notes.attrs(integrators)})
    start = system.unpack(y0)[:2]  # the scene's parameters as the runs used them, as a run file has them
    ds.attrs.update(with_units(scene_attrs(scene, system.edges, system.thickness.zeta1, start, system.reference[:2],
                                           requested=asked.params())))
    if isinstance(scene, Unshearable):  # every integrator here runs its free shell, ida too
        ds.attrs["model"] = ("the unshearable scene's free shell (the ODE every integrator runs); its constrained "
                             "DAE, run by `run --integrator ida`, is not compared")
        log(f"model: {ds.attrs['model']}")
    return ds


#: the counts of a comparison: floats here, NaN where a point has none (not run, or a route that does not count it);
#: in its file 32-bit integers, :data:`~mol_shell.results.study_dataset.INT_FILL` there, declared as the variable's
#: ``_FillValue`` whether or not a point has none (xarray reads them back as floats, NaN there), as a study's counts
COUNTS = ("n_steps", "n_rhs", "n_rhs_jacobian", "n_jac")


def best_at(ds, name, target):
    """Cheapest sweep point of ``name`` whose error is at most ``target`` (index or None)."""
    row = ds.sel(integrator=name)
    ok = np.flatnonzero((row.error.values <= target) & (row.status.values == "complete"))
    return None if ok.size == 0 else int(ok[np.argmin(row.wall_time_s.values[ok])])


def baseline_time(ds, baseline=("leapfrog", 1e-6)):
    """``(wall time, "")`` of the ``baseline`` sweep point, or ``(None, why)`` when there is none to compare with: the
    integrator not compared, the point not in its sweep, or a run that did not complete (a speed-up against a run
    that stopped, unstable or at a limit, would be measured against a part of the work)."""
    name, value = baseline
    if name not in ds.integrator.values:
        return None, f"{name} was not among the integrators compared (--integrators)"
    row = ds.sel(integrator=name)
    hit = np.flatnonzero(np.isclose(settings(ds, name), value))
    if not hit.size:
        return None, f"{name} {value:g} is not in the sweep"
    status, wall = str(row.status.values[hit[0]]), float(row.wall_time_s.values[hit[0]])
    if status != "complete" or not np.isfinite(wall):
        return None, f"{name} {value:g} did not complete ({status or 'not run'}; its note in the file says why)"
    return wall, ""


def markdown_table(ds, target=1e-6, baseline=("leapfrog", 1e-6)):
    """Per integrator: the cheapest run reaching ``target``, and its speed against ``baseline`` (``n/a``, with a note
    under the table saying why, when the baseline point did not complete or is not in the sweep)."""
    base, why = baseline_time(ds, baseline)
    checked = ds.attrs.get("reference_check_status", "complete") == "complete"
    said = [] if checked else [f"Not cross-checked: {reference_said(ds.attrs, ds.attrs['reference_error'])}."]
    lines = [f"Cheapest run with error <= {target:g} (scene {ds.attrs['scene']}, n = {ds.attrs['n']}, "
             f"saved times {ds.attrs['times']} s; reference {ds.attrs['reference']}, "
             f"{'converged to' if checked else 'error estimated as'} {ds.attrs['reference_error']:.2g}).",
             parameters_line(ds), *said, "",
             "| integrator | setting | error | wall [s] | steps | RHS evals (all) | of them in DQ Jacobians | "
             f"Jacobian evals | speed-up vs {baseline[0]} {baseline[1]:g} |", "|---|---|---|---|---|---|---|---|---|"]
    for name in ds.integrator.values:
        j = best_at(ds, str(name), target)
        if j is None:
            cut = "interrupted" in set(ds.status.sel(integrator=name).values.tolist())
            lines.append(f"| {name} | {'interrupted before' if cut else 'none'} reached {target:g} in the sweep "
                         "| | | | | | | |")
            continue
        p = ds.sel(integrator=name).isel(level=j)
        key = swept(str(name))
        speed = f"{base / float(p.wall_time_s):.1f}x" if base else "n/a" if why else ""
        lines.append(f"| {name} | {key} = {float(p[key]):.0e} | {float(p.error):.2g} | {float(p.wall_time_s):.3g} | "
                     f"{int(p.n_steps)} | {int(p.n_rhs)} | {_int(p.get('n_rhs_jacobian', np.nan))} | {_int(p.n_jac)} | "
                     f"{speed} |")
    lines += ["", RHS_NOTE]
    if why:
        lines += ["", f"Speed-up n/a: the baseline {why}, so no speed-up is measured against it."]
    if ds.attrs.get("left_out"):
        lines += ["", f"Left out of the default set (they cannot run the scene): {ds.attrs['left_out']}."]
    if ds.attrs.get(NOTES_ATTR):  # what held an integrator's steps, if not its tolerance (as a run says it)
        lines += ["", "Steps held, not by the tolerance:", *(f"* {line}" for line in str(ds.attrs[NOTES_ATTR]).splitlines())]
    if ds.attrs.get("status") == "interrupted":
        lines += ["", f"Not complete: {ds.attrs['message']}."]
    return "\n".join(lines)


#: under the tables: what the counts of right-hand side evaluations count
RHS_NOTE = ("RHS evals (all): every right-hand side (IDA: residual) evaluation, those of SUNDIALS' difference-quotient "
            "(DQ) Jacobians included (a run file's n_rhs + n_rhs_jacobian); of them in DQ Jacobians: those alone (0 "
            "where the Jacobian is exact or none is used). Jacobian evals: Jacobians formed, exact or by DQ.")


def parameters_set(ds):
    """``name = value unit`` of each scene parameter in ``ds``'s attrs that differs from its scene's default (one left
    to the code, with ``NAME_requested = "auto"``, is not); ``[]`` where ``ds`` does not name a registered scene."""
    fields = dataclasses.fields(SCENES[ds.attrs["scene"]]) if ds.attrs.get("scene") in SCENES else ()
    out = []
    for field in fields:
        if field.name not in ds.attrs or ds.attrs.get(f"{field.name}_requested") == "auto":
            continue
        value = ds.attrs[field.name]
        value = value.item() if isinstance(value, np.generic) else value
        if field.default is not dataclasses.MISSING and attr_value(field.default) == value:
            continue
        unit = str(ds.attrs.get(f"units_{field.name}", "1"))
        shown = f"{value:g}" if isinstance(value, (int, float)) else repr(value)
        out.append(f"{field.name} = {shown}" + ("" if unit == "1" or isinstance(value, str) else f" {unit}"))
    return out


def parameters_line(ds):
    """The scene's parameters the comparison ran with, as far as they are not the scene's defaults, in one line."""
    changed = parameters_set(ds)
    return (f"Scene parameters: {', '.join(changed)}; the others the scene's defaults (each as used in the .nc's "
            "attributes)." if changed else "Scene parameters: the scene's defaults (each as used in the .nc's "
            "attributes).")


def full_table(ds):
    lines = ["| integrator | setting | error | wall [s] | steps | RHS evals (all) | of them in DQ Jacobians | status |",
             "|---|---|---|---|---|---|---|---|"]
    for name in ds.integrator.values:
        row, values = ds.sel(integrator=name), settings(ds, str(name))
        jacobian = row.n_rhs_jacobian.values if "n_rhs_jacobian" in row else np.full(ds.sizes["level"], np.nan)
        for j in range(ds.sizes["level"]):
            if np.isnan(values[j]):
                continue
            lines.append(f"| {name} | {swept(str(name))} = {values[j]:.0e} | {row.error.values[j]:.2g} | "
                         f"{row.wall_time_s.values[j]:.3g} | {_int(row.n_steps.values[j])} | "
                         f"{_int(row.n_rhs.values[j])} | {_int(jacobian[j])} | {row.status.values[j]} |")
    return "\n".join(lines)


def _int(v):
    v = float(v)
    return "" if np.isnan(v) or v < 0 else str(int(v))
