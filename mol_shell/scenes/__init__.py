"""Scenes: frozen dataclasses holding every physical parameter of a run, and their registry.

Vary a scene with :func:`dataclasses.replace` (or :func:`with_params` from strings, as the CLI
does); a bad value raises :class:`~mol_shell._core.errors.ParameterError` naming the parameter and its
allowed range.
"""

from __future__ import annotations

from mol_shell._core.errors import ParameterError
from mol_shell.scenes.base import (
    DESCRIPTIONS,
    DISPLACEMENTS,
    DRIVES,
    LOADS,
    N_QUAD_RANGE,
    UNITS,
    ShellScene,
    _check,
    _coerce,
    check_radius,
    describe,
    with_params,
    zeta1_used,
)
from mol_shell.scenes.cylinder import Axisymmetric, CylinderScene, SpinningRing, TwistedCylinder
from mol_shell.scenes.segments import Vessel
from mol_shell.scenes.shells import Cone, MeridianShell, Sphere, Torus
from mol_shell.scenes.unshearable import UNSHEARABLE_INTEGRATORS, Unshearable

SCENES = {cls.name: cls for cls in (TwistedCylinder, SpinningRing, Axisymmetric, Sphere, Cone, Torus, MeridianShell,
                                  Unshearable, Vessel)}


def get_scene(name, **params):
    """The scene registered as ``name`` with parameters replaced by ``params``."""
    if name not in SCENES:
        raise ParameterError("scene", name, "{" + ", ".join(sorted(SCENES)) + "}")
    cls = SCENES[name]
    if cls is MeridianShell and "points" in params:  # the scene is made with its file first
        params = dict(params)
        return with_params(MeridianShell(points=params.pop("points")), params)
    return with_params(cls(), params)


__all__ = [
    "DESCRIPTIONS", "DISPLACEMENTS", "DRIVES", "LOADS", "N_QUAD_RANGE", "SCENES", "UNITS", "Axisymmetric", "Cone", "CylinderScene", "MeridianShell",
    "ShellScene", "SpinningRing", "Sphere", "Torus", "TwistedCylinder", "UNSHEARABLE_INTEGRATORS", "Unshearable", "Vessel", "check_radius", "describe", "get_scene", "with_params",
    "zeta1_used", "_check", "_coerce",
]
