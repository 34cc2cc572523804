"""Viscoelastic shells of strain-rate type: the dissipation identity, and leap-frog's limits."""

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.integrators import Leapfrog
from mol_shell.runs.simulate import build, resolve


def _perturbed_state(system, scene, seed=1, size=1e-2):
    y = system.initial_state(scene)
    free = np.tile(np.r_[~system.fixed[1], ~system.fixed[1]], system.n)
    return y + size * np.random.default_rng(seed).standard_normal(y.size) * free


@pytest.mark.parametrize("eta_lambda,eta_mu", [(0.0, 30.0), (100.0, 0.0), (100.0, 50.0)])
def test_energy_rate_equals_minus_dissipation(eta_lambda, eta_mu):
    """dH/dt = grad H . f(y) must equal -2D (the stress power of S_visc) at any state: an identity."""
    scene = resolve(mol_shell.TwistedCylinder(eta_lambda=eta_lambda, eta_mu=eta_mu, omega=3.0, psi0=0.1))
    system, _ = build(scene, 12)
    y = ca.SX.sym("y", system.size)
    out = system.observables(y, 0.0)
    energy = out[1] + out[2]
    terms = ca.gradient(energy, y) * system.rhs(0, y)
    rate = ca.Function("rate", [y], [ca.sum1(terms), ca.sum1(ca.fabs(terms)), out[5]])
    for seed in range(3):
        de_dt, scale, dissipation = (float(x) for x in rate(_perturbed_state(system, scene, seed)))
        assert dissipation > 0
        # the conservative terms of grad H . f cancel exactly; round-off is relative to their size
        assert abs(de_dt + dissipation) <= 1e-13 * scale
        assert abs(de_dt + dissipation) <= 1e-9 * dissipation


def test_elastic_shell_dissipates_nothing():
    scene = resolve(mol_shell.TwistedCylinder())
    system, _ = build(scene, 12)
    assert not system.viscous
    assert float(system.observables(_perturbed_state(system, scene), 0.0)[5]) == 0.0


def test_energy_decreases_by_the_integrated_dissipation():
    """Weak viscosity, leap-frog at small dt: E(0) - E(t) = int 2D dt (trapezoid on a fine save grid)."""
    scene = mol_shell.TwistedCylinder(eta_lambda=0.02, eta_mu=0.01)
    ds = mol_shell.simulate(scene, n=20, times=np.arange(0, 0.0201, 0.0005), dt=2e-6, progress=False)
    lost = ds.energy[0] - ds.energy
    dissipated = np.concatenate([[0], np.cumsum(np.diff(ds.time) * 0.5 * (ds.dissipation[1:].values + ds.dissipation[:-1].values))])
    assert np.all(np.diff(ds.energy) < 0)
    # trapezoid error ~ (dt_save^2/12) * max|d^2 P/dt^2| * t: a few percent of the loss at most;
    # leap-frog's own O(dt^2) energy oscillation (1e-10 relative at dt = 1e-6 for the elastic shell,
    # so ~4e-10 here) bounds the absolute error early on
    np.testing.assert_allclose(lost[1:], dissipated[1:], rtol=0.05, atol=2e-9 * float(ds.energy[0]))
    assert float(lost[-1]) > 100 * 2e-9 * float(ds.energy[0])


def test_leapfrog_refused_for_strong_viscosity():
    with pytest.raises(ParameterError, match="integrator = 'leapfrog'.*exp"):
        mol_shell.simulate(mol_shell.TwistedCylinder(eta_mu=50.0), n=20, t_end=0.02, progress=False)


def test_unstable_step_is_detected_by_energy_growth():
    """Bypass the up-front check: a step 1.5x beyond the bound blows up and is reported, data kept."""
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 20)
    omega_max = np.abs(np.linalg.eigvals(np.array(system.jac(0, system.initial_state(scene))))).max()
    dt = 1.5 / omega_max
    times = dt * np.arange(0, 2001, 100)
    traj = Leapfrog(dt=dt, chunk=50).integrate(system, compiled, system.initial_state(scene), times)
    assert traj.status == "unstable"
    assert "energy balance E - W + D" in traj.message
    assert np.all(np.isfinite(traj.y))
    assert 1 <= len(traj.t) < len(times)
