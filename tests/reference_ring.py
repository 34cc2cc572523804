"""An independent NumPy reference for the cylinder's stored energy and the ring ODE of section 5.

Nothing here imports :mod:`mol_shell`: the deformation gradient is typed in from the table
in ``MODEL_NOTES.md`` (eq. 7.4 repaired), the St Venant-Kirchhoff energy and its first
Piola stress are written out with NumPy, the thickness integral uses NumPy's own
Gauss-Legendre nodes, and the base surface and inertias are derived here in closed form.
The tests compare the package against these functions.

Geometry of the section-6 cylinder: reference radius ``r0 = 1``, reference tangent ``k``
(``theta0 = 0``, ``theta0_s = 0``), so the reference volume element is
``(1 + zeta) dzeta dphi ds`` and the third column of ``F`` is divided by ``1 + zeta``.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def lame(E, nu):
    """Lame constants of isotropic linear elasticity from Young's modulus and Poisson's ratio."""
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def _moment(k, a, b):
    """``int_a^b zeta^k (1 + zeta) dzeta`` in closed form."""
    return (b ** (k + 1) - a ** (k + 1)) / (k + 1) + (b ** (k + 2) - a ** (k + 2)) / (k + 2)


def zeta1_centroidal(h):
    """Lower face ``zeta1`` of ``[zeta1, zeta1 + 2h]`` with ``int zeta (1 + zeta) dzeta = 0`` (so ``rhoI = 0``).

    The moment is a cubic in ``zeta1``; it is negative at ``zeta1 = -2h`` (the interval lies
    below the base surface) and positive at ``zeta1 = 0``, so a root is bracketed; Brent's
    method finds it to round-off. (Expansion: ``zeta1 = -h - h^2/3 + O(h^4)``.)
    """
    return brentq(lambda a: _moment(1, a, a + 2 * h), -2 * h, 0.0, xtol=1e-18, rtol=1e-15)


def inertias(rho, h, zeta1):
    """``(rhoA, rhoI, rhoJ) = rho int zeta^{0,1,2} (1 + zeta) dzeta`` (eq. 7.8 with r0 = 1, theta0 = 0)."""
    return tuple(rho * _moment(k, zeta1, zeta1 + 2 * h) for k in range(3))


def gauss(h, zeta1, n_quad):
    """Gauss-Legendre nodes and weights on ``[zeta1, zeta1 + 2h]``."""
    x, w = np.polynomial.legendre.leggauss(n_quad)
    return zeta1 + h * (1 + x), h * w


def deformation_gradient(strains, zeta):
    """``F`` (shape ``(len(zeta), 3, 3)``) from the table of MODEL_NOTES (eq. 7.4 repaired) for the cylinder.

    ``strains = (z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)``.
    """
    z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi = strains
    zeta = np.atleast_1d(np.asarray(zeta, dtype=float))
    ct, st, cp, sp = np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    beta1 = z_s * ct + r_s * st
    beta2 = -z_s * st + r_s * ct
    beta3 = r * chi_s
    twist = psi_s + chi_s * ct
    c3 = 1.0 / (1.0 + zeta)  # third column over r0 + zeta cos(theta0); first column over 1 - zeta theta0_s = 1
    F = np.zeros((zeta.size, 3, 3))
    F[:, 0, 0] = beta1 - zeta * (chi_s * sp * st + theta_s * cp)
    F[:, 0, 1] = 0.0
    F[:, 0, 2] = -zeta * sp * st * c3
    F[:, 1, 0] = beta2 - zeta * sp * twist
    F[:, 1, 1] = cp
    F[:, 1, 2] = -zeta * sp * ct * c3
    F[:, 2, 0] = beta3 + zeta * cp * twist
    F[:, 2, 1] = sp
    F[:, 2, 2] = (r + zeta * cp * ct) * c3
    return F


def svk(F, lam, mu):
    """``W = lam/2 (tr E)^2 + mu E:E`` and the first Piola stress ``P = F (lam tr E I + 2 mu E)``, ``E = (F^T F - I)/2``."""
    E = 0.5 * (np.einsum("...ki,...kj->...ij", F, F) - np.eye(3))
    tr = np.trace(E, axis1=-2, axis2=-1)
    W = 0.5 * lam * tr**2 + mu * np.einsum("...ij,...ij->...", E, E)
    S = lam * tr[..., None, None] * np.eye(3) + 2 * mu * E
    return W, F @ S


def what(strains, lam, mu, h, zeta1, n_quad=8):
    """Stored energy per unit reference area ``What = int W(F) (1 + zeta) dzeta`` by ``n_quad``-point Gauss."""
    zeta, w = gauss(h, zeta1, n_quad)
    W, _ = svk(deformation_gradient(strains, zeta), lam, mu)
    return float(np.sum(w * (1 + zeta) * W))


def ring_forces(r, psi, lam, mu, h, zeta1, n_quad=8):
    """``(dWhat/dr, dWhat/dpsi)`` on the uniform state ``z_s = 1``, other strains 0, ``theta = 0``.

    Chain rule through the stress: ``dWhat/dq = int P : dF/dq (1 + zeta) dzeta``. With the table,
    ``dF/dr`` has the single entry ``F33: 1/(1 + zeta)``; ``dF/dpsi`` has ``F22: -sin psi``,
    ``F23: -zeta cos psi/(1 + zeta)``, ``F32: cos psi``, ``F33: -zeta sin psi/(1 + zeta)``.
    """
    zeta, w = gauss(h, zeta1, n_quad)
    _, P = svk(deformation_gradient((1.0, 0.0, 0.0, 0.0, 0.0, r, 0.0, psi), zeta), lam, mu)
    c3 = 1.0 / (1.0 + zeta)
    dr = P[:, 2, 2] * c3
    dpsi = -np.sin(psi) * P[:, 1, 1] - zeta * np.cos(psi) * c3 * P[:, 1, 2] + np.cos(psi) * P[:, 2, 1]
    dpsi = dpsi - zeta * np.sin(psi) * c3 * P[:, 2, 2]
    J = w * (1 + zeta)
    return float(np.sum(J * dr)), float(np.sum(J * dpsi))


class Ring:
    """Section 5 as an ODE, derived from the ring Lagrangian per unit reference area.

    With ``theta = 0``, ``z_s = 1``, ``chi_s = 0`` and ``rhoI = 0`` (``|d_t|^2 = (psi_t + chi_t)^2``),

        l = rhoA/2 (r_t^2 + r^2 chi_t^2) + rhoJ/2 (psi_t + chi_t)^2 - What(r, psi)

    (the common factor ``2 pi`` drops out). Momenta ``p_r = rhoA r_t``,
    ``p_chi = rhoA r^2 chi_t + rhoJ (psi_t + chi_t)``, ``p_psi = rhoJ (psi_t + chi_t)``, so

        chi_t = (p_chi - p_psi) / (rhoA r^2),    psi_t = p_psi / rhoJ - chi_t,    r_t = p_r / rhoA,
        p_r_t = rhoA r chi_t^2 - dWhat/dr,       p_chi_t = 0,                     p_psi_t = -dWhat/dpsi.
    """

    def __init__(self, E, nu, rho, h, n_quad=8):
        self.lam, self.mu = lame(E, nu)
        self.h, self.zeta1, self.n_quad = h, zeta1_centroidal(h), n_quad
        self.rho_a, self.rho_i, self.rho_j = inertias(rho, h, self.zeta1)

    def rates(self, y):
        r, chi, psi, p_r, p_chi, p_psi = y
        chi_t = (p_chi - p_psi) / (self.rho_a * r**2)
        return p_r / self.rho_a, chi_t, p_psi / self.rho_j - chi_t

    def rhs(self, t, y):
        r, psi = y[0], y[2]
        r_t, chi_t, psi_t = self.rates(y)
        f_r, f_psi = ring_forces(r, psi, self.lam, self.mu, self.h, self.zeta1, self.n_quad)
        return np.array([r_t, chi_t, psi_t, self.rho_a * r * chi_t**2 - f_r, 0.0, -f_psi])

    def initial(self, R, omega, psi0):
        """State ``(r, chi, psi, p_r, p_chi, p_psi)`` for ``r = R``, ``chi = 0``, ``psi = psi0``, ``chi_t = omega``, at rest otherwise."""
        return np.array([R, 0.0, psi0, 0.0, (self.rho_a * R**2 + self.rho_j) * omega, self.rho_j * omega])

    def solve(self, R, omega, psi0, times, rtol=1e-11):
        """``(r, chi, psi, chi_t)`` at ``times`` by DOP853; ``atol`` scaled per component to the same relative level."""
        y0 = self.initial(R, omega, psi0)
        scale = np.array([R, 1.0, 1.0, self.rho_a * 1.0, abs(y0[4]) + self.rho_a, abs(y0[5]) + self.rho_j])
        sol = solve_ivp(self.rhs, (times[0], times[-1]), y0, method="DOP853", t_eval=times, rtol=rtol,
                        atol=1e-3 * rtol * scale)
        assert sol.success, sol.message
        chi_t = np.array([self.rates(y)[1] for y in sol.y.T])
        return sol.y[0], sol.y[1], sol.y[2], chi_t
