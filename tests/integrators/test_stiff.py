"""Stiff viscoelastic shells: implicit integrators step past the explicit bound and agree with explicit routes.

Kelvin-Voigt viscosity adds modes that decay at the rate ``max(-Re lambda)`` of the exact Jacobian,
proportional to the viscosity. With ``eta_mu = 1e4`` Pa s (``eta_lambda = 2e4``) on 40 nodes the fastest
mode decays at ~8e5 1/s: an explicit method needs ``t max|lambda| / c`` steps, ``c`` its stability
interval on the negative real axis (3.3 for Dormand-Prince 5(4)), about 2,500 over 10 ms, while BDF
steps are set by the accuracy of the slow motion only. Leap-frog's parasitic root grows such modes like
``exp(max(-Re lambda) t)`` (faster near the step bound): it is usable only over a few decay times,
checked with ``eta_mu = 1e3`` and ``eta_mu = 1``.
"""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.integrators import Leapfrog
from mol_shell.integrators.leapfrog import parasitic_growth_rate
from mol_shell.model.equilibrium import spectrum_bounds
from mol_shell.runs.leapfrog_guard import LEAPFROG_MAX_LOG_GROWTH
from mol_shell.runs.simulate import build, resolve

STIFF = mol_shell.TwistedCylinder(eta_mu=1e4, eta_lambda=2e4)
MILD = mol_shell.TwistedCylinder(eta_mu=1e3, eta_lambda=2e3)
N, T_END = 40, 0.01
RK45_STABILITY_INTERVAL = 3.31  # Dormand-Prince 5(4) on the negative real axis


def _spectrum(scene):
    scene = resolve(scene)
    system, compiled = build(scene, N)
    y0 = system.initial_state(scene)
    omega_max, damping = spectrum_bounds(system.jac, y0, True)
    return scene, system, compiled, y0, omega_max, damping


@pytest.fixture(scope="module")
def stiff():
    return _spectrum(STIFF)


def _max_rel(a, b):
    return max(float(np.abs(a[f].values - b[f].values).max() / np.abs(b[f].values).max()) for f in ("r", "theta", "chi"))


def test_case_is_stiff(stiff):
    *_, omega_max, damping = stiff
    assert damping > 0.5 * omega_max  # the fastest mode is (over)damped, not a wave
    assert damping * T_END > 1000  # leap-frog over T_END would amplify it by more than e^1000


@pytest.fixture(scope="module")
def explicit_run(stiff):
    return mol_shell.simulate(STIFF, "scipy-rk45", n=N, times=[0.0, T_END / 2, T_END], rtol=1e-6, atol=1e-9,
                              progress=False)


def test_an_explicit_method_is_held_to_its_stability_bound(stiff, explicit_run):
    *_, omega_max, _ = stiff
    assert explicit_run.attrs["status"] == "complete"
    # the step controller keeps RK45 at (not far below) its real-axis stability limit
    assert explicit_run.attrs["n_steps"] >= 0.8 * T_END * omega_max / RK45_STABILITY_INTERVAL


@pytest.mark.parametrize("name,other", [("cvode-bdf", "ida"), ("ida", "cvode-bdf")])
def test_implicit_steps_far_fewer_than_the_explicit_bound(stiff, explicit_run, name, other):
    *_, omega_max, _ = stiff
    times = [0.0, T_END / 2, T_END]
    run = mol_shell.simulate(STIFF, name, n=N, times=times, rtol=1e-6, atol=1e-9, progress=False)
    # reference: the other formulation (CVODE on the Hamiltonian ODE, IDA on the residual in (q, v)) at tight tolerance
    ref = mol_shell.simulate(STIFF, other, n=N, times=times, rtol=1e-10, atol=1e-12, progress=False)
    assert run.attrs["status"] == "complete"
    assert run.attrs["n_steps"] < T_END * omega_max / 20  # 20x fewer than the explicit bound 1/max|lambda|
    assert run.attrs["n_steps"] < explicit_run.attrs["n_steps"] / 5  # and 5x fewer than RK45 needed
    assert _max_rel(run, ref) < 1e-4
    assert _max_rel(explicit_run, ref) < 1e-4  # the explicit run is the same solution
    assert np.all(np.diff(run.energy.values) < 0)  # viscosity only takes energy out


def test_agrees_with_leapfrog_at_a_small_step_while_leapfrog_is_stable():
    scene, system, compiled, y0, omega_max, damping = _spectrum(MILD)
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


def test_parasitic_growth_is_faster_near_the_step_bound():
    """``eta_mu = 1`` Pa s: the fastest mode is an underdamped wave (``a << w``). Leap-frog's parasitic
    root for ``lambda dt = -a dt + i w dt`` has ``|z|^2 = 1 + 2 a dt / sqrt(1 - (w dt)^2)``: at
    ``w dt = 0.95`` it grows 3.2 times faster than at small steps. Over a horizon with ``a t = ln(1e6) / 2``
    the refusal counts that growth and refuses dt = 0.95 / w, and the run itself (past the refusal) trips
    the energy check; at ``w dt = 0.3`` (1.05 times faster) the same horizon is allowed and completes."""
    scene, system, compiled, y0, omega_max, damping = _spectrum(mol_shell.TwistedCylinder(eta_mu=1.0, eta_lambda=2.0))
    assert damping < 0.05 * omega_max
    t_end = LEAPFROG_MAX_LOG_GROWTH / 2 / damping
    for fraction, refused in ((0.95, True), (0.3, False)):
        steps = int(np.ceil(t_end * omega_max / fraction))
        dt = t_end / steps
        assert (parasitic_growth_rate(damping, omega_max, dt) * t_end > LEAPFROG_MAX_LOG_GROWTH) == refused
        if refused:
            with pytest.raises(ParameterError, match="parasitic root"):
                mol_shell.simulate(scene, "leapfrog", n=N, dt=dt, times=[0.0, t_end], progress=False)
            traj = Leapfrog(dt=dt).integrate(system, compiled, y0, np.array([0.0, t_end]))
            assert traj.status == "unstable"
        else:
            ds = mol_shell.simulate(scene, "leapfrog", n=N, dt=dt, times=[0.0, t_end], progress=False)
            assert ds.attrs["status"] == "complete"
