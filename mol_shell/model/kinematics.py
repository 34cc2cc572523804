"""Kinematics of rotationally symmetric motions of a special Cosserat shell.

Every function takes scalars that may be Python floats or CasADi ``SX``/``MX``
expressions (``casadi.sin`` and friends accept both), so the same code is
evaluated numerically in tests and traced into graphs by the model.

Notation (Antman & Bourne 2010, section 2): the unknowns are ``z, r, chi,
theta, psi`` of ``(s, t)``; ``a1 = k``, ``a2 = cos(chi) j2 + sin(chi) j3``,
``a3 = k x a2``; ``b1 = cos(theta) a1 + sin(theta) a2``, ``b2 = -sin(theta) a1
+ cos(theta) a2``, ``b3 = a3``; the director ``d = c2 = cos(psi) b2 + sin(psi)
b3``, ``c1 = b1``, ``c3 = b1 x d``.
"""

from __future__ import annotations

from casadi import cos, sin

# Field order used throughout the package (node-major state: these five, then
# their momenta, for node 0, then node 1, ...).
from mol_shell._core.constants import FIELDS  # noqa: F401  (kinematics speaks of these fields)


def trigonometry(theta, psi, trig=None):
    """``(cos theta, sin theta, cos psi, sin psi)``, or ``trig`` when the caller has them already.

    The compiled kernels compute the trigonometry of a node's angles once and pass it to every cell and
    node kernel that needs it (``trig``); everything else leaves ``trig`` out.
    """
    return trig if trig is not None else (cos(theta), sin(theta), cos(psi), sin(psi))


def trigonometry_rates(trig, theta_t, psi_t):
    """The time derivatives of :func:`trigonometry`'s ``(cos theta, sin theta, cos psi, sin psi)`` given as ``trig``,
    from the rates ``theta_t, psi_t``."""
    ct, st, cs, sn = trig
    return (-st * theta_t, ct * theta_t, -sn * psi_t, cs * psi_t)


def betas(z_s, r_s, chi_s, r, theta, trig=None):
    """Components of ``r_s`` in the ``b`` basis, eq. (2.18).

    ``beta1 = z_s cos(theta) + r_s sin(theta)``,
    ``beta2 = -z_s sin(theta) + r_s cos(theta)``, ``beta3 = r chi_s``.
    ``trig``: ``(cos theta, sin theta)`` if known.
    """
    ct, st = trig if trig is not None else (cos(theta), sin(theta))
    return (
        z_s * ct + r_s * st,
        -z_s * st + r_s * ct,
        r * chi_s,
    )


def delta(z_s, r_s, r, theta, psi):
    """``delta = r beta1 cos(psi)``, eq. (2.20); the model requires ``delta > 0``."""
    beta1 = z_s * cos(theta) + r_s * sin(theta)
    return r * beta1 * cos(psi)


def deformation_gradient(strains, zeta, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0, beta2_0=0.0):
    """Components ``F[k][l]`` of ``F = sum F_kl b_k b0_l`` at depth ``zeta``, eq. (7.4) repaired.

    Parameters
    ----------
    strains : tuple
        ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)``.
    zeta : float
        Thickness coordinate along the reference director.
    r0, theta0, theta0_s : float
        Reference radius, reference tangent angle and its derivative. The
        cylinder of section 6 has ``r0 = 1, theta0 = 0`` (the tangent is ``k``).
    beta1_0, beta2_0 : float
        ``r0_s`` of the reference configuration in its own ``b0`` basis: ``(1, 0)`` for the exact
        meridian (``dz0/ds = cos theta0``, ``dr0/ds = sin theta0``); the discrete system passes
        the values of its difference formulas applied to the nodal reference coordinates, so the
        discrete natural state has ``F = I`` exactly.

    Notes
    -----
    Column 1 is ``p_s = r_s + zeta d_s`` divided by ``1 - zeta theta0_s``;
    column 2 is ``p_zeta = d``; column 3 is ``p_phi = k x (r + zeta d)``
    divided by ``r0 + zeta cos(theta0)``. The extracted paper lost the first
    term of ``F31`` (it is ``beta3 = r chi_s``); see MODEL_NOTES.

    In general ``F = G G0^-1`` with ``G = [p_s, p_zeta, p_phi]`` in the ``b`` basis and ``G0`` the
    same for the reference configuration in the ``b0`` basis,
    ``G0 = [[beta1_0 - zeta theta0_s, 0, 0], [beta2_0, 1, 0], [0, 0, r0 + zeta cos theta0]]``;
    with ``beta1_0 = 1, beta2_0 = 0`` this is the table of (7.4). Its determinant
    ``det G0 = (beta1_0 - zeta theta0_s)(r0 + zeta cos theta0)`` is the reference volume element.
    """
    return scaled_deformation_gradient(strains, zeta, 1.0 / (beta1_0 - zeta * theta0_s),
                                       1.0 / (r0 + zeta * cos(theta0)), beta2_0)


