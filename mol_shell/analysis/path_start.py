"""Starting a run or a modes analysis from an equilibrium path: a step's state, or a critical point's, perturbed.

A path file (:func:`mol_shell.analysis.path.path`) keeps the scene's name and parameters in its attrs (the
continued load left out: a value the scene gave it is ``parameter_scene_value``, replaced by the path's) and the
equilibrium fields at every step (``z, r, chi, theta, psi`` on ``(step, s)``) and at every critical point
(``point_z, ...`` on ``(point, s)``) with the critical mode (``point_mode_*``, scaled to a largest entry of 1).
:func:`path_start` gives back the scene with the continued load at that state's value and constant in time
(whatever history the scene gave it), the grid and the fields, at rest. ``perturb`` adds ``perturb x`` the
critical mode: a launch of post-buckling dynamics (``mol-shell run --from path.nc --point K --perturb A``). The mode is 0 on imposed and gauge-held
coordinates, so the edges stay where they were.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from pathlib import Path

import numpy as np

from mol_shell._core.errors import ParameterError, is_number, kind_of
from mol_shell._core.user_files import absent, name_from_text
from mol_shell.model.edges import EDGE_PARAMETERS
from mol_shell.model.kinematics import FIELDS
from mol_shell.model.laws import renamed_law, renamed_layers
from mol_shell.results.dataset import read_netcdf
from mol_shell.scenes import SCENES, get_scene
from mol_shell.scenes.files import FILE_KEYS

ALLOWED = "a netCDF file written by mol-shell path"
#: how :func:`path_start` names its parameters in its refusals: as Python's keywords, or as the command line's flags
#: (``mol-shell run/modes --from``; it named the flags to Python callers too: ``--step = 999 is outside ...``)
KEYWORDS = {"ds": "ds", "step": "step", "point": "point", "perturb": "perturb"}
FLAGS = {"ds": "--from", "step": "--step", "point": "--point", "perturb": "--perturb"}


def is_path(ds):
    """Whether Dataset ``ds`` is an equilibrium path."""
    return "step" in ds.dims and "parameter" in ds and "parameter" in ds.attrs and "r" in ds \
        and ds["r"].dims == ("step", "s")


def read_path(filename, name="--from"):
    """Read a path file; anything else is refused naming ``name``."""
    path = Path(os.fspath(filename)) if filename is not None and str(filename) else None
    problem = "is not a file" if path is None else absent(path)  # a name too long: Path.is_file raised it
    if problem is None and not path.is_file():
        problem = "is not a file"
    if problem:
        raise ParameterError.invalid(name, str(filename), problem, ALLOWED)
    try:
        ds = read_netcdf(path)
    except (OSError, ValueError, RuntimeError):
        raise ParameterError.invalid(name, str(path), "is not a netCDF file", ALLOWED) from None
    return checked_path(ds, name, str(path))


def checked_path(ds, name="ds", shown=None):
    """``ds`` if it is an equilibrium path of a registered scene, else refused naming ``name`` (its value said as
    ``shown``: a file's name, or the kind of object given)."""
    allowed = ALLOWED if shown is not None else "the Dataset of mol_shell.path, or its netCDF file"
    shown = shown if shown is not None else f"<{kind_of(ds)}>"
    if not (hasattr(ds, "attrs") and hasattr(ds, "dims") and hasattr(ds, "data_vars")) or not is_path(ds):
        dims = ", ".join(map(str, getattr(ds, "dims", ()))) or "none"
        raise ParameterError.invalid(name, shown, "is not an equilibrium path", allowed, hint=f"it holds dims {dims}")
    scene = str(ds.attrs.get("scene", ""))
    if scene not in SCENES:  # edited or damaged: the states belong to no scene this code knows
        raise ParameterError.invalid(name, shown, "has no scene attribute" if "scene" not in ds.attrs else
                                     f"names no registered scene in its attribute scene = {scene!r}", allowed)
    return ds


def scene_params(ds):
    """``{name: value}``: the parameters of the scene of a path or run file ``ds`` (a registered scene's, its
    ``attrs["scene"]``) as they were asked for, from its attrs: those left to the code (``NAME_requested = "auto"``)
    ``None`` again, those run with the opposite sign (a vessel drawn down) as given, a law renamed since by its name
    now, a file's name (a meridian's ``points``) stored escaped (its bytes that are not UTF-8) as its own again."""
    fields = {f.name for f in dataclasses.fields(SCENES[str(ds.attrs["scene"])])}
    params = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in ds.attrs.items() if k in fields}
    for k in fields & params.keys():  # left to the code when the path was traced (stored as the values used): again
        if ds.attrs.get(f"{k}_requested") == "auto" or k in EDGE_PARAMETERS and params[k] == "none":  # (0.5.0's)
            params[k] = None
    for k in fields & set(str(ds.attrs.get("reversed_parameters", "")).split(", ")):  # run with the opposite sign
        if f"{k}_requested" in ds.attrs:  # (a vessel's segments drawn down): as given, which the scene turns again
            given = ds.attrs[f"{k}_requested"]
            params[k] = given.item() if isinstance(given, np.generic) else given
    for k in fields & params.keys() & set(FILE_KEYS):  # a file name that is not UTF-8: stored escaped (\xfc)
        params[k] = name_from_text(params[k])
    version = ds.attrs.get("mol_shell_version", "")
    if "material" in params:  # a law renamed since the file was written: by its name now
        params["material"] = renamed_law(params["material"], version)
    if params.get("layers"):
        params["layers"] = renamed_layers(params["layers"], version)
    return params


