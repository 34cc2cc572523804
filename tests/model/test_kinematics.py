"""Kinematics (section 2) and the deformation gradient (7.4) against Cartesian vectors differentiated by CasADi.

The package's component formulas (``mol_shell.model.kinematics``) are checked pointwise
against ``mol_shell.model.balance``, which builds ``r``, ``d`` and the frames in the fixed
basis ``(k, j2(0), j3(0))`` and differentiates them with ``casadi.jacobian``.
Fields are affine in ``(s, t)`` about ``(0, 0)`` with random coefficients, so at
``s = t = 0`` their values, strains and rates are the random numbers themselves.
"""

import casadi as ca
import numpy as np
import pytest

from mol_shell.model.balance import configuration, deformation_gradient_cartesian, moving_frames, reference_frame
from mol_shell.model.kinematics import (
    betas,
    deformation_gradient,
    delta,
    director_velocity_c,
    kinetic_energy_density,
    position_velocity_c,
)

S, T, PHI = ca.SX.sym("s"), ca.SX.sym("t"), ca.SX.sym("phi")
VAL, GRAD, RATE = ca.SX.sym("val", 5), ca.SX.sym("grad", 5), ca.SX.sym("rate", 5)
FIELDS = [VAL[j] + GRAD[j] * S + RATE[j] * T for j in range(5)]
ARGS = [S, T, PHI, VAL, GRAD, RATE]


def random_state(rng):
    """Values ``(z, r, chi, theta, psi)``, strains and rates with ``|theta|, |psi| <= 0.6``, ``r ~ 1``."""
    val = np.array([rng.uniform(-1, 1), rng.uniform(0.6, 1.6), rng.uniform(-3, 3), *rng.uniform(-0.6, 0.6, 2)])
    grad = np.array([rng.uniform(0.7, 1.3), *rng.uniform(-0.5, 0.5, 4)])
    rate = rng.uniform(-2, 2, 5)
    return val, grad, rate


def evaluate(exprs, val, grad, rate, phi=0.0):
    f = ca.Function("f", ARGS, list(exprs))
    return [np.array(out, dtype=float).squeeze() for out in f.call([0.0, 0.0, phi, val, grad, rate])]


def components(vector, frames, names):
    return [ca.dot(vector, frames[name]) for name in names]


@pytest.mark.parametrize("seed", range(6))
def test_deformation_gradient_table_matches_differentiated_position(seed):
    """``b_k . F . b0_l`` from ``p = r + zeta d`` and (7.2) equals the repaired table (7.4)."""
    rng = np.random.default_rng(seed)
    zeta, r0, theta0, theta0_s = ca.SX.sym("zeta"), ca.SX.sym("r0"), ca.SX.sym("theta0"), ca.SX.sym("theta0_s")
    F = deformation_gradient_cartesian(FIELDS, S, PHI, zeta, r0, theta0, theta0_s)
    _, _, frames = configuration(FIELDS, PHI)
    reference = reference_frame(theta0, PHI)
    table = [ca.dot(frames[f"b{k + 1}"], ca.mtimes(F, reference[l])) for k in range(3) for l in range(3)]
    f = ca.Function("table", [*ARGS, zeta, r0, theta0, theta0_s], [ca.vertcat(*table)])
    for _ in range(4):
        val, grad, rate = random_state(rng)
        ref = (rng.uniform(0.5, 2.0), rng.uniform(-0.6, 0.6), rng.uniform(-0.4, 0.4))
        depth = rng.uniform(-0.2, 0.2)
        got = np.array(f(0.0, 0.0, rng.uniform(0, 2 * np.pi), val, grad, rate, depth, *ref)).reshape(3, 3)
        strains = (*grad, val[1], val[3], val[4])
        expected = np.array(deformation_gradient(strains, depth, *ref), dtype=float)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)


def test_frames_are_right_handed_orthonormal():
    rng = np.random.default_rng(10)
    _, _, fr = configuration(FIELDS, PHI)
    checks = []
    for letter in "abc":
        e = [fr[f"{letter}{i}"] for i in (1, 2, 3)]
        gram = ca.mtimes(ca.horzcat(*e).T, ca.horzcat(*e)).reshape((9, 1))
        checks.append(ca.vertcat(gram, ca.cross(e[0], e[1]) - e[2]))
    val, grad, rate = random_state(rng)
    out = evaluate(checks, val, grad, rate, phi=0.7)
    for o in out:
        np.testing.assert_allclose(o, [1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0], atol=1e-15)


