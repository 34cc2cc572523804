"""The balance laws (3.6)-(3.8) in Cartesian vectors agree pointwise with the Euler-Lagrange equations.

Route 1 is the package's Lagrangian density ``l = 2 pi r0 (T_dens - What)`` with
``kinetic_energy_density`` and ``shell_energy``; route 2 is ``mol_shell.model.balance``
(``p = r + zeta d`` differentiated by CasADi, 3-D stress integrated through the thickness).
Both are exact at the continuum level, evaluated on smooth explicit fields of ``(s, t)``
with twist, breathing, shear and bending all present; no grid is involved, so they must
agree to rounding. The elastic and inertial parts are compared separately so that a wrong
small term cannot hide behind a large one.
"""

import math
from functools import lru_cache

import casadi as ca
import numpy as np
import pytest

from mol_shell.model.balance import (
    balance_laws,
    end_fluxes,
    euler_lagrange,
    svk_piola,
    virtual_power_projections,
)
from mol_shell.model.kinematics import deformation_gradient, kinetic_energy_density
from mol_shell.model.material import Thickness, centroidal_offset, inertias, shell_energy, svk_energy, svk_stress

S, T = ca.SX.sym("s"), ca.SX.sym("t")
#: Agreement of the two routes, relative to the equation's size (max over the points). A bound
#: from the round-off of the terms: each side is a sum over <= 6 Gauss points of terms carrying
#: ~100 roundings each (3x3 products, E = (F^T F - I)/2, CasADi's derivative sweeps), i.e.
#: ~100 EPS of the largest term. The largest terms exceed the result where the membrane stresses
#: cancel through the thickness: the couple fluxes m^s.a3, m^s.c1 and the theta, psi equations
#: are first moments int zeta T (1 + zeta) of stresses dominated by their membrane parts, smaller
#: than the terms by ~ h x (bending strain)/(membrane strain) >= h min(1, |theta_s|) ~ 2e-3 for the
#: paper's h = 6.3e-3 m and theta_s ~ 0.3 here. So 100 EPS / 2e-3 ~ 1e-11. Measured: at most
#: 800 EPS = 1.8e-13 (the psi flux of the paper material), 1e-15 .. 1e-14 for most equations.
TOL = 1e-11


def twist_breathing(r0):
    return (
        S + 0.04 * ca.sin(1.1 * S + 0.6 * T),
        r0 * (1 + 0.03 * ca.cos(0.7 * S - 1.3 * T)) + 0.02 * S * T,
        0.1 * (S - 2) + 0.15 * ca.sin(0.9 * T + 0.4 * S),
        0.12 * ca.sin(0.8 * S + 1.2 * T) + 0.05,
        0.1 * ca.cos(1.3 * S - 0.5 * T) + 0.08 * T,
    )


def shear_bending(r0):
    return (
        1.02 * S - 0.05 * ca.cos(0.9 * S + T),
        r0 + 0.05 * ca.sin(1.4 * S) * ca.cos(0.8 * T),
        0.2 * ca.sin(0.6 * S - 0.7 * T) + 0.05 * S * T,
        0.3 * ca.cos(1.1 * S - 0.9 * T),
        0.25 * ca.sin(0.7 * S + 1.5 * T) - 0.1,
    )


def spin_stretch(r0):
    return (
        0.97 * S + 0.03 * S * ca.sin(T),
        r0 * (0.98 + 0.04 * ca.sin(0.5 * S) * ca.sin(2.0 * T)),
        3.0 * T * (1 + 0.2 * S) + 0.1 * ca.sin(S),
        0.2 * ca.sin(0.5 * S) * ca.cos(1.7 * T),
        0.15 + 0.1 * ca.sin(2.1 * T - 0.3 * S),
    )


MATERIALS = {  # (lambda, mu, rho, h)
    "unit": (2.0, 1.0, 1.0, 0.1),
    "paper": (1.644e-2, 3.356e-4, 1000.0, 2 * math.pi * 1e-3),  # section 6
}

# (fields, material, base surface zeta1 / h or "centroidal", n_quad, r0)
CASES = {
    "twist-centroidal-q2": (twist_breathing, "unit", "centroidal", 2, 1.0),
    "twist-mid-q6-r0": (twist_breathing, "unit", -1.0, 6, 1.5),
    "shear-outer-q6": (shear_bending, "unit", -2.0, 6, 1.0),
    "shear-paper-q2": (shear_bending, "paper", "centroidal", 2, 1.0),
    "spin-paper-mid-q6": (spin_stretch, "paper", -1.0, 6, 1.0),
    "spin-offset-q3-r0": (spin_stretch, "unit", -0.3, 3, 0.8),
}

