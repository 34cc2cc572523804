"""Section 4: a spinning unshearable shell moves axisymmetrically; the free shell from the same state does not."""

import numpy as np
import pytest

import mol_shell

from mol_shell._core.errors import ParameterError
from mol_shell.discretization.unshearable_dae import UnshearableDAE
from mol_shell.runs.unshearable import defects, simulate_unshearable
from mol_shell.scenes import Unshearable

TIMES = np.linspace(0.0, 0.03, 7)


@pytest.fixture(scope="module")
def spinning():
    """r = 1 + 0.01 cos(2 pi s / L), spin 20 rad/s; n = 41 resolves the free shell's psi (n = 81 agrees to 2 %)."""
    scene = Unshearable()
    return (simulate_unshearable(scene, n=41, times=TIMES),
            simulate_unshearable(scene, n=41, times=TIMES, constrained=False, dt=2e-6))


def test_constraints_hold_and_the_multipliers_work(spinning):
    constrained, _ = spinning
    assert constrained.attrs["complete"] == 1 and constrained.attrs["integrator"] == "ida"
    chi_s, psi = defects(constrained)
    assert chi_s < 1e-12 and psi == 0.0  # linear constraints: BDF keeps them to round-off
    assert float(constrained.chi_t.std("s").max()) < 1e-10  # one spin rate for the whole shell
    # ideal constraints do no work and exert no net torque
    e = constrained.energy.values
    assert np.abs(e - e[0]).max() < 1e-9 * e[0]
    L = constrained.angular_momentum.values
    assert np.abs(L - L[0]).max() < 1e-12 * L[0]
    # none needed at t = 0 (every section spins with r_t = 0), then they carry the Coriolis torques
    assert float(abs(constrained.lambda_chi.isel(time=0)).max()) < 1e-9
    assert float(abs(constrained.lambda_chi).max()) > 10.0  # N: 2 pi lambda_chi > 60 N m of torque
    assert float(abs(constrained.lambda_psi).max()) > 1e-3
    assert constrained.lambda_chi.attrs["units"] == "N" and constrained.lambda_chi.dims == ("time", "s_cell")


def test_the_free_shell_twists_and_shears(spinning):
    constrained, free = spinning
    assert free.attrs["complete"] == 1
    assert float(free.chi_s_max[-1]) > 1e-3 and float(free.psi_max.max()) > 3e-6
    assert np.all(np.diff(free.chi_s_max.values[:4]) > 0)
    # early on each section keeps its own angular momentum r^2 chi_t (4.7): that is what twists it
    i, omega = 1, Unshearable().omega
    predicted = omega * (free.r.isel(time=0) / free.r.isel(time=i)) ** 2 - omega
    spin_change = free.chi_t.isel(time=i) - omega
    assert float(abs(spin_change - predicted).max()) < 0.02 * float(abs(predicted).max())
    assert float(spin_change.max() - spin_change.min()) > 0.05  # rad/s: not uniform
    # same start, same energy and angular momentum
    assert float(free.energy[0]) == pytest.approx(float(constrained.energy[0]), rel=1e-12)
    assert float(free.angular_momentum[0]) == pytest.approx(float(constrained.angular_momentum[0]), rel=1e-12)


