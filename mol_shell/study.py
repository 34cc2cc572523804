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
import itertools
import json
import os
import socket
import sys
import time
import warnings

import numpy as np

from . import resources
from .errors import ParameterError
from .scheduling import SCHEDULER_TIMEOUT, connect, execute, scheduler_name
from .study_data import Store, assemble

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

    @property
    def key(self):
        """Hash of the package version, scene class and parameters, integrator, grid, saved times and options."""
        from .version import __version__

        spec = {"version": __version__, "scene": type(self.scene).__name__, "params": self.scene.params(),
                "integrator": self.integrator, "n": self.n, "times": list(self.times), "options": self.options}
        return hashlib.sha256(json.dumps(spec, sort_keys=True, default=repr).encode()).hexdigest()[:20]


def run_scene(scene, integrator, *, n, times, **options):
    """Run one scene through :func:`mol_shell.simulate` (which hands a DAE scene to its own ``run``)."""
    from .simulate import simulate

    return simulate(scene, integrator, n=n, times=np.asarray(times), progress=False, **options)


def run_task(task):
    """Worker entry point: run a :class:`Task`; never raises for a failing case.

    Returns ``(index, dataset or None, info)`` with ``info`` holding ``status``, ``message``,
    ``case_wall_time_s`` and ``worker``.
    """
    start = time.perf_counter()
    ds = None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            ds = run_scene(task.scene, task.integrator, n=task.n, times=task.times, **task.options)
        status, message = str(ds.attrs.get("status", "complete")), str(ds.attrs.get("message", ""))
    except ParameterError as exc:
        status, message = "refused", str(exc)
    except KeyboardInterrupt:
        status, message = "interrupted", "interrupted by the user"
    except Exception as exc:  # noqa: BLE001 - a failing case is data, not a crash
        status, message = "error", f"{type(exc).__name__}: {exc}"
    info = {"status": status, "message": message, "case_wall_time_s": time.perf_counter() - start,
            "worker": f"{socket.gethostname()}:{os.getpid()}"}
    return task.index, ds, info


def resolve_scene(scene):
    """A scene object from an object or a registered name."""
    from .simulate import as_scene

    return as_scene(scene)


