"""Balance laws (3.6)-(3.8) in Cartesian vector form: an independent route to the equations of motion.

The package derives its equations of motion from Hamilton's principle for
``2 pi r0 int (T - What) ds`` with the component formulas of
:mod:`mol_shell.model.kinematics` (route 1). This module builds the same equations
from the other end (route 2), sharing nothing with route 1 but the St Venant-Kirchhoff
law and the thickness quadrature:

1. the position ``p = r + zeta d`` of the constrained 3-D body, eq. (2.8), is written in
   the fixed basis ``(k, j2(0), j3(0))`` with ``phi`` kept as a symbol, ``r = z k + r a2``
   (2.6), ``d = cos(psi) b2 + sin(psi) b3`` (2.11);
2. ``F`` follows from ``casadi.jacobian`` of ``p`` in ``(s, phi, zeta)`` and (7.2)-(7.3);
3. the resultants are the thickness integrals (7.5) of the first Piola-Kirchhoff stress;
4. the residuals of the balance laws (3.6)-(3.7) (no loads) are formed with the actual
   ``phi``-derivatives of ``n^phi, m^phi`` (which (3.8) says are ``k x n^phi, k x m^phi``)
   and with ``r_tt, d_tt`` from differentiating the Cartesian ``p`` twice in ``t``.

Virtual power (section 4, eqs. 4.10-4.13) links the two routes. The variations of the five
fields move the shell by

    delta r = delta_z k + delta_r a2 + r delta_chi a3,
    delta d = omega x d,   omega = delta_chi k + delta_theta a3 + delta_psi c1,

because ``d_chi = k x d``, ``d_theta = a3 x d`` (``b1_theta = b2 = a3 x b1``) and
``d_psi = b1 x d``. Pairing the residuals with ``(delta r, omega)`` gives the first
variation of the action, so the Euler-Lagrange expressions
``EL_j = d_s(dl/dq_j,s) + d_t(dl/dq_j,t) - dl/dq_j`` of ``l = 2 pi r0 (T - What)`` are

    EL_z     = -2 pi  R_lin . k
    EL_r     = -2 pi  R_lin . a2
    EL_chi   = -2 pi (R_lin . (r a3) + R_ang . k)
    EL_theta = -2 pi  R_ang . a3      (= -2 pi cos(psi) R_ang . c3: the c3 balance, 3.13)
    EL_psi   = -2 pi  R_ang . c1      (the c1 balance, 3.12)

with ``R_lin = d_s(r0 n^s) + k x n^phi - r0 (rhoA r_tt + rhoI d_tt)`` and
``R_ang = d_s(r0 m^s) + k x m^phi + r0 r_s x n^s + r_phi x n^phi - r0 d x (rhoI r_tt + rhoJ d_tt)``.
``R_ang . d`` vanishes identically (the "constitutive identity" after 3.13), so ``omega``
may carry any component along ``d``. The natural boundary terms are
``dl/dq_s = -2 pi r0 (n^s . k, n^s . a2, r n^s . a3 + m^s . k, m^s . a3, m^s . c1)``.

All functions take CasADi ``SX``; ``s``, ``t`` must be pure symbols.
"""

from __future__ import annotations

import casadi as ca

K = ca.DM([1.0, 0.0, 0.0])


def axial_pair(phi):
    """``j2(phi) = cos(phi) i2 + sin(phi) i3`` and ``j3(phi) = k x j2(phi)``, eq. (2.5)."""
    return ca.vertcat(0, ca.cos(phi), ca.sin(phi)), ca.vertcat(0, -ca.sin(phi), ca.cos(phi))


def moving_frames(chi, theta, psi, phi):
    """Cartesian columns of the bases ``a_k`` (2.5), ``b_k`` (2.10) and ``c_k`` (2.13).

    Returns a dict with keys ``a1 .. a3, b1 .. b3, c1 .. c3``; ``c2`` is the director ``d``.
    """
    j2, j3 = axial_pair(phi)
    a1 = ca.SX(K)
    a2 = ca.cos(chi) * j2 + ca.sin(chi) * j3
    a3 = -ca.sin(chi) * j2 + ca.cos(chi) * j3
    b1 = ca.cos(theta) * a1 + ca.sin(theta) * a2
    b2 = -ca.sin(theta) * a1 + ca.cos(theta) * a2
    c2 = ca.cos(psi) * b2 + ca.sin(psi) * a3
    return {"a1": a1, "a2": a2, "a3": a3, "b1": b1, "b2": b2, "b3": a3, "c1": b1, "c2": c2, "c3": ca.cross(b1, c2)}


