"""A stiff viscoelastic shell: implicit integrators step past the explicit bound and agree with leap-frog.

With eta_mu = 1000 Pa s (eta_lambda = 2000 Pa s) the fastest mode of the paper scene on 40 nodes
is a viscous one that decays at ~8e4 1/s, whatever the grid: an explicit method needs
``t max|eig J|`` steps (~800 over 10 ms), and leap-frog's parasitic root grows that mode like
``exp(8e4 t)``, so leap-frog is usable only over the first ~1e-4 s.
"""

import numpy as np
import pytest

import mol_shell
from mol_shell.equilibrium import spectrum_bounds
from mol_shell.integrators import Leapfrog
from mol_shell.simulate import build, resolve

SCENE = mol_shell.TwistedCylinder(eta_mu=1000.0, eta_lambda=2000.0)
N, T_END = 40, 0.01


@pytest.fixture(scope="module")
def spectrum():
    scene = resolve(SCENE)
    system, compiled = build(scene, N)
    y0 = system.initial_state(scene)
    omega_max, damping = spectrum_bounds(system.jac, y0, True)
    return scene, system, compiled, y0, omega_max, damping


def _max_rel(a, b):
    return max(float(np.abs(a[f].values - b[f].values).max() / np.abs(b[f].values).max()) for f in ("r", "theta", "chi"))


def test_case_is_stiff(spectrum):
    *_, omega_max, damping = spectrum
    assert damping > 0.5 * omega_max  # the fastest mode is (over)damped, not a wave
    assert damping * T_END > 100  # leap-frog over T_END would amplify it by more than e^100


@pytest.mark.parametrize("name,other", [("cvode-bdf", "ida"), ("ida", "cvode-bdf")])
def test_implicit_steps_far_fewer_than_the_explicit_bound(spectrum, name, other):
    *_, omega_max, _ = spectrum
    times = [0.0, T_END / 2, T_END]
    run = mol_shell.simulate(SCENE, name, n=N, times=times, rtol=1e-6, atol=1e-9, progress=False)
    # reference: the other formulation (CVODE on the Hamiltonian ODE, IDA on the residual in (q, v)) at tight tolerance
    ref = mol_shell.simulate(SCENE, other, n=N, times=times, rtol=1e-10, atol=1e-12, progress=False)
    explicit_steps = T_END * omega_max
    assert run.attrs["status"] == "complete"
    assert run.attrs["n_steps"] < explicit_steps / 3
    assert _max_rel(run, ref) < 1e-4
    assert np.all(np.diff(run.energy.values) < 0)  # viscosity only takes energy out


def test_agrees_with_leapfrog_at_a_small_step_while_leapfrog_is_stable(spectrum):
    scene, system, compiled, y0, omega_max, damping = spectrum
    t_end = 4.0 / damping  # parasitic growth at most e^4
    steps = int(np.ceil(20 * t_end * omega_max))  # dt = bound / 20 or less
    traj = Leapfrog(dt=t_end / steps).integrate(system, compiled, y0, np.array([0.0, t_end]))
    assert traj.status == "complete"
    lf = system.unpack(traj.y[-1])
    for name in ("cvode-bdf", "ida"):
        ds = mol_shell.simulate(scene, name, n=N, times=[0.0, t_end], rtol=1e-9, atol=1e-12, progress=False)
        for k, field in enumerate(("r", "chi", "theta"), start=1):
            moved = ds[field].values[-1] - ds[field].values[0]  # the motion so far, not the fields themselves
            assert np.abs(moved).max() > 1e-11  # (chi moves by 7e-7 rad, theta 5e-9 rad, r 5e-11 m)
            # leap-frog's error ~ (dt omega)^2 / 24 ~ 1e-4 of the motion
            np.testing.assert_allclose(lf[k] - ds[field].values[0], moved, rtol=0, atol=1e-3 * np.abs(moved).max(),
                                       err_msg=f"{name} {field}")
