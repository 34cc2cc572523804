"""Stability: the leap-frog bound predicted from the Jacobian's spectrum matches bisection."""

import dataclasses

import numpy as np
import pytest

import mol_shell
from mol_shell.equilibrium import spectrum_bounds
from mol_shell.model.material import lame
from mol_shell.simulate import build, resolve
from mol_shell.stability import Case, markdown_table, report, stable_leapfrog_step


@pytest.mark.parametrize("changes", [{}, {"nu": 0.499}, {"h": 1e-3}])
def test_bisection_finds_the_eigenvalue_bound(changes):
    """Leap-frog on y' = i w y is stable iff |w dt| <= 1: the largest stable step of the
    nonlinear run must sit at 1/max|eig J(y0)| (bisection resolves it to (2)^(1/2^8) ~ 0.3 %;
    the state moves little in 3000 steps, so the spectrum hardly changes)."""
    scene = resolve(dataclasses.replace(mol_shell.TwistedCylinder(), **changes))
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    omega_max, damping = spectrum_bounds(system.jac, y0, system.viscous)
    assert damping == 0.0
    dt = stable_leapfrog_step(system, compiled, y0, 1.0 / omega_max)
    assert dt == pytest.approx(1.0 / omega_max, rel=0.01)


def test_locking_raises_the_frequency_and_plane_stress_removes_it():
    """nu -> 0.5 with the inextensible director: the axial/hoop stiffness lambda + 2 mu grows
    without bound, and the top of the spectrum is the grid's shortest axial wave,
    (2/ds) sqrt((lambda + 2 mu)/rho) (lumped mass, two-point difference). Condensed (plane
    stress) the membrane stiffness E/(1 - nu^2) stays small, so the top stays the transverse
    shear mode of the director, whose frequency scales as sqrt(mu)."""
    n, tops = 20, {}
    for material in ("svk", "svk-plane-stress"):
        for nu in (0.3, 0.4999):
            scene = resolve(mol_shell.TwistedCylinder(nu=nu, material=material))
            system, _ = build(scene, n)
            tops[material, nu] = spectrum_bounds(system.jac, system.initial_state(scene), False)[0]
    scene = mol_shell.TwistedCylinder(nu=0.4999)
    lam, mu = lame(scene.E, scene.nu)
    axial = 2 / (scene.L / (n - 1)) * np.sqrt((lam + 2 * mu) / scene.rho)
    assert tops["svk", 0.4999] == pytest.approx(axial, rel=0.01)
    mu_ratio = lame(1.0, 0.3)[1] / lame(1.0, 0.4999)[1]
    assert tops["svk-plane-stress", 0.3] / tops["svk-plane-stress", 0.4999] == pytest.approx(np.sqrt(mu_ratio), rel=0.01)


def test_report_table_has_a_row_per_case():
    ds = report([Case("paper", mol_shell.TwistedCylinder(), n=12, t_end=0.002)], integrators=(), bisect=False)
    table = markdown_table(ds)
    assert table.count("\n") == 2 and "| paper | 12 |" in table
    assert str(ds["leapfrog_status"].values[0]) == "complete"
    assert np.isfinite(ds["leapfrog_dt_bound"].values[0])