POINTS = np.column_stack([np.random.default_rng(3).uniform(0.0, 4.0, 5), np.random.default_rng(4).uniform(0.0, 1.0, 5)])


def strains_of(q, q_s):
    """``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)`` of the package."""
    return (*q_s, q[1], q[3], q[4])


@lru_cache(maxsize=None)
def case(name):
    """Both routes for one case, evaluated at :data:`POINTS`: a dict of arrays ``(n_points, ...)``."""
    make, material, base, n_quad, r0 = CASES[name]
    lam, mu, rho, h = MATERIALS[material]
    zeta1 = centroidal_offset(h, r0) if base == "centroidal" else base * h
    thickness = Thickness(zeta1, h, n_quad)
    rho_a, rho_i, rho_j = inertias(rho, thickness, r0)
    fields = make(r0)
    laws = balance_laws(fields, S, T, lam, mu, rho, thickness, r0)
    r = fields[1]

    def stored(q, q_s, q_t):  # route 1, elastic part of l
        return -2 * math.pi * r0 * shell_energy(strains_of(q, q_s), lam, mu, thickness, r0)

    def kinetic(q, q_s, q_t):  # route 1, inertial part of l
        return 2 * math.pi * r0 * kinetic_energy_density(q, q_t, rho_a, rho_i, rho_j)

    el_elastic, flux = euler_lagrange(stored, fields, S, T)
    el_inertia, _ = euler_lagrange(kinetic, fields, S, T)
    q = ca.vertcat(*fields)
    what = shell_energy(strains_of(ca.vertsplit(q), ca.vertsplit(ca.jacobian(q, S))), lam, mu, thickness, r0)

    # What with beta_k -> beta_k + eps_k in the package's table (7.4): column 1 is r_s + zeta d_s
    eps = ca.SX.sym("eps", 3)
    perturbed = 0
    for zeta, w in zip(*thickness.nodes_weights):
        F = [list(row) for row in deformation_gradient(strains_of(fields, ca.vertsplit(ca.jacobian(q, S))), zeta, r0)]
        for k in range(3):
            F[k][0] = F[k][0] + eps[k]
        perturbed = perturbed + w * (r0 + zeta) / r0 * svk_energy(F, lam, mu)
    dwhat_dbeta = ca.substitute(ca.gradient(perturbed, eps), eps, ca.DM.zeros(3))
    n_s_b = ca.vertcat(*[ca.dot(laws["n_s"], laws[f"b{k}"]) for k in (1, 2, 3)])

    outputs = {
        "proj_elastic": -2 * math.pi * virtual_power_projections(laws["elastic_lin"], laws["elastic_ang"], laws, r),
        "proj_inertia": 2 * math.pi * virtual_power_projections(laws["inertia_lin"], laws["inertia_ang"], laws, r),
        "proj_total": -2 * math.pi * virtual_power_projections(laws["residual_lin"], laws["residual_ang"], laws, r),
        "el_elastic": el_elastic,
        "el_inertia": el_inertia,
        "el_total": el_elastic + el_inertia,
        "ang_d": ca.vertcat(ca.dot(laws["elastic_ang"], laws["d"]), ca.norm_2(laws["elastic_ang"])),
        "ang_c3": ca.dot(laws["residual_ang"], laws["c3"]) * ca.cos(fields[4]),
        "sym_n": ca.horzcat(laws["dphi_n_phi"], laws["k_x_n_phi"]),
        "sym_m": ca.horzcat(laws["dphi_m_phi"], laws["k_x_m_phi"]),
        "flux_lagrange": flux,
        "flux_balance": -2 * math.pi * end_fluxes(laws, r, r0),
        "power_balance": laws["stress_power"],
        "power_energy": r0 * ca.jacobian(what, T),
        "dwhat_dbeta": dwhat_dbeta,
        "n_s_b": n_s_b,
        "m_s_d": ca.vertcat(ca.dot(laws["m_s"], laws["d"]), ca.dot(laws["m_phi"], laws["d"]), ca.norm_2(laws["m_s"])),
    }
    f = ca.Function("routes", [S, T], list(outputs.values()))
    values = [f.call([s, t]) for s, t in POINTS]
    return {key: np.array([np.array(v[i], dtype=float) for v in values]) for i, key in enumerate(outputs)}


