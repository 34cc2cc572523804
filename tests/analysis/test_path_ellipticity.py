"""Equilibrium paths record whether the shell's equations stay elliptic in s (docs/materials.md): per step and at
each critical point, with a warning where the path leaves that range (its later critical points are the grid's)."""

import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.analysis.path import path


@pytest.fixture(scope="module")
def buckled():
    # the default law (svk, nu = 0.49) buckles at about 30 kPa; on the buckled branch a compressed zone passes the
    # loss (1 % equibiaxial compression) a few kPa further on
    with pytest.warns(mol_shell.MaterialWarning, match=r"lost ellipticity by step \d+ \(pressure = "):
        return path(mol_shell.Sphere(h=0.05), "pressure", 0.0, -1e5, n=21, steps=20, max_steps=50)


def test_a_default_sphere_past_buckling_loses_ellipticity_and_says_at_which_step(buckled):
    ds = buckled
    margin = ds.ellipticity_margin.values
    k = ds.attrs["ellipticity_lost_step"]
    assert margin[k] <= 0 < margin[k - 1] and np.all(margin[:k] > 0)
    assert ds.attrs["ellipticity_lost_parameter"] == ds.parameter.values[k]
    before = ds.point_step.values < k
    assert before.any() and np.all(ds.point_ellipticity_margin.values[before] > 0)  # the first buckling is sound


def test_a_thin_plane_stress_sphere_to_its_first_buckling_stays_elliptic():
    # svk-plane-stress at nu = 0.3 loses ellipticity only at 19 % compression; the classical buckling strain of
    # a/t = 40 is 1 %
    h = 0.0125
    with warnings.catch_warnings():
        warnings.simplefilter("error", mol_shell.MaterialWarning)
        ds = path(mol_shell.Sphere(a=1.0, h=h, E=1e6, nu=0.3, material="svk-plane-stress"), "pressure", 0.0, -800.0,
                  n=40, steps=8)
    assert "ellipticity_lost_step" not in ds.attrs
    assert np.all(ds.ellipticity_margin.values > 0.5) and np.all(ds.point_ellipticity_margin.values > 0.5)
    assert ds.ellipticity_margin.attrs["units"] == "1"


def test_modes_about_a_state_past_the_loss_say_so(buckled):
    k = buckled.attrs["ellipticity_lost_step"]
    fields = np.stack([buckled[name].values for name in ("z", "r", "chi", "theta", "psi")], axis=1)
    sound = mol_shell.modes(mol_shell.Sphere(h=0.05, pressure=float(buckled.parameter[k - 1])), n=21, count=3,
                            initial=fields[k - 1])
    assert "ellipticity_warning" not in sound.attrs and sound.attrs["ellipticity_margin"] > 0
    with pytest.warns(mol_shell.MaterialWarning, match="past the loss of ellipticity"):
        past = mol_shell.modes(mol_shell.Sphere(h=0.05, pressure=float(buckled.parameter[k])), n=21, count=3, initial=fields[k])
    assert past.attrs["ellipticity_margin"] == pytest.approx(buckled.ellipticity_margin.values[k], rel=1e-9)
