"""Parameter studies: the product of varied parameters, run on local processes or a dask cluster.

``study(scene, vary={"gamma": [...], "nu": [...]})`` runs every case in its own task (each
task builds its own CasADi graphs and compiled code; nothing CasADi crosses a process
boundary) and returns one :class:`xarray.Dataset` with a dimension per varied parameter
(a ``case`` dimension for a list of cases), plus ``status``, ``message`` and statistics per
case. A case that fails (a refused parameter, a model limit, a solver failure) is recorded
and the others go on. With ``output`` every finished case is stored as its own netCDF file
in ``<output stem>.cases/``, named by a hash of everything that defines it; running the same
study again loads those and runs only what is missing (an interrupted study resumes).
``mol-shell study`` is the command line.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import pickle
import socket
import time
import warnings

import numpy as np

from mol_shell._core.atomic import keep_inputs
from mol_shell._core.errors import ModelLimitError, MolShellWarning, ParameterError, by_interrupt, scalar
from mol_shell._core.paths import writable_path
from mol_shell._core.progress import progress_meter, progress_mode
from mol_shell._core.version import __version__
from mol_shell.discretization import kernel_cache
from mol_shell.discretization.compiled import cache_dir
from mol_shell.integrators import INTEGRATORS
from mol_shell.model.laws import REGISTRY, register, user_material
from mol_shell.model.layers import parse_layers
from mol_shell.results.cf import header
from mol_shell.results.dataset import NETCDF_SUFFIXES, write_netcdf
from mol_shell.results.study_dataset import assemble
from mol_shell.results.study_store import KEY_LENGTH, Store
from mol_shell.runs import resources
from mol_shell.runs.scheduling import check_workers, connect, execute, refuse_in_starting_worker, scheduler_attrs
from mol_shell.runs.simulate import (
    DEFAULT_DT,
    as_scene,
    check_options,
    integrator_options,
    leapfrog_times,
    parse_times,
    simulate,
    steps_to,
)
from mol_shell.runs.study_design import design, label_coords, material_names, scene_fields
from mol_shell.scenes import Unshearable, with_params
from mol_shell.scenes.scene_warnings import hush_in_case, say_case_warnings, say_once

#: keywords of :func:`mol_shell.simulate` that a study sets itself for every case, and how
SET_BY_STUDY = {
    "threads": "each case runs on one thread; a study shares the cores among its processes, as workers says",
    "stresses": "each case adds its resultants and stresses as a run does by default, where they are cheap",
    "initial": "each case starts from its own scene's initial data",
}
#: the keywords :func:`study` takes besides the integrator's options
STUDY_KEYWORDS = ("vary", "integrator", "n", "times", "t_end", "scheduler", "workers", "output", "progress")

#: statuses that are final: stored, and skipped on resume ("interrupted" and "lost" are run again)
FINAL = ("complete", "limit", "unstable", "refused", "error")


@dataclasses.dataclass(frozen=True)
class Task:
    """One case: everything a worker needs (plain data; CasADi objects are built in the worker)."""

    index: tuple
    label: str
    scene: object
    integrator: str
    n: int
    times: tuple
    options: dict
    materials: tuple = ()  # the laws of one's own it names, for a worker process (:func:`carried_materials`)

    @property
    def key(self):
        """Hash of the package version, scene class and parameters, integrator, grid, saved times and options."""
        spec = {"version": __version__, "scene": type(self.scene).__name__, "params": self.scene.params(),
                "inputs": case_inputs(self.scene), "integrator": self.integrator, "n": self.n,
                "times": list(self.times), "options": self.options}
        return hashlib.sha256(json.dumps(spec, sort_keys=True, default=repr).encode()).hexdigest()[:KEY_LENGTH]


def _laws_named(scene):
    """The laws ``scene`` names: its ``material`` and its layers' (built-in names, user names, import paths)."""
    names = [scene.material] if hasattr(scene, "material") else []
    names += [material for _, material, _ in parse_layers(scene.layers)] if getattr(scene, "layers", "") else []
    return [name for name in dict.fromkeys(names) if isinstance(name, str)]


