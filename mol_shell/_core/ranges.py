"""Allowed ranges as objects: what a check accepts and how an error message states it.

A check declares its range as an :class:`Interval` or a :class:`Choice` and raises
:class:`~mol_shell._core.errors.ParameterError` with it; the error keeps the object (``exc.range``)
beside its text, so code that needs the range (the refusal of the numerically impossible, the
property-based tests) reads it from there, never from the message.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from dataclasses import dataclass

#: the smallest normal double: below it a number keeps fewer digits (a subnormal) or is 0
TINY = sys.float_info.min


@dataclass(frozen=True)
class Interval:
    """``low < x < high`` (or ``<=`` at a closed end); ``integer`` for integer parameters; ``normal`` for a
    parameter that must be 0 or a normal double, at least :data:`TINY` in magnitude (a modulus or a density: a
    subnormal one lost its digits in the products it enters, and ``E = 1e-320`` ran from a radius that ignored it).

    ``shown`` replaces the plain text of the range in messages where it says more
    (``"(a/2, 2a) = (0.5, 2) m"``); it never changes what is accepted.
    """

    low: float
    high: float
    low_closed: bool = False
    high_closed: bool = False
    integer: bool = False
    unit: str = ""
    shown: str = dataclasses.field(default="", compare=False)
    normal: bool = False

    def __contains__(self, value):
        try:
            v = float(value)
        except (TypeError, ValueError, OverflowError):
            return False
        if math.isnan(v) or (self.integer and not v.is_integer()) or (self.normal and 0 < abs(v) < TINY):
            return False
        above = v >= self.low if self.low_closed else v > self.low
        below = v <= self.high if self.high_closed else v < self.high
        return above and below

    def text(self):
        if self.shown:
            return self.shown
        if self.integer:
            return f"integers {self.low:g}..{self.high:g}" if math.isfinite(self.high) else f"integers >= {self.low:g}"
        if self.low == -math.inf and self.high == math.inf:
            return "finite values" + (f" ({self.unit})" if self.unit else "")
        if self.normal and self.low == 0 and self.high == math.inf:  # TINY in full: rounded, it would be below it
            return ("0 or " if self.low_closed else "") + f"[{TINY!r}, inf)" + (f" {self.unit}" if self.unit else "")
        ends = f"{'[' if self.low_closed else '('}{self.low:.4g}, {self.high:.4g}{']' if self.high_closed else ')'}"
        return ends + (f" {self.unit}" if self.unit else "")

    __str__ = text

    def with_low(self, low, closed=True):
        return dataclasses.replace(self, low=low, low_closed=closed, shown="")

    def with_high(self, high, closed=True):
        return dataclasses.replace(self, high=high, high_closed=closed, shown="")


def finite(unit=""):
    """Any finite value."""
    return Interval(-math.inf, math.inf, unit=unit)


def positive(unit=""):
    """``(0, inf)``."""
    return Interval(0.0, math.inf, unit=unit)


def non_negative(unit=""):
    """``[0, inf)``."""
    return Interval(0.0, math.inf, low_closed=True, unit=unit)


def modulus(unit, zero=False):
    """A modulus, viscosity or density: a normal double, at least :data:`TINY` (``[2.2250738585072014e-308, inf)``),
    or also 0 with ``zero``."""
    return Interval(0.0, math.inf, low_closed=zero, unit=unit, normal=True)


def subnormal(value):
    """Whether ``value`` is a nonzero number smaller in magnitude than :data:`TINY`."""
    try:
        return 0 < abs(float(value)) < TINY
    except (TypeError, ValueError, OverflowError):
        return False


@dataclass(frozen=True)
class Choice:
    """One of a set of names."""

    values: tuple

    def __contains__(self, value):
        return value in self.values

    def text(self):
        return "{" + ", ".join(self.values) + "}"

    __str__ = text