def discrepancy(a, b):
    """Per equation: ``max |a - b| / max |b|`` over the points (the last axis is the equation)."""
    a, b = a.reshape(len(POINTS), -1), b.reshape(len(POINTS), -1)
    return np.abs(a - b).max(axis=0) / np.abs(b).max(axis=0)


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("part", ["elastic", "inertia", "total"])
def test_balance_laws_equal_euler_lagrange(name, part):
    """``EL_j = -2 pi <(R_lin, R_ang), (delta r, omega)_j>`` for ``z, r, chi, theta, psi``."""
    out = case(name)
    assert np.abs(out[f"el_{part}"]).max(axis=0).min() > 0  # every equation is exercised
    err = discrepancy(out[f"proj_{part}"], out[f"el_{part}"])
    assert err.max() < TOL, dict(zip(("z", "r", "chi", "theta", "psi"), err))


@pytest.mark.parametrize("name", CASES)
def test_director_component_of_angular_balance_is_an_identity(name):
    """``R_ang . d = 0`` identically (the remark after 3.13), and ``m^s . d = m^phi . d = 0`` (3.3)."""
    out = case(name)
    ang_d, ang_norm = out["ang_d"][:, 0], out["ang_d"][:, 1]
    assert np.all(np.abs(ang_d) < 1e-13 * ang_norm)
    m = out["m_s_d"]
    assert np.all(np.abs(m[:, :2]) < 1e-15 * m[:, 2:])
    # hence the theta equation is the c3 balance (3.13) scaled by cos(psi)
    err = discrepancy(out["ang_c3"], out["el_total"][:, 3] / (-2 * math.pi))
    assert err.max() < TOL


@pytest.mark.parametrize("name", CASES)
def test_rotational_symmetry_3_8(name):
    """``d_phi n^phi = k x n^phi`` and ``d_phi m^phi = k x m^phi`` for the differentiated 3-D stress."""
    out = case(name)
    for key in ("sym_n", "sym_m"):
        derivative, cross = out[key][..., 0], out[key][..., 1]
        assert np.abs(derivative - cross).max() < 1e-11 * np.abs(cross).max()


@pytest.mark.parametrize("name", CASES)
def test_natural_boundary_terms(name):
    """``dl/dq_s = -2 pi r0 (n^s.k, n^s.a2, r n^s.a3 + m^s.k, m^s.a3, m^s.c1)``.

    At an end where ``z`` and ``theta`` are prescribed, the natural conditions
    ``dl/dr_s = dl/dchi_s = dl/dpsi_s = 0`` are ``n^s.a2 = 0``, ``r n^s.a3 + m^s.k = 0`` (no axial
    torque) and ``m^s.c1 = 0``.
    """
    out = case(name)
    err = discrepancy(out["flux_balance"], out["flux_lagrange"])
    assert err.max() < TOL, err


@pytest.mark.parametrize("name", CASES)
def test_stress_power_is_rate_of_stored_energy(name):
    """``r0 n^s.(r_st - w x r_s) + n^phi.(r_phit - w x r_phi) + r0 m^s.w_s + m^phi.w_phi = r0 dWhat/dt``."""
    out = case(name)
    err = discrepancy(out["power_balance"], out["power_energy"])
    assert err.max() < TOL, err


@pytest.mark.parametrize("name", CASES)
def test_force_resultant_is_gradient_of_stored_energy(name):
    """``n^s . b_j = dWhat/dbeta_j`` with ``What`` built from the package's table (7.4)."""
    out = case(name)
    err = discrepancy(out["n_s_b"], out["dwhat_dbeta"])
    assert err.max() < TOL, err


def test_piola_stress_is_energy_gradient():
    """``svk_piola`` (matrix form) equals ``svk_stress`` (package) and ``dW/dF``."""
    F = ca.SX.sym("F", 3, 3)
    rows = [[F[i, j] for j in range(3)] for i in range(3)]
    W = svk_energy(rows, 2.0, 0.7)
    package = ca.vertcat(*[ca.horzcat(*row) for row in svk_stress(rows, 2.0, 0.7)])
    f = ca.Function("T", [F], [svk_piola(F, 2.0, 0.7), package, ca.jacobian(W, F).reshape((3, 3))])
    value = np.eye(3) + np.random.default_rng(5).uniform(-0.3, 0.3, (3, 3))
    mine, theirs, gradient = (np.array(x) for x in f.call([value]))
    np.testing.assert_allclose(mine, theirs, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(mine, gradient, rtol=1e-14, atol=1e-15)
