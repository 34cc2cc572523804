"""Labelled results: xarray Datasets with units, and their netCDF4 files."""

from __future__ import annotations

import dataclasses
import errno
import os
from pathlib import Path

import numpy as np
import xarray as xr

from mol_shell._core import interrupts
from mol_shell._core.atomic import atomic_path, utf8_alias
from mol_shell._core.errors import ParameterError, is_number
from mol_shell._core.paths import writable_path
from mol_shell._core.user_files import UserFileError, absent, name_text, not_regular
from mol_shell.model.edges import IMPOSED
from mol_shell.model.kinematics import FIELDS
from mol_shell.model.wall_parameters import law_attrs
from mol_shell.results.cf import attr_value, coordinates, header, utf8_words, variables, wide_integer
from mol_shell.scenes import UNITS
from mol_shell.scenes.base import mean_over

FIELD_META = {
    "z": ("m", "axial position of the base surface"),
    "r": ("m", "radius of the base surface"),
    "chi": ("rad", "azimuthal rotation"),
    "theta": ("rad", "angle of the generator tangent from the axis"),
    "psi": ("rad", "shear angle of the director out of the meridional plane"),
}
RATE_UNITS = {"m": "m s-1", "rad": "rad s-1"}
#: a run's ``energy_balance_error`` where it has no loads (and so no ``work``)
NO_LOADS = "n/a (no loads)"
#: why ``time`` has no CF epoch (the one departure from CF 1.8; docs/netcdf.md)
TIME_COMMENT = ("model time in seconds from the start of the run, without a calendar epoch (deliberately: "
                "readers keep it as numbers, not dates); see docs/netcdf.md")


def scene_attrs(scene, edges, zeta1, initial=None, reference=None, requested=None, given=None):
    """Every parameter of ``scene`` as the run used it, each with its ``units_NAME``, for a Dataset's attrs.

    A parameter left to the code (``None``, "auto": the edges, ``zeta1``, a vessel's ``crown`` and ``knuckle``,
    ``R`` or ``dilation``) is stored as the value used (the edge kinds ``edges`` chosen, the number ``zeta1``, the
    scene's :meth:`~mol_shell.scenes.ShellScene.geometry_values`, and what the scene's
    :meth:`~mol_shell.scenes.ShellScene.auto_values` says of the nodal ``(z, r)`` of ``initial`` against
    ``reference``: the start's radius or scale, a static equilibrium found from a cylinder's computed ``R``
    included) with ``NAME_requested = "auto"`` beside it. ``requested``: the parameters as asked, when
    ``scene`` had some of them computed before (``R`` of a cylinder: :func:`mol_shell.runs.checks.resolve`).
    ``given``: the initial data a start given as fields has in place of the scene's (:func:`given_values`; ``R``
    and ``dilation`` the start's, by ``auto_values``), each stored as the start has it, with the scene's value in
    ``NAME_requested`` (and its ``units_NAME_requested``) beside it where they differ. A vessel whose segments run
    backwards runs a twist and one fibre family with the opposite sign and a graded wall's ``h_profile`` as
    ``h(L - s)`` (its ``ran_values``): each stored as run, the value given in ``NAME_requested``, and their names in
    ``reversed_parameters``. ``zeta1`` (the lower face as used) is stored as ``zeta1_used`` too, in m.
    """
    used = scene.params()
    asked = dict(used if requested is None else requested)
    used["end1"], used["end2"] = edges
    if "zeta1" in used:
        used["zeta1"] = float(zeta1)
    used.update(scene.geometry_values())
    ran = getattr(scene, "ran_values", dict)()  # a vessel drawn down: gamma, fibre_angle, h_profile as they run
    used.update(ran)
    if initial is not None:
        used.update(_as_computed(scene, asked, given is not None).auto_values(initial, reference))
    used.update(given or {})
    meta = {}
    for name, value in used.items():
        meta[name] = value
        meta[f"units_{name}"] = UNITS.get(name, "1")
        wanted = asked.get(name, value)
        if wanted is None and value is not None:
            meta[f"{name}_requested"] = "auto"
        elif (name in ran or name in getattr(scene, "initial", ())) and value is not None and wanted != value:
            if _differ(wanted, value):  # initial data the start does not have (given as fields)
                meta[f"{name}_requested"] = wanted
                meta[f"units_{name}_requested"] = meta[f"units_{name}"]
            else:  # the same to round-off (a mean psi of 1e-161 rad): as asked
                meta[name] = wanted
    reversed_ = [name for name in ran if meta.get(name) == ran[name]]  # (not a start's gamma given as fields)
    if reversed_:  # NAME as run, NAME_requested as given
        meta["reversed_parameters"] = ", ".join(reversed_)
    meta["zeta1_used"], meta["units_zeta1_used"] = float(zeta1), "m"  # every file of a scene has it, as docs/netcdf.md says
    meta.update(law_attrs(scene))  # which law of one's own ran, and its parameters
    return meta


