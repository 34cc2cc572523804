"""The inputs of :func:`mol_shell.analysis.path.path`, checked before anything is built.

The range ``|stop - start|`` is the scale of the load in the arclength (``lambda / |stop - start|``; the first
tangent has a load component ``1 / |stop - start|``). It must be a normal double: below the smallest one,
``2.2250738585072014e-308``, it is subnormal (fewer significant digits, and below ``1 / 1.8e308 = 5.6e-309`` its
reciprocal overflows, so the tangent and the arclength equation are no longer numbers). Above it every range
works as it does at any size: a load that small moves the shell linearly. A range that overflows (``-1e308`` to
``1e308``) is refused too.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.analysis.equilibria import PATH_PARAMETERS
from mol_shell.model.loads import history, parse_history
from mol_shell.runs import resources
from mol_shell.scenes import LOADS, UNITS

#: the smallest range ``|stop - start|`` a path takes: the smallest normal double
RANGE_MIN = float(np.finfo(float).tiny)
#: the largest: the largest double
RANGE_MAX = float(np.finfo(float).max)
#: the smallest range relative to ``max(|start|, |stop|)``: narrower, the loads a path steps through are a few
#: thousand doubles apart or fewer, and the corrector's noise is larger than its steps
RANGE_RELATIVE_MIN = 1e-9
#: the smallest first step ``ds`` (scaled arclength): 100 times the corrector's tolerance (``path.TOL``), below
#: which its noise turns steps around (``ds = 1e-300`` came back below start)
DS_MIN = 1e-8
#: the most ``steps``: the default first step, ``sqrt(2) / steps``, not below :data:`DS_MIN` (``steps = 1e23`` stopped
#: at a first step of 1.4e-23 whose corrector was noise: "left the predictor's neighbourhood", exit 3)
STEPS_MAX = int(math.sqrt(2.0) / DS_MIN)


def check_range(start, stop):
    """Refuse ``stop`` (naming it) when ``|stop - start|`` is 0, below :data:`RANGE_MIN` or above :data:`RANGE_MAX`."""
    if start == stop:
        raise ParameterError("stop", stop, f"values other than start = {start:g}")
    width = abs(float(stop) - float(start))
    if not RANGE_MIN <= width <= RANGE_MAX:
        raise ParameterError("stop", stop, f"values with {RANGE_MIN:.17g} <= |stop - start| <= {RANGE_MAX:.17g} "
                             f"(start = {start:g})", hint="the range scales the load in the arclength: a subnormal "
                             "one has too few digits and its reciprocal overflows")
    if width < RANGE_RELATIVE_MIN * max(abs(float(start)), abs(float(stop))):
        raise ParameterError("stop", stop, f"values with |stop - start| >= {RANGE_RELATIVE_MIN:g} x max(|start|, "
                             f"|stop|) (start = {start:.17g})", hint="a narrower range has too few doubles between "
                             "its ends to step through")


def check_shared(parameter, start, stop, scene_name=None):
    """Refuse a path's parameter or range, naming it: what does not depend on the scene (a path study's cases share
    it)."""
    if parameter not in PATH_PARAMETERS:
        raise ParameterError("parameter", parameter, "{" + ", ".join(PATH_PARAMETERS) + "}",
                             hint=f"the loads of scene {scene_name} a path can be continued in" if scene_name else "")
    for name, value in (("start", start), ("stop", stop)):
        if not is_number(value) or not math.isfinite(value):
            raise ParameterError.not_a(name, value, "a finite number", "(-inf, inf)")
    check_range(start, stop)


def check_inputs(scene, parameter, start, stop, n, steps, max_steps, ds, branch=None):
    """Refuse the first bad input of a path, naming it (``ParameterError``)."""
    check_shared(parameter, start, stop, scene.name)
    for value in (start, stop) if parameter in LOADS else ():  # the scene's own checks of a load, on the user's
        dataclasses.replace(scene, **{parameter: float(value)})  # values (not on the unit load used inside)
    for name, value, low in (("n", n, 3), ("steps", steps, 1), ("max_steps", max_steps, 1)):
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < low:
            raise ParameterError(name, value, f"integers >= {low}")
    if steps > STEPS_MAX:
        raise ParameterError("steps", steps, f"integers 1..{STEPS_MAX}", hint=f"the first step, sqrt(2) / steps of the "
                             f"scaled arclength, at least ds's least, {DS_MIN:g}: smaller ones are below the "
                             "corrector's noise")
    if ds is not None and not (is_number(ds) and math.isfinite(ds) and ds >= DS_MIN):
        raise ParameterError("ds", ds, f"[{DS_MIN:g}, inf), or None", hint="the first step in the scaled arclength; "
                             "smaller ones are below the corrector's noise")
    if branch is not None and (not isinstance(branch, (int, np.integer)) or isinstance(branch, bool) or branch < 0):
        raise ParameterError("branch", branch, "integers >= 0 (a critical point of the path), or None")
    resources.check_analysis(n, max_steps + 1, f"tracing a path of up to {max_steps} steps", "states",
                             fields=len(getattr(scene, "fields", range(5))), name="max_steps", value=max_steps,
                             fewer="allow fewer steps (--max-steps)")


def history_loads(scene, parameter=None, why="a path's states are at rest"):
    """One sentence per load of the scene other than ``parameter`` whose history makes its value at ``t = 0`` (``h(0)
    x`` the magnitude; a ramp, a sine and a later step give 0 there) differ from its magnitude, for states at rest
    (``why``: a path's, or the state natural modes are taken about), which take it at ``t = 0``; none for ``drag``,
    which vanishes at rest."""
    notes = []
    for load in LOADS:
        value = getattr(scene, load, 0.0)
        spec = getattr(scene, load + "_history", "constant")
        if load in (parameter, "drag") or not value or spec == "constant":
            continue
        factor = history(parse_history(load + "_history", spec), 0.0)
        if factor != 1.0:
            notes.append(f"the scene's {load} = {value:g} {UNITS[load]} ({load}_history {spec!r}) acts at its value at "
                         f"t = 0 in every state, {factor * value:g} {UNITS[load]} ({why}; "
                         f"{load}_history = constant holds {value:g})")
    return notes


def loads_at_rest(scene, parameter):
    """What each of the scene's other loads is in the path's states, when its history makes that differ from its
    magnitude (:func:`history_loads`), and a sentence for a spin ``omega``, left out, and for a twist ``gamma`` or
    tilt ``psi0``, initial data only."""
    notes = history_loads(scene, parameter)
    if getattr(scene, "omega", 0.0):  # initial data of a motion: the states are at rest
        notes.append(f"the scene's omega = {scene.omega:g} rad s-1 is left out: a path's states are at rest")
    for name, unit in (("gamma", "rad m-1"), ("psi0", "rad")):  # initial data too: the path starts from them only
        if getattr(scene, name, 0.0):
            notes.append(f"the scene's {name} = {getattr(scene, name):g} {unit} is initial data: a path's states are "
                         "equilibria at rest, where edges that leave chi free let a twist unwind (end1_dchi, end2_dchi "
                         "on edges that hold chi keep one)")
    return notes


def check_start(initial, heading, scales):
    """Refuse a path's ``heading`` or ``scales`` that is not one (``initial``'s fields are checked as a state is)."""
    if heading is not None and initial is None:  # its fields are checked as a state is, named heading
        raise ParameterError("heading", "<given>", "None without initial (it orients the path from initial)")
    if scales is not None:
        values = list(scales) if isinstance(scales, (tuple, list, np.ndarray)) else None
        if values is None or len(values) != 2 or not all(is_number(v) and 0 < v < math.inf for v in values):
            raise ParameterError("scales", scales, "(displacement factor, load scale): two finite positive numbers, "
                                 "or None")
