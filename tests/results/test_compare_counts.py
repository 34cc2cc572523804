"""A compare file's counts are 32-bit integers, as docs/netcdf.md says of every file (they were float64, NaN where a
point has none): -1 there, declared as the variable's ``_FillValue``, so xarray reads them back as the floats they
were (NaN there); a count that every point has is declared with the same fill, so the write does not warn."""

import warnings

import netCDF4
import numpy as np
import xarray as xr

import mol_shell
from mol_shell.analysis.workprecision import work_precision


def test_a_comparisons_counts_are_32_bit_integers_with_minus_one_where_a_point_has_none(tmp_path):
    # dop853-c at one tolerance, leap-frog at two steps: the first's second level is padding; neither counts Jacobians
    ds = work_precision(mol_shell.TwistedCylinder(), ["dop853-c", "leapfrog"], n=6, times=[0.0, 1e-4], repeats=1,
                        sweeps={"dop853-c": {"rtol": (1e-5,)}, "leapfrog": {"dt": (1e-5, 5e-6)}}, log=lambda *a: None)
    path = tmp_path / "compare.nc"
    mol_shell.write_netcdf(ds, path)
    leapfrog_steps = [10, 20]  # 1e-4 s in steps of 1e-5 s and 5e-6 s
    with netCDF4.Dataset(path) as nc:
        nc.set_auto_mask(False)
        for name in ("n_steps", "n_rhs", "n_rhs_jacobian", "n_jac"):
            assert nc[name].dtype == np.int32, name
            assert nc[name]._FillValue == -1, name  # each has a point without it: the padding, or every point
        assert nc["n_steps"][1].tolist() == leapfrog_steps and nc["n_steps"][0, 1] == -1
        assert (nc["n_jac"][:] == -1).all()
    back = xr.load_dataset(path)
    for name in ("n_steps", "n_rhs", "n_rhs_jacobian", "n_jac"):
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)  # NaN where NaN


def test_a_comparison_without_a_missing_count_is_written_without_a_warning(tmp_path):
    # one dop853-c point: its steps, right-hand sides and difference-quotient Jacobian evaluations (0: it has none)
    # are all there, only n_jac is not (an explicit pair evaluates no Jacobian). Floats written as integers without a
    # _FillValue made xarray warn once per such count (studies/work_precision.py --quick said three on a clean run)
    ds = work_precision(mol_shell.TwistedCylinder(), ["dop853-c"], n=6, times=[0.0, 1e-4], repeats=1,
                        sweeps={"dop853-c": {"rtol": (1e-5,)}}, log=lambda *a: None)
    assert not np.isnan(ds.n_steps).any() and not np.isnan(ds.n_rhs).any()
    assert ds.n_rhs_jacobian.values.tolist() == [[0.0]] and np.isnan(ds.n_jac).all()
    path = tmp_path / "compare.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning of the write fails the test
        mol_shell.write_netcdf(ds, path)
    with netCDF4.Dataset(path) as nc:
        nc.set_auto_mask(False)
        for name in ("n_steps", "n_rhs", "n_rhs_jacobian", "n_jac"):
            assert nc[name].dtype == np.int32 and nc[name]._FillValue == -1, name
        assert nc["n_rhs_jacobian"][:].tolist() == [[0]] and nc["n_jac"][:].tolist() == [[-1]]
    back = xr.load_dataset(path)
    for name in ("n_steps", "n_rhs", "n_rhs_jacobian", "n_jac"):
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)  # read back as returned