def test_the_multipliers_are_the_coriolis_torque_and_couple(spinning):
    """At psi = chi_s = 0 the stored energy has no chi or psi force, so the multipliers carry all
    the inertia of (3.11)-(3.12), i.e. (4.4)-(4.6) with rhoI = 0 (per unit reference area):
    d(lambda_chi)/ds = rhoA (r^2 chi_t)_t + rhoJ (cos^2(theta) chi_t)_t and
    lambda_psi = -rhoJ (chi_tt cos(theta) - 2 chi_t theta_t sin(theta))."""
    from mol_shell.runs.simulate import build

    constrained, _ = spinning
    shell, _ = build(Unshearable(), 41)
    dae = UnshearableDAE(shell)
    x = constrained.isel(time=3)
    Q = np.stack([x[k].values for k in ("z", "r", "chi", "theta", "psi")])
    V = np.stack([x[k + "_t"].values for k in ("z", "r", "chi", "theta", "psi")])
    y, yp = dae.consistent(Q, V)
    _, A, _, _ = dae.unpack(yp)  # accelerations
    _, _, Lc, Lp = dae.unpack(y)  # multipliers
    # the saved multipliers are those of the saved state to IDA's tolerance on them: Newton's iteration stops
    # within the error weights rtol |lambda| + atol_lambda, atol_lambda = 1e-10 x the membrane stiffness
    # (times L for lambda_chi), as simulate_unshearable sets them (3e-7 of 2e-5 seen for lambda_psi)
    stiffness = (shell.lam + 2 * shell.mu) * 2 * shell.scene.h
    np.testing.assert_allclose(x.lambda_chi, Lc, rtol=1e-5, atol=1e-10 * stiffness * shell.scene.L)
    np.testing.assert_allclose(x.lambda_psi, Lp, rtol=1e-5, atol=1e-10 * stiffness)
    r, th, chi_t, r_t, th_t, chi_tt = Q[1], Q[3], V[2], V[1], V[3], A[2]
    torque_rate = shell.rho_a * (2 * r * r_t * chi_t + r**2 * chi_tt) + shell.rho_j * (
        np.cos(th) ** 2 * chi_tt - 2 * np.cos(th) * np.sin(th) * th_t * chi_t)
    np.testing.assert_allclose(np.diff(np.r_[0.0, Lc, 0.0]), shell.weights * torque_rate,
                               atol=1e-9 * abs(shell.weights * torque_rate).max())
    couple = -shell.rho_j * (chi_tt * np.cos(th) - 2 * chi_t * th_t * np.sin(th))
    np.testing.assert_allclose(Lp, couple, rtol=1e-9, atol=1e-12 * abs(couple).max())
    assert abs(couple).max() > 1e-3


def test_without_spin_the_multipliers_vanish_and_the_dae_is_the_free_shell():
    """No spin: the free motion is axisymmetric by itself, so both must agree (leap-frog error ~ dt^2)."""
    scene, times = Unshearable(omega=0.0), np.linspace(0.0, 0.01, 3)
    dae = simulate_unshearable(scene, n=10, times=times, rtol=1e-10, atol=1e-12)
    assert float(abs(dae.lambda_chi).max()) == 0.0 and float(abs(dae.lambda_psi).max()) == 0.0
    errors = []
    for dt in (4e-6, 2e-6):
        free = simulate_unshearable(scene, n=10, times=times, constrained=False, dt=dt)
        assert defects(free) == (0.0, 0.0)
        errors.append(max(float(abs(free[k] - dae[k]).max()) for k in ("r", "z", "theta")))
    assert 3.0 < errors[0] / errors[1] < 5.0 and errors[1] < 1e-6


def test_consistent_initial_values_solve_the_residual():
    from mol_shell.runs.simulate import build

    scene = Unshearable()
    shell, _ = build(scene, 8)
    dae = UnshearableDAE(shell)
    y0, yp0 = dae.consistent(*scene.initial_fields(shell.s))
    assert np.abs(np.array(dae.residual(y0, yp0))).max() < 1e-9
    assert dae.bandwidth[0] < 2 * 12 and dae.bandwidth[1] < 2 * 12  # node-major: banded


def test_simulate_hands_the_scene_to_its_dae_and_refuses_other_integrators():
    with pytest.raises(ParameterError, match="integrator"):
        mol_shell.simulate("unshearable", "cvode-bdf", n=10, times=[0, 0.001])
    ds = mol_shell.simulate("unshearable", "ida", n=10, times=[0, 0.001], progress=False)
    assert ds.attrs["constrained"] == 1 and "lambda_chi" in ds
    free = mol_shell.simulate("unshearable", "leapfrog", n=10, times=[0, 0.001], dt=1e-5, progress=False)
    assert free.attrs["constrained"] == 0 and "lambda_chi" not in free
    with pytest.raises(ParameterError, match="dR"):
        Unshearable(dR=0.5)


