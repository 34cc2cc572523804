"""The Dataset of a parameter study: every case's run with the study's dimensions in front.

What the cases share is stored once, as a run file stores it; what differs between them is stored per case
(docs/netcdf.md, "Study files"):

* the grids (``s``, ``s_cell``, ``zeta``: every coordinate of a run but ``time``): the run's coordinate where every
  case has the same values, else ``NAME_case`` with the study's dimensions in front (a study of ``L`` or of ``h``).
  The dimension keeps its name, without a coordinate variable, so xarray aligns it by position: ``st.sel(h=0.008)``
  and the run of ``h = 0.008`` line up face by face. A coordinate that is no dimension (``zeta_face``) keeps its name.
* what the runs said in their global attributes (:func:`case_attrs`): an attribute every finished case shares stays
  one, with its ``units_NAME``; one that differs between cases, or that only some have (``material_warning``), is a
  variable on the study's dimensions with ``units`` and a ``long_name``. The statistics (:data:`STATS`) are always
  per case. Integers stay integers, :data:`INT_FILL` where a case has none.

:func:`study_case` gives one case back as its run's Dataset.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.model.kinematics import FIELDS
from mol_shell.results.cf import coordinates, variables
from mol_shell.results.dataset import DERIVED_UNITS, NO_LOADS, TIME_COMMENT
from mol_shell.scenes import DESCRIPTIONS, UNITS

#: per-case numbers kept as variables even when every case has the same value
STATS = ("n_steps", "n_rhs", "wall_time_s", "build_time_s", "failure_time", "complete", "R")
#: a case's attributes that a study does not carry: the header of the case's own file and how it ended (the
#: study's ``status`` and ``message`` say that per case)
NOT_CARRIED = ("title", "history", "status", "message")
#: what a per-case integer holds where a case has none (it did not run): the variable's ``_FillValue`` then (xarray
#: reads such a variable back as floats, NaN there); ``complete`` is 0 there, as a case without a run did not complete
INT_FILL = -1
#: what a per-case grid's or attribute's long name says after the run's
EACH = " of each case"
#: the global attributes of a study that its cases' runs do not have
STUDY_ATTRS = ("study_vary", "study_integrator", "n_cases", "n_executed", "n_reused", "n_failed", "scheduler",
               "study_wall_time_s")
#: long names of what a run's attributes hold besides the scene's parameters (:data:`mol_shell.scenes.DESCRIPTIONS`)
LONG_NAMES = {
    "n": "nodes in s",
    "complete": "1 where the case ran to its last saved time, else 0",
    "failure_time": "time at which the case stopped short (NaN: it did not)",
    "n_steps": "steps the integrator took",
    "n_rhs": "evaluations of the right-hand side",
    "n_jac": "evaluations of the Jacobian",
    "n_restarts": "restarts of the leap-frog",
    "n_failed_steps": "failed steps of the integrator",
    "wall_time_s": "wall time of the integration (the stepping only)",
    "setup_time_s": "wall time of the integrator's set-up",
    "build_time_s": "wall time of building the graphs and compiled code",
    "case_wall_time_s": "wall time of the case in its worker, from start to end",
    "omega_max_rad_s": "largest |eigenvalue| of the Jacobian at the start (angular frequency of the fastest mode)",
    "max_damping_rate": "largest damping rate of the modes at the start",
    "leapfrog_dt_bound_s": "leap-frog stability bound 1/omega_max_rad_s",
    "rho_A": "mass per unit reference area (moment 0 of rho through the wall, eq. 7.8)",
    "rho_I": "moment 1 of rho through the wall (eq. 7.8)",
    "rho_J": "moment 2 of rho through the wall (eq. 7.8)",
    "zeta1_used": "lower face of the thickness interval as used",
    "meridian": "the meridian, as its description says it",
    "meridian_length": "length of the meridian",
    "edge_s0": "edge kind at s = 0 as used",
    "edge_sL": "edge kind at s = L as used",
    "energy_balance_error": "largest relative error of the energy balance with the loads' work (NaN: no loads)",
    "initial_state": "how the start was made",
    "material_warning": "warning the run gave about its material law ('': none)",
    "scene_warning": "warning the run gave about a parameter without effect ('': none)",
    "stability_warning": "warning the run gave about an unstable equilibrium as its start ('': none)",
    "ellipticity_warning": "where and when the shell's equations lost ellipticity ('': they did not)",
    "ellipticity_lost_time": "first time at which the shell's equations were not elliptic (NaN: none)",
    "ellipticity_lost_position": "arc length where the shell's equations first lost ellipticity (NaN: none)",
    "ellipticity_checked_every": "saved times between checks of ellipticity",
    "stresses": "whether the stresses are included",
    "R": "the radius the case starts at (computed where R was left to the code: r(t = 0) of a uniform start, the "
         "static equilibrium under loads included, else the start's mean radius)",
    "initial_data_note": "what a start given as fields stands in for of the scene's initial data ('': none)",
    "branch_point": "step of the path's branch point (-1: none)",
    "n_rejected": "rejected steps of the integrator",
    "rhs_instructions": "instructions of the right-hand side's graph (CasADi SX)",
    "cell_kernel_instructions": "instructions of the cell kernel's graph (CasADi SX)",
    "node_kernel_instructions": "instructions of the node kernel's graph (CasADi SX)",
    "jacobian_nnz": "non-zeros of the Jacobian",
    "jacobian_bw_lower": "lower bandwidth of the Jacobian",
    "jacobian_bw_upper": "upper bandwidth of the Jacobian",
}


def assemble(dims, coords, cases, results, times):
    """One Dataset from per-case results (``index -> (run Dataset or None, info)``); runs that stopped early are NaN
    after their last saved time; grids and attributes as the module says."""
    shape = tuple(len(coords[d]) for d in dims) if dims != ["case"] else (len(cases),)
    grid = {d: (d, list(coords[d])) for d in dims} if dims != ["case"] else {
        k: ("case", list(v)) for k, v in coords.items()}
    if dims == ["case"]:
        grid["case"] = ("case", np.arange(len(cases)))
    done = [(index, results[index][0]) for index, _ in cases
            if results.get(index, (None, None))[0] is not None and results[index][0].data_vars]
    data = _fields(dims, shape, done, times)
    shared, per_case = case_grids(dims, shape, done)
    carried, attrs, fills = case_attrs(dims, shape, {index: ds.attrs for index, ds in done}, skip=coords, stats=STATS)
    data.update(carried)
    lost = {"status": "lost", "message": "not run", "worker": ""}
    infos = [results.get(index, (None, lost))[1] for index, _ in cases]
    data["case_wall_time_s"] = (tuple(dims), np.array([i.get("case_wall_time_s", np.nan) for i in infos],
                                                      dtype=float).reshape(shape),
                                {"units": "s", "long_name": LONG_NAMES["case_wall_time_s"]})
    long = {"status": "how the case ended: complete, limit, unstable, refused, error, lost or interrupted",
            "message": "account of how the case ended", "worker": "host:pid of the process that ran the case"}
    for key, text in long.items():
        values = np.array([str(i.get(key, "")) for i in infos], dtype=object).reshape(shape)
        data[key] = (tuple(dims), values, {"long_name": text})
    coords_out = {**grid, "time": ("time", np.asarray(times), {"units": "s", "long_name": "time", "standard_name":
                                                               "time", "axis": "T", "comment": TIME_COMMENT}),
                  **shared, **per_case}
    out = xr.Dataset(variables(data), coords=coordinates(coords_out), attrs=attrs)
    for name, fill in fills.items():
        out[name].encoding["_FillValue"] = fill
    return out


def _fields(dims, shape, done, times):
    """Every float variable of the finished cases' runs with the study's dims in front (NaN where a case has none)."""
    data = {}
    names = list(dict.fromkeys(k for _, ds in done for k in ds.data_vars))
    for name in names:
        var = next(ds[name] for _, ds in done if name in ds)
        if var.dtype.kind != "f":
            continue
        sizes = [len(times) if d == "time" else var.sizes[d] for d in var.dims]
        arr = np.full(shape + tuple(sizes), np.nan)
        for index, ds in done:
            if name in ds:
                vals = ds[name].values
                arr[index][tuple(slice(0, k) for k in vals.shape)] = vals
        data[name] = (tuple(dims) + var.dims, arr, dict(var.attrs))
    return data


def case_grids(dims, shape, done):
    """``(shared, per_case)`` coordinate entries of the finished cases' runs (``[(index, Dataset)]``), ``time`` left
    out: one the cases share as it is; one that differs per case, ``NAME_case`` for a dimension's coordinate (which
    must be one-dimensional), its own name for another, NaN (``""``) for a case without it."""
    names = list(dict.fromkeys(str(n) for _, ds in done for n in ds.coords if n != "time"))
    shared, per_case = {}, {}
    for name in names:
        have = [(index, ds[name].variable) for index, ds in done if name in ds.coords]
        first = have[0][1]
        if all(v.dims == first.dims and v.shape == first.shape and np.array_equal(v.values, first.values)
               for _, v in have[1:]):
            shared[name] = (first.dims, first.values, dict(first.attrs))
            continue
        numeric = first.dtype.kind in "fiu"
        values = np.full(shape + first.shape, np.nan if numeric else "", dtype=float if numeric else object)
        for index, var in have:
            values[index] = var.values
        attrs = {**first.attrs, "long_name": str(first.attrs.get("long_name", name)) + EACH}
        per_case[f"{name}_case" if first.dims == (name,) else name] = (tuple(dims) + first.dims, values, attrs)
    return shared, per_case


def case_attrs(dims, shape, records, skip=(), stats=(), long_names=None):
    """``(variables, attrs, fills)`` of what the finished cases' runs (or paths) said in their global attributes
    (``records``: ``{index: attrs}``).

    An attribute every case in ``records`` has, with one value, is one of ``attrs`` (with the ``units_NAME`` a case
    gives it); one that differs, that only some cases have, or that is named in ``stats``, is one of ``variables``
    on the study's ``dims``: numbers with ``units``, words (``""`` where a case has none), each with a long name.
    Integers stay integers (32-bit: CF 1.8 has no 64-bit ones), :data:`INT_FILL` where a case has none (``fills``:
    ``{name: fill}`` for the variables' ``_FillValue``); ``complete`` is 0 there. A name in ``skip`` (a varied
    parameter, a coordinate of the study) is left out with its ``units_NAME`` and ``NAME_requested``, and so are
    :data:`NOT_CARRIED` and every ``units_*`` on its own. A name given as a number by some cases and in words by
    others (``energy_balance_error`` where some cases have no loads) is a number, NaN where it is words.
    ``long_names``: the caller's, before :data:`LONG_NAMES`.
    """
    left_out = set(NOT_CARRIED) | set(skip) | {f"units_{k}" for k in skip} | {f"{k}_requested" for k in skip}
    keys = [k for k in dict.fromkeys(k for attrs in records.values() for k in attrs)
            if k not in left_out and not k.startswith("units_")]
    data, attrs, fills = {}, {}, {}
    for key in keys:
        given = {index: _plain(a[key]) for index, a in records.items() if key in a}
        numbers = {i: v for i, v in given.items() if is_number(v)}
        chosen = numbers or {i: v for i, v in given.items() if isinstance(v, str)}
        if not chosen:  # lists: kept where every case agrees
            if len({repr(v) for v in given.values()}) == 1 and len(given) == len(records):
                attrs[key] = next(iter(given.values()))
            continue
        unit = next((str(a[f"units_{key}"]) for a in records.values() if f"units_{key}" in a), None)
        if key not in stats and len(chosen) == len(records) and len({_same(v) for v in chosen.values()}) == 1:
            attrs[key] = next(iter(chosen.values()))
            if unit is not None:
                attrs[f"units_{key}"] = unit
            continue
        meta = {"long_name": (long_names or {}).get(key) or _long_name(key)}
        if numbers and all(isinstance(v, int) and abs(v) < 2**31 for v in numbers.values()):
            fill = 0 if key == "complete" else INT_FILL
            values = np.full(shape, fill, dtype=np.int32)  # CF 1.8 has no 64-bit integers
            if len(numbers) < values.size and key != "complete":
                fills[key] = fill
        elif numbers:
            values = np.full(shape, np.nan)
        else:
            values = np.full(shape, "", dtype=object)
        for index, value in chosen.items():
            values[index] = value
        if numbers:
            meta["units"] = unit or _units(key)
        data[key] = (tuple(dims), values, meta)
    return data, attrs, fills


def _plain(value):
    """An attribute as a Python number or string (netCDF gives NumPy scalars back)."""
    return value.item() if isinstance(value, np.generic) else value


def _same(value):
    """``value`` for telling cases apart, NaN equal to NaN (``failure_time`` of complete runs)."""
    return "nan" if isinstance(value, float) and math.isnan(value) else value


def _units(key):
    """The unit of a per-case number no case names: a run's (:data:`~mol_shell.results.dataset.DERIVED_UNITS`), a
    parameter's, seconds for ``*_s``, else 1."""
    return DERIVED_UNITS.get(key) or UNITS.get(key) or ("s" if key.endswith("_s") else "1")


