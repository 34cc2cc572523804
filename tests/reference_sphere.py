"""An independent NumPy reference for the uniformly dilated spherical shell (closed forms and a quadrature).

Nothing here imports :mod:`mol_shell`. The sphere of radius ``a`` and wall ``[zeta1, zeta1 + 2h]``, its director
the outward normal: dilated to base radius ``R``, the point at depth ``zeta`` goes from radius ``a + zeta`` to
``R + zeta``. In the F table (``r = (R/a) r0``, ``z = (R/a) z0``, ``theta = theta0``, ``psi = 0``,
``theta0_s = -1/a``) ``F11 = (R + zeta)/(a + zeta) = F33``, ``F22 = 1``, no shear:
``F = diag(Lambda, 1, Lambda)``. Used by tests/test_sphere.py and tests/test_loads.py.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def layer_moment(k, zeta1, h, a):
    """``int (a + zeta)^k dzeta`` over ``[zeta1, zeta1 + 2h]``, in closed form."""
    return ((a + zeta1 + 2 * h) ** (k + 1) - (a + zeta1) ** (k + 1)) / (k + 1)


def zeta1_centroidal(h, a):
    """``zeta1`` with ``int zeta (a + zeta)^2 dzeta = int (a + zeta)^3 - a (a + zeta)^2 = 0`` (``rhoI = 0``).

    The moment is negative at ``zeta1 = -2h`` and positive at ``0``: a bracketed root.
    """
    return brentq(lambda z1: layer_moment(3, z1, h, a) - a * layer_moment(2, z1, h, a), -2 * h, 0.0, xtol=1e-18)


def dilated_sphere(R, a, h, zeta1, lam, mu, points=16):
    """``(zeta, w, W, P)``: Gauss-Legendre points through the wall and their weights (``sum w = 2h``), the St
    Venant-Kirchhoff energy density ``W`` and the first Piola stress ``P`` of ``F = diag(Lambda, 1, Lambda)``."""
    x, w = np.polynomial.legendre.leggauss(points)
    zeta = zeta1 + h * (1 + x)
    stretch = (R + zeta) / (a + zeta)
    F = np.zeros((points, 3, 3))
    F[:, 0, 0], F[:, 1, 1], F[:, 2, 2] = stretch, 1.0, stretch
    E = 0.5 * (np.einsum("qki,qkj->qij", F, F) - np.eye(3))
    tr = np.trace(E, axis1=1, axis2=2)
    W = 0.5 * lam * tr**2 + mu * np.einsum("qij,qij->q", E, E)
    S = lam * tr[:, None, None] * np.eye(3) + 2 * mu * E
    return zeta, h * w, W, F @ S