def reference_frame(theta0, phi):
    """``b0_1, b0_2 = d0, b0_3`` of the reference configuration (2.2): ``b0_1`` is the generator's tangent."""
    j2, j3 = axial_pair(phi)
    k = ca.SX(K)
    return ca.cos(theta0) * k + ca.sin(theta0) * j2, -ca.sin(theta0) * k + ca.cos(theta0) * j2, j3


def configuration(fields, phi):
    """Base surface ``r = z k + r a2`` (2.6), director ``d`` (2.11) and the frames, all Cartesian."""
    z, r, chi, theta, psi = fields
    frames = moving_frames(chi, theta, psi, phi)
    return z * ca.SX(K) + r * frames["a2"], frames["c2"], frames


def deformation_gradient_cartesian(fields, s, phi, zeta, r0=1.0, theta0=0.0, theta0_s=0.0):
    """Cartesian ``F`` of ``p = r + zeta d`` (2.8) by differentiation, eqs. (7.2)-(7.3).

    ``F = p_s b0_1 / (1 - zeta theta0_s) + p_phi b0_3 / (r0 + zeta cos theta0) + p_zeta d0``.
    ``s`` and ``phi`` must be the pure symbols the ``fields`` depend on; ``zeta`` may be a
    number or an expression; ``r0, theta0, theta0_s`` are the reference data at the point.
    """
    depth = ca.SX.sym("zeta")
    pos, d, _ = configuration(fields, phi)
    grad = ca.jacobian(pos + depth * d, ca.vertcat(s, phi, depth))
    b01, b02, b03 = reference_frame(theta0, phi)
    F = (
        ca.mtimes(grad[:, 0], b01.T) / (1 - depth * theta0_s)
        + ca.mtimes(grad[:, 1], b03.T) / (r0 + depth * ca.cos(theta0))
        + ca.mtimes(grad[:, 2], b02.T)
    )
    return ca.substitute(F, depth, zeta)


def svk_piola(F, lam, mu):
    """First Piola-Kirchhoff stress ``T = F S``, ``S = lambda tr(E) I + 2 mu E``, ``E = (F^T F - I)/2`` (7.9)."""
    E = 0.5 * (ca.mtimes(F.T, F) - ca.SX.eye(3))
    return ca.mtimes(F, lam * ca.trace(E) * ca.SX.eye(3) + 2 * mu * E)


