"""The stresses of an unshearable run: the torque through a section is the constraint's.

With ``chi_s = 0`` and ``psi = 0`` the law carries no torque, and ``add_stresses`` said 1.5e-10 N m where the
constraint carried 1.4e3 N m (``2 pi r0 lambda_chi``, docs/studies.md); ``run unshearable --stresses`` wrote no
stresses at all. The torque is checked against the multiplier and, independently of it, against the balance of
angular momentum: the torque through a section is the rate of change of the angular momentum on its smaller ``s``
side (the ends, magnets, leave ``chi`` free)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.scenes import Unshearable

N = 21
TIMES = np.linspace(0.0, 0.004, 41)


@pytest.fixture(scope="module")
def constrained():
    """The spinning shell with a bulge (omega = 20 rad/s), constrained, its stresses added by simulate."""
    return mol_shell.simulate(Unshearable(), "ida", n=N, times=TIMES, progress=False)


def test_the_torque_is_the_constraint_s_two_pi_r0_lambda_chi(constrained):
    ds = constrained
    assert ds.attrs["stresses"].startswith("included") and "constraint" in ds.attrs["stresses"]
    a = Unshearable().a  # the natural radius: r0 of the cylinder the scene starts from
    expected = 2 * math.pi * a * ds.lambda_chi.values
    assert np.abs(expected).max() > 10.0  # N m: the constraint carries a torque worth the name
    np.testing.assert_allclose(ds.axial_torque.values, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
    assert "2 pi r0 lambda_chi" in ds.axial_torque.attrs["comment"]


def test_the_torque_balances_the_angular_momentum_on_one_side_of_the_section(constrained):
    """Lumped at the nodes (trapezoid weights), a node's angular momentum is
    ``2 pi r0 w (rho_A r^2 + rho_J cos^2 theta) chi_t`` (rho_I = 0 for the centred wall); their sum is the file's
    ``angular_momentum``, and d/dt of the sum over the nodes left of a section (central differences over the saved
    times) is the torque through it."""
    ds = constrained
    a, ds_ = Unshearable().a, float(ds.s[1] - ds.s[0])
    assert ds.attrs["rho_I"] == 0.0
    w = np.full(N, ds_)
    w[[0, -1]] = ds_ / 2
    r, theta, chi_t = (ds[f].values for f in ("r", "theta", "chi_t"))
    p = 2 * math.pi * a * w * (ds.attrs["rho_A"] * r**2 + ds.attrs["rho_J"] * np.cos(theta) ** 2) * chi_t
    np.testing.assert_allclose(p.sum(axis=1), ds.angular_momentum.values, rtol=1e-12)
    left = np.cumsum(p, axis=1)[:, :-1]  # the nodes left of each cell's section
    dt = TIMES[1] - TIMES[0]
    rate = (left[2:] - left[:-2]) / (2 * dt)
    torque = ds.axial_torque.values[1:-1]
    scale = np.abs(torque).max()
    assert scale > 10.0
    np.testing.assert_allclose(rate, torque, atol=5e-4 * scale)  # 9e-5 seen: the differences in time


def test_the_command_writes_them_with_stresses_and_without_when_asked(tmp_path, capsys):
    run = tmp_path / "u.nc"
    argv = ["run", "unshearable", "--integrator", "ida", "--n", "8", "--t-end", "2e-3"]
    assert main([*argv, "--stresses", "-o", str(run)]) == 0
    ds = mol_shell.read_netcdf(run)
    assert "axial_torque" in ds and ds.attrs["stresses"].startswith("included")
    assert float(np.abs(ds.axial_torque).max()) > 1.0
    assert main(["animate", str(run), "--field", "axial_torque", "--n-phi", "6", "--fibres", "2", "--width", "100",
                 "-o", str(tmp_path / "u.gif")]) == 0
    capsys.readouterr()
    assert main([*argv, "--no-stresses", "-o", str(tmp_path / "bare.nc")]) == 0
    assert "axial_torque" not in mol_shell.read_netcdf(tmp_path / "bare.nc")
    assert main(["animate", str(tmp_path / "bare.nc"), "--field", "axial_torque", "-o", str(tmp_path / "b.gif")]) == 2
    assert "rerun without --no-stresses" in capsys.readouterr().err
