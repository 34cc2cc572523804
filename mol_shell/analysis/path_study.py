"""Studies of equilibrium paths: one path per case of a parameter grid, their critical points in one Dataset.

``path_study(scene, vary, parameter, start, stop)`` runs :func:`mol_shell.analysis.path.path` for every case of
``vary`` (the design of :func:`mol_shell.runs.study_design.design`: the product of the values, or a list of cases)
on the back ends of run studies (:func:`mol_shell.runs.scheduling.execute`: this process, local processes, or a dask
cluster), keeps each finished path in ``<output stem>.cases/`` (:class:`mol_shell.results.study_store.Store`: a rerun
reuses it), and gathers the critical points: dims ``(*study dims, point)``, the points of each case in the order its
path met them, padded (``point_kind = ""``, ``point_parameter = NaN``) to the longest, with their modes' grid-mode
shares; and the near-critical points (imperfect bifurcations) the same way along ``near``. ``first_critical`` is the
first point's load (the buckling load when the path starts unloaded). ``mol-shell study SCENE --vary ... --path
NAME=START:STOP`` is the command.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import time

import numpy as np
import xarray as xr

from mol_shell._core.atomic import keep_inputs
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import writable_path
from mol_shell._core.version import __version__
from mol_shell.analysis.path import path
from mol_shell.analysis.path_dataset import GRID_SHARE_NAME, SYMMETRY_NOTE
from mol_shell.analysis.path_inputs import check_shared
from mol_shell.discretization import kernel_cache
from mol_shell.results.cf import attr_value, header
from mol_shell.results.dataset import NETCDF_SUFFIXES, write_netcdf
from mol_shell.results.study_dataset import case_attrs
from mol_shell.results.study_store import KEY_LENGTH
from mol_shell.runs import resources
from mol_shell.runs.building import as_scene
from mol_shell.runs.scheduling import check_workers, connect, refuse_in_starting_worker, scheduler_attrs
from mol_shell.runs.study import carried_materials, case_inputs, case_result, cases_attrs, input_files, run_cases
from mol_shell.runs.study_design import design, label_coords
from mol_shell.scenes import UNITS, with_params
from mol_shell.scenes.scene_warnings import say_case_warnings, say_once

#: statuses of a path that are final (stored, not run again on resume)
FINAL = ("complete", "max_steps", "returned", "failed", "limit", "refused", "error")
#: a path's attributes the study says once itself (``path_parameter``, ...) or per case as variables (``status``)
PATH_OWN = ("parameter", "parameter_units", "start", "stop", "n", "complete", "critical_points")


@dataclasses.dataclass(frozen=True)
class PathTask:
    """One case: a scene and the path to trace (plain data, sent to a worker)."""

    index: tuple
    label: str
    scene: object
    parameter: str
    start: float
    stop: float
    n: int
    options: dict
    materials: tuple = ()  # the laws of one's own it names, for a worker process (carried_materials)

    @property
    def key(self):
        spec = {"version": __version__, "kind": "path", "scene": type(self.scene).__name__,
                "params": self.scene.params(), "inputs": case_inputs(self.scene), "parameter": self.parameter,
                "start": self.start, "stop": self.stop, "n": self.n, "options": self.options}
        return hashlib.sha256(json.dumps(spec, sort_keys=True, default=repr).encode()).hexdigest()[:KEY_LENGTH]


def run_path_task(task):
    """Worker entry point: ``(index, path Dataset or None, info)``; never raises for a failing case."""
    return case_result(task.index, lambda: path(task.scene, task.parameter, task.start, task.stop, n=task.n,
                                                progress=False, **task.options), task.materials)


def path_study(scene, vary, parameter, start, stop, *, n=40, steps=20, max_steps=200, scheduler=None, workers=None,
               output=None, progress=None):
    """Trace the path in ``parameter`` from ``start`` to ``stop`` for every case of ``vary``; gather the critical
    points.

    Parameters
    ----------
    scene : ShellScene or str
        The base scene; each case replaces the varied parameters (scene parameters only).
    vary : dict or list of dict
        As for :func:`mol_shell.runs.study.study`.
    parameter, start, stop, n, steps, max_steps
        As for :func:`mol_shell.analysis.path.path`, the same for every case.
    scheduler, workers, output, progress
        As for :func:`mol_shell.runs.study.study` (``output``: the gathered Dataset, and each case's path in
        ``<output stem>.cases/``, reused by a rerun; ``progress``: finished paths, as a study's cases:
        by default a bar on a terminal, else a line a minute).

    Returns
    -------
    xarray.Dataset
        Dims: the study's, and ``point``. Per case: ``status``, ``message``, ``steps``, ``reached`` (the load at
        the path's last state: how far a path that ended short got), ``first_critical`` (the first critical point's
        load, NaN without one: none up to ``reached``), ``case_wall_time_s``; per point: ``point_kind``,
        ``point_parameter``, ``point_family``, ``point_located``, ``point_ellipticity_margin``,
        ``point_grid_mode_share``; per near-critical point (dim ``near``, :data:`MODES`): ``near_parameter``,
        ``near_step``, ``near_located``, ``near_eigenvalue``, ``near_eigenvalue_share``, ``near_family``,
        ``near_grid_mode_share``, each padded past a case's last. Attrs: the scene's
        parameters as the paths used them, as a path file has them (where the cases differ, a variable per case:
        :func:`mol_shell.results.study_dataset.case_attrs`), and ``path_parameter``, ``path_start``, ``path_stop``
        (with ``units_path_start``, ``units_path_stop``).
    """
    refuse_in_starting_worker()
    clock = time.perf_counter()
    scene = as_scene(scene)
    check_shared(parameter, start, stop)  # what every case shares: refused once, not as each case's status
    check_workers(workers, scheduler)
    kernel_cache.check_opt_level()
    if output is not None:
        writable_path(output, "output", suffixes=NETCDF_SUFFIXES)
        keep_inputs(input_files(scene, vary), [output], "output", output)  # as the command line's -o
    if isinstance(max_steps, (int, np.integer)) and not isinstance(max_steps, bool) and max_steps >= 1:
        # each case's path keeps its steps' states: refused once here, not case by case
        resources.check_analysis(n, max_steps + 1, f"tracing each path of up to {max_steps} steps", "states",
                                 name="max_steps", value=max_steps, fewer="allow fewer steps (--max-steps)",
                                 fields=len(getattr(scene, "fields", range(5))))
    dims, coords, cases = design(scene, vary, integrator=None)
    fields = {f.name for f in dataclasses.fields(scene)}
    for name in coords:
        if name not in fields:
            raise ParameterError("vary", name, "{" + ", ".join(sorted(fields)) + "}",
                                 hint="a path study varies scene parameters")
        if name == parameter:
            raise ParameterError("vary", name, "parameters other than the continued one")
    options = {"steps": steps, "max_steps": max_steps}
    results, tasks = {}, []
    for index, changes in cases:
        label = ", ".join(f"{k}={v}" for k, v in changes.items())
        try:
            case_scene = with_params(scene, changes)
        except ParameterError as exc:
            results[index] = (None, {"status": "refused", "message": str(exc), "case_wall_time_s": 0.0, "worker": ""})
            continue
        tasks.append(PathTask(index, label, case_scene, parameter, float(start), float(stop), int(n), options,
                              carried_materials(case_scene)))
    client = connect(scheduler) if tasks else None
    say_once([task.scene for task in tasks], parameter=parameter)  # as a study of runs: once, not per case
    started = []
    pending, reused = run_cases(run_path_task, tasks, results, output=output, final=FINAL, scheduler=scheduler,
                                workers=workers, client=client, progress=progress, total=len(cases), desc="paths",
                                started=started)
    say_case_warnings(cases_attrs(tasks, results))  # each path's loss of ellipticity, naming its case
    out = _gather(scene, dims, coords, cases, results, parameter)
    failed = sum(1 for _, info in results.values() if info["status"] not in ("complete", "max_steps", "returned"))
    units = UNITS.get(parameter, "1")
    out.attrs.update({k: attr_value(v) for k, v in {
        "study_vary": ", ".join(coords), "path_parameter": parameter, "path_start": float(start),
        "units_path_start": units, "path_stop": float(stop), "units_path_stop": units, "n": int(n),
        "n_cases": len(cases), "n_executed": len(pending), "n_reused": reused, "n_failed": failed,
        **scheduler_attrs(scheduler, started), "study_wall_time_s": time.perf_counter() - clock,
    }.items()})
    if output is not None:
        write_netcdf(out, output)
    return out


def _gather(scene, dims, coords, cases, results, parameter):
    shape = tuple(len(coords[d]) for d in dims) if dims != ["case"] else (len(cases),)
    count = max([ds.sizes.get("point", 0) for ds, _ in results.values() if ds is not None] + [0])
    kind = np.full(shape + (count,), "", dtype=object)
    family = np.full(shape + (count,), "", dtype=object)
    value = np.full(shape + (count,), np.nan)
    located = np.full(shape + (count,), -1, dtype=np.int8)  # -1 past a case's last point (0 is "not located")
    margin = np.full(shape + (count,), np.nan)
    reactions = {}  # point_end*_reaction_*: where some case's edges hold z or chi (NaN in the others)
    status = np.full(shape, "", dtype=object)
    message = np.full(shape, "", dtype=object)
    steps = np.zeros(shape, dtype=np.int32)
    reached = np.full(shape, np.nan)
    wall = np.full(shape, np.nan)
    for index, _ in cases:
        ds, info = results[index]
        status[index], message[index], wall[index] = info["status"], info["message"], info["case_wall_time_s"]
        if ds is None:
            continue
        steps[index] = ds.sizes["step"] - 1  # its states less the start, as mol-shell path counts steps
        reached[index] = float(ds.parameter.values[-1]) if ds.sizes["step"] else np.nan
        m = ds.sizes.get("point", 0)
        kind[index][:m] = ds.point_kind.values
        family[index][:m] = ds.point_family.values
        value[index][:m] = ds.point_parameter.values
        located[index][:m] = ds.point_located.values
        if "point_ellipticity_margin" in ds:
            margin[index][:m] = ds.point_ellipticity_margin.values
        for name in [v for v in ds.data_vars if v.startswith("point_end")]:
            if name not in reactions:
                reactions[name] = (np.full(shape + (count,), np.nan), dict(ds[name].attrs))
            reactions[name][0][index][:m] = ds[name].values
    units = UNITS.get(parameter, "1")
    sdims = tuple(dims)
    modes = _gather_modes(sdims, shape, cases, results, units, count)
    data = {
        "status": (sdims, status, {"long_name": "how the case's path ended (complete, max_steps, failed, limit, ...)"}),
        "message": (sdims, message, {"long_name": "what the case's path said"}),
        "steps": (sdims, steps, {"units": "1", "long_name": "steps of the case's path (its states less the start)"}),
        "reached": (sdims, reached, {"units": units, "long_name": f"{parameter} at the last state of the case's path "
                    "(the range's stop where status is complete; NaN: the case has no path)"}),
        "first_critical": (sdims, value[..., 0] if count else np.full(shape, np.nan), {"units": units, "long_name":
                           f"{parameter} at the first critical point the path met (NaN: none)"}),
        "case_wall_time_s": (sdims, wall, {"units": "s", "long_name": "wall time of the case"}),
        "point_kind": (sdims + ("point",), kind.astype(str),  # strings, also when no case met a point
                       {"long_name": "limit or bifurcation ('' past a case's last point)"}),
        "point_parameter": (sdims + ("point",), value, {"units": units, "long_name": f"{parameter} at the critical "
                            "point (NaN past a case's last point)"}),
        "point_family": (sdims + ("point",), family.astype(str), {"long_name": "family of the critical mode"}),
        "point_located": (sdims + ("point",), located, {"units": "1", "long_name":
                          "1 where the point was located to the path's tolerance, 0 where not (-1 past a case's "
                          "last point)"}),
        "point_ellipticity_margin": (sdims + ("point",), margin, {"units": "1", "long_name":
                                     "ellipticity margin at the critical point (not positive: the point is the grid's)"}),
    }
    data.update(modes)
    for name, (values, attrs) in sorted(reactions.items()):
        data[name] = (sdims + ("point",), values, {**attrs, "long_name": attrs["long_name"] + " (NaN past a case's "
                      "last point, and where a case's edge leaves the field free)"})
    coord_vars = {d: (d, np.asarray(coords[d]) if d != "case" else np.arange(len(cases))) for d in dims}
    if dims == ["case"]:  # (units and long names: label_coords, numbers only)
        for name, vals in coords.items():
            coord_vars[name] = ("case", np.asarray(vals))
    coord_vars["point"] = ("point", np.arange(count, dtype=np.int32),
                           {"units": "1", "long_name": "critical point, as met"})
    coord_vars["near"] = ("near", np.arange(modes["near_parameter"][1].shape[-1], dtype=np.int32),
                          {"units": "1", "long_name": "near-critical point (a local minimum of the lowest eigenvalue "
                           "without a crossing), as met"})
    records = {index: results[index][0].attrs for index, _ in cases if results[index][0] is not None}
    carried, shared, fills = case_attrs(dims, shape, records, skip=(*coords, *PATH_OWN),
                                        long_names={"wall_time_s": "wall time of tracing the path"})
    data.update(carried)  # the scene's parameters as used where the cases agree, per case where they differ
    attrs = {**shared, **header(f"mol_shell study of equilibrium paths of scene {scene.name} in {parameter}"),
             "scene": scene.name, "critical_points": SYMMETRY_NOTE}
    ds = xr.Dataset(data, coords=coord_vars, attrs=attrs)
    for name, fill in fills.items():
        ds[name].encoding["_FillValue"] = fill
    for name in ("point_located", "near_located", "near_step"):
        if (ds[name].values < 0).any():  # a case with fewer points: declared, read as NaN there (as a study's counts)
            ds[name].encoding["_FillValue"] = ds[name].dtype.type(-1)
    label_coords(ds, coords, dims)  # the varied parameters' long names, as a study of runs has them
    return ds


#: what a study gathers of each path's critical modes, as the path file has them: ``(name, dim, fill, dtype, units
#: and long name where no case's file has the variable)``; padded with ``fill`` past a case's last point
MODES = (
    ("point_grid_mode_share", "point", np.nan, float, "1", GRID_SHARE_NAME),
    ("near_parameter", "near", np.nan, float, None,
     "the load at the near-critical point (where the lowest eigenvalue has its local minimum, searched between the "
     "steps around it; the step's where near_located is 0): an estimate of the perfect shell's critical load"),
    ("near_step", "near", -1, np.int32, "1",
     "the step where the lowest eigenvalue is least of the steps (the minimum lies between the steps around it)"),
    ("near_located", "near", -1, np.int8, "1",
     "1 where the eigenvalue's minimum was located between the steps, 0 where the step's load is kept"),
    ("near_eigenvalue", "near", np.nan, float, "s-2", "the lowest non-negative eigenvalue at its local minimum"),
    ("near_eigenvalue_share", "near", np.nan, float, "1", "that eigenvalue over its value at the path's start"),
    ("near_family", "near", "", object, None, "family of the near-critical mode: torsional or axisymmetric"),
    ("near_grid_mode_share", "near", np.nan, float, "1", GRID_SHARE_NAME),
)
#: what a padded entry reads as, said in each gathered variable's long name
_PADDING = {"point": "past a case's last critical point", "near": "past a case's last near-critical point"}


def _gather_modes(sdims, shape, cases, results, units, points):
    """The variables of :data:`MODES` on ``(*study dims, point)`` and ``(*study dims, near)``: each case's values as
    its path file has them, padded past its last point, with the path files' units and long names (a file without
    the variable, of an earlier version, reads as padding)."""
    sizes = {"point": points, "near": max([ds.sizes.get("near", 0) for ds, _ in results.values() if ds is not None]
                                          + [0])}
    out = {}
    for name, dim, fill, dtype, unit, long_name in MODES:
        values = np.full(shape + (sizes[dim],), fill, dtype=dtype)
        attrs = {"units": units if name == "near_parameter" else unit, "long_name": long_name}
        for index, _ in cases:
            ds = results[index][0]
            if ds is not None and name in ds:
                values[index][:ds.sizes[dim]] = ds[name].values
                attrs = {k: v for k, v in ds[name].attrs.items() if k in ("units", "long_name")}
        if attrs.get("units") is None:
            attrs.pop("units", None)
        said = "NaN" if dtype is float else "''" if dtype is object else "-1"
        attrs["long_name"] = f"{attrs['long_name']} ({said} {_PADDING[dim]})"
        out[name] = ((*sdims, dim), values.astype(str) if dtype is object else values, attrs)
    return out