def balance_laws(fields, s, t, lam, mu, rho, thickness, r0=1.0, theta0=0.0, theta0_s=0.0):
    """Resultants, inertia terms and residuals of the balance laws (3.6)-(3.7) at ``phi = 0``.

    Parameters
    ----------
    fields : sequence of casadi.SX
        ``(z, r, chi, theta, psi)`` as explicit expressions of the symbols ``s`` and ``t``.
    s, t : casadi.SX
        Pure symbols.
    lam, mu : float
        Lame coefficients of ``W_SVK``.
    rho : float
        Density per unit reference volume.
    thickness : Thickness
        Gauss-Legendre rule on ``[zeta1, zeta2]``.
    r0, theta0, theta0_s : float or casadi.SX
        Reference radius, tangent angle and its derivative (may be expressions of ``s``).

    Returns
    -------
    dict of casadi.SX
        Cartesian vectors: ``r, d``, the frames (``a1 .. c3``), ``n_s, n_phi, m_s, m_phi``
        (7.5); ``elastic_lin = d_s(r0 n^s) + d_phi n^phi``, ``inertia_lin = r0 (rhoA r_tt +
        rhoI d_tt)``, ``elastic_ang = d_s(r0 m^s) + d_phi m^phi + r0 r_s x n^s + r_phi x n^phi``,
        ``inertia_ang = r0 d x (rhoI r_tt + rhoJ d_tt)`` and the residuals ``residual_lin =
        elastic_lin - inertia_lin``, ``residual_ang = elastic_ang - inertia_ang``;
        ``dphi_n_phi, k_x_n_phi, dphi_m_phi, k_x_m_phi`` to check (3.8); ``stress_power``
        ``= r0 n^s.(r_st - w x r_s) + n^phi.(r_phit - w x r_phi) + r0 m^s.w_s + m^phi.w_phi``
        with the angular velocity ``w = chi_t k + theta_t a3 + psi_t c1`` of ``d``; it equals
        ``d/dt (r0 What)`` for a hyperelastic shell.

    Notes
    -----
    Eq. (7.5) with (7.6): ``r0 n^s = int T b0_1 (r0 + zeta cos theta0) dzeta``,
    ``n^phi = int T b0_3 (1 - zeta theta0_s) dzeta``, ``r0 m^s = d x int zeta T b0_1 (r0 +
    zeta cos theta0) dzeta``, ``m^phi = d x int zeta T b0_3 (1 - zeta theta0_s) dzeta``.
    The inertia terms are the same integrals of the 3-D momentum density,
    ``int rho p_tt J0 dzeta`` and ``d x int rho zeta p_tt J0 dzeta`` with
    ``J0 = (1 - zeta theta0_s)(r0 + zeta cos theta0)``, which by (7.8) are
    ``r0 (rhoA r_tt + rhoI d_tt)`` and ``r0 d x (rhoI r_tt + rhoJ d_tt)``.
    """
    phi = ca.SX.sym("phi")
    pos, d, frames = configuration(fields, phi)
    b01, _, b03 = reference_frame(theta0, phi)
    depth = ca.SX.sym("zeta")
    F_depth = deformation_gradient_cartesian(fields, s, phi, depth, r0, theta0, theta0_s)
    p_tt = ca.jacobian(ca.jacobian(pos + depth * d, t), t)
    zero = ca.SX.zeros(3)
    r0_n_s, n_phi, moment_s, moment_phi, inertia_lin, inertia_moment = zero, zero, zero, zero, zero, zero
    for zeta, w in zip(*thickness.nodes_weights):
        T = svk_piola(ca.substitute(F_depth, depth, zeta), lam, mu)
        across_s = w * (r0 + zeta * ca.cos(theta0))  # |z_zeta x z_phi| dzeta, (7.6)
        across_phi = w * (1 - zeta * theta0_s)  # |z_s x z_zeta| dzeta
        r0_n_s = r0_n_s + across_s * ca.mtimes(T, b01)
        n_phi = n_phi + across_phi * ca.mtimes(T, b03)
        moment_s = moment_s + zeta * across_s * ca.mtimes(T, b01)
        moment_phi = moment_phi + zeta * across_phi * ca.mtimes(T, b03)
        acc = ca.substitute(p_tt, depth, zeta)
        inertia_lin = inertia_lin + rho * across_s * (1 - zeta * theta0_s) * acc
        inertia_moment = inertia_moment + rho * across_s * (1 - zeta * theta0_s) * zeta * acc
    r0_m_s, m_phi = ca.cross(d, moment_s), ca.cross(d, moment_phi)
    k = ca.SX(K)
    r_s, r_phi = ca.jacobian(pos, s), ca.jacobian(pos, phi)
    elastic_lin = ca.jacobian(r0_n_s, s) + ca.jacobian(n_phi, phi)
    elastic_ang = (
        ca.jacobian(r0_m_s, s) + ca.jacobian(m_phi, phi) + ca.cross(r_s, r0_n_s) + ca.cross(r_phi, n_phi)
    )
    inertia_ang = ca.cross(d, inertia_moment)
    _, _, chi, theta, psi = fields
    omega = ca.jacobian(chi, t) * k + ca.jacobian(theta, t) * frames["a3"] + ca.jacobian(psi, t) * frames["c1"]
    stress_power = (
        ca.dot(r0_n_s, ca.jacobian(r_s, t) - ca.cross(omega, r_s))
        + ca.dot(n_phi, ca.jacobian(r_phi, t) - ca.cross(omega, r_phi))
        + ca.dot(r0_m_s, ca.jacobian(omega, s))
        + ca.dot(m_phi, ca.jacobian(omega, phi))
    )
    out = dict(frames)
    out.update(
        r=pos,
        d=d,
        n_s=r0_n_s / r0,
        n_phi=n_phi,
        m_s=r0_m_s / r0,
        m_phi=m_phi,
        elastic_lin=elastic_lin,
        inertia_lin=inertia_lin,
        elastic_ang=elastic_ang,
        inertia_ang=inertia_ang,
        residual_lin=elastic_lin - inertia_lin,
        residual_ang=elastic_ang - inertia_ang,
        dphi_n_phi=ca.jacobian(n_phi, phi),
        k_x_n_phi=ca.cross(k, n_phi),
        dphi_m_phi=ca.jacobian(m_phi, phi),
        k_x_m_phi=ca.cross(k, m_phi),
        stress_power=stress_power,
    )
    return {key: ca.substitute(value, phi, 0) for key, value in out.items()}