def path_scene(ds, value, names=FLAGS):
    """The scene of path ``ds`` (its name and parameters from the attrs: :func:`scene_params`) with the continued
    load at ``value`` (``names``: :data:`FLAGS` or :data:`KEYWORDS`, how a refusal names the path)."""
    name = str(ds.attrs["scene"])
    if name not in SCENES:
        raise ParameterError.invalid(names["ds"], name, "names no registered scene", ALLOWED)
    fields = {f.name for f in dataclasses.fields(SCENES[name])}
    params = scene_params(ds)
    params[str(ds.attrs["parameter"])] = float(value)
    if str(ds.attrs["parameter"]) + "_history" in fields:  # the path's states are at rest under a constant load
        params[str(ds.attrs["parameter"]) + "_history"] = "constant"
    scene = get_scene(name, **params)
    then, now = str(ds.attrs.get("meridian", "")), scene.meridian().describe() if hasattr(scene, "meridian") else ""
    if "sha256" not in then:  # a path written before descriptions carried the points' digest: compared without it
        now = re.sub(r", sha256 [0-9a-f]+\)$", ")", now)
    if then and now and then != now and "points" in ds.attrs:  # a points file edited since the path was traced
        raise ParameterError.invalid("points", str(ds.attrs["points"]), "describes another meridian now",
                                     f"the meridian the path ({names['ds']}) was traced on",
                                     hint=f"the path's: {then}; now: {now}")
    if then and now and then != now:  # a scene drawn differently by this version (a vessel drawn down, say)
        raise ParameterError.invalid(names["ds"], str(ds.encoding.get("source", name)),
                                     f"was traced on a {name} meridian this version draws differently",
                                     "a path traced by this version (trace it again)",
                                     hint=f"the path's: {then}; now: {now}")
    return scene


#: the largest perturbation, as a share of the shell's size (the largest |z| or r of the state)
PERTURB_SHARE = 0.1


def _check_perturbation(amplitude, fields, mode, name="--perturb"):
    """Refuse an amplitude of the critical mode (largest entry 1) that is no perturbation: beyond
    :data:`PERTURB_SHARE` of the shell's size, or one that takes ``r`` to 0 or below at a node off the axis. A run
    from there failed on whatever check met it first (the step bound, a solver error at t = 0, r <= 0)."""
    size = float(np.abs(fields[:2]).max())
    low, high = -PERTURB_SHARE * size, PERTURB_SHARE * size
    r, dr = fields[1], mode[1]
    off_axis = r > 0
    if np.any(off_axis & (dr < 0)):
        high = min(high, float(np.min(r[off_axis & (dr < 0)] / -dr[off_axis & (dr < 0)])))
    if np.any(off_axis & (dr > 0)):
        low = max(low, float(np.max(-r[off_axis & (dr > 0)] / dr[off_axis & (dr > 0)])))
    if not low < amplitude < high and amplitude != 0:
        raise ParameterError(name, amplitude, f"({low:.4g}, {high:.4g}) m or rad (a perturbation: at most "
                             f"{PERTURB_SHARE:g} of the shell's size, {size:.4g} m, with r > 0 off the axis)")