def _long_name(key):
    """What a per-case variable holds, in words."""
    if key in LONG_NAMES:
        return LONG_NAMES[key]
    if key.endswith("_requested") and key.removesuffix("_requested") in DESCRIPTIONS:
        return f"{DESCRIPTIONS[key.removesuffix('_requested')]} as requested ('auto': left to the code)"
    if key in DESCRIPTIONS:
        return f"{DESCRIPTIONS[key]} as used"
    return f"the case's {key} (an attribute of its run)"


def study_case(ds, **where):
    """One case of a study of runs as its run's Dataset, for what takes one run (:func:`mol_shell.add_stresses`,
    the views, a comparison with a run of :func:`mol_shell.simulate`).

    ``ds.sel(**where)``, every dimension of the study named (by value; ``case=INDEX`` for a list of cases), with each
    ``NAME_case`` as the coordinate ``NAME`` again, the case's varied parameters and per-case numbers and words in
    attrs (with ``units_NAME`` where a run has it), as its run had them, the study's own attributes (``study_vary``,
    ``n_cases``, ...), ``worker`` and ``case_wall_time_s`` left out, and its saved times up to its last one (a run
    that stopped early has no NaN after it). What only other cases' runs had is left out (:func:`_had`): a variable
    all NaN for this case (``work`` of a case without loads, ``dissipation`` of an elastic one), an attribute without
    a value for it (``ellipticity_lost_time`` of a case that kept it); ``energy_balance_error`` of a case without
    loads is its run's words again. A case without a run (refused, error, lost) is refused naming its status and
    message.
    """
    if not isinstance(ds, xr.Dataset) or "status" not in ds or not all(f in ds for f in ("r", "theta", "chi")):
        raise ParameterError.not_a("ds", ds, "a study of runs", "a Dataset from mol_shell.study or mol-shell study "
                                   "(mol_shell.read_netcdf(PATH) reads a file)")
    dims = list(ds["status"].dims)
    if sorted(where) != sorted(dims):
        raise ParameterError.invalid("where", ", ".join(f"{k}={v}" for k, v in where.items()) or "nothing",
                                     "does not name one case", "a value of each of " + ", ".join(dims),
                                     hint="e.g. " + ", ".join(f"{d}={ds[d].values.ravel()[0].item()!r}" for d in dims))
    for key, value in where.items():  # one value each: a list would keep the dimension (no case, no run)
        if np.ndim(value) or isinstance(value, (list, tuple, set, dict)):
            raise ParameterError.not_a(key, value, "one value", "one of " + ", ".join(
                repr(v.item()) for v in ds[key].values.ravel()))
    try:
        case = ds.sel(where)
    except (KeyError, ValueError, TypeError) as exc:
        raise ParameterError.invalid("where", ", ".join(f"{k}={v}" for k, v in where.items()), "is not a case of "
                                     "the study", "the values of its coordinates " + ", ".join(dims),
                                     hint=f"{type(exc).__name__}: {exc}") from None
    field = next(f for f in FIELDS if f in case and case[f].dims == ("time", "s"))
    saved = np.flatnonzero(np.isfinite(case[field].values).any(axis=1))
    if not saved.size:
        raise ParameterError.invalid("where", ", ".join(f"{k}={v}" for k, v in where.items()), "is a case without a "
                                     "run", "a case that ran", hint=f"{case.status.values}: {case.message.values}")
    attrs = {k: v for k, v in ds.attrs.items() if k not in STUDY_ATTRS}
    attrs["title"] = f"mol_shell run of scene {ds.attrs.get('scene', '')}, a case of a study"
    attrs["comment"] = "time: " + TIME_COMMENT  # a run's (a study's speaks of its per-case variables too)
    scalars = [str(name) for name, var in case.variables.items() if var.ndim == 0]
    for name in scalars:
        var = case.variables[name]
        value = var.values.item()
        if name in CASE_ONLY or not _had(name, value, var.encoding.get("_FillValue")):
            continue
        attrs[name] = value
        if "units" in var.attrs and (name in DERIVED_UNITS or name in UNITS):  # as a run's attrs (with_units)
            attrs[f"units_{name}"] = var.attrs["units"]
    case = case.drop_vars(scalars).isel(time=slice(0, int(saved[-1]) + 1))
    for name in [str(n) for n in case.coords if str(n).endswith("_case")]:
        base = name.removesuffix("_case")
        grid = case[name]
        if grid.dims == (base,):
            meta = {**grid.attrs, "long_name": str(grid.attrs.get("long_name", base)).removesuffix(EACH)}
            case = case.drop_vars(name).assign_coords(coordinates({base: (base, grid.values, meta)}))
    case = _without_others(case)
    if _nan(attrs.get("energy_balance_error")) and "work" not in case:
        attrs["energy_balance_error"] = NO_LOADS
    case.attrs = attrs
    return case


