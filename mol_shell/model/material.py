"""St Venant-Kirchhoff material integrated through the thickness (section 7).

The shell's stored energy per unit reference area is

    What = (1/r0) int_{zeta1}^{zeta2} W_SVK(F(zeta)) (1 - zeta theta0_s)(r0 + zeta cos theta0) dzeta,

evaluated by Gauss-Legendre quadrature; ``W_SVK = lambda/2 (tr E)^2 + mu tr(E^2)``
with ``E = (F^T F - I)/2`` (eq. 7.9). Scalars may be floats or CasADi symbols.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from mol_shell.model.kinematics import column_polynomials, scaled_deformation_gradient, trigonometry_rates


def lame(young, poisson):
    """Lame coefficients ``(lambda, mu)`` from Young's modulus and Poisson's ratio."""
    lam = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    mu = young / (2.0 * (1.0 + poisson))
    return lam, mu


MATERIALS = ("svk", "svk-plane-stress")
#: from this Poisson's ratio on, the paper's law under the inextensible director (``material = "svk"``) is
#: warned about: its in-plane stiffness grows without bound as ``nu -> 1/2`` (locking), while a thin rubber
#: wall, free to thin, keeps the plane-stress value
LOCKING_NU = 0.45


def locking_warning(material, poisson):
    """One line saying how much stiffer than a thin wall in plane stress the director law is, or ``None``.

    With the thickness held by the inextensible director a stretch in the plane is resisted by
    ``lambda + 2 mu`` (hoop alone) and ``2 (lambda + mu)`` (equal both ways), against a plane-stress wall's
    ``E / (1 - nu^2)`` and ``E / (1 - nu)``: ratios ``(1 - nu)^2 / (1 - 2 nu)`` and
    ``(1 - nu) / ((1 + nu)(1 - 2 nu))``, 13.0 and 17.1 at ``nu = 0.49``. Said for ``material = "svk"`` with
    ``nu >= LOCKING_NU`` only.
    """
    if material != "svk" or not poisson >= LOCKING_NU:
        return None
    hoop = (1 - poisson) ** 2 / (1 - 2 * poisson)
    both = (1 - poisson) / ((1 + poisson) * (1 - 2 * poisson))
    return (f'material = "svk" at nu = {poisson:g}: the inextensible director holds the thickness, so the wall is '
            f"{hoop:.3g} times stiffer in a hoop stretch ({both:.3g} times stretched equally both ways) than a thin "
            'wall in plane stress; for rubber-like walls choose material = "svk-plane-stress"')


def effective_lame(young, poisson, material="svk"):
    """Lame pair used in ``W_SVK`` for the chosen thickness treatment.

    ``"svk"`` is the paper's: 3-D St Venant-Kirchhoff under the inextensible-director
    constraint (``E22 = 0``), so the hoop and axial stiffness is ``lambda + 2 mu``, which
    locks as ``nu -> 0.5``. ``"svk-plane-stress"`` condenses the thickness stress out
    (``S22 = 0`` minimises ``W`` over ``E22``): ``lambda* = 2 lambda mu / (lambda + 2 mu)``,
    giving the classical ``lambda* + 2 mu = E / (1 - nu^2)``.
    """
    return condensed(*lame(young, poisson), material)


def condensed(first, second, material="svk"):
    """A pair ``(lambda, mu)`` of an isotropic law ``lambda tr(X) I + 2 mu X``, condensed for ``material``.

    ``"svk"``: unchanged. ``"svk-plane-stress"``: ``(2 lambda mu / (lambda + 2 mu), mu)``, the law
    with its ``22`` (thickness) stress eliminated. Applied to the elastic moduli and, separately, to
    the Kelvin-Voigt viscosities of a plane-stress law (``S22 = 0`` for each part). For the sum of the two this is
    exact under proportional damping (``eta_lambda / eta_mu = lambda / mu``); otherwise the thickness
    stress of the sum relaxes instead of vanishing, and condensing each part is our modelling choice (docs/materials.md:
    a sphere's breathing at ``nu = 0.3``, ``eta_lambda = 10 eta_mu`` decays at 5.33 1/s, at 8.96 1/s with the sum's
    thickness stress relaxing). Not for an incompressible law, whose thickness rate is kinematic
    (:func:`~mol_shell.model.hyperelastic.incompressible_dissipation`).
    """
    if material == "svk":
        return first, second
    if material == "svk-plane-stress":
        total = first + 2.0 * second  # the ratio first: 2 lambda mu underflowed from E ~ 1e-154 on (the twisted
        return (2.0 * first * (second / total) if total else 0.0), second  # cylinder's R off by 2e-3 at E = 1e-200)
    raise ValueError(f"material = {material!r} is outside {{{', '.join(MATERIALS)}}}")


def plane_stress_thickness(E11, E33, first, second):
    """``C_22 = 1 + 2 E_22`` of St Venant-Kirchhoff in plane stress (``material = "svk-plane-stress"``) from the
    in-plane normal strains and the condensed pair ``(lambda*, mu)`` of :func:`condensed`.

    ``S_22 = lambda tr E + 2 mu E_22 = 0`` (the 3-D law; the shears do not enter) gives
    ``E_22 = -lambda/(lambda + 2 mu) (E_11 + E_33) = -lambda*/(2 mu) (E_11 + E_33)``, i.e.
    ``-nu/(1 - nu) (E_11 + E_33)``. The thickness stretch is its square root, which has no real value where
    ``E_11 + E_33 >= (1 - nu)/(2 nu)`` (an equibiaxial stretch of 1.47 at ``nu = 0.3``, 1.23 at ``nu = 0.49``).
    """
    return 1.0 - first / second * (E11 + E33)


def green_strain(F):
    """``E = (F^T F - I)/2`` for ``F`` given as nested 3x3 tuples of scalars."""
    return tuple(
        tuple(0.5 * (sum(F[k][i] * F[k][j] for k in range(3)) - (1.0 if i == j else 0.0)) for j in range(3))
        for i in range(3)
    )


def svk_energy(F, lam, mu):
    """St Venant-Kirchhoff stored energy ``lambda/2 (tr E)^2 + mu E:E`` per unit reference volume."""
    E = green_strain(F)
    trace = E[0][0] + E[1][1] + E[2][2]
    return 0.5 * lam * trace**2 + mu * sum(E[i][j] ** 2 for i in range(3) for j in range(3))


def svk_stress(F, lam, mu):
    """First Piola-Kirchhoff stress ``T = F S`` with ``S = lambda tr(E) I + 2 mu E`` (eq. 7.9)."""
    E = green_strain(F)
    trace = E[0][0] + E[1][1] + E[2][2]
    S = tuple(tuple(lam * trace * (i == j) + 2.0 * mu * E[i][j] for j in range(3)) for i in range(3))
    return tuple(tuple(sum(F[i][k] * S[k][j] for k in range(3)) for j in range(3)) for i in range(3))


@dataclass(frozen=True)
class Thickness:
    """Gauss-Legendre rule on the thickness interval ``[zeta1, zeta1 + 2h]``.

    ``zeta1`` places the base surface; :func:`centroidal_offset` chooses it so
    that ``rhoI = 0`` for the cylinder of section 6.
    """

    zeta1: float
    h: float
    n_quad: int

    @property
    def nodes_weights(self):
        x, w = np.polynomial.legendre.leggauss(self.n_quad)
        mid = self.zeta1 + self.h
        return tuple(mid + self.h * x), tuple(self.h * w)


def centroidal_offset(h, r0=1.0):
    """Lower face ``zeta1`` such that ``int zeta (r0 + zeta) dzeta = 0`` over ``[zeta1, zeta1 + 2h]``.

    The midsurface offset ``m = zeta1 + h`` solves ``m r0 + m^2 + h^2/3 = 0``, whose
    root near zero is ``m = (-r0 + sqrt(r0^2 - 4 h^2/3)) / 2`` (about ``-h^2/(3 r0)``).
    """
    m = (-r0 + math.sqrt(r0 * r0 - 4.0 * h * h / 3.0)) / 2.0
    return m - h


def inertias(rho, thickness, r0=1.0, theta0=0.0, theta0_s=0.0):
    """``(rhoA, rhoI, rhoJ)`` of eq. (7.8) for uniform density, by the same quadrature."""
    nodes, weights = thickness.nodes_weights
    out = [0.0, 0.0, 0.0]
    for zeta, w in zip(nodes, weights):
        jac = (1.0 - zeta * theta0_s) * (r0 + zeta * math.cos(theta0)) / r0
        for k in range(3):
            out[k] += rho * w * jac * zeta**k
    return tuple(out)


def quadrature_factors(thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0):
    """Per thickness point ``(zeta, j1, j3, vol)``: the column factors of ``F`` and ``weight x det G0``.

    ``j1 = 1/(beta1_0 - zeta theta0_s)``, ``j3 = 1/(r0 + zeta cos theta0)``,
    ``vol = w (beta1_0 - zeta theta0_s)(r0 + zeta cos theta0)`` (see
    :func:`~mol_shell.model.kinematics.deformation_gradient`). Numbers or CasADi expressions.
    """
    out = []
    for zeta, w in zip(*thickness.nodes_weights):
        a, c = beta1_0 - zeta * theta0_s, r0 + zeta * ca.cos(theta0)
        out.append((zeta, 1.0 / a, 1.0 / c, w * a * c))
    return out


def thickness_energy(strains, lam, mu, factors, beta2_0=0.0):
    """``sum_q vol_q W_SVK(F_q)``: the thickness integral of the stored energy for :func:`quadrature_factors`."""
    total = 0.0
    for zeta, j1, j3, vol in factors:
        total = total + vol * svk_energy(scaled_deformation_gradient(strains, zeta, j1, j3, beta2_0), lam, mu)
    return total


def thickness_energy_shared(strains, lam, mu, factors, beta2_0=0.0):
    """:func:`thickness_energy` with everything that does not depend on ``zeta`` computed once.

    With ``F = [(a + zeta b) j1, c2, (c + zeta d) j3]`` (:func:`~mol_shell.model.kinematics.column_polynomials`)
    the Green strain ``E = (F^T F - I)/2`` at thickness point ``zeta`` is

        E11 = ((|a|^2 + 2 zeta a.b + zeta^2 |b|^2) j1^2 - 1)/2,   E33 = ((r^2 + 2 zeta r d3 + zeta^2 |d|^2) j3^2 - 1)/2,
        E13 = (a.c + zeta (a.d + b.c) + zeta^2 b.d) j1 j3 / 2,     E12 = (a.c2) j1 / 2,   E23 = (c.c2) j3 / 2,

    and ``E22 = 0`` (``|c2| = 1``; ``b.c2 = d.c2 = 0`` identically). Eleven dot products per sample, then a
    few operations per thickness point instead of a 3x3 product: the same quadrature of the same
    ``W_SVK`` (eq. 7.9), equal to :func:`thickness_energy` up to round-off.
    """
    a, b, c, d, c2 = column_polynomials(strains, beta2_0)

    def dot(u, v):
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]

    r = c[2]
    aa, ab2, bb = dot(a, a), 2 * dot(a, b), dot(b, b)
    cc, cd2, dd = r * r, 2 * r * d[2], dot(d, d)
    ac, adbc, bd = a[2] * r, dot(a, d) + b[2] * r, dot(b, d)
    e12, e23 = a[1] * c2[1] + a[2] * c2[2], r * c2[2]  # twice E12 / j1, twice E23 / j3
    total = 0.0
    for zeta, j1, j3, vol in factors:
        j11, j33 = j1 * j1, j3 * j3
        e11 = 0.5 * ((aa + zeta * (ab2 + zeta * bb)) * j11 - 1.0)
        e33 = 0.5 * ((cc + zeta * (cd2 + zeta * dd)) * j33 - 1.0)
        e13 = 0.5 * (ac + zeta * (adbc + zeta * bd)) * (j1 * j3)
        shear = 0.5 * (e12 * e12 * j11 + e23 * e23 * j33) + 2.0 * e13 * e13  # 2 (E12^2 + E23^2 + E13^2)
        trace = e11 + e33
        total = total + vol * (0.5 * lam * trace * trace + mu * (e11 * e11 + e33 * e33 + shear))
    return total


#: the thickness moments of :func:`thickness_energy_moments`: (power of j1, power of j3, highest power of zeta)
MOMENTS = ((4, 0, 4), (0, 4, 4), (2, 2, 4), (2, 0, 2), (0, 2, 2), (0, 0, 0))


def thickness_moments(factors):
    """``sum_q vol_q j1^a j3^b zeta^k`` for each ``(a, b, kmax)`` of :data:`MOMENTS`, ``k = 0..kmax`` (22 numbers).

    The same quadrature as :func:`thickness_energy`, summed once per cell instead of once per evaluation.
    """
    out = []
    for a, b, kmax in MOMENTS:
        out += [sum(vol * j1**a * j3**b * zeta**k for zeta, j1, j3, vol in factors) for k in range(kmax + 1)]
    return out


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _times(p, q):
    """The product of two quadratics in ``zeta``: 5 coefficients."""
    return (p[0] * q[0], p[0] * q[1] + p[1] * q[0], p[0] * q[2] + p[1] * q[1] + p[2] * q[0],
            p[1] * q[2] + p[2] * q[1], p[2] * q[2])


def _with_row(coeffs, row):
    return sum(x * m for x, m in zip(coeffs, row))


def _moment_rows(moments):
    """The moments of :func:`thickness_moments` split by :data:`MOMENTS`: ``(m41, m43, mx, m21, m23, (m0,))``."""
    m = list(moments)
    rows, k = [], 0
    for _, _, kmax in MOMENTS:
        rows.append(m[k:k + kmax + 1])
        k += kmax + 1
    return rows


def _svk_sums(P, Q, R, e12, e23, rows, lam, mu, linear=True):
    """``sum vol W_SVK`` from :func:`strain_coefficients` (or their rates) and :func:`_moment_rows`: the quadratic
    sums of ``E11``, ``E33`` and the shears; ``linear=False`` leaves out ``E``'s constant and linear parts (``E_t`` has
    none: ``E11_t = P_t j1^2 / 2``)."""
    m41, m43, mx, m21, m23, (m0,) = rows
    p1, q3, m0 = (_with_row(P, m21), _with_row(Q, m23), m0) if linear else (0.0, 0.0, 0.0)
    e11_sq = 0.25 * (_with_row(_times(P, P), m41) - 2 * p1 + m0)  # sum vol E11^2
    e33_sq = 0.25 * (_with_row(_times(Q, Q), m43) - 2 * q3 + m0)
    e11_e33 = 0.25 * (_with_row(_times(P, Q), mx) - p1 - q3 + m0)
    shear = 0.5 * (e12 * e12 * m21[0] + e23 * e23 * m23[0] + _with_row(_times(R, R), mx))
    return (0.5 * lam + mu) * (e11_sq + e33_sq) + lam * e11_e33 + mu * shear


def strain_coefficients(a, b, c, d, c2):
    """The eleven numbers that make ``C`` at every depth (:func:`~mol_shell.model.kinematics.column_polynomials`):
    ``C_11 = P(zeta) j1^2``, ``C_33 = Q(zeta) j3^2``, ``C_13 = R(zeta) j1 j3``, ``C_12 = e12 j1``, ``C_23 = e23 j3``
    with ``P, Q, R`` quadratics in ``zeta`` (3 coefficients each), ``C_22 = 1``."""
    r = c[2]
    P = (_dot(a, a), 2 * _dot(a, b), _dot(b, b))
    Q = (r * r, 2 * r * d[2], _dot(d, d))
    R = (a[2] * r, _dot(a, d) + b[2] * r, _dot(b, d))
    return P, Q, R, a[1] * c2[1] + a[2] * c2[2], r * c2[2]


def thickness_energy_moments(strains, lam, mu, moments, beta2_0=0.0, trig=None):
    """:func:`thickness_energy_shared` with the thickness sums done beforehand (:func:`thickness_moments`).

    ``W_SVK`` is a polynomial in ``zeta`` and ``j1^2, j3^2`` with coefficients from the eleven dot products
    of :func:`thickness_energy_shared`: with ``P = |a|^2 + 2 zeta a.b + zeta^2 |b|^2``, ``Q = r^2 + ...``
    and ``R = a.c + ...``, ``sum vol W = (lambda/2 + mu) sum vol (E11^2 + E33^2) + lambda sum vol E11 E33
    + mu sum vol 2 (E12^2 + E13^2 + E23^2)``, and each sum is a dot product of a polynomial's coefficients
    with a row of moments. Equal to the quadrature up to round-off, at a cost independent of ``n_quad``.
    ``trig``: the sample's ``(cos theta, sin theta, cos psi, sin psi)`` if known.
    """
    return _svk_sums(*strain_coefficients(*column_polynomials(strains, beta2_0, trig)), _moment_rows(moments), lam, mu)


def thickness_dissipation_moments(strains, rates, eta_lambda, eta_mu, moments, beta2_0=0.0, trig=None):
    """:func:`thickness_dissipation` with the thickness sums done beforehand (:func:`thickness_moments`).

    ``E_t`` has the form of ``E`` (:func:`strain_coefficients`) with each of the eleven numbers replaced by its
    rate (their derivatives along ``rates``, linear in them) and no constant part; ``E_22 = 0`` under the
    director, so ``tr E_t = E11_t + E33_t`` and ``D`` is :func:`thickness_energy_moments`' quadratic form in the
    rates with ``(eta_lambda, eta_mu)`` for ``(lambda, mu)``. Equal to the quadrature up to round-off, at a cost
    independent of ``n_quad`` (CasADi ``strains``/``rates``). ``trig``: the sample's ``(cos theta, sin theta,
    cos psi, sin psi)`` if known (their rates follow from those of ``theta`` and ``psi``, the last two strains).
    """
    e_sym, r_sym, t_sym = ca.SX.sym("e", 8), ca.SX.sym("edot", 8), ca.SX.sym("trig", 4)
    b_sym = ca.SX.sym("beta2_0")
    b = 0.0 if isinstance(beta2_0, (int, float)) and beta2_0 == 0 else b_sym  # left out when it is 0
    P, Q, R, e12, e23 = strain_coefficients(*column_polynomials(ca.vertsplit(e_sym), b,
                                                                None if trig is None else ca.vertsplit(t_sym)))
    flat = ca.vertcat(*P, *Q, *R, e12, e23)
    if trig is None:
        rate = ca.vertsplit(ca.jtimes(flat, e_sym, r_sym))
    else:  # d(cos theta)/dt = -sin theta theta_t, ...
        t_rate = ca.vertcat(*trigonometry_rates(ca.vertsplit(t_sym), r_sym[6], r_sym[7]))
        rate = ca.vertsplit(ca.jtimes(flat, ca.vertcat(e_sym, t_sym), ca.vertcat(r_sym, t_rate)))
    m_sym = ca.SX.sym("m", sum(kmax + 1 for _, _, kmax in MOMENTS))
    total = _svk_sums(rate[0:3], rate[3:6], rate[6:9], rate[9], rate[10], _moment_rows(ca.vertsplit(m_sym)),
                      eta_lambda, eta_mu, linear=False)
    fn = ca.Function("dissipation_moments", [e_sym, r_sym, t_sym, b_sym, m_sym], [total])
    return fn(ca.vertcat(*strains), ca.vertcat(*rates), ca.vertcat(*(trig if trig is not None else [0.0] * 4)),
              beta2_0, ca.vertcat(*moments))


#: SVK's nominal stress in a uniaxial stretch ``l``, ``(E/2)(l^3 - l)``, is extreme at ``l^2 = 1/3``: compressed further,
#: the law's stress turns back (it softens to zero at ``l = 0``), a limit of the law, not of the shell
SVK_TURNING_C = 1.0 / 3.0


def svk_turning_limit(strains, moments, beta2_0=0.0, trig=None):
    """``det(C_t - I/3)`` of the in-plane (tangent) block ``C_t`` of the thickness-averaged metric where
    ``tr(C_t - I/3) > 0``, else ``-|det|``: positive exactly while every in-plane stretch exceeds ``1/sqrt(3)``, where
    SVK's stress turns back in compression (:data:`SVK_TURNING_C`).

    From the natural state (``C_t = I``: 4/9) the first stretch to reach ``1/sqrt(3)`` makes it vanish. The
    determinant alone is positive again when both stretches are past it (a state that starts there: an equilibrium
    radius under a large external pressure); the trace tells the two apart, and the function stays continuous
    (where the trace vanishes the determinant is not positive). ``C_11``,
    ``C_33`` and ``C_13^2`` are taken at the base surface with the thickness-averaged reference factors of the
    moments (:func:`thickness_moments`): ``|a|^2 <j1^2>``, ``r^2 <j3^2>``, ``(a_3 r)^2 <j1^2 j3^2>``, ``<.>`` the
    moment over ``sum vol``; a membrane criterion (a bent wall's faces reach it a little earlier).
    """
    a, _, c, _, _ = column_polynomials(strains, beta2_0, trig)
    m = list(moments)
    m0 = m[21]
    c11 = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * m[15] / m0
    c33 = c[2] * c[2] * m[18] / m0
    c13_sq = (a[2] * c[2]) ** 2 * m[10] / m0
    det = (c11 - SVK_TURNING_C) * (c33 - SVK_TURNING_C) - c13_sq
    return ca.if_else(c11 + c33 - 2 * SVK_TURNING_C > 0, det, -ca.fabs(det))


def thickness_dissipation(strains, rates, eta_lambda, eta_mu, factors, beta2_0=0.0):
    """``sum_q vol_q [eta_lambda/2 (tr E_t)^2 + eta_mu E_t : E_t]`` (CasADi ``strains``/``rates``), ``E_t,22 = 0``
    (the director's; a plane-stress law passes its condensed pair, :func:`condensed`)."""
    e_sym, r_sym = ca.SX.sym("e", 8), ca.SX.sym("edot", 8)
    f_sym = [ca.SX.sym(f"f{i}", 4) for i in range(len(factors))]  # zeta (a graded wall's are symbols), j1, j3, vol
    b_sym = ca.SX.sym("beta2_0")
    b = 0.0 if isinstance(beta2_0, (int, float)) and beta2_0 == 0 else b_sym  # left out when it is 0
    total = 0.0
    for f in f_sym:
        E = green_strain(scaled_deformation_gradient(ca.vertsplit(e_sym), f[0], f[1], f[2], b))
        flat = ca.vertcat(*[E[i][j] for i in range(3) for j in range(3)])
        Et = ca.reshape(ca.jtimes(flat, e_sym, r_sym), 3, 3)
        trace = Et[0, 0] + Et[1, 1] + Et[2, 2]
        total = total + f[3] * (0.5 * eta_lambda * trace**2 + eta_mu * ca.sumsqr(Et))
    fn = ca.Function("dissipation", [e_sym, r_sym, b_sym, *f_sym], [total])
    values = [ca.vertcat(zeta, j1, j3, vol) for zeta, j1, j3, vol in factors]
    return fn(ca.vertcat(*strains), ca.vertcat(*rates), beta2_0, *values)


def shell_dissipation(strains, rates, eta_lambda, eta_mu, thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0,
                      beta2_0=0.0):
    """Rayleigh function of the Kelvin-Voigt stress per unit reference area (section 3, strain-rate type).

    With ``S_visc = eta_lambda tr(E_t) I + 2 eta_mu E_t`` the stress power is ``S_visc : E_t = 2 D`` where

        D = (1/r0) int [eta_lambda/2 (tr E_t)^2 + eta_mu E_t : E_t] (1 - zeta theta0_s)(r0 + zeta cos theta0) dzeta,

    ``E_t = dE/dstrains . rates`` and ``rates`` are the time derivatives of ``strains``; ``E_t,22 = 0`` under the
    director, and a plane-stress law passes the pair condensed (:func:`condensed`: each part's thickness stress
    eliminated). An incompressible law's ``D`` has the thickness rate ``det C = 1`` sets and ``eta_mu`` alone:
    :func:`~mol_shell.model.hyperelastic.law_shell_dissipation`.
    ``beta1_0, beta2_0``: the reference configuration's strains, as in :func:`shell_energy`.
    The generalised viscous forces are ``-dD/d(rates)``; the energy decays at the rate ``2 D``.
    Needs CasADi symbols for ``strains``/``rates`` (it differentiates ``E``).
    """
    factors = quadrature_factors(thickness, r0, theta0, theta0_s, beta1_0)
    return thickness_dissipation(strains, rates, eta_lambda, eta_mu, factors, beta2_0) / r0


def shell_energy(strains, lam, mu, thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0, beta2_0=0.0):
    """Stored energy per unit reference area ``What`` (section 7), by Gauss-Legendre quadrature.

    Parameters
    ----------
    strains : tuple
        ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)``, floats or CasADi scalars.
    lam, mu : float
        Lame coefficients.
    thickness : Thickness
        Quadrature rule on the thickness interval.
    r0, theta0, theta0_s : float or casadi.SX
        Reference radius, tangent angle and its derivative at the point.
    beta1_0, beta2_0 : float or casadi.SX
        The reference configuration's ``r0_s`` in its ``b0`` basis (``1, 0`` for the exact meridian;
        the discrete system passes its difference values so its natural state has ``F = I``).

    The integrand carries ``det G0 / r0 = (beta1_0 - zeta theta0_s)(r0 + zeta cos theta0) / r0``:
    energy per unit reference area of the base surface (per unit ``s`` when ``beta1_0 != 1``).
    """
    factors = quadrature_factors(thickness, r0, theta0, theta0_s, beta1_0)
    return thickness_energy(strains, lam, mu, factors, beta2_0) / r0
