"""What every meridian must be for the model to run it, whatever draws it (segments, a torus, a table of points).

The model runs an open curve in the half-plane ``r >= 0`` (:mod:`mol_shell.model.geometry`):

* no point at ``r < 0``, its ends included (a meridian past the axis: ``r = -0.01 m`` at the end of a vessel's
  segments stopped its run at ``t = 0`` with the model's limit, and ``modes`` listed modes of it);
* ``r = 0`` only at an end, a pole, whose tangent is perpendicular to the axis (``theta0 = pi/2`` leaving it at
  ``s = 0``, ``-pi/2`` reaching it at ``s = L``): the pole's conditions impose ``theta = theta0``, and a tangent at
  an angle to the axis is an apex, which is not a smooth shell (the cone's ``r1 = 0`` is refused alike);
* its ends apart: the model has no periodic meridian, so a closed one (a whole torus) ran as a tube slit along a
  circle, two free edges at one point. A tube symmetric about a plane ``z = const`` (a pressurised torus about its
  mid-plane) runs as its half between that plane's two circles, with magnet edges there (``z`` and ``theta``
  imposed: what the mirror symmetry imposes); motions antisymmetric about that plane are left out.

:func:`check_meridian` refuses, naming the parameter that drew the curve; a table of points is checked row by row
by :class:`~mol_shell.model.geometry.PointsMeridian` itself (naming the file and the line).
"""

from __future__ import annotations

import math

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.model.geometry import POLE_TOLERANCE, on_axis

#: a pole's tangent may differ from the normal to the axis by this, rad: the round-off of a meridian's formulas
POLE_TANGENT_TOLERANCE = 1e-9

#: what a full torus (a closed meridian symmetric about a plane z = const) runs as
HALF_TUBE = ("the model has no periodic meridian: a tube symmetric about a plane z = const (a torus under pressure, "
             "about its mid-plane) runs as its half between the two circles on that plane, with magnet edges there "
             "(end1 = end2 = magnet, the default: z and theta imposed, as the symmetry imposes), e.g. the torus's "
             "alpha1 = -pi/2, alpha2 = pi/2; modes antisymmetric about the plane are left out")


def meridian_problem(meridian, samples=2001):
    """Why the model cannot run ``meridian`` (module docstring), in words, or ``''``: sampled at ``samples`` arc
    lengths, its ends and the interior."""
    s = np.linspace(0.0, meridian.length, samples)
    r, z, theta, _ = meridian.at(s)
    size = max(float(np.max(np.abs(r))), float(np.max(np.abs(z))), meridian.length)
    ends = ((0, "first", math.pi / 2), (-1, "last", -math.pi / 2))
    if math.hypot(r[0] - r[-1], z[0] - z[-1]) <= POLE_TOLERANCE * max(1.0, size):
        return (f"its ends meet at (r, z) = ({r[0]:.6g}, {z[0]:.6g}) m: a closed meridian, which would run as a tube "
                f"slit there (two edges at one point); {HALF_TUBE}")
    for i, which, radial in ends:
        if on_axis(r[i], size):
            off = abs(math.remainder(float(theta[i]) - radial, 2 * math.pi))
            if off > POLE_TANGENT_TOLERANCE:
                return (f"its {which} point (r, z) = (0, {z[i]:.6g}) m is on the axis with its tangent at "
                        f"{math.degrees(off):.4g} degrees from the normal to the axis: an apex, not a smooth shell "
                        "(a pole leaves the axis at a right angle)")
        elif r[i] < 0:
            return f"its {which} point (r, z) = ({r[i]:.6g}, {z[i]:.6g}) m is past the axis (r < 0)"
    inner = r[1:-1] <= POLE_TOLERANCE * max(1.0, size)
    if np.any(inner):
        k = 1 + int(np.argmax(inner))
        return f"it reaches the axis at s = {s[k]:.4g} m (r = {r[k]:.4g} m), between its ends"
    return ""


def check_meridian(meridian, name, value, allowed, samples=2001):
    """Refuse ``meridian`` (:func:`meridian_problem`) with a :class:`ParameterError` naming ``name = value``."""
    problem = meridian_problem(meridian, samples)
    if problem:
        raise ParameterError(name, value, allowed, hint=problem)
