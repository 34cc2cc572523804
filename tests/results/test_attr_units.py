"""A run's dimensional numbers carry their units (``units_NAME``), not only the scene's parameters: the inertia
densities, the failure time, zeta1 as used, the meridian's length and the integrators' time options had none."""

import math

import pytest

import mol_shell
from mol_shell.model.material import Thickness, inertias


@pytest.mark.parametrize("integrator", ["leapfrog", "cvode-bdf"])
def test_the_run_s_own_numbers_carry_units(integrator):
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), integrator, t_end=2e-4, n=8, progress=False, stresses=False)
    a = ds.attrs
    expected = {"failure_time": "s", "rho_A": "kg m-2", "rho_I": "kg m-1", "rho_J": "kg", "zeta1_used": "m",
                "meridian_length": "m"}
    expected.update({"dt": "s", "restart": "s"} if integrator == "leapfrog" else {"max_step": "s", "first_step": "s"})
    for name, unit in expected.items():
        assert name in a and a[f"units_{name}"] == unit, name
    # the densities are the moments 0, 1, 2 of rho through the wall (eq. 7.8), whence their units; rho_A is rho 2h
    # to the wall's curvature correction, 1 + (mean zeta) / a
    scene = mol_shell.TwistedCylinder()
    mean = a["zeta1_used"] + scene.h
    assert a["rho_A"] == pytest.approx(scene.rho * 2 * scene.h * (1 + mean / scene.a), rel=1e-12)
    moments = inertias(scene.rho, Thickness(a["zeta1_used"], scene.h, scene.n_quad), scene.a)
    for name, moment in zip(("rho_A", "rho_I", "rho_J"), moments):
        assert math.isclose(a[name], moment, rel_tol=1e-12, abs_tol=1e-12 * a["rho_A"] * scene.h), name  # rho_I: 0


def test_the_ring_ode_s_numbers_carry_units_too():
    ds = mol_shell.simulate_ring(mol_shell.SpinningRing(), t_end=0.01)
    for name, unit in {"rho_A": "kg m-2", "rho_I": "kg m-1", "rho_J": "kg", "failure_time": "s"}.items():
        assert ds.attrs[f"units_{name}"] == unit, name
