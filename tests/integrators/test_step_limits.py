"""Runs whose steps are held by stiffness or stability rather than by their tolerance say so
(:mod:`mol_shell.runs.step_limits`): a fixed-point ``cvode-adams`` on a stiff viscous wall, and BDF orders 3-5 on an
undamped oscillation far above the shell's motion (the director's rotation of a thin wall)."""

import math
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.integrators import sundials_c
from mol_shell.runs import step_limits

STIFF = mol_shell.TwistedCylinder(eta_mu=1e4, eta_lambda=2e4)
THIN = mol_shell.TwistedCylinder(h=1e-6)
TIMES = np.linspace(0, 0.05, 11)


def _run(scene, integrator, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(scene, integrator, n=11, progress=False, **kw)
    return ds, [str(w.message) for w in caught if issubclass(w.category, (RuntimeWarning, UserWarning))]


def _bdf_largest_root(order, z):
    """The largest root of BDF's characteristic polynomial ``sum_j (1/j) nabla^j - z`` (closed form of the method)."""
    coeffs = np.zeros(order + 1, dtype=complex)
    for j in range(1, order + 1):
        coeffs[: j + 1] += np.array([(-1) ** i * math.comb(j, i) for i in range(j + 1)]) / j
    coeffs[0] -= z
    return max(abs(np.roots(coeffs)))


@pytest.fixture(scope="module")
def stiff_reference():
    return mol_shell.simulate(STIFF, "ida", n=11, times=TIMES, rtol=1e-11, atol=1e-14, progress=False)


def _error(ds, ref):
    return max(float(np.abs(ds[k].values - ref[k].values).max() / np.abs(ref[k].values).max())
               for k in ("r", "theta", "chi"))


def test_fixed_point_adams_on_a_stiff_wall_warns_that_its_steps_are_not_the_tolerances(stiff_reference):
    """eta_mu = 1e4: the fixed-point iteration converges only for ``h beta_0 L < 1`` (``L`` the damping rate, beta_0
    <= 1), so its steps sit below 1/damping whatever rtol; a third of its attempts fail to converge and its error was
    10.6 rtol at rtol 1e-6, silently. Now a warning names the stiff routes; Newton's iteration follows rtol."""
    rtol = 1e-6
    ds, said = _run(STIFF, "cvode-adams", times=TIMES, rtol=rtol, atol=1e-3 * rtol)
    mean_step = TIMES[-1] / ds.attrs["n_steps"]
    assert mean_step * ds.attrs["max_damping_rate"] < 1.0  # held by the fixed-point iteration's convergence
    assert ds.attrs["n_convergence_fails"] >= 0.1 * ds.attrs["n_steps"]
    note = [m for m in said if "fixed-point iteration failed to converge" in m]
    assert len(note) == 1 and 'iteration="newton"' in note[0] and "cvode-bdf or ida" in note[0], said
    assert ds.attrs["step_warning"] == note[0]
    newton, said = _run(STIFF, "cvode-adams", times=TIMES, rtol=rtol, atol=1e-3 * rtol, iteration="newton")
    assert not [m for m in said if "fixed-point" in m] and "step_warning" not in newton.attrs
    assert _error(newton, stiff_reference) < 10 * rtol


def test_fixed_point_adams_says_up_front_and_at_max_steps_that_stiffness_holds_its_steps():
    """``t_end damping / 0.8`` steps (0.05 s x 8.3e5 1/s: 5e4) are more than max_steps = 2,000: a warning before the
    run, and the stop at max_steps says why and what to use (it said only "took max_steps = ... steps by t = ...")."""
    ds, said = _run(STIFF, "cvode-adams", times=TIMES, max_steps=2000)
    expected = TIMES[-1] * ds.attrs["max_damping_rate"] / step_limits.ADAMS_STEP_DAMPING
    assert expected > 2000
    assert any(m.startswith("cvode-adams's fixed-point iteration converges only for steps below about 1/damping")
               and "more than max_steps = 2000" in m for m in said), said
    stop = [m for m in said if m.startswith("run incomplete")]
    assert len(stop) == 1 and "took max_steps = 2000 steps by t = " in stop[0], said
    assert "its fixed-point iteration failed to converge" in stop[0] and "cvode-bdf or ida" in stop[0], stop


def test_bdf_steps_held_by_an_undamped_director_mode_suggest_max_order_2():
    """h = 1e-6: the director's rotation (omega_max = 3.3e7 rad/s, undamped) holds BDF3-5's steps below 0.71 /
    omega_max (no order above 2 is stable on the imaginary axis between 0.71 and 1.94, BDF3 and BDF4 not below them:
    order 5 it is, under its bound; BDF2 is A-stable); the run
    names max_order = 2, which takes fewer steps and gets no note."""
    ds, said = _run(THIN, "cvode-bdf", t_end=2e-4)
    held = 2e-4 / ds.attrs["n_steps"] * ds.attrs["omega_max_rad_s"]
    assert ds.attrs["max_damping_rate"] == 0.0
    assert _bdf_largest_root(3, 1j * held) > 1 > _bdf_largest_root(2, 1j * held)
    note = [m for m in said if "held by the stability of BDF orders 3-5" in m]
    assert len(note) == 1 and "--option max_order=2" in note[0], said
    low, said = _run(THIN, "cvode-bdf", t_end=2e-4, max_order=2)
    assert "step_warning" not in low.attrs and low.attrs["n_steps"] < ds.attrs["n_steps"] / 2


def test_no_bdf_note_where_the_fastest_mode_is_the_shells_motion():
    """The paper's scene at rtol 1e-2 steps at 0.55 / omega_max, but its fields move at 0.012 omega_max or more: its
    fastest mode is its motion (max_order = 2 takes 7x more steps there); damped or low-order runs get no note."""
    method, stats = sundials_c.CVODEBDF(), {"n_steps": 20_000}
    omega, t_end = 5.29e3, 20_000 * 0.55 / 5.29e3
    assert step_limits.bdf_note(method, stats, t_end, omega, 0.0, 0.012 * omega) is None
    assert step_limits.bdf_note(method, stats, t_end, omega, 0.0, 1e-3 * omega) is not None
    assert step_limits.bdf_note(method, stats, t_end, omega, omega, 1e-3 * omega) is None  # damped: BDF-stable
    assert step_limits.bdf_note(sundials_c.CVODEBDF(max_order=2), stats, t_end, omega, 0.0, 1e-3 * omega) is None
    assert step_limits.bdf_note(sundials_c.CVODEAdams(), stats, t_end, omega, 0.0, 1e-3 * omega) is None
