"""Going on along an equilibrium path from one of its steps: :func:`continue_path` (``mol-shell path --from``).

A path that ended short of where it is wanted (``max_steps``, a stop too near, a corrector that failed at a hard
spot) is continued from a step of its file rather than traced again: the step's state is the start (Newton
polishes it); towards a ``stop`` on from the step the way the path went, the displacements since the step before
orient the first tangent (so a path past a limit point goes on along its branch instead of turning back to the fold),
towards one back towards its start the tangent heads for ``stop``; and the scene is the path's own (its name and
parameters from the file's attrs, :func:`~mol_shell.analysis.path_start.path_scene`). The continuation is a path of
its own: its step 0 is the step it left, its critical points those it meets from there.
"""

from __future__ import annotations

import math
import os

import numpy as np

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.analysis.path import path
from mol_shell.analysis.path_start import ALLOWED, KEYWORDS, checked_path, path_scene, path_start, read_path
from mol_shell.model.kinematics import FIELDS


def onwards(source, value, stop):
    """Whether ``stop`` lies on from the load ``value`` the way path ``source`` went (from its ``start`` towards its
    ``stop``): then the continuation goes on as the path went (the way its displacements went from the step before,
    which past a fold leads away from ``stop`` at first, on along the branch); else it heads for ``stop`` (back towards the start:
    along the chord it ran away until ``max_steps``)."""
    start = float(source.attrs.get("start", source.parameter.values[0]))
    end = float(source.attrs.get("stop", source.parameter.values[-1]))
    return (stop - value) * (end - start) > 0


def scales_of(source, name="source", shown="<xarray.Dataset>"):
    """The arclength's scales path ``source`` stepped in (its attrs; ``None`` for a file written before they were
    recorded: the continuation weighs at its own start); a value that is no finite positive number is refused
    naming ``name`` (the path, said as ``shown``)."""
    keys = ("arclength_displacement_scale", "arclength_load_scale")
    if not all(k in source.attrs for k in keys) or source.sizes["step"] < 2:  # a path that took no step (one that
        return None  # failed at its start, its range too wide) has no metric worth keeping
    for key in keys:
        value = source.attrs[key]
        if not (is_number(value) and 0 < value < math.inf):
            raise ParameterError.invalid(name, shown, f"holds {key} = {value!r}, not a finite positive number",
                                         ALLOWED)
    return tuple(float(source.attrs[k]) for k in keys)


#: how :func:`continue_path`'s refusals name the path and the step: its own parameters (``source``, ``step``)
NAMES = {**KEYWORDS, "ds": "source"}


def continue_path(source, stop, *, step=None, steps=20, max_steps=200, ds=None, branch=None, progress=None):
    """Follow path ``source`` on from its step ``step`` (default: its last) to ``stop``.

    Parameters
    ----------
    source : xarray.Dataset or path
        A path (:func:`mol_shell.path`'s Dataset or its netCDF file; a continuation's too).
    stop : float
        Where the continued load goes (its units the path's, ``attrs["parameter_units"]``).
    step : int, optional
        The step to go on from (``0 .. steps - 1``; default the last).
    steps, max_steps, ds, branch, progress
        As :func:`mol_shell.path`'s, for the continuation (``ds`` the first arclength step, as there).

    Returns
    -------
    xarray.Dataset
        The continuation, a path from the step's load to ``stop`` (its step 0 is the step it left); attrs
        ``continued_from`` (the file or Dataset, the step and its load) and ``initial_state``.

    Raises
    ------
    ParameterError
        Named by the parameter at fault: ``source`` (no path, or a file that holds no usable one), ``step``,
        ``stop``, or :func:`mol_shell.path`'s keywords.
    """
    return continue_named(source, stop, NAMES, step=step, steps=steps, max_steps=max_steps, ds=ds, branch=branch,
                          progress=progress)


def continue_named(source, stop, names, *, step=None, steps=20, max_steps=200, ds=None, branch=None, progress=None):
    """:func:`continue_path` with its refusals naming the path and the step as ``names`` says (``names["ds"]`` the
    path, ``names["step"]`` the step: :data:`NAMES`, or :data:`~mol_shell.analysis.path_start.FLAGS` for the command
    line's ``--from`` and ``--step``)."""
    shown = str(source) if isinstance(source, (str, os.PathLike)) else "<xarray.Dataset>"
    named = os.path.abspath(source) if isinstance(source, (str, os.PathLike)) else getattr(source, "encoding", {}).get(
        "source", shown)  # continued_from names the file wherever it is read from
    if not is_number(stop) or not math.isfinite(stop):
        raise ParameterError.not_a("stop", stop, "a finite number", "(-inf, inf)")
    source = read_path(source, names["ds"]) if isinstance(source, (str, os.PathLike)) else checked_path(
        source, names["ds"])
    count = source.sizes["step"]
    k = count - 1 if step is None else step
    _, n, fields, info = path_start(source, step=k, names=names)
    k = int(k)
    parameter, units = str(source.attrs["parameter"]), str(source.attrs.get("parameter_units", ""))
    value = float(source.parameter.values[k])
    scene = path_scene(source, float(source.attrs.get("parameter_scene_value", 0.0)), names)
    heading = None
    if k > 0 and onwards(source, value, stop):  # the step before orients the first tangent
        heading = np.stack([source[f].values[k - 1] for f in FIELDS])
    try:
        out = path(scene, parameter, value, stop, n, steps=steps, max_steps=max_steps, ds=ds, branch=branch,
                   initial=fields, heading=heading, scales=scales_of(source, names["ds"], shown), progress=progress)
    except ParameterError as exc:
        if not getattr(exc, "residual", None):
            raise
        # the step's state, out of equilibrium under the file's scene (its attributes edited): refused by the file
        error = ParameterError.invalid(names["ds"], shown, f"holds a state at step {k} that is no equilibrium under "
                                       f"its scene ({exc.residual})", ALLOWED)
        error.residual = exc.residual
        raise error from None
    out.attrs["continued_from"] = f"{named}, step {k} of {count} ({parameter} = {value:.10g} {units})"
    out.attrs["initial_state"] = info
    return out