def carried_materials(scene):
    """``((name, payload), ...)``: the laws of one's own that ``scene`` names by a name registered in this process
    (an import path is imported where it is needed), for a study's worker processes, where that name means nothing
    (a script's ``Material`` made under ``if __name__ == "__main__":``, or a dask worker's). The payload is the
    pickled ``Material``, by value with cloudpickle where it is installed (the dask extra), else by reference
    (its energy function must then be found at the top level of its module); or, where it cannot be pickled, the
    reason, said by the cases that need it."""
    try:  # the dask extra's: a law made anywhere in a script reaches worker processes by value
        from cloudpickle import dumps
    except ImportError:  # pragma: no cover - without the extra, by reference
        dumps = pickle.dumps
    out = []
    for name in _laws_named(scene):
        try:
            user = user_material(name) if ":" not in name else None
        except ParameterError:  # unknown here: the case is refused naming it where it runs
            continue
        if user is None:
            continue
        try:
            payload = dumps(user)
        except Exception as exc:  # noqa: BLE001 - a law pickle cannot carry (a lambda without cloudpickle, say)
            payload = f"{type(exc).__name__}: {exc}"
        out.append((name, payload))
    return tuple(out)


#: ``name -> (payload, law)`` restored in this process: a study's later cases find their law registered as it was
#: (neither unpickled nor compared again; a law registered since under that name is another one)
_RESTORED = {}


def restore_materials(materials):
    """Register the laws of :func:`carried_materials` in this process (a worker) where their names are unknown or
    name another law; a law that could not be carried is refused naming ``material``."""
    for name, payload in materials:
        done = _RESTORED.get(name)
        if done is not None and done[0] == payload and REGISTRY.get(name) is done[1]:
            continue
        reason = payload if isinstance(payload, str) else None
        if reason is None:
            try:
                law = pickle.loads(payload)
            except Exception as exc:  # noqa: BLE001 - the payload's function may be missing here
                reason = f"{type(exc).__name__}: {exc}"
        if reason is not None:
            if name in REGISTRY:  # this process made it: the study's own
                continue
            raise ParameterError.invalid(
                "material", name, "could not be sent to the study's worker processes",
                "a law whose energy function is defined at the top level of a module or script, or its import path "
                "'module:attr'", hint=reason + "; or run the study with workers=1")
        if name not in REGISTRY or REGISTRY[name].fingerprint() != law.fingerprint():
            register(name, law)  # under the key the study's scenes store (the law's name, or name@digest)
        _RESTORED[name] = (payload, REGISTRY[name])


def case_inputs(scene):
    """What a case reads besides its parameters, for its key: the meridian's description (a points file's digest,
    so an edited file is another case) and the fingerprint of each law of one's own it uses (an edited energy
    function under the same name or import path). A file or law that cannot be read is said so: the case then
    runs, and is refused by name."""
    out = {}
    try:
        if callable(getattr(scene, "meridian", None)):
            out["meridian"] = scene.meridian().describe()
        for name in _laws_named(scene):
            user = user_material(name)
            if user is not None:  # by the law's name (its key may be name@digest): the keys of stored cases kept
                out["law " + user.name] = user.fingerprint()
    except ParameterError as exc:
        out["unreadable"] = str(exc)
    return out


def input_files(scene, vary):
    """``{label: path}`` of the files a study reads, as its arguments name them: the base scene's ``points`` (a
    meridian's table) and each that ``vary`` gives (``{"points": [...]}``, or a case's ``"points"``). :func:`study`
    refuses an ``output`` that is one of them (:func:`mol_shell._core.atomic.keep_inputs`), as the command line
    refuses its ``-o``: a table named ``shell.nc`` was replaced by the study it described."""
    files = {"scene.points": getattr(scene, "points", None)}
    given = []
    if isinstance(vary, dict):
        given = vary.get("points", [])
    elif isinstance(vary, (list, tuple)):
        given = [case.get("points") for case in vary if isinstance(case, dict)]
    for i, value in enumerate(np.atleast_1d(np.asarray(given, dtype=object)).ravel().tolist()):
        files[f"vary['points'][{i}]"] = value
    return {label: path for label, path in files.items() if isinstance(path, (str, os.PathLike)) and str(path).strip()}


