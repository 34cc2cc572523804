"""Datasets: labels, units, attrs, netCDF round trip; runs that stop keep their data."""

import dataclasses

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.integrators import Leapfrog
from mol_shell.simulate import build, resolve


@pytest.fixture(scope="module")
def short_run():
    return mol_shell.simulate("twisted-cylinder", times=[0, 0.001, 0.002], progress=False)


def test_every_variable_has_units_and_long_name(short_run):
    for name, var in {**short_run.data_vars, **short_run.coords}.items():
        assert var.attrs.get("units"), name
        assert var.attrs.get("long_name"), name
    assert set(short_run.dims) == {"time", "s"}
    for field in ("z", "r", "chi", "theta", "psi"):
        assert short_run[field].dims == ("time", "s")
        assert short_run[field + "_t"].dims == ("time", "s")


def test_attrs_hold_every_scene_parameter(short_run):
    scene = mol_shell.TwistedCylinder()
    for field in dataclasses.fields(scene):
        assert field.name in short_run.attrs
    # R is stored as computed, not as "None"
    assert short_run.attrs["R"] == pytest.approx(resolve(scene).R, rel=1e-15)
    for key in ("integrator", "dt", "n_steps", "n_rhs", "wall_time_s", "mol_shell_version", "rhs_instructions"):
        assert key in short_run.attrs
    assert short_run.attrs["n_steps"] == 2000
    assert short_run.attrs["n_rhs"] == 2001  # one extra evaluation for the midpoint start


def test_netcdf_round_trip_is_identical(short_run, tmp_path):
    path = tmp_path / "run.nc"
    mol_shell.write_netcdf(short_run, path)
    back = mol_shell.read_netcdf(path)
    xr.testing.assert_identical(short_run, back)


def test_energy_is_kinetic_plus_stored(short_run):
    np.testing.assert_allclose(short_run.energy, short_run.kinetic_energy + short_run.stored_energy, rtol=1e-15)
    assert short_run.kinetic_energy[0] == 0.0  # initial data at rest


class _InterruptAfter:
    def __init__(self, calls):
        self.calls = calls

    def update(self, _):
        self.calls -= 1
        if self.calls == 0:
            raise KeyboardInterrupt


def test_ctrl_c_keeps_the_saved_times():
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    times = np.arange(0, 0.011, 0.001)
    traj = Leapfrog(dt=1e-5, chunk=50).integrate(
        system, compiled, system.initial_state(scene), times, progress=_InterruptAfter(9)
    )
    assert traj.status == "interrupted"
    assert len(traj.t) == 5  # 9 chunks of 50 steps of 1e-5 s: saved 0 .. 0.004 s
    assert traj.failure_time == pytest.approx(0.0045)
    assert np.all(np.isfinite(traj.y))


def test_overflow_inside_a_chunk_never_reaches_the_file(tmp_path):
    """A step 3x beyond the bound: the fastest mode grows ~5.8x per step, so by the end of the first
    1,000-step chunk an unchecked state has overflowed to inf/NaN. The run stops at the first step
    that leaves the model's limits (checked every step in C) or whose energy grew (checked once a
    chunk, then located by redoing the chunk step by step), and the file holds only finite states."""
    from mol_shell.compiled import CompiledRHS
    from mol_shell.output import build_dataset
    from mol_shell.simulate import observe

    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    dt = 3.0 / np.abs(np.linalg.eigvals(np.array(system.jac(0, y0)))).max()
    times = dt * np.arange(0, 20001, 1000)
    unchecked = CompiledRHS(system.rhs_mapped)  # no limits: what a run without checks would have saved
    chunk_end = y0.copy(), y0 + dt * np.array(unchecked.evaluator()(y0))
    assert unchecked.leapfrog(*chunk_end, 1000, dt) == 1000
    assert not np.all(np.isfinite(chunk_end[1]))
    traj = Leapfrog(dt=dt, chunk=2000).integrate(system, compiled, y0, times)
    assert traj.status in ("unstable", "limit"), traj.message
    assert any(word in traj.message for word in ("non-finite", "energy grew", "<= 0", "pi/2")), traj.message
    assert traj.failure_time < 1000 * dt  # within the first chunk: at the first bad step, not at its end
    velocities, totals = observe(system, traj.y)
    ds = build_dataset(system, scene, traj, velocities, totals, {"integrator": "leapfrog", "dt": dt})
    mol_shell.write_netcdf(ds, tmp_path / "blown.nc")
    back = mol_shell.read_netcdf(tmp_path / "blown.nc")
    assert back.attrs["complete"] == 0 and back.attrs["status"] == traj.status
    for name in ("r", "chi", "energy"):
        assert np.all(np.isfinite(back[name].values))


def test_attribute_names_are_plain_and_rates_carry_their_units(short_run):
    """netCDF/CF names: letters, digits, underscores (``max_damping_rate_s-1`` was not); units in ``units_*``."""
    import re

    for key in short_run.attrs:
        assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", key), key
    assert short_run.attrs["max_damping_rate"] == 0.0 and short_run.attrs["units_max_damping_rate"] == "s-1"


def test_write_netcdf_creates_directories_and_names_an_unwritable_path(short_run, tmp_path):
    from mol_shell.errors import ParameterError

    mol_shell.write_netcdf(short_run, tmp_path / "a" / "b" / "run.nc")
    assert (tmp_path / "a" / "b" / "run.nc").exists()
    with pytest.raises(ParameterError, match="^path = .* is a directory"):
        mol_shell.write_netcdf(short_run, tmp_path / "a")
    with pytest.raises(ParameterError, match="^path = '' is empty"):
        mol_shell.write_netcdf(short_run, "")