#: initial data that :meth:`~mol_shell.scenes.ShellScene.auto_values` gives as the start has it
STARTING_SIZE = ("R", "dilation")


def _as_computed(scene, asked, given=False):
    """``scene`` with ``R``/``dilation`` left to the code again where they were asked so and computed before (a
    cylinder's ``R``: :func:`mol_shell.runs.checks.resolve`) or, ``given``, where a start given as fields stands in
    for them: its ``auto_values`` then give them as the start has them."""
    names = [k for k in STARTING_SIZE if k in getattr(scene, "initial", ()) and getattr(scene, k, None) is not None
             and (given or asked.get(k, 0.0) is None)]
    return dataclasses.replace(scene, **dict.fromkeys(names)) if names else scene


def _differ(wanted, value):
    """Whether an initial-data parameter as asked and as the start has it differ: by more than 1e-12 of it and 1e-12
    in SI units (a start given as the scene's own fields, read back by a fit, and a mean shear angle of 1e-161 rad
    from a solve are the same)."""
    try:
        return not np.isclose(float(wanted), float(value), rtol=1e-12, atol=1e-12)
    except (TypeError, ValueError):
        return wanted != value


def given_values(scene, start, s, r0):
    """``{name: value}``: the scene's initial data ``gamma``, ``psi0`` and ``omega`` as a start given as fields
    (``start``: ``z, r, chi, theta, psi`` at the nodes ``s``, at rest: a path's step) has them, in place of the
    scene's: its twist (the least-squares slope of ``chi`` over the nodes off the axis, ``r0 > 0``: a pole's ``chi``
    is tied), its mean shear angle, and 0 (at rest). ``R`` and ``dilation``: :func:`scene_attrs` (``auto_values``)."""
    names = getattr(scene, "initial", ())
    out = {}
    if "gamma" in names:
        off = np.asarray(r0) > 0
        x, chi = np.asarray(s, dtype=float)[off], np.asarray(start[2], dtype=float)[off]
        dx = x - x.mean()
        out["gamma"] = float(np.sum(dx * (chi - chi.mean())) / np.sum(dx * dx)) if x.size > 1 else 0.0
    if "psi0" in names:
        out["psi0"] = mean_over(start[4], s)
    if "omega" in names:
        out["omega"] = 0.0
    return out


def given_note(meta):
    """One sentence naming the initial data a start given as fields stands in for (``NAME_requested`` a number
    beside ``NAME`` in ``meta``), or ``""``."""
    def shown(name, value):
        unit = meta.get(f"units_{name}", "1")
        return f"{value:.6g}" + ("" if unit == "1" else f" {unit}")

    reversed_ = str(meta.get("reversed_parameters", "")).split(", ")  # not the start's: the meridian's direction
    names = [k.removesuffix("_requested") for k in meta if k.endswith("_requested") and is_number(meta[k])
             and k.removesuffix("_requested") not in reversed_]
    said = [f"{name} = {shown(name, meta[name])} (the scene's {shown(name, meta[f'{name}_requested'])})"
            for name in names if is_number(meta.get(name))]
    if not said:
        return ""
    return ("the start given as fields (at rest) stands in for the scene's initial data: the file holds it as used, "
            "the scene's values beside it as NAME_requested: " + ", ".join(said))