def test_a_held_chi_under_the_constraint_has_no_computed_torque_and_a_held_z_its_force():
    """A pinned edge (z, r, chi held) on the constrained DAE: the support's torque is shared with the constraint
    ``chi_s = 0`` (its multiplier ``lambda_chi``), which the shell's own equations leave out, so the torque is NaN
    with a note, not a number computed without it; the held z (no constraint acts on z) has its force. The free
    run of the same scene computes both."""
    scene = mol_shell.Unshearable(end1="pinned", omega=0.0, dR=0.01)  # held chi: the constrained shell cannot spin
    ds = mol_shell.simulate_unshearable(scene, n=11, times=np.linspace(0.0, 0.002, 3))
    assert ds.attrs["complete"] == 1
    assert np.all(np.isnan(ds.reaction_torque.values[:, 0])) and "lambda_chi" in ds.attrs["reaction_torque_note"]
    assert np.all(np.isfinite(ds.reaction_force.values))
    spun = mol_shell.Unshearable(end1="pinned", omega=20.0, dR=0.01)
    free = mol_shell.simulate_unshearable(spun, n=11, times=np.linspace(0.0, 0.001, 3), constrained=False)
    assert np.all(np.isfinite(free.reaction_torque.values)) and "reaction_torque_note" not in free.attrs


@pytest.mark.parametrize("sets, key", [(["--set", "end1=clamped", "--set", "omega=0"], "end1 = 'clamped' holds psi"),
                                       (["--set", "end2=z,psi", "--set", "omega=0"], "end2 = 'z,psi' holds psi"),
                                       (["--set", "end1=pinned"], "omega = 20.0 spins")])
def test_edges_the_constraints_leave_no_room_for_are_refused_in_one_line(sets, key, tmp_path, capsys, monkeypatch):
    """The constrained shell imposes psi = 0 at every node: an edge that holds psi too made the multipliers
    undetermined (an internal error, a singular Newton matrix, on 0.6.0 before this); chi_s = 0 turns every
    section with an edge that holds chi, so an initial spin contradicts it (a spurious 'numerical instability'
    before). Both are refused naming the key, exit 2, before the graph is built; a held chi without spin runs
    (above)."""
    from mol_shell.cli.main import main
    from mol_shell.runs import unshearable

    def no_build(*args, **kwargs):
        raise AssertionError("the graph was built before the edges were checked")

    monkeypatch.setattr(unshearable, "build", no_build)

    code = main(["run", "unshearable", "--integrator", "ida", *sets, "--n", "11", "--t-end", "0.001",
                 "-o", str(tmp_path / "u.nc")])
    err = [line for line in capsys.readouterr().err.splitlines() if "warning" not in line]
    assert code == 2 and len(err) == 1 and key in err[0] and "allowed:" in err[0], err
    assert not (tmp_path / "u.nc").exists()


def test_the_scenes_registered_name_is_taken_as_simulate_takes_it():
    """``simulate_unshearable("unshearable", ...)`` said ``scene = 'unshearable' is outside {unshearable}``."""
    by_name = mol_shell.simulate_unshearable("unshearable", t_end=1e-3, n=21)
    by_object = mol_shell.simulate_unshearable(mol_shell.Unshearable(), t_end=1e-3, n=21)
    assert by_name.attrs["status"] == "complete"
    np.testing.assert_array_equal(by_name.r.values, by_object.r.values)
    with pytest.raises(ParameterError, match=r"^scene = 'sphere' is outside \{unshearable\}"):
        mol_shell.simulate_unshearable("sphere", t_end=1e-3, n=21)