@pytest.mark.parametrize("seed", range(4))
def test_frame_derivatives_2_12_to_2_15(seed):
    """``b_s, b_phi`` (2.12), ``d_s, d_phi`` (2.12)/(2.14), ``c3_s, c3_phi`` (2.15) in the moving bases."""
    rng = np.random.default_rng(100 + seed)
    _, _, fr = configuration(FIELDS, PHI)
    val, grad, rate = random_state(rng)
    _, r, chi, theta, psi = val
    _, _, chi_s, theta_s, psi_s = grad
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    bs = ["b1", "b2", "b3"]
    cs = ["c1", "c2", "c3"]
    d = lambda name, x: ca.jacobian(fr[name], x)  # noqa: E731
    got = evaluate(
        [
            ca.vertcat(*components(d("b1", S), fr, bs)),
            ca.vertcat(*components(d("b2", S), fr, bs)),
            ca.vertcat(*components(d("b3", S), fr, ["a1", "a2", "a3"])),
            ca.vertcat(*components(d("c2", S), fr, cs)),
            ca.vertcat(*components(d("c2", PHI), fr, cs)),
            ca.vertcat(*components(d("c2", PHI), fr, bs)),
            ca.vertcat(*components(d("c3", S), fr, cs)),
            ca.vertcat(*components(d("c3", PHI), fr, cs)),
        ],
        val,
        grad,
        rate,
        phi=rng.uniform(0, 6),
    )
    twist = psi_s + chi_s * ct
    expected = [
        [0, theta_s, chi_s * st],
        [-theta_s, 0, chi_s * ct],
        [0, -chi_s, 0],
        [-(chi_s * sp * st + theta_s * cp), 0, twist],
        [-sp * st, 0, ct],
        [-sp * st, -sp * ct, cp * ct],
        [theta_s * sp - chi_s * cp * st, -twist, 0],
        [-cp * st, -ct, 0],
    ]
    for g, e in zip(got, expected):
        np.testing.assert_allclose(g, e, atol=1e-14)


@pytest.mark.parametrize("seed", range(4))
def test_velocities_2_17_and_strains_2_18_2_20(seed):
    """``d_t``, ``r_t`` in the c basis (2.17), ``r_s = beta_k b_k`` (2.18) and ``delta`` (2.20).

    (2.20) prints ``delta := (r_s x r_phi) . d``; that triple product is ``-r gamma1 cos(psi)``
    (``-1`` in the reference state ``r_s = k, r_phi = j3, d = j2``). The positive one, equal
    to ``det F`` at ``zeta = 0``, is ``(r_phi x r_s) . d = r gamma1 cos(psi)``, which is what
    :func:`delta` returns.
    """
    rng = np.random.default_rng(200 + seed)
    pos, d, fr = configuration(FIELDS, PHI)
    cs = ["c1", "c2", "c3"]
    r_s, r_phi = ca.jacobian(pos, S), ca.jacobian(pos, PHI)
    val, grad, rate = random_state(rng)
    got = evaluate(
        [
            ca.vertcat(*components(ca.jacobian(d, T), fr, cs)),
            ca.vertcat(*components(ca.jacobian(pos, T), fr, cs)),
            ca.vertcat(*components(r_s, fr, ["b1", "b2", "b3"])),
            ca.dot(ca.cross(r_phi, r_s), d),
            ca.vertcat(ca.dot(r_phi, ca.jacobian(d, S)), ca.dot(r_phi, ca.jacobian(d, PHI))),
        ],
        val,
        grad,
        rate,
        phi=rng.uniform(0, 6),
    )
    _, r, _, theta, psi = val
    z_s, r_s_, chi_s, _, psi_s = grad
    z_t, r_t, chi_t, theta_t, psi_t = rate
    np.testing.assert_allclose(got[0], director_velocity_c(chi_t, theta_t, psi_t, theta, psi), atol=1e-14)
    np.testing.assert_allclose(got[1], position_velocity_c(z_t, r_t, chi_t, r, theta, psi), atol=1e-14)
    np.testing.assert_allclose(got[2], betas(z_s, r_s_, chi_s, r, theta), atol=1e-14)
    np.testing.assert_allclose(got[3], delta(z_s, r_s_, r, theta, psi), atol=1e-14)
    # (2.21) as printed has r_phi . d_s = r cos(psi)(psi_s - chi_s cos theta) and
    # r_phi . d_phi = -r cos(psi) cos(theta); both signs are wrong (misprints, unused by the code):
    expected = [r * np.cos(psi) * (psi_s + chi_s * np.cos(theta)), r * np.cos(psi) * np.cos(theta)]
    np.testing.assert_allclose(got[4], expected, atol=1e-14)