def run_scene(scene, integrator, *, n, times, **options):
    """Run one scene through :func:`mol_shell.simulate` (which hands a DAE scene to its own ``run``)."""
    return simulate(scene, integrator, n=n, times=np.asarray(times), progress=False, **options)


def run_task(task):
    """Worker entry point: run a :class:`Task`; never raises for a failing case.

    Returns ``(index, dataset or None, info)`` with ``info`` holding ``status``, ``message``,
    ``case_wall_time_s`` and ``worker``.
    """
    return case_result(task.index, lambda: run_scene(task.scene, task.integrator, n=task.n, times=task.times,
                                                     **task.options), task.materials)


def case_result(index, work, materials=()):
    """``(index, work() or None, info)`` for a study's worker: the Dataset's ``status`` and ``message`` (a refusal,
    an interruption or any other exception recorded as data, never raised), the case's wall time and the worker
    (host:pid). Shared by the studies of runs and of paths. ``materials``: :func:`carried_materials`, registered
    first."""
    start = time.perf_counter()
    ds = None
    try:
        restore_materials(materials)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            hush_in_case()  # the scene's warnings: said once by the study, in its own process
            ds = work()
        status, message = str(ds.attrs.get("status", "complete")), str(ds.attrs.get("message", ""))
    except ParameterError as exc:
        status, message = "refused", str(exc)
    except ModelLimitError as exc:  # a limit met before the run (its static start outside the law's domain)
        status, message = exc.status, str(exc)
    except KeyboardInterrupt:
        status, message = "interrupted", "interrupted by the user"
    except Exception as exc:  # noqa: BLE001 - a failing case is data, not a crash
        status, message = ("interrupted", "interrupted by the user") if by_interrupt(exc) else (
            "error", f"{type(exc).__name__}: {exc}")
    info = {"status": status, "message": message, "case_wall_time_s": time.perf_counter() - start,
            "worker": f"{socket.gethostname()}:{os.getpid()}"}
    return index, ds, info


def resolve_scene(scene):
    """A scene object from an object or a registered name."""
    return as_scene(scene)


