"""Every integrator on the paper scene: agreement, orders, exact Jacobians, statistics, the compare command."""

import numpy as np
import pytest

import mol_shell
from mol_shell import workprecision as wp
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.sundials import pieces
from mol_shell.simulate import build, resolve

TIMES = np.array([0.0, 0.0025, 0.005])  # short horizon: a few hundred adaptive steps


@pytest.fixture(scope="module")
def paper():
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    y0 = system.initial_state(scene)
    ref = wp.fields_of(system, wp.run_once(system, compiled, y0, TIMES, "cvode-adams", 1e-11).y)
    return system, compiled, y0, ref


def _error(paper, name, value):
    system, compiled, y0, ref = paper
    traj = wp.run_once(system, compiled, y0, TIMES, name, value)
    assert traj.status == "complete", traj.message
    return wp.relative_error(wp.fields_of(system, traj.y), ref), traj


@pytest.mark.parametrize("name", [n for n in INTEGRATORS if n != "leapfrog"])
def test_all_integrators_agree_to_their_tolerance(paper, name):
    err, traj = _error(paper, name, 1e-6)
    # casadi-cvodes takes one scalar abstol (1e-9 on momenta too) and runs BDF: looser than its rtol
    assert err < (100 if name == "casadi-cvodes" else 10) * 1e-6, (name, err)
    assert traj.stats["n_steps"] > 0 and traj.stats["n_rhs"] >= traj.stats["n_steps"]


def test_leapfrog_is_second_order(paper):
    dts = np.array([5e-6, 2.5e-6, 1.25e-6])
    errors = np.array([_error(paper, "leapfrog", dt)[0] for dt in dts])
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert abs(slope - INTEGRATORS["leapfrog"].order) < 0.1, (errors, slope)


@pytest.mark.parametrize("name", ["cvode-bdf", "cvode-adams", "ida"])
def test_sundials_reach_their_tolerance(paper, name):
    rtols = [1e-5, 1e-7, 1e-9]
    errors = [_error(paper, name, rtol)[0] for rtol in rtols]
    assert all(e < 10 * rtol for e, rtol in zip(errors, rtols)), errors
    assert errors[0] > errors[1] > errors[2]
    assert INTEGRATORS[name].order is None  # variable order: the tolerance is the contract


def test_compiled_jacobian_equals_finite_differences(paper):
    system, compiled, y0, _ = paper
    f = compiled.evaluator()
    y = y0.copy()
    for _ in range(20):  # leave the symmetric initial state so that every coupling is active
        y = y + 1e-5 * f(y)
    parts = pieces(system, "cvode")
    J = np.zeros((system.size, system.size))
    J[parts["rows"], parts["cols"]] = parts["jac"](0.0, y)
    fd = np.empty_like(J)
    for j in range(system.size):
        h = 1e-6 * max(1.0, abs(y[j]))
        e = np.zeros(system.size)
        e[j] = h
        fd[:, j] = (f(y + e).copy() - f(y - e).copy()) / (2 * h)
    scale = np.abs(J).max(axis=0) + 1e-300
    assert np.max(np.abs(J - fd).max(axis=0) / scale) < 1e-6


def test_dae_residual_and_iteration_matrix(paper):
    system, compiled, y0, _ = paper
    parts = pieces(system, "ida")
    dae = parts["dae"]
    y = y0 + 1e-5 * compiled.evaluator()(y0)
    x, xp = dae.consistent_rates(y)
    F = parts["residual"](0.0, x, xp).copy()
    assert np.abs(F).max() < 1e-9 * np.abs(xp).max()  # the ODE's motion solves the DAE as it stands
    np.testing.assert_allclose(np.array(dae.to_momenta(x)).ravel(), y, rtol=0, atol=1e-12)
    cj = 1e3
    J = np.zeros((system.size, system.size))
    J[parts["rows"], parts["cols"]] = parts["jac"](0.0, x, xp, cj)
    res = dae.residual
    for j in range(0, system.size, 7):
        h = 1e-6 * max(1.0, abs(x[j]))
        e = np.zeros(system.size)
        e[j] = h
        col = (np.array(res(0, x + e, xp + cj * e) - res(0, x - e, xp - cj * e)).ravel()) / (2 * h)
        assert np.abs(col - J[:, j]).max() <= 1e-6 * max(1.0, np.abs(J[:, j]).max())


def test_statistics_reach_the_dataset():
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-bdf", times=TIMES, progress=False, rtol=1e-6,
                            atol={"r": 1e-9, "theta": 1e-10})
    for key in ("n_steps", "n_rhs", "n_jac", "n_failed_steps", "wall_time_s", "linsolver", "rtol", "atol"):
        assert key in ds.attrs, key
    assert ds.attrs["linsolver"] == "band" and ds.attrs["n_jac"] >= 1 and ds.attrs["complete"] == 1


def test_linear_solvers_agree(paper):
    base = _error(paper, "cvode-bdf", 1e-7)[1].y
    system, compiled, y0, _ = paper
    for linsolver in ("dense", "sparse"):
        traj = INTEGRATORS["cvode-bdf"](rtol=1e-7, atol=1e-10, linsolver=linsolver).integrate(system, compiled, y0, TIMES)
        np.testing.assert_allclose(traj.y, base, rtol=0, atol=1e-9)


def test_compare_command_writes_netcdf_png_and_table(tmp_path):
    from mol_shell.cli import main

    out = tmp_path / "wp.nc"
    code = main(["compare", "twisted-cylinder", "--integrators", "leapfrog,cvode-adams", "--t-end", "0.002",
                 "--repeats", "1", "-o", str(out)])
    assert code == 0 and out.exists() and (tmp_path / "wp.png").exists()
    table = (tmp_path / "wp.md").read_text()
    assert "| cvode-adams |" in table and "reference" in table
    ds = wp.xr.open_dataset(out)
    assert set(ds.integrator.values) == {"leapfrog", "cvode-adams"} and np.nanmax(ds.error.values) < 0.1
    assert ds.attrs["reference_error"] < 1e-7