def build_dataset(system, scene, traj, velocities, totals, attrs, requested=None, given=False):
    """Assemble the Dataset of one run.

    Parameters
    ----------
    system : ShellSystem
    scene : TwistedCylinder
        With ``R`` resolved.
    traj : Trajectory
    velocities : ndarray
        ``(time, 5, s)`` rates of the fields.
    totals : dict
        Per-time arrays ``kinetic``, ``stored``, ``angular_momentum``, ``delta_min`` (and of a loaded shell
        ``work``, ``dissipated`` with the scalar ``balance_error``), as :func:`mol_shell.runs.building.observe`
        computes them.
    attrs : dict
        Integrator name and settings, graph statistics and the like.
    requested : dict, optional
        The scene's parameters as asked, before ``R`` was computed (see :func:`scene_attrs`).
    given : bool
        Whether the run started from fields given in place of the scene's initial data (a path's step): those are
        stored as the start has them (:func:`given_values`), with ``initial_data_note`` saying so.
    """
    fields = system.unpack(traj.y)
    data = {}
    for k, name in enumerate(FIELDS):
        units, long_name = FIELD_META[name]
        data[name] = (("time", "s"), fields[:, k], {"units": units, "long_name": long_name})
        data[name + "_t"] = (
            ("time", "s"),
            velocities[:, k],
            {"units": RATE_UNITS[units], "long_name": f"rate of change of {name}"},
        )
    data["kinetic_energy"] = (("time",), totals["kinetic"], {"units": "J", "long_name": "kinetic energy of the shell"})
    data["stored_energy"] = (("time",), totals["stored"], {"units": "J", "long_name": "stored (strain) energy"})
    data["energy"] = (
        ("time",),
        totals["kinetic"] + totals["stored"],
        {"units": "J", "long_name": "total energy (kinetic + stored)"},
    )
    data["angular_momentum"] = (
        ("time",),
        totals["angular_momentum"],
        {"units": "kg m2 s-1", "long_name": "angular momentum of the whole shell about the axis"},
    )
    data["delta_min"] = (
        ("time",),
        totals["delta_min"],
        {"units": "m", "long_name": "minimum over s of delta = r beta1 cos(psi) (must stay positive)"},
    )
    balance = totals.get("balance_error")
    if system.n_extra:
        data["work"] = (("time",), totals["work"], {"units": "J", "long_name":
                        "work done on the shell so far by the loads (pressure, gravity, end forces and torques)"})
        data["dissipated"] = (("time",), totals["dissipated"], {"units": "J", "long_name":
                              "energy dissipated so far by viscosity and drag"})
    names = getattr(system, "reaction_names", [])
    if names:
        for k, (var, units, what) in {0: ("reaction_force", "N", "axial force"), 2: ("reaction_torque", "N m",
                                                                                       "axial torque")}.items():
            cols = [j for j, (_, field) in enumerate(names) if field == k]
            if cols:
                values = reaction_columns(len(traj.t), system.edges, k)
                for j in cols:
                    values[:, 0 if names[j][0] == 0 else 1] = totals["reactions"][:, j]
                data[var] = (("time", "end"), values, {"units": units, "long_name":
                             f"{what} the driver or support applies to the edge (0 where the edge leaves "
                             f"{FIELDS[k]} free)"})
    if system.viscous:
        data["dissipation"] = (
            ("time",),
            totals["dissipation"],
            {"units": "W", "long_name": "power dissipated by the Kelvin-Voigt stress (= -d energy/dt)"},
        )
    z0, r0, theta0 = system.reference
    data["z0"] = (("s",), z0, {"units": "m", "long_name": "axial position of the reference base surface"})
    data["r0"] = (("s",), r0, {"units": "m", "long_name": "radius of the reference base surface"})
    data["theta0"] = (("s",), theta0, {"units": "rad", "long_name": "angle of the reference generator tangent from the axis"})
    coords = {
        "time": ("time", traj.t, {"units": "s", "long_name": "time", "standard_name": "time", "axis": "T",
                                  "comment": TIME_COMMENT}),
        "s": ("s", system.s, {"units": "m", "long_name": "arc length of the reference generator"}),
    }
    if names:
        coords["end"] = ("end", ["end1", "end2"], {"long_name": "edge (end1 at s = 0, end2 at s = L)"})
    meta = {
        **header(f"mol_shell run of scene {scene.name}"),
        "comment": "time: " + TIME_COMMENT,
        "scene": scene.name,
        "n": system.n,
        "status": traj.status,
        "complete": int(traj.status == "complete"),
        "message": traj.message,
        "failure_time": traj.failure_time,
        "rho_A": system.rho_a,
        "rho_I": float(system.rho_i),
        "rho_J": system.rho_j,
        "zeta1_used": system.thickness.zeta1,
        "energy_balance_error": NO_LOADS if balance is None else balance,
        "edge_s0": system.edges[0],
        "edge_sL": system.edges[1],
        "meridian": system.meridian.describe(),
        "meridian_length": system.L,
    }
    start = given_values(scene, fields[0], system.s, system.reference[1]) if given else None
    meta.update(scene_attrs(scene, system.edges, system.thickness.zeta1, fields[0, :2], system.reference[:2],
                            requested, start))
    note = given_note(meta)
    if note:
        meta["initial_data_note"] = note
    meta.update(traj.stats)
    meta.update(attrs)
    return xr.Dataset(variables(data), coords=coordinates(coords), attrs=with_units(meta))


