"""The allowed range of every scene parameter, as the scene's own checks declare it.

A scene checks its parameters in ``__post_init__`` and refuses a value with a
:class:`~mol_shell._core.errors.ParameterError` that carries the declared range
(:class:`~mol_shell._core.ranges.Interval` or :class:`~mol_shell._core.ranges.Choice`) as ``range``.
:func:`scene_ranges` asks each check with a value no range admits (NaN, or a string that names
nothing) and reads the range it declares, so code that needs the ranges (the refusal of the
numerically impossible, the property-based tests) follows the checks of every registered scene,
new ones included, with the other parameters as given, without a table of its own.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import warnings

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Interval


def _probe(scene, name, value):
    try:
        dataclasses.replace(scene, **{name: value})
    except ParameterError as exc:
        if exc.name == name:
            return exc.range
    except (TypeError, ValueError):
        return None
    return None


def parameter_range(scene, name):
    """The :class:`Interval` (or :class:`Choice`) the scene's check declares for ``name``, or ``None``."""
    field = {f.name: f for f in dataclasses.fields(scene)}[name]
    if "str" in str(field.type) and "float" not in str(field.type):
        return _probe(scene, name, "\x00not a value\x00")
    return _probe(scene, name, math.nan)


def _refusal(scene, name, value):
    with warnings.catch_warnings(), np.errstate(all="ignore"):  # a huge value's overflows are the checks' business
        warnings.simplefilter("ignore")
        try:
            dataclasses.replace(scene, **{name: value})
        except ParameterError as exc:
            return exc if exc.name == name else None
        except (TypeError, ValueError, ArithmeticError):
            return None
    return None


def parameter_bounds(scene, name):
    """The declared :class:`Interval` of ``name`` narrowed at an infinite end by a check that depends on the other
    parameters and declares an interval (the twisted cylinder's ``h < a/2``, which a NaN does not reach: the base
    check of ``h``, ``(0, inf)``, refuses it first), found by asking the checks with half the largest double beyond
    that end; ``None`` when ``name`` has no declared interval. A check that states its range only in words (a wall
    off the axis) is not asked: the declared range's ``shown`` says it (``(0, inf) m, and the thickness off the
    axis``)."""
    allowed = parameter_range(scene, name)
    if not isinstance(allowed, Interval):
        return None
    for end, probe in (("high", sys.float_info.max / 2), ("low", -sys.float_info.max / 2)):
        exc = None if math.isfinite(getattr(allowed, end)) else _refusal(scene, name, probe)
        other = None if exc is None else exc.range
        if isinstance(other, Interval) and end == "high" and other.high < allowed.high:
            allowed = dataclasses.replace(allowed, high=other.high, high_closed=other.high_closed, shown="")
        elif isinstance(other, Interval) and end == "low" and other.low > allowed.low:
            allowed = dataclasses.replace(allowed, low=other.low, low_closed=other.low_closed, shown="")
    return allowed


def scene_ranges(scene):
    """``{parameter: Interval | Choice | None}`` for every field of ``scene`` (an instance or a scene class)."""
    if isinstance(scene, type):
        scene = scene()
    return {f.name: parameter_range(scene, f.name) for f in dataclasses.fields(scene)}
