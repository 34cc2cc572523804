"""What counts as a zero omega^2 among natural modes, a count refused before any solve, and loads on a history.

* The natural state of a stress-free shell stores no energy to first order: every strain is zero, the stiffness is
  ``B^T C B``, positive semi-definite, so no mode has omega^2 < 0. At h = 1e-8 m the largest omega^2 (shear over
  rotary inertia, ~1/h^2) is 1e19 s-2 and the solver's round-off a few thousand s-2: the sphere was declared
  unstable (omega^2 = -2847.62 s-2, frequency NaN).
* At a path's located critical point the critical omega^2 is zero to the bracket the path closes: -7.3e-6 s-2 was
  listed as unstable.
* The number of free coordinates is known before the solve: a count above it was refused after computing every mode
  (n = 601: 36 s), or, by the sparse route, never.
* A ramp's factor is 0 at t = 0: modes about the start take no pressure, and say so.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg
import xarray as xr

import mol_shell
import mol_shell.analysis.modes as modes_module
from mol_shell import ParameterError, Sphere, TwistedCylinder
from mol_shell.analysis.mode_zero import LOCATED_SAFETY, located_band
from mol_shell.analysis.path_stability import LOCATE_RTOL
from mol_shell.analysis.path_start import path_start
from mol_shell.cli.main import main
from mol_shell.runs.resources import LongRunWarning


def _modes(scene, **kw):
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        ds = mol_shell.modes(scene, **kw)
    return ds, [str(w.message) for w in said]


@pytest.mark.parametrize("material", ["svk", "svk-plane-stress"])
def test_a_stress_free_thin_sphere_has_no_unstable_mode(material):
    ds, said = _modes(Sphere(h=1e-8, material=material), n=21, count=2)
    assert "unstable_modes" not in ds.attrs and not any(" is unstable" in s for s in said)
    assert np.isfinite(ds.frequency.values).all()
    negative = ds.omega_squared.values < 0  # round-off, listed at 0 rad/s and said as such
    assert (ds.frequency.values[negative] == 0).all()
    assert "zero to the eigensolver's round-off, not unstable" in ds.attrs["roundoff_warning"]


def test_a_moderately_thin_sphere_keeps_its_positive_modes():
    ds, _ = _modes(Sphere(h=1e-7), n=21, count=2)
    assert (ds.omega_squared.values > 0).all() and (ds.frequency.values > 0).all()
    assert "roundoff_warning" not in ds.attrs


def test_a_located_bifurcation_lists_its_critical_mode_at_zero(tmp_path):
    scene = TwistedCylinder(gamma=0, L=1.4576, h=0.005, material="svk-plane-stress", nu=0.3, end1="z,theta",
                            end2="theta")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traced = mol_shell.path(scene, "end2_force", 0.0, -400.0, n=11, steps=10)
    assert traced.sizes["point"] == 1 and traced.point_located.values.all()
    traced.to_netcdf(tmp_path / "path.nc")
    start, n, initial, _ = path_start(str(tmp_path / "path.nc"), point=0)
    ds, said = _modes(start, n=n, count=2, initial=initial, zero_band=located_band(traced, 0))
    # at the first bifurcation: the critical mode at zero (not unstable), the next one positive
    assert "unstable_modes" not in ds.attrs and not any(" is unstable" in s for s in said)
    assert ds.frequency.values[0] == 0 and ds.frequency.values[1] > 0


def test_the_band_of_a_located_point_is_its_bracket_times_the_eigenvalues_slope():
    path = xr.Dataset({"parameter": ("step", [0.0, -10.0, -20.0]), "arclength": ("step", [0.0, 0.1, 0.3]),
                       "smallest_eigenvalues": (("step", "eigenvalue"), [[5.0, 9.0], [3.0, 8.0], [-1.0, 6.0]]),
                       "point_step": ("point", [1, 1]), "point_kind": ("point", ["bifurcation", "limit"]),
                       "point_located": ("point", [1, 1])}, attrs={"start": 0.0, "stop": -40.0})
    assert located_band(path, 0) == pytest.approx(LOCATED_SAFETY * LOCATE_RTOL * 40.0 * 4.0 / 10.0)
    assert located_band(path, 1) == pytest.approx(LOCATED_SAFETY * LOCATE_RTOL * 4.0 / 0.2)
    path["point_located"] = ("point", [0, 0])
    assert located_band(path, 0) == 0.0


def _no_solve(*args, **kwargs):
    raise AssertionError("the eigensolver ran")


@pytest.mark.parametrize("dense_max", [10**6, 10])  # the dense route and the sparse one
def test_a_count_beyond_the_modes_is_refused_before_any_solve(monkeypatch, dense_max):
    monkeypatch.setattr(modes_module, "DENSE_MAX", dense_max)
    monkeypatch.setattr(scipy.linalg, "eigh", _no_solve)
    monkeypatch.setattr(modes_module, "sparse_modes", _no_solve)
    with pytest.raises(ParameterError, match=r"count = 100000 is outside integers 1\.\.45 for n = 11"):
        mol_shell.modes(Sphere(), n=11, count=100_000)


def test_a_count_near_the_size_goes_to_the_dense_route(monkeypatch):
    monkeypatch.setattr(modes_module, "DENSE_MAX", 10)  # every size above it: sparse for a few modes
    few, _ = _modes(Sphere(), n=11, count=3)
    assert few.attrs["method"] == "sparse shift-invert"
    most, _ = _modes(Sphere(), n=11, count=45)  # 45 of 47 free coordinates (2 rigid motions)
    assert most.attrs["method"] == "dense" and most.sizes["mode"] == 45
    np.testing.assert_allclose(most.frequency.values[:3], few.frequency.values, rtol=1e-8)


def test_a_long_dense_solve_is_announced_and_one_that_does_not_fit_refused(monkeypatch):
    monkeypatch.setattr(modes_module, "DENSE_S_PER_CUBE", 1.0)
    with pytest.warns(LongRunWarning, match=r"computing the modes of 47 free coordinates densely \(LAPACK\)"):
        mol_shell.modes(Sphere(), n=11, count=1)
    monkeypatch.setattr(modes_module, "DENSE_COPIES", 1e15)
    monkeypatch.setattr(scipy.linalg, "eigh", _no_solve)
    # a count the sparse route takes goes there (it was refused as "count = 1 is outside integers 1..9": a range
    # holding the count); one only the dense route takes is refused with the sparse route's range
    few, _ = _modes(Sphere(), n=11, count=1)
    assert few.attrs["method"] == "sparse shift-invert"
    with pytest.raises(ParameterError, match=r"count = 10 is outside integers 1\.\.9 for n = 11"):
        mol_shell.modes(Sphere(), n=11, count=10)


def test_modes_say_a_load_on_a_ramp_is_zero_at_rest(tmp_path, capsys):
    out = tmp_path / "m.nc"
    assert main(["modes", "sphere", "--set", "pressure=1000", "--set", "pressure_history=ramp 0.05", "--n", "11",
                 "--count", "1", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "note: the scene's pressure = 1000 Pa (pressure_history 'ramp 0.05') acts at its value at t = 0" in err
    with xr.open_dataset(out) as ds:
        assert "0 Pa (the modes are taken about a state at rest" in ds.attrs["loads_at_rest"]
        loaded = float(ds.frequency[0])
    unloaded, _ = _modes(Sphere(), n=11, count=1)  # a ramp is 0 at t = 0: the natural sphere's modes
    assert loaded == pytest.approx(float(unloaded.frequency[0]), rel=1e-12)


@pytest.mark.parametrize("band", [np.inf, np.nan, -1.0, "1", 1e12])
def test_a_zero_band_that_is_not_one_is_refused(band):
    """An infinite band (or 1e12 s-2) listed every mode at 0 rad/s, silently; NaN and -1 were taken."""
    with pytest.raises(ParameterError, match=r"^zero_band = "):
        mol_shell.modes(Sphere(), n=11, count=2, zero_band=band)