def design(scene, vary, integrator="leapfrog"):
    """``(dims, coords, cases)`` of a study: a grid for a dict of lists, a ``case`` dim for a list of dicts.

    Each case is ``(index, {name: value})``; names are scene parameters or integrator options.
    """
    allowed = set(_scene_fields(scene)) | _option_names(scene, integrator)
    if isinstance(vary, dict):
        if not vary:
            raise ParameterError("vary", vary, "at least one parameter with values")
        names = list(vary)
        values = [[_typed(scene, k, v) for v in np.atleast_1d(np.asarray(vary[k], dtype=object)).tolist()] for k in names]
        for name, vals in zip(names, values):
            _check_name(name, allowed, scene, integrator)
            if not vals or len(set(map(repr, vals))) != len(vals):
                raise ParameterError(f"vary[{name!r}]", vals, "distinct values, at least one")
        cases = [(idx, dict(zip(names, (values[d][i] for d, i in enumerate(idx)))))
                 for idx in itertools.product(*(range(len(v)) for v in values))]
        return names, {k: v for k, v in zip(names, values)}, cases
    cases = [dict(c) for c in vary]
    if not cases:
        raise ParameterError("vary", vary, "at least one case")
    names = sorted({k for c in cases for k in c})
    for name in names:
        _check_name(name, allowed, scene, integrator)
    coords = {k: [_typed(scene, k, c.get(k, _default(scene, k))) for c in cases] for k in names}
    return ["case"], coords, [((i,), {k: coords[k][i] for k in names}) for i in range(len(cases))]


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
        parameters or integrator options (``dt``, ``rtol``, ...).
    integrator : str
        As for :func:`mol_shell.simulate`; ``"ida"`` for the unshearable scene.
    n : int
        Nodes in ``s`` (the same for every case).
    times, t_end : optional
        Saved times, the same for every case (``t_end`` alone: 11 times, snapped to ``dt``
        for leap-frog).
    scheduler : None, "serial", str or distributed.Client
        ``None``: local processes (``workers`` of them, default the number of cores);
        ``"serial"``: in this process; an address such as ``"tcp://host:8786"`` or a
        ``Client``: that dask.distributed cluster.
    workers : int, optional
        Local processes (``scheduler=None`` only), this one included: it runs cases too, taking them from
        the back of the queue while ``workers - 1`` spawned processes take them from the front.
    output : path, optional
        Write the combined Dataset here (netCDF) and keep every finished case in
        ``<output stem>.cases/`` so a rerun skips them.
    progress : bool, optional
        Progress bar over cases; default only when stderr is a terminal.
    **options
        Passed to every run (``dt``, ``rtol``, ``atol``, ...).

    Notes
    -----
    Local processes are started with ``spawn`` (safe with threads and CasADi): a script that
    calls ``study`` must guard its entry point with ``if __name__ == "__main__":``. The calling process
    runs its share of the cases on one thread (compiled kernels and BLAS), as the spawned ones do; it
    computes from the start while a worker spends about a second starting, so short studies gain most. A dask
    cluster's workers need ``mol_shell`` importable and gcc (each compiles its right-hand side
    once into its own cache). Stored cases are keyed by their settings and the package version
    (a new version computes every case again); a model changed in place without a new version
    needs ``<output stem>.cases/`` deleted by hand.

    Returns
    -------
    xarray.Dataset
        Every variable of a single run with the study's dims in front; per case
        ``status``, ``message``, ``worker`` and statistics (``n_steps``, ``wall_time_s``,
        ``case_wall_time_s``, ``R``, ...); attrs ``n_cases``, ``n_executed`` (run by this
        call), ``n_reused`` (loaded from ``output``), ``n_failed``.
    """
    from .simulate import DEFAULT_DT, check_options, leapfrog_times, parse_times

    start = time.perf_counter()
    scene = resolve_scene(scene)
    check_options(scene, integrator, options)  # also refuses an unknown integrator
    if workers is not None and not (isinstance(workers, (int, np.integer)) and not isinstance(workers, bool)
                                    and workers >= 1):
        raise ParameterError("workers", workers, "integers >= 1")
    if output is not None:
        from .output import writable_path

        writable_path(output, "output")
    if isinstance(vary, dict):  # the product's size, before its cases are made
        resources.check_cases(int(np.prod([len(np.atleast_1d(np.asarray(v, dtype=object))) for v in vary.values()],
                                          dtype=float)), n)
    dims, coords, cases = design(scene, vary, integrator)
    if times is None and integrator == "leapfrog":  # as simulate: on the step grid, t_end a multiple of dt
        times = leapfrog_times(t_end, options.get("dt", DEFAULT_DT))
    times = parse_times(times, t_end)
    resources.check_study(len(cases), n, times, integrator, fields=len(getattr(scene, "fields", range(5))),
                          dt=options.get("dt", DEFAULT_DT) if integrator == "leapfrog" else None,
                          workers=1 if scheduler == "serial" else (workers or os.cpu_count() or 1))
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
    store = Store(output) if output is not None else None
    pending, reused = [], 0
    for task in tasks:
        loaded = store.load(task) if store else None
        if loaded is not None:
            results[task.index] = loaded
            reused += 1
        else:
            pending.append(task)
    if progress is None:
        progress = sys.stderr.isatty()
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(cases), initial=len(cases) - len(pending), desc="study", unit="case")
    by_index = {task.index: task for task in pending}
    finished = execute(run_task, pending, scheduler, workers, client)
    try:
        for index, ds, info in finished:
            results[index] = (ds, info)
            if store and info["status"] in FINAL:
                store.save(by_index[index], ds, info)
            if bar is not None:
                bar.set_postfix_str(f"{info['status']}")
                bar.update(1)
            if info["status"] == "interrupted":  # Ctrl-C reached a case (serial, or a worker): stop the study
                raise KeyboardInterrupt
    finally:
        finished.close()  # on Ctrl-C: cancel what has not started, shut the workers down
        if bar is not None:
            bar.close()
        if client is not None and client is not scheduler:
            client.close()
    out = assemble(dims, coords, cases, results, times)
    _label_coords(out, coords, dims)
    failed = sum(1 for ds, info in results.values() if info["status"] != "complete")
    out.attrs.update({
        "title": f"mol_shell parameter study of scene {scene.name}", "study_vary": ", ".join(coords),
        "study_integrator": integrator, "n_cases": len(cases), "n_executed": len(pending), "n_reused": reused,
        "n_failed": failed, "scheduler": scheduler_name(scheduler), "study_wall_time_s": time.perf_counter() - start,
    })
    if output is not None:
        from .output import write_netcdf

        write_netcdf(out, output)
    return out


def _task(scene, index, label, changes, integrator, n, times, options):
    from .scenes import with_params

    fields = set(_scene_fields(scene))
    scene_changes = {k: v for k, v in changes.items() if k in fields}
    opts = {**options, **{k: v for k, v in changes.items() if k not in fields}}
    case_scene = with_params(scene, scene_changes)
    return Task(index, label, case_scene, integrator, int(n), tuple(float(t) for t in times), opts)


def _scene_fields(scene):
    return [f.name for f in dataclasses.fields(scene)]


def _option_names(scene, integrator):
    from .simulate import integrator_options

    return integrator_options(scene, integrator)


def _label_coords(ds, coords, dims):
    """Units and long names of the varied parameters (and of the ``case`` index)."""
    from .scenes import DESCRIPTIONS, UNITS

    for name in coords:
        if name not in ds.coords:
            continue
        attrs = {"long_name": f"{DESCRIPTIONS.get(name, name)} (varied)"}
        if ds[name].dtype.kind in "iuf":
            attrs["units"] = UNITS.get(name, "1")
        ds[name].attrs.update(attrs)
    if "case" in dims and "case" in ds.coords:
        ds["case"].attrs.update({"units": "1", "long_name": "index of the case in the list of cases"})


def _check_name(name, allowed, scene, integrator=None):
    if name not in allowed:
        raise ParameterError("vary", name, "{" + ", ".join(sorted(allowed)) + "}",
                             hint=f"parameters of scene {scene.name}" + (f" and options of {integrator}" if integrator else ""))


def _default(scene, name):
    return getattr(scene, name, None)


def _typed(scene, name, value):
    """A value as the scene field's type wants it (strings from the command line are converted).

    A string that is not a number, for a numeric parameter, is refused here (for every case at once).
    """
    from .scenes import _coerce

    if isinstance(value, np.generic):
        value = value.item()
    fields = {f.name: f for f in dataclasses.fields(scene)}
    if name not in fields:
        if isinstance(value, str):
            try:
                return float(value)
            except ValueError:
                raise ParameterError.not_a(f"--vary {name}", value, "a number", "numbers") from None
        return value
    annotation = str(fields[name].type)
    value = _coerce(name, value, fields[name].type)
    if isinstance(value, str) and annotation != "str":
        dataclasses.replace(scene, **{name: value})  # raises: "gamma = 'abc' is not a number; allowed: ..."
    if "int" in annotation and isinstance(value, float) and value.is_integer():
        return int(value)
    return value


# -- command line ------------------------------------------------------------------------------
def parse_vary(items, n=40):
    """``["gamma=0.02:0.2:0.02", "nu=0.3,0.45,0.49"]`` -> ``{"gamma": [...], "nu": [...]}`` (ranges include the stop).

    A range with more cases than a study on ``n`` nodes could hold in memory is refused before it is expanded.
    """
    from .cli import parse_range_or_list

    form = "NAME=START:STOP:STEP or NAME=V1,V2,..."
    vary = {}
    for item in items or []:
        name, sep, spec = (x.strip() for x in item.partition("="))
        if not sep or not name:
            raise ParameterError("--vary", item, form)
        if name in vary:
            raise ParameterError.invalid("--vary", item, f"varies {name} a second time", "each parameter once")
        if ":" in spec:
            values = parse_range_or_list(spec, f"--vary {name}", words=("START", "STOP", "STEP"), item="V",
                                         count_check=lambda count: resources.check_cases(
                                             count, n, name=f"--vary {name}", value=spec))
        else:
            entries = [v.strip() for v in spec.split(",")]
            if not spec or any(not v for v in entries):
                raise ParameterError.invalid("--vary", item, "has an empty entry" if spec else "has no values", form)
            values = [_number_or_text(v) for v in entries]
        vary[name] = values
    if not vary:
        raise ParameterError.missing("--vary", f"give {form}, at least one")
    return vary


def _number_or_text(text):
    try:
        return float(text)
    except ValueError:
        return text


def cmd_study(args):
    from .cli import CLI_OPTIONS, EXIT_INCOMPLETE, integrator_option_args, parse_sets, parse_times_arg
    from .scenes import with_params

    from .simulate import check_options

    sets, vary = parse_sets(args.set), parse_vary(args.vary, args.n)
    both = [name for name in vary if name in sets]
    if both:
        raise ParameterError.invalid("--set", f"{both[0]}={sets[both[0]]}", f"sets {both[0]}, which --vary varies",
                                     "parameters not in --vary")
    scene = with_params(resolve_scene(args.scene), sets)
    times = parse_times_arg(args.times, n=args.n) if args.times else None
    options = integrator_option_args(args)
    check_options(scene, args.integrator, options, offered=CLI_OPTIONS)
    try:
        ds = study(scene, vary, args.integrator, n=args.n, times=times, t_end=args.t_end,
                   scheduler=args.scheduler, workers=args.workers, output=args.output, progress=None, **options)
    except KeyboardInterrupt:
        print(f"mol-shell: study interrupted; finished cases are kept in {Store(args.output).folder}; "
              "run the same command again to resume", file=sys.stderr)
        return 130
    statuses = ds.status.values.ravel().tolist()
    counts = ", ".join(f"{statuses.count(s)} {s}" for s in dict.fromkeys(statuses))
    print(f"wrote {args.output}: {ds.attrs['n_cases']} cases ({counts}); ran {ds.attrs['n_executed']}, "
          f"reused {ds.attrs['n_reused']}, in {ds.attrs['study_wall_time_s']:.3g} s")
    return 0 if ds.attrs["n_failed"] == 0 else EXIT_INCOMPLETE


def register(subparsers):
    """Add ``mol-shell study`` to the command line."""
    from .cli import integer_arg, number_arg, parse_atol

    p = subparsers.add_parser("study", help="run a parameter study (product of --vary values) and write one netCDF")
    p.add_argument("scene", help="a registered scene, or unshearable")
    p.add_argument("--vary", action="append", required=True, metavar="NAME=VALUES",
                   help="START:STOP:STEP (stop included) or V1,V2,...; repeat for more dimensions")
    p.add_argument("--integrator", default="leapfrog", help="leapfrog, ... (ida for unshearable)")
    p.add_argument("--n", type=integer_arg("--n", 3), default=40, help="nodes in s (default 40)")
    p.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None, help="final time, s")
    p.add_argument("--times", default=None, help="saved times: T0:T1:DT (T1 included) or t1,t2,...")
    p.add_argument("--dt", type=number_arg("--dt", unit="s"), default=None,
                   help="leap-frog step, s (default 1e-6); adaptive integrators refuse it")
    p.add_argument("--rtol", type=number_arg("--rtol", 1e-14, 1.0, low_closed=True), default=None,
                   help="relative tolerance in [1e-14, 1) (adaptive integrators)")
    p.add_argument("--atol", type=parse_atol, default=None, help="one value, or per field as r=1e-9,theta=1e-10")
    p.add_argument("--max-step", type=number_arg("--max-step", unit="s"), default=None, help="largest step, s (adaptive)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="base scene parameter, repeatable")
    p.add_argument("--scheduler", default=None,
                   help="dask.distributed scheduler address, or serial (default: local processes); "
                   f"refused if it does not answer within {SCHEDULER_TIMEOUT:g} s")
    p.add_argument("--workers", type=integer_arg("--workers", 1), default=None,
                   help="local processes, this one included (default: all cores)")
    p.add_argument("-o", "--output", required=True,
                   help="netCDF file; finished cases kept next to it in <stem>.cases/ (missing directories are created)")
    p.set_defaults(func=cmd_study)
