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

from mol_shell._core.errors import ParameterError


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


def scene_ranges(scene):
    """``{parameter: Interval | Choice | None}`` for every field of ``scene`` (an instance or a scene class)."""
    if isinstance(scene, type):
        scene = scene()
    return {f.name: parameter_range(scene, f.name) for f in dataclasses.fields(scene)}
