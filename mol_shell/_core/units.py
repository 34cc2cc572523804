"""Quantities as messages show them."""

from __future__ import annotations


def show_seconds(value):
    """A duration for a message: ``3.2 s``, ``1.8 min``, ``2.5 h``, ``4 days``."""
    for unit, size in (("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if value >= size:
            return f"{value / size:.3g} {unit}"
    return f"{value:.3g} s"
