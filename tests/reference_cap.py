"""A shallow clamped spherical cap under external pressure: its geometry from the shallow-shell parameter.

Nothing here imports :mod:`mol_shell`. A cap of a sphere of radius ``a``, wall thickness ``t = 2h`` (``h`` is the
half-thickness in mol_shell), base radius ``b = a sin(alpha)``, rise ``H = a (1 - cos alpha)``. Shallow-shell
theory (Budiansky 1959; Weinitschke 1960; Huang 1964) describes it by one geometric parameter

    lambda = [12 (1 - nu^2)]^(1/4) b / sqrt(a t)   (= 2 [3 (1 - nu^2)]^(1/4) sqrt(H / t) for a shallow cap)

and measures pressures by the classical buckling pressure of the complete sphere,
``p_cl = 2 E t^2 / (a^2 sqrt(3 (1 - nu^2)))``. Clamped caps with lambda above about 3.2 snap through
axisymmetrically at a limit point below ``p_cl``.
"""

from __future__ import annotations

import math

E, NU, A, H_HALF = 1.0e6, 0.3, 1.0, 0.005
T = 2 * H_HALF


def p_classical(h=H_HALF, a=A, E=E, nu=NU):
    t = 2 * h
    return 2 * E * t**2 / (a**2 * math.sqrt(3 * (1 - nu**2)))


def cap_angle(lam, h=H_HALF, a=A, nu=NU):
    """The polar angle ``alpha`` of the edge of the cap with shallow-shell parameter ``lam``."""
    b = lam * math.sqrt(a * 2 * h) / (12 * (1 - nu**2)) ** 0.25
    return math.asin(b / a)


def cap_params(lam, h=H_HALF):
    """Keyword arguments of ``mol_shell.Sphere`` for the clamped cap (pole at s = 0, clamped edge at s = L)."""
    return {"a": A, "h": h, "E": E, "nu": NU, "alpha2": cap_angle(lam, h), "end2": "clamped",
            "material": "svk-plane-stress"}


def cap_angle_from_rise(lam, h=H_HALF, a=A, nu=NU):
    """The edge angle of the cap whose rise ``H = a (1 - cos alpha)`` gives ``lam = 2 [3 (1 - nu^2)]^(1/4)
    sqrt(H / t)``: the definition of the published tables below (the same as :func:`cap_angle` for a shallow cap;
    at lambda = 5 the two angles differ by 1 %)."""
    t = 2 * h
    rise = t * lam**2 / (4 * math.sqrt(3 * (1 - nu**2)))
    return math.acos((a - rise) / a)


#: published axisymmetric snap-through pressures of clamped spherical caps, ``p_cr / p_cl`` against lambda, as
#: tabulated by Teng & Rotter (1989a, Computers & Structures 31(2), 211-233, their Table 1): Budiansky (1959,
#: shallow-shell theory), Dumir & Nath (1984), Teng & Rotter (1989a, a non-shallow axisymmetric shell analysis)
PUBLISHED = {4.0: (0.578, 0.58, 0.563), 5.0: (0.629, 0.63, 0.615), 6.0: (0.995, 0.986, 0.972)}