def with_units(meta):
    """A run's attrs, netCDF-ready (:func:`~mol_shell.results.cf.attr_value`), each dimensional number with its
    ``units_NAME`` beside it: the scene's parameters, the run's own (:data:`DERIVED_UNITS`), the integrator's options."""
    out = {k: attr_value(v) for k, v in meta.items()}
    for name in list(out):
        unit = DERIVED_UNITS.get(name, UNITS.get(name))
        if unit is not None and f"units_{name}" not in out:
            out[f"units_{name}"] = unit
    return out


#: units of a run's numbers that are not scene parameters (:data:`mol_shell.scenes.UNITS` has those and the
#: integrators' options): the inertia densities of eq. (7.8), moments 0, 1, 2 of rho through the thickness; the
#: fastest mode's angular frequency, whose name ends in ``_s`` (a name that does is in seconds otherwise)
DERIVED_UNITS = {"failure_time": "s", "rho_A": "kg m-2", "rho_I": "kg m-1", "rho_J": "kg", "zeta1_used": "m",
                 "meridian_length": "m", "first_step": "s", "restart": "s", "omega_max_rad_s": "rad s-1",
                 "t_end_requested": "s", "max_damping_rate": "s-1", "ellipticity_lost_time": "s",
                 "ellipticity_lost_position": "m"}


def reaction_columns(count, edges, field):
    """``(count, 2)`` reactions on ``field`` (0 = z, 2 = chi) at the two edges before the computed ones (driven or
    held: :mod:`mol_shell.discretization.reactions`) are filled in: 0 at an edge that leaves the field free (nothing
    there to push: a free edge, ``chi`` at a magnet, a pole, where ``chi`` has no inertia on the axis), NaN at one
    whose support holds it where no reaction is computed (none is left: a guard)."""
    values = np.zeros((count, 2))
    for end, kind in enumerate(edges):
        if field in IMPOSED[kind]:
            values[:, end] = np.nan
    return values


#: file name suffixes of netCDF files: what every writer of a netCDF output accepts
NETCDF_SUFFIXES = frozenset({"nc", "nc4", "cdf"})