RHO = (1.3, 0.21, 0.05)  # rhoA rhoJ - rhoI^2 > 0, rhoI != 0


def test_kinetic_energy_density_and_axial_angular_momentum():
    """``T_dens = rhoA |r_t|^2/2 + rhoI r_t.d_t + rhoJ |d_t|^2/2`` (sec. 7) and Noether's axial momentum (3.1).

    ``dT_dens/dchi_t = k . (rhoA r x r_t + rhoJ d x d_t + rhoI (r x d_t + d x r_t))``.
    """
    rng = np.random.default_rng(7)
    rho_a, rho_i, rho_j = RHO
    pos, d, _ = configuration(FIELDS, PHI)
    r_t, d_t = ca.jacobian(pos, T), ca.jacobian(d, T)
    cartesian = 0.5 * rho_a * ca.dot(r_t, r_t) + rho_i * ca.dot(r_t, d_t) + 0.5 * rho_j * ca.dot(d_t, d_t)
    k = ca.DM([1, 0, 0])
    momentum = ca.dot(
        k,
        rho_a * ca.cross(pos, r_t) + rho_j * ca.cross(d, d_t) + rho_i * (ca.cross(pos, d_t) + ca.cross(d, r_t)),
    )
    q, v = ca.SX.sym("q", 5), ca.SX.sym("v", 5)
    dens = kinetic_energy_density(ca.vertsplit(q), ca.vertsplit(v), rho_a, rho_i, rho_j)
    package = ca.substitute([dens, ca.gradient(dens, v)[2]], [q, v], [ca.vertcat(*FIELDS), RATE])
    for _ in range(5):
        val, grad, rate = random_state(rng)
        got = evaluate([cartesian, momentum, *package], val, grad, rate, phi=rng.uniform(0, 6))
        assert got[2] == pytest.approx(float(got[0]), rel=1e-13)
        assert got[3] == pytest.approx(float(got[1]), rel=1e-13)
    # rhoI really enters: the cross term is not negligible for these data
    assert abs(float(evaluate([rho_i * ca.dot(r_t, d_t)], val, grad, rate)[0])) > 1e-3


def test_reference_frame_of_the_cylinder():
    """``theta0 = 0``: ``b0_1 = k``, ``d0 = j2``, ``b0_3 = j3``; the reference deformation gradient is ``I``."""
    b01, b02, b03 = [np.array(ca.evalf(ca.substitute(b, PHI, 0.0))).ravel() for b in reference_frame(0.0, PHI)]
    np.testing.assert_allclose([b01, b02, b03], np.eye(3), atol=0)
    reference = [S, 1.0 + 0 * S, 0 * S, 0 * S, 0 * S]
    F = deformation_gradient_cartesian(reference, S, PHI, 0.03)
    np.testing.assert_allclose(np.array(ca.Function("F", [S, PHI], [F])(0.4, 1.1)), np.eye(3), atol=1e-15)
    assert moving_frames(0.0, 0.0, 0.0, PHI)["c2"].shape == (3, 1)


def test_delta_is_the_jacobian_at_the_base_surface():
    """``det F(zeta = 0) = delta / r0`` with ``delta = r beta1 cos(psi) > 0`` (2.20): orientation is kept."""
    rng = np.random.default_rng(11)
    r0 = 1.4
    det = ca.det(deformation_gradient_cartesian(FIELDS, S, PHI, 0.0, r0, 0.0, 0.0))
    for _ in range(3):
        val, grad, rate = random_state(rng)
        got = float(evaluate([det], val, grad, rate, phi=rng.uniform(0, 6))[0])
        assert got == pytest.approx(delta(grad[0], grad[1], val[1], val[3], val[4]) / r0, rel=1e-13)