def _index(value, name, count, what):
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or not 0 <= value < count:
        allowed = f"integers 0..{count - 1} (the path's {what})" if count else f"none: the path has no {what}"
        raise ParameterError(name, value, allowed)
    return int(value)


def path_start(ds, *, step=None, point=None, perturb=0.0, names=KEYWORDS):
    """``(scene, n, fields, info)``: where a run or modes analysis starts from path ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset or path
        A path (:func:`read_path`), or its file.
    step, point : int
        One of them: the step (``0 .. steps - 1``) or the critical point (``0 .. points - 1``).
    perturb : float
        Amplitude of the critical mode added to a critical point's state (m or rad: the mode's largest entry is
        1); only with ``point``.
    names : dict
        How refusals name the parameters: :data:`KEYWORDS` (Python's, the default) or :data:`FLAGS` (the command
        line's ``--from``, ``--step``, ``--point``, ``--perturb``).

    Returns
    -------
    scene : ShellScene
        The path's scene with the continued load at the state's value.
    n : int
        The path's nodes.
    fields : ndarray
        ``(5, n)``: ``z, r, chi, theta, psi`` at rest.
    info : str
        Where the state comes from (for the attrs of what is computed from it).
    """
    ds = read_path(ds, "ds") if isinstance(ds, (str, os.PathLike)) else checked_path(ds, "ds")
    if (step is None) == (point is None):
        cli = names["step"].startswith("--")
        given = {k: f"{names[k]} K" if cli else f"{names[k]}=K" for k in ("step", "point")}
        also = f" with {names['ds']}" if cli else ""
        raise ParameterError(names["step"], step, f"one of {given['step']} or {given['point']}{also}",
                             message=f"give one of {given['step']} (a step) or {given['point']} (a critical point)"
                             f"{also}")
    if not is_number(perturb) or not math.isfinite(perturb):
        raise ParameterError.not_a(names["perturb"], perturb, "a finite number", "(-inf, inf) m or rad")
    name = str(ds.attrs["parameter"])
    units = str(ds.attrs.get("parameter_units", ""))
    if step is not None:
        if perturb:
            raise ParameterError(names["perturb"], perturb, f"0 with {names['step']} (the critical mode is a "
                                 f"point's: use {names['point']})")
        k = _index(step, names["step"], ds.sizes["step"], "steps")
        value = float(ds.parameter.values[k])
        fields = np.stack([ds[f].values[k] for f in FIELDS])
        info = f"equilibrium path step {k}: {name} = {value:.10g} {units}"
    else:
        k = _index(point, names["point"], ds.sizes.get("point", 0), "critical points")
        value = float(ds.point_parameter.values[k])
        fields = np.stack([ds[f"point_{f}"].values[k] for f in FIELDS])
        mode = np.stack([ds[f"point_mode_{f}"].values[k] for f in FIELDS])
        _check_perturbation(float(perturb), fields, mode, names["perturb"])
        fields = fields + float(perturb) * mode
        info = (f"equilibrium path critical point {k} ({ds.point_kind.values[k]}): {name} = {value:.10g} {units}"
                + (f", perturbed by {float(perturb):g} x its critical mode" if perturb else ""))
    where = f"step {k}" if step is not None else f"critical point {k}"
    bad = [f for f, values in zip(("parameter", *FIELDS), ([value], *fields)) if not np.all(np.isfinite(values))]
    if bad:  # a file edited or damaged since: refused by its name, not as the `initial` fields it would become
        prefix = "point_" if point is not None and bad[0] != "parameter" else ""
        raise ParameterError.invalid(names["ds"], ds.encoding.get("source", "<xarray.Dataset>"),
                                     f"holds values of {prefix}{bad[0]} at {where} that are not finite", ALLOWED)
    return path_scene(ds, value, names), int(ds.sizes["s"]), fields, info