#: what a study says per case of its own that a case's run does not have
CASE_ONLY = ("worker", "case", "case_wall_time_s")
#: a run's attributes that every run has, whatever their value (NaN: ``failure_time`` of a run that completed)
EVERY_RUN = ("failure_time", "energy_balance_error", "complete", "R")


def _nan(value):
    return isinstance(value, float) and math.isnan(value)


def _had(name, value, fill=None):
    """Whether a case's run had the attribute ``name`` of per-case ``value``: a scene's parameter and what every
    run says (:data:`EVERY_RUN`) always; another only with a value (not the fill of a case without it: NaN, ``''``,
    the integer fill)."""
    if name in DESCRIPTIONS or name in UNITS or name in EVERY_RUN:
        return True
    return not (_nan(value) or value == "" or (fill is not None and value == fill))


def _without_others(case):
    """``case`` without the variables that only other cases' runs had: all NaN for this case (a run writes none
    such; one that stopped early has values up to its stop), and the coordinates only those used."""
    others = [name for name, var in case.data_vars.items() if var.dtype.kind == "f" and np.isnan(var.values).all()]
    if not others:
        return case
    case = case.drop_vars(others)
    used = {d for var in case.data_vars.values() for d in var.dims}
    return case.drop_vars([name for name, var in case.coords.items() if var.dims and not set(var.dims) & used])