def study(scene, vary, integrator="leapfrog", *, n=40, times=None, t_end=None, scheduler=None, workers=None,
          output=None, progress=None, **options):
    """Run every case of a parameter study and return one Dataset.

    Parameters
    ----------
    scene : ShellScene or str
        The base scene (object or registered name); each case replaces the varied parameters.
    vary : dict or list of dict
        ``{"gamma": [...], "nu": [...]}``: the product of the values, one dimension per name
        (in this order). A list of dicts is an irregular design along a ``case`` dimension
        (parameters missing from a case keep the base scene's value). Names are scene
        parameters or integrator options (``dt``, ``rtol``, ...). Each name's values are a list, tuple, range or
        1-D array of numbers (words for a parameter that takes words; ``None`` only where it is one, as an edge's
        ``"auto"``); a set, a generator, a dict, a complex number or ``None`` is refused by ``vary['NAME']``
        before any case runs.
    integrator : str
        As for :func:`mol_shell.simulate`; ``"ida"`` for the unshearable scene.
    n : int
        Nodes in ``s`` (the same for every case): an integer >= 3, refused before any case otherwise.
    times, t_end : optional
        Saved times, the same for every case (``t_end`` alone: 11 times, snapped to ``dt``
        for leap-frog).
    scheduler : None, "serial", str or distributed.Client
        ``None``: local processes (``workers`` of them, default the number of cores);
        ``"serial"``: in this process; an address such as ``"tcp://host:8786"`` or a
        ``Client``: that dask.distributed cluster.
    workers : int, optional
        Local processes (``scheduler=None`` only), this one included: it runs cases too, taking them from
        the back of the queue while ``workers - 1`` started processes take them from the front.
    output : path, optional
        Write the combined Dataset here (netCDF: ``.nc``, ``.nc4`` or ``.cdf``) and keep every finished case in
        ``<output stem>.cases/`` so a rerun skips them.
    progress : bool, optional
        Progress over cases on stderr: ``True`` a bar (tqdm), ``False`` nothing; default (``None``) a bar when
        stderr is a terminal, else a line every :data:`mol_shell._core.progress.LOG_INTERVAL_S` s of a longer
        study (the cases done, the last one's status) and a last one at its end.
    **options
        Passed to every run (``dt``, ``rtol``, ``atol``, ...). :func:`mol_shell.simulate`'s ``threads``,
        ``stresses`` and ``initial`` are the study's to set (:data:`SET_BY_STUDY`): refused by name.

    Notes
    -----
    Local processes are forked where that is safe (Linux, kernels on one thread, and no other threads in this
    process than OpenBLAS's pools hold, which OpenBLAS stops across a fork:
    :func:`mol_shell.runs.worker_start.fork_is_safe`), else spawned; the environment variable
    ``MOL_SHELL_START_METHOD``, when set, chooses instead (``spawn``, ``fork`` or ``forkserver``). The attr
    ``worker_start`` says which. A spawned worker imports the calling script again, so a script that calls
    ``study`` must guard its entry point with ``if __name__ == "__main__":``. Every process, this one
    included, runs its share of the cases on one thread (compiled kernels and BLAS). A dask
    cluster's workers need ``mol_shell`` importable and gcc (each compiles its right-hand side
    once into its own cache). Stored cases are keyed by their settings and the package version
    (a new version computes every case again); a model changed in place without a new version
    needs ``<output stem>.cases/`` deleted by hand.

    Returns
    -------
    xarray.Dataset
        Every variable of a single run with the study's dims in front; per case
        ``status``, ``message``, ``worker`` and statistics (``n_steps``, ``wall_time_s``,
        ``case_wall_time_s``, ``R``, ...); attrs ``n_cases``, ``n_executed`` (handed to a run by
        this call, those the run refused included), ``n_reused`` (loaded from ``output``), ``n_failed``, and on local
        processes ``worker_start`` (``"fork"``, ``"spawn"``, ``"forkserver"``, ``"fork, spawn"`` when a broken pool's
        successor could not fork, ``"none"`` when this process ran every case: see Notes).
    """
    refuse_in_starting_worker()
    start = time.perf_counter()
    scene = resolve_scene(scene)
    check_study_options(scene, integrator, options)  # also refuses an unknown integrator
    kernel_cache.check_opt_level()
    n = scalar(n)
    resources.check_nodes(n)  # once, before any case (int(n) made 20.9 a study at n = 20, n = 2 a refusal per case)
    if not (isinstance(vary, dict) or (isinstance(vary, (list, tuple)) and all(isinstance(c, dict) for c in vary))):
        raise ParameterError.not_a("vary", vary, "a dict or a list of dicts",
                                   "{name: [values, ...]} (a grid), or [{name: value, ...}, ...] (cases)")
    varied = set(vary) if isinstance(vary, dict) else set()  # a list's cases leaving one out take the keyword's
    for name in sorted(varied & set(options)):  # on a grid the varied values won silently (the command line refuses it)
        raise ParameterError.invalid(name, options[name], f"is set while vary[{name!r}] varies it",
                                     "a keyword not in vary (give it in one place)")
    check_workers(workers, scheduler)
    if output is not None:
        writable_path(output, "output", suffixes=NETCDF_SUFFIXES)
        keep_inputs(input_files(scene, vary), [output], "output", output)  # as the command line's -o
    if scheduler is None or scheduler == "serial":  # the cases compile or load their kernels here: a cache that
        cache_dir()  # cannot be used is refused once, before the cases, not once per case
    if isinstance(vary, dict):  # the product's size, before its cases are made
        resources.check_cases(int(np.prod([len(np.atleast_1d(np.asarray(v, dtype=object))) for v in vary.values()],
                                          dtype=float)), n, early=True)
    dims, coords, cases = design(scene, vary, integrator, options)
    if times is None and integrator == "leapfrog":  # as simulate: on the step grid, t_end a multiple of dt; a dt
        # varied: the grid of the coarsest one t_end is a multiple of (the others' too when they divide it; a case
        # whose dt does not is refused, as one t_end is not a multiple of: the whole study only when none is)
        steps = [float(v) for v in coords["dt"]] if "dt" in coords else [options.get("dt", DEFAULT_DT)]
        if "dt" in options:  # dt's own range first (a subnormal one was said as t_end out of range)
            INTEGRATORS[integrator](**options)
        times = leapfrog_times(t_end, max([d for d in steps if steps_to(t_end, d)] or steps),
                               dt_given="dt" in options or "dt" in coords)
    times = parse_times(times, t_end)
    resources.check_study(len(cases), n, times, integrator, fields=len(getattr(scene, "fields", range(5))),
                          dt=options.get("dt", DEFAULT_DT) if integrator == "leapfrog" else None,
                          workers=1 if scheduler == "serial" else (workers or os.cpu_count() or 1),
                          methods=case_methods(scene, integrator, options, cases))
    results, tasks = {}, []
    for index, changes in cases:
        label = ", ".join(f"{k}={v}" for k, v in changes.items())
        try:
            task = _task(scene, index, label, changes, integrator, n, times, options)
        except ParameterError as exc:  # a case whose parameters are out of range: refused, recorded
            results[index] = (None, {"status": "refused", "message": str(exc), "case_wall_time_s": 0.0, "worker": ""})
            continue
        tasks.append(task)
    client = connect(scheduler) if tasks else None  # an unreachable cluster is refused before anything runs
    say_once([task.scene for task in tasks])  # once per distinct warning, not per case (each case's Dataset records
    # its own)
    started = []
    pending, reused = run_cases(run_task, tasks, results, output=output, final=FINAL, scheduler=scheduler,
                                workers=workers, client=client, progress=progress, total=len(cases), started=started)
    say_case_warnings(cases_attrs(tasks, results))  # what each case recorded of its own course, naming it
    out = assemble(dims, coords, cases, results, times)
    label_coords(out, coords, dims)
    failed = sum(1 for ds, info in results.values() if info["status"] != "complete")
    out.attrs.update({
        **header(f"mol_shell parameter study of scene {scene.name}"), "study_vary": ", ".join(coords),
        "study_integrator": integrator, "n_cases": len(cases), "n_executed": len(pending), "n_reused": reused,
        "n_failed": failed, **scheduler_attrs(scheduler, started), "study_wall_time_s": time.perf_counter() - start,
    })
    if output is not None:
        write_netcdf(out, output)
    return out