def write_netcdf(ds, path):
    """Write a run as netCDF4 (model time in plain seconds, no CF calendar decoding).

    Coordinate variables get no ``_FillValue`` (CF 2.5.1; xarray would write NaN for floats). Integer variables and
    coordinates are written as 32-bit ``int`` (CF 1.8 has no 64-bit or unsigned integers; numpy's default is int64),
    for every file written here: run, study, modes, path, compare and stability files alike.
    ``time`` is the unlimited (record) dimension, so it may come first (CF 2.4 asks other
    dimensions to stand left of T "whenever possible"); variables along it are chunked in blocks
    of about 1 MB (netCDF's default chunk of one record made large runs 10x slower to write).
    Missing directories of ``path`` are created; a path that cannot be written, or that does not end in
    one of :data:`NETCDF_SUFFIXES`, raises :class:`~mol_shell._core.errors.ParameterError`. The file is
    written under a temporary name and renamed onto ``path`` (:mod:`mol_shell._core.atomic`): a process killed
    while writing leaves the previous file intact. A Ctrl-C while it is written lets the write finish and is raised
    after it (``KeyboardInterrupt("after writing PATH")``): xarray and netCDF4 hold process-wide locks that an
    interrupt in the middle left taken, and the write's clean-up then waited for them forever
    (:func:`mol_shell._core.interrupts.held`).
    """
    if not isinstance(ds, xr.Dataset):
        raise ParameterError.not_a("ds", ds, "an xarray.Dataset", "a Dataset, as mol_shell.simulate returns")
    path = writable_path(path, suffixes=NETCDF_SUFFIXES)
    ds = _netcdf_attrs(ds)
    encoding = {name: {"_FillValue": None} for name, var in ds.coords.items() if var.dtype.kind == "f"}
    for name, var in ds.variables.items():  # CF 1.8 has no 64-bit or unsigned integers: numpy's default int64
        if wide_integer(var):
            encoding.setdefault(name, {})["dtype"] = "int32"
    unlimited = ["time"] if "time" in ds.dims else []
    for name, var in ds.variables.items():
        if "time" in var.dims and var.dtype.kind in "fiu":
            other = int(np.prod([ds.sizes[d] for d in var.dims if d != "time"], dtype=np.int64))
            block = max(1, min(ds.sizes["time"], 2**17 // max(other, 1)))
            encoding.setdefault(name, {})["chunksizes"] = tuple(block if d == "time" else ds.sizes[d] for d in var.dims)
    with interrupts.held(f"after writing {path}"):
        with atomic_path(path) as tmp:  # a killed run: the previous file
            ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=encoding, unlimited_dims=unlimited)
        interrupts.wrote(path)  # an interrupt from here on: said after writing it


def _netcdf_attrs(ds):
    """``ds`` (a shallow copy where needed) with attributes netCDF can hold: a bool as 0 or 1 and ``None`` as
    ``"none"`` (as this package writes its own); anything but numbers, strings and flat lists of them is refused
    naming the attribute (netCDF4 raised a TypeError naming its internal type, ``b1``, after the file was begun).
    Words that are not UTF-8 (a file's name), in an attribute, a list attribute or a variable of words (a study's
    ``points`` over its cases), are escaped (:func:`~mol_shell.results.cf.utf8_words`)."""
    def fixed(attrs, where):
        out = {}
        for key, value in attrs.items():
            value = attr_value(value.item() if isinstance(value, np.bool_) else value)
            many = isinstance(value, (list, tuple, np.ndarray))
            flat = np.asarray(value, dtype=object).ravel() if many else ()
            kinds = {isinstance(v, str) for v in flat}  # all strings or all numbers: netCDF has no mixed attribute
            if not isinstance(value, (str, int, float, list, tuple, np.ndarray)) or many and (
                    np.ndim(np.asarray(value, dtype=object)) != 1 or len(kinds) > 1) or any(
                    not isinstance(v, (str, int, float, np.integer, np.floating)) or isinstance(v, bool) for v in flat):
                raise ParameterError.not_a(f"{where}[{key!r}]", value, "a netCDF attribute",
                                           "a number, a string, or a flat list of numbers or of strings")
            out[key] = value
        return out

    words = {}
    for name, var in ds.variables.items():
        values = var.values if var.dtype.kind in "OU" else None
        if values is not None and utf8_words(values) is not values:
            words[name] = (var.dims, utf8_words(values), var.attrs)
    if not words and all(_plain(v) for v in ds.attrs.values()) and all(_plain(v) for var in ds.variables.values()
                                                                       for v in var.attrs.values()):
        return ds
    out = ds.copy(deep=False).assign_coords({k: v for k, v in words.items() if k in ds.coords})
    out = out.assign({k: v for k, v in words.items() if k not in ds.coords})
    out.attrs = fixed(ds.attrs, "ds.attrs")
    for name, var in out.variables.items():
        var.attrs = fixed(var.attrs, f"ds[{name!r}].attrs")
    return out


def _plain(value):
    return isinstance(value, str) and name_text(value) is value or isinstance(value, float) or \
        isinstance(value, int) and not isinstance(value, bool)


def read_netcdf(path):
    """Read a run back into memory (times stay float seconds).

    A path that is not a readable netCDF file raises :class:`~mol_shell._core.errors.ParameterError` naming it.
    """
    allowed = "a netCDF file"
    try:
        path = Path(os.fspath(path)).expanduser()
    except TypeError:
        raise ParameterError.not_a("path", path, "a file path", allowed) from None
    if not str(path).strip():
        raise ParameterError.invalid("path", str(path), "does not exist", allowed)
    problem = absent(path)  # a name too long for the file system: Path.exists raised it
    if problem:
        raise ParameterError.invalid("path", str(path), problem, allowed)
    if path.is_dir():
        raise ParameterError.invalid("path", str(path), "is a directory", allowed)
    problem = not_regular(path)  # a named pipe nobody writes to: netCDF's open waited on it for ever
    if problem:
        raise ParameterError.invalid("path", str(path), problem, allowed)
    try:
        return _load(path)
    except (OSError, ValueError, RuntimeError) as exc:
        raise ParameterError.invalid("path", str(path), "cannot be read", allowed, hint=_unreadable(exc)) from None


def _load(path):
    """The whole file in memory; a Ctrl-C while it is read is raised once the file is closed (as for writing, the
    libraries' locks: :func:`write_netcdf`). A path that is not UTF-8 is read through a link of a name that is
    (:func:`~mol_shell._core.atomic.utf8_alias`): netCDF's library cannot encode it. Only a regular file is opened
    (a named pipe would be waited on, deaf to signals, in netCDF's library)."""
    problem = not_regular(path)
    if problem:
        raise UserFileError(errno.EINVAL, problem)
    with interrupts.held(), utf8_alias(path) as alias, xr.open_dataset(alias, engine="netcdf4",
                                                                        decode_times=False) as ds:
        return ds.load()


def _unreadable(exc):
    """Why a file could not be read as netCDF, in a few words."""
    return "not a netCDF file" if "Unknown file format" in str(exc) or "HDF" in str(exc) else str(exc)


RUN_FILE = "a netCDF file written by mol-shell run"


def read_run(path, name="FILE", allowed=RUN_FILE, what="a mol_shell run file"):
    """Read a file written by ``mol-shell run`` (or :func:`write_netcdf` of a run); refuse anything else by name.

    A run file holds ``r``, ``theta`` and ``chi`` on ``(time, s)``. Parameter studies, work-precision
    comparisons, stability reports and modes are netCDF files too, but not runs. ``allowed`` and ``what``: what the
    refusal says the caller accepts (a command that reads other files too, as ``plot``, names them).
    """
    path = Path(os.fspath(path)) if path is not None and str(path) else None
    if path is None:
        raise ParameterError.invalid(name, "", "is empty", allowed)
    problem = absent(path)  # a name too long for the file system: Path.exists raised it
    if problem:
        raise ParameterError.invalid(name, str(path), problem, allowed)
    if path.is_dir():
        raise ParameterError.invalid(name, str(path), "is a directory", allowed)
    problem = not_regular(path)  # a named pipe nobody writes to: netCDF's open waited on it for ever
    if problem:
        raise ParameterError.invalid(name, str(path), problem, allowed)
    try:
        ds = _load(path)
    except (OSError, ValueError, RuntimeError) as exc:
        raise ParameterError.invalid(name, str(path), f"is not {what}", allowed,
                                     hint=_unreadable(exc)) from None
    if not is_run(ds):
        raise ParameterError.invalid(name, str(path), f"is not {what}", allowed, hint=f"it holds {holdings(ds)}")
    return ds


def is_run(ds):
    """Whether Dataset ``ds`` is one run's: ``r``, ``theta`` and ``chi`` on ``(time, s)``, with the coordinate ``s``
    (a study's case selected with ``isel`` is, unless its study's grids differ between cases, whose ``s`` has no
    coordinate: :func:`mol_shell.results.study_dataset.study_case` gives that case as a run; the study, a path,
    modes and the reduced ring ODE's run are not)."""
    return all(v in ds and ds[v].dims == ("time", "s") for v in ("r", "theta", "chi")) and "s" in ds.coords


def holdings(ds):
    """What a Dataset that is not a run holds, in a few words, as a refusal says it (``a parameter study
    (mol-shell study) over gamma``)."""
    title = str(ds.attrs.get("title", ""))
    vary = [str(d) for d in ds.dims if d not in ("time", "s", "s_cell", "zeta", "end")]
    return ("a study of equilibrium paths (mol-shell study --path)" if "study of equilibrium paths" in title else
            "a case of a parameter study whose grids differ between cases, without its coordinate s "
            "(mol_shell.results.study_dataset.study_case(STUDY, ...) gives a case as its run)"
            if "parameter study" in title and not vary and "s_case" in ds.coords else
            "a parameter study (mol-shell study)" + (f" over {', '.join(vary)}" if vary else "")
            if "parameter study" in title else
            "an equilibrium path (mol-shell path)" if "equilibrium path" in title else
            "a work-precision comparison (mol-shell compare)" if "work-precision" in title else
            "a stability report (mol-shell stability)" if "leapfrog_dt_bound" in ds else
            "natural modes (mol-shell modes)" if "natural modes" in title else
            "the reduced ring ODE's run (simulate_ring)" + (", without s" if "s" not in ds.coords else "")
            if "reduced ODE" in title else
            f"dims {', '.join(map(str, ds.dims)) or 'none'}")