def scaled_deformation_gradient(strains, zeta, j1, j3, beta2_0=0.0):
    """:func:`deformation_gradient` with the reference factors given: ``F = G G0^-1``.

    ``j1 = 1/(beta1_0 - zeta theta0_s)`` and ``j3 = 1/(r0 + zeta cos theta0)`` scale columns 1 and 3;
    ``beta2_0`` removes the reference's own shear from column 1 (left out of the expression when it
    is the number 0). The discrete system passes per-cell factors as kernel inputs. ``strains`` and
    ``1/j1`` may both be multiplied by the same length (the cell kernel uses differences, not
    derivatives): ``F`` does not change.
    """
    z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi = strains
    beta1, beta2, beta3 = betas(z_s, r_s, chi_s, r, theta)
    cs, sn = cos(psi), sin(psi)
    ct, st = cos(theta), sin(theta)
    twist = psi_s + chi_s * ct
    col2 = (0.0, cs, sn)
    col1 = (beta1 - zeta * (chi_s * sn * st + theta_s * cs), beta2 - zeta * sn * twist, beta3 + zeta * cs * twist)
    if not (isinstance(beta2_0, (int, float)) and beta2_0 == 0):
        col1 = tuple(a - beta2_0 * b for a, b in zip(col1, col2))
    col3 = (-zeta * sn * st, -zeta * sn * ct, r + zeta * cs * ct)
    return tuple((col1[k] * j1, col2[k], col3[k] * j3) for k in range(3))


def column_polynomials(strains, beta2_0=0.0, trig=None):
    """``F``'s columns as polynomials in ``zeta``: ``F = [(a + zeta b) j1, c2, (c + zeta d) j3]``.

    The same ``F`` as :func:`scaled_deformation_gradient` (eq. 7.4): column 1 is ``a + zeta b``
    (``a = beta - beta2_0 c2``, ``b = -zeta``-coefficient of ``d_s``), column 2 the director
    ``c2 = (0, cos psi, sin psi)`` and column 3 ``c + zeta d`` with ``c = (0, 0, r)``, all in the
    ``b`` basis. Nothing here depends on ``zeta``, so a thickness integral computes them once.
    Returns ``(a, b, c, d, c2)``, each a 3-tuple. ``trig``: see :func:`trigonometry`.
    """
    z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi = strains
    ct, st, cs, sn = trigonometry(theta, psi, trig)
    beta1, beta2, beta3 = betas(z_s, r_s, chi_s, r, theta, (ct, st))
    twist = psi_s + chi_s * ct
    a = (beta1, beta2, beta3)
    if not (isinstance(beta2_0, (int, float)) and beta2_0 == 0):
        a = (beta1, beta2 - beta2_0 * cs, beta3 - beta2_0 * sn)
    b = (-(chi_s * sn * st + theta_s * cs), -sn * twist, cs * twist)
    return a, b, (0.0, 0.0, r), (-sn * st, -sn * ct, cs * ct), (0.0, cs, sn)


def director_velocity_c(chi_t, theta_t, psi_t, theta, psi, trig=None):
    """Components of ``d_t`` in the ``c`` basis, eq. (2.17): ``(c1, c2, c3)``. ``trig``: :func:`trigonometry`."""
    ct, st, cs, sn = trigonometry(theta, psi, trig)
    return (
        -(chi_t * sn * st + theta_t * cs),
        0.0,
        psi_t + chi_t * ct,
    )


def position_velocity_c(z_t, r_t, chi_t, r, theta, psi, trig=None):
    """Components of ``r_t = z_t a1 + r_t a2 + r chi_t a3`` in the ``c`` basis, eq. (2.17)."""
    ct, st, cs, sn = trigonometry(theta, psi, trig)
    along = r_t * st + z_t * ct
    across = r_t * ct - z_t * st
    spin = r * chi_t
    return (
        along,
        across * cs + spin * sn,
        -across * sn + spin * cs,
    )


def kinetic_energy_density(q, v, rho_a, rho_i, rho_j, trig=None):
    """Kinetic energy per unit reference area (section 7).

    ``rhoA |r_t|^2 / 2 + rhoI r_t . d_t + rhoJ |d_t|^2 / 2`` with
    ``q = (z, r, chi, theta, psi)`` and ``v`` their rates. The ``rhoI`` term is
    left out of the expression when ``rho_i == 0`` (a plain number), so graphs
    for the usual base-surface placement do not carry it.
    """
    _, r, _, theta, psi = q
    z_t, r_t, chi_t, theta_t, psi_t = v
    dt1, _, dt3 = director_velocity_c(chi_t, theta_t, psi_t, theta, psi, trig)
    energy = 0.5 * rho_a * (z_t**2 + r_t**2 + (r * chi_t) ** 2)
    energy = energy + 0.5 * rho_j * (dt1**2 + dt3**2)
    if not (isinstance(rho_i, (int, float)) and rho_i == 0):
        rt1, _, rt3 = position_velocity_c(z_t, r_t, chi_t, r, theta, psi, trig)
        energy = energy + rho_i * (rt1 * dt1 + rt3 * dt3)
    return energy