def check_study_options(scene, integrator, options):
    """:func:`check_options` for a study's ``options``, after refusing a keyword of :func:`mol_shell.simulate` that a
    study sets itself (:data:`SET_BY_STUDY`; ``threads`` was said to be no option of leapfrog), naming the study's
    keywords and the integrator's options."""
    for name in options:
        if name in SET_BY_STUDY:
            offered = ", ".join(sorted(integrator_options(scene, integrator)))
            raise ParameterError.invalid(
                name, options[name], "is a keyword of simulate that a study sets itself",
                f"study's keywords {', '.join(STUDY_KEYWORDS)} and the options of {integrator} ({offered})",
                hint=SET_BY_STUDY[name])
    check_options(scene, integrator, options)


def cases_attrs(tasks, results):
    """``[(label, attrs), ...]``: each task's Dataset's attrs in ``results`` (its run's, or the stored case's)."""
    return [(task.label, results[task.index][0].attrs) for task in tasks
            if results.get(task.index, (None,))[0] is not None]


def run_cases(run, tasks, results, *, output, final, scheduler, workers, client, progress, total, desc="study",
              started=None):
    """Run a study's ``tasks`` with ``run`` (importable by name) into ``results`` (``index -> (ds, info)``);
    ``(pending, reused)``: the tasks that ran and how many finished cases were read back instead.

    With ``output``, a case stored by an earlier run (:class:`Store`, keyed by the task) is reused and each case
    that ends in a status of ``final`` is stored as it finishes, so an interrupted study resumes. Progress as
    :func:`mol_shell._core.progress.progress_mode` says (``None``: a bar on a terminal, else a line a minute). A
    case interrupted by Ctrl-C stops the study (``KeyboardInterrupt``, after the workers are shut down); ``client``
    is closed unless it is ``scheduler`` itself (the user's). ``started`` gets how local workers started
    (:func:`execute`)."""
    store = Store(output) if output is not None else None
    pending, reused = [], 0
    for task in tasks:
        loaded = store.load(task) if store else None
        if loaded is not None:
            results[task.index] = loaded
            reused += 1
        else:
            pending.append(task)
    if store and store.rejected:  # damaged, or edited by hand: said, not silently run again
        (where, why), more = store.rejected[0], len(store.rejected) - 1
        warnings.warn(f"{len(store.rejected)} stored case file{'s' * bool(more)} could not be reused and "
                      f"{'run' if more else 'runs'} again ({why}: {where}{f' and {more} more' if more else ''})",
                      MolShellWarning, stacklevel=3)
    bar = progress_meter(progress_mode(progress), desc, count="{n} of {total} cases", postfix="last case {}",
                         total=total, initial=total - len(pending), unit="case")
    by_index = {task.index: task for task in pending}
    finished = execute(run, pending, scheduler, workers, client, started)
    try:
        for index, ds, info in finished:
            results[index] = (ds, info)
            if store and info["status"] in final:
                store.save(by_index[index], ds, info)
            if bar is not None:
                bar.set_postfix_str(f"{info['status']}")
            if info["status"] == "interrupted":  # Ctrl-C reached a case (serial, or a worker): stop the study; the
                raise KeyboardInterrupt  # case not counted as done (the last line: the finished ones, no time left)
            if bar is not None:
                bar.update(1)
    finally:
        finished.close()  # on Ctrl-C: cancel what has not started, shut the workers down
        if bar is not None:
            bar.close()
        if client is not None and client is not scheduler:
            client.close()
    return pending, reused