def virtual_power_projections(lin, ang, frames, r):
    """Generalised forces of the five fields from a linear and an angular balance (section 4).

    ``(lin . k, lin . a2, lin . (r a3) + ang . k, ang . a3, ang . c1)``: the coefficients of
    ``delta_z, delta_r, delta_chi, delta_theta, delta_psi`` in ``lin . delta r + ang . omega``
    with ``delta r = delta_z k + delta_r a2 + r delta_chi a3`` (4.10) and
    ``omega = delta_chi k + delta_theta a3 + delta_psi c1`` (4.12).
    """
    a2, a3, c1 = frames["a2"], frames["a3"], frames["c1"]
    k = ca.SX(K)
    return ca.vertcat(
        ca.dot(lin, k),
        ca.dot(lin, a2),
        r * ca.dot(lin, a3) + ca.dot(ang, k),
        ca.dot(ang, a3),
        ca.dot(ang, c1),
    )


def end_fluxes(laws, r, r0=1.0):
    """``r0 (n^s . k, n^s . a2, r n^s . a3 + m^s . k, m^s . a3, m^s . c1)``: what ``-dl/dq_s / (2 pi)`` must equal.

    The natural boundary conditions at an end where ``z`` and ``theta`` are prescribed
    (eq. 6.8 repaired) are the vanishing of the 2nd, 3rd and 5th entries.
    """
    return r0 * virtual_power_projections(laws["n_s"], laws["m_s"], laws, r)


def euler_lagrange(density, fields, s, t):
    """Euler-Lagrange expressions of a Lagrangian density along explicit fields.

    ``EL_j = d_s(dl/dq_j,s) + d_t(dl/dq_j,t) - dl/dq_j``: the partials are taken with respect
    to placeholder symbols, the fields are substituted, then ``d_s, d_t`` are total derivatives.

    Parameters
    ----------
    density : callable
        ``(q, q_s, q_t) -> l``, each argument a list of five SX scalars.
    fields : sequence of casadi.SX
        ``(z, r, chi, theta, psi)`` as expressions of ``s`` and ``t``.

    Returns
    -------
    (casadi.SX, casadi.SX)
        ``EL`` (5-vector) and the flux ``dl/dq_s`` along the fields (5-vector).
    """
    q = ca.vertcat(*fields)
    Q, Qs, Qt = ca.SX.sym("Q", 5), ca.SX.sym("Qs", 5), ca.SX.sym("Qt", 5)
    ell = density(ca.vertsplit(Q), ca.vertsplit(Qs), ca.vertsplit(Qt))
    partials = [ca.gradient(ell, x) for x in (Q, Qs, Qt)]
    dq, flux_s, flux_t = ca.substitute(partials, [Q, Qs, Qt], [q, ca.jacobian(q, s), ca.jacobian(q, t)])
    return ca.jacobian(flux_s, s) + ca.jacobian(flux_t, t) - dq, flux_s
