"""The allowed range of every scene parameter, as the scene's own checks state it.

A scene checks its parameters in ``__post_init__`` and names the allowed range in the
:class:`~mol_shell.errors.ParameterError` it raises (``"(0, 0.5) m: ..."``, ``"integers 2..32"``,
``"{svk, svk-plane-stress}"``, ``"finite values (rad/m)"``). :func:`scene_ranges` asks each check
with a value no range admits (NaN, or a string that names nothing) and parses the answer, so code
that needs the ranges (error messages, the property-based tests) follows the checks of every
registered scene, new ones included, without a table of its own.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

from mol_shell._core.errors import ParameterError

_DECIMAL = r"(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?"
_NUMBER = rf"[-+]?(?:inf|(?:{_DECIMAL})?\s*\*?\s*pi(?:\s*/\s*\d+)?|{_DECIMAL})"
_INTERVAL = re.compile(rf"([\[(])\s*({_NUMBER})\s*,\s*({_NUMBER})\s*([\])])", flags=re.I)
_INTEGERS = re.compile(r"integers\s+([-+]?\d+)\s*\.\.\s*([-+]?\d+)", flags=re.I)
_AT_LEAST = re.compile(r"integers\s*>=\s*([-+]?\d+)", flags=re.I)


def _number(text):
    """A number as the checks write it: ``0.5``, ``-inf``, ``1e-3``, ``pi/2``, ``-2 pi``."""
    text = text.replace(" ", "").replace("*", "").lower()
    if "pi" not in text:
        return float(text)
    sign = -1.0 if text.startswith("-") else 1.0
    factor, _, divisor = text.lstrip("+-").partition("pi")
    return sign * float(factor or 1.0) * math.pi / float(divisor.lstrip("/") or 1.0)
_CHOICE = re.compile(r"\{([^{}]*)\}")


@dataclass(frozen=True)
class Interval:
    """``low < x < high`` (or ``<=`` at a closed end); ``integer`` for integer parameters."""

    low: float
    high: float
    low_closed: bool = False
    high_closed: bool = False
    integer: bool = False
    unit: str = ""

    def __contains__(self, value):
        try:
            v = float(value)
        except (TypeError, ValueError, OverflowError):
            return False
        if math.isnan(v) or (self.integer and not v.is_integer()):
            return False
        above = v >= self.low if self.low_closed else v > self.low
        below = v <= self.high if self.high_closed else v < self.high
        return above and below

    def text(self):
        if self.integer:
            return f"integers {self.low:g}..{self.high:g}" if math.isfinite(self.high) else f"integers >= {self.low:g}"
        ends = f"{'[' if self.low_closed else '('}{self.low:.4g}, {self.high:.4g}{']' if self.high_closed else ')'}"
        return ends + (f" {self.unit}" if self.unit else "")

    def with_low(self, low, closed=True):
        return dataclasses.replace(self, low=low, low_closed=closed)

    def with_high(self, high, closed=True):
        return dataclasses.replace(self, high=high, high_closed=closed)


@dataclass(frozen=True)
class Choice:
    """One of a set of names."""

    values: tuple

    def __contains__(self, value):
        return value in self.values

    def text(self):
        return "{" + ", ".join(self.values) + "}"


def parse_allowed(text):
    """An :class:`Interval` or :class:`Choice` from a check's ``allowed`` text; ``None`` if it names neither."""
    text = str(text)
    found = _AT_LEAST.search(text)
    if found:
        return Interval(float(found.group(1)), math.inf, True, False, integer=True)
    found = _INTEGERS.search(text)
    if found:
        return Interval(float(found.group(1)), float(found.group(2)), True, True, integer=True)
    for found in _INTERVAL.finditer(text):
        low, high = _number(found.group(2)), _number(found.group(3))
        unit = re.match(r"\s*([A-Za-z/^0-9-]+(?: [A-Za-z/^0-9-]+)?)?", text[found.end():]).group(1) or ""
        unit = unit if unit and not unit.startswith(("for", "the", "and", "or")) else ""
        return Interval(low, high, found.group(1) == "[", found.group(4) == "]", unit=unit.split(":")[0])
    if text.lstrip().startswith("finite values"):
        unit = re.search(r"\(([^)]*)\)", text)
        return Interval(-math.inf, math.inf, unit=unit.group(1) if unit else "")
    found = _CHOICE.search(text)
    if found:
        return Choice(tuple(v.strip() for v in found.group(1).split(",") if v.strip()))
    return None


def _probe(scene, name, value):
    try:
        dataclasses.replace(scene, **{name: value})
    except ParameterError as exc:
        if exc.name == name:
            return exc.allowed
    except (TypeError, ValueError):
        return None
    return None


def allowed_text(scene, name):
    """What the scene's check of ``name`` says is allowed (with the other parameters as in ``scene``), or ``None``."""
    field = {f.name: f for f in dataclasses.fields(scene)}[name]
    if "str" in str(field.type) and "float" not in str(field.type):
        return _probe(scene, name, "\x00not a value\x00")
    return _probe(scene, name, math.nan)


def scene_ranges(scene):
    """``{parameter: Interval | Choice | None}`` for every field of ``scene`` (an instance or a scene class)."""
    if isinstance(scene, type):
        scene = scene()
    return {f.name: parse_allowed(allowed_text(scene, f.name) or "") for f in dataclasses.fields(scene)}


def parameter_range(scene, name):
    """The :class:`Interval` (or :class:`Choice`) the scene's check allows for ``name``, or ``None``."""
    return parse_allowed(allowed_text(scene, name) or "")