def _split(scene, changes, options):
    """A case's ``changes`` as ``(scene parameters, integrator options)``: the options over the study's ``options``."""
    fields = set(scene_fields(scene)) | material_names(scene)
    return ({k: v for k, v in changes.items() if k in fields},
            {**options, **{k: v for k, v in changes.items() if k not in fields}})


def case_methods(scene, integrator, options, cases):
    """The integrators of the ``cases``, each distinct set of options once, made as :func:`mol_shell.simulate` makes
    a run's (whose memory check counts their linear solvers' matrices); none for the unshearable scene (its own runs)
    and for options a run refuses (that case is refused by name when it runs)."""
    if isinstance(scene, Unshearable) or integrator not in INTEGRATORS:
        return []
    methods = {}
    for _, changes in cases:
        opts = _split(scene, changes, options)[1]
        key = json.dumps(opts, sort_keys=True, default=repr)
        if key not in methods:
            try:
                methods[key] = INTEGRATORS[integrator](**opts)
            except (ParameterError, TypeError):
                methods[key] = None
    return [method for method in methods.values() if method is not None]


def _task(scene, index, label, changes, integrator, n, times, options):
    scene_changes, opts = _split(scene, changes, options)
    case_scene = with_params(scene, scene_changes)
    return Task(index, label, case_scene, integrator, int(n), tuple(float(t) for t in times), opts,
                carried_materials(case_scene))
