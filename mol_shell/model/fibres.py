"""Fibre reinforcement on any law: helical families in the reference tangent plane (the paper's Figure 1c).

A family of fibres has the reference direction ``a = cos(alpha) b0_1 + sin(alpha) b0_3``: ``alpha`` from the
meridian direction ``b0_1`` towards the circumferential direction ``b0_3 = +phi`` (the reference tangent plane at
every depth ``zeta``; ``C`` of :func:`~mol_shell.model.hyperelastic.shell_cauchy_green` is written in that
orthonormal basis, index 0 the meridian, 2 the circumference). Each family adds the standard reinforcing energy

    W_f = (E_f / 2) (a . E a)^2,   a . E a = (cos^2 alpha (C_11 - 1) + 2 cos alpha sin alpha C_13 + sin^2 alpha (C_33 - 1)) / 2,

``E = (C - I)/2`` the Green strain (``= E_f/8 (I4 - 1)^2``, ``I4 = a . C a``); with ``compression = False`` the
fibres carry tension only: ``(E_f / 2) max(a . E a, 0)^2``, an energy with a continuous first derivative (the
stress) whose tangent jumps where a fibre goes slack. ``a`` lies in the tangent plane, so ``W_f`` does not depend
on the thickness component ``C_22``: a law's plane-stress or incompressible condensation is unchanged and the
fibres are added after it.

``C_13`` carries the shell's twist: ``C_13 = (r^2 chi_s + zeta (...)) j1 j3`` (``beta3 = r chi_s``, eq. 2.18), so
one family at ``0 < alpha < pi/2`` couples stretch and inflation with twist, the rotationally symmetric but not
axisymmetric anisotropy of the paper's Comments. Two balanced families (``+alpha`` and ``-alpha``) cancel the
coupling.

A scene with ``fibre_E = 0`` (the default) has no fibres: nothing of this module is in its graph.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca

from mol_shell._core.ranges import Interval
from mol_shell.model.hyperelastic import shell_cauchy_green
from mol_shell.model.kinematics import column_polynomials

#: the scene parameters of the fibres (all but fibre_E are unused when fibre_E = 0)
FIBRE_PARAMETERS = ("fibre_E", "fibre_angle", "fibre_families", "fibre_compression")
#: their defaults
FIBRE_DEFAULTS = {"fibre_E": 0.0, "fibre_angle": 0.0, "fibre_families": 1, "fibre_compression": True}
#: fibre angles from the meridian: each direction of the tangent plane once (alpha and alpha + pi are one fibre)
#: (to 1e-3 rad: pi/2 as typed, 1.5708 or 1.571, is the hoop direction)
FIBRE_ANGLES = Interval(-math.pi / 2 - 1e-3, math.pi / 2 + 1e-3, True, True, unit="rad", shown="[-pi/2, pi/2] rad")


def fibre_angle_hint(angle):
    """What a ``fibre_angle`` outside :data:`FIBRE_ANGLES` may have meant: the same fibre in range, or degrees."""
    if not (isinstance(angle, (int, float)) and math.isfinite(angle)):
        return ""
    same = math.remainder(angle, math.pi)
    degrees = f"; {angle:g} degrees would be {math.radians(angle):.6g} rad" if abs(angle) <= 90 else ""
    return f"in rad: the same fibre is {same:.6g} rad{degrees}"


@dataclass(frozen=True)
class Fibres:
    """Fibre reinforcement: modulus ``E`` (Pa), angle ``angle`` (rad, from the meridian towards ``+phi``),
    ``families`` 1 (one helix) or 2 (``+angle`` and ``-angle``), ``compression`` (False: tension only)."""

    E: float
    angle: float
    families: int = 1
    compression: bool = True

    @property
    def directions(self):
        """``(cos alpha, sin alpha)`` of each family."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        return ((c, s),) if self.families == 1 else ((c, s), (c, -s))


def fibre_strain(C, direction):
    """``a . E a`` for ``a = (cos, 0, sin)`` in the reference basis, ``E = (C - I)/2``."""
    c, s = direction
    return 0.5 * (c * c * (C[0][0] - 1.0) + 2.0 * c * s * C[0][2] + s * s * (C[2][2] - 1.0))


def fibre_energy(C, fibres):
    """``sum over families (E_f / 2) (a . E a)^2`` per unit reference volume (tension only: ``max(a.E a, 0)``)."""
    total = 0.0
    for direction in fibres.directions:
        e = fibre_strain(C, direction)
        if not fibres.compression:
            e = ca.fmax(e, 0.0) if isinstance(e, (ca.SX, ca.MX)) else max(e, 0.0)
        total = total + 0.5 * fibres.E * e * e
    return total


def fibre_thickness_energy(strains, fibres, factors, beta2_0=0.0, trig=None):
    """``sum_q vol_q W_f(C_q)``: the fibres' share of :func:`~mol_shell.model.hyperelastic.law_thickness_energy`."""
    a, b, c, d, c2 = column_polynomials(strains, beta2_0, trig)
    total = 0.0
    for zeta, j1, j3, vol in factors:
        total = total + vol * fibre_energy(shell_cauchy_green(a, b, c, d, c2, zeta, j1, j3), fibres)
    return total


def scene_fibres(scene):
    """The scene's :class:`Fibres`, or ``None`` when ``fibre_E = 0`` (then nothing of them is in any graph); the angle
    the scene runs with (a vessel drawn down runs backwards, one family at ``-fibre_angle``: its ``ran_values``)."""
    E = getattr(scene, "fibre_E", 0.0)
    if not E:
        return None
    angle = getattr(scene, "ran_values", dict)().get("fibre_angle", scene.fibre_angle)
    return Fibres(float(E), float(angle), int(scene.fibre_families), bool(scene.fibre_compression))


def unused_fibres_warning(scene):
    """One line when fibre parameters are set but ``fibre_E = 0`` leaves them unused, or ``None``."""
    if getattr(scene, "fibre_E", 0.0):
        return None
    changed = [name for name in FIBRE_PARAMETERS[1:] if getattr(scene, name, FIBRE_DEFAULTS[name]) != FIBRE_DEFAULTS[name]]
    if not changed:
        return None
    return (", ".join(f"{name} = {getattr(scene, name)}" for name in changed)
            + " is unused: fibre_E = 0 (no fibres); set fibre_E > 0 (Pa) to reinforce the wall")
