"""What a study's Dataset (and file) says of each case: the grids that differ between cases, the numbers and words
of the cases' runs, one case back as its run (docs/netcdf.md, "Study files")."""

import netCDF4
import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.results.dataset import is_run
from mol_shell.results.stresses import add_stresses
from mol_shell.results.study_dataset import study_case
from mol_shell.results.study_store import summarize

SMALL = {"n": 10, "t_end": 1e-5, "scheduler": "serial", "progress": False}


def test_a_study_of_a_length_or_a_thickness_keeps_each_case_s_grid(tmp_path):
    """``s``, ``s_cell`` and ``zeta`` were the first case's for every case: a study of L = 3, 4 had s end at 3.0 for
    L = 4 (its z0 at 4.0), one of h had the faces of the first h, and comparing a case with its run aligned the
    stresses on the wrong faces."""
    out = tmp_path / "h.nc"
    st = mol_shell.study(mol_shell.TwistedCylinder(), {"h": [0.004, 0.008]}, output=out, **SMALL)
    run = mol_shell.simulate(mol_shell.TwistedCylinder(h=0.008), n=10, t_end=1e-5, progress=False)
    for ds in (st, mol_shell.read_netcdf(out)):
        assert "zeta" not in ds.coords and ds.zeta_case.dims == ("h", "zeta") and ds.zeta_case.attrs["units"] == "m"
        np.testing.assert_array_equal(ds.zeta_case.sel(h=0.008), run.zeta)
        np.testing.assert_array_equal(ds.s, run.s)  # the same grid in s: one coordinate, as a run's
        # a case and its run line up face by face (a dimension without an index aligns by position)
        diff = ds.sel(h=0.008).von_mises_stress - run.von_mises_stress
        assert float(abs(diff).max()) == 0.0 and np.array_equal(diff.zeta, run.zeta)
    case = study_case(mol_shell.read_netcdf(out), h=0.008)
    xr.testing.assert_identical(case.von_mises_stress, run.von_mises_stress)
    assert case.attrs["h"] == 0.008 and case.attrs["units_h"] == "m" and case.attrs["zeta1_used"] == run.zeta1_used
    xr.testing.assert_allclose(add_stresses(case).von_mises_stress, run.von_mises_stress, rtol=1e-12)
    st = mol_shell.study(mol_shell.TwistedCylinder(), {"L": [3.0, 4.0]}, **SMALL)
    assert "s" not in st.coords and "s_cell" not in st.coords
    assert st.s_case.sel(L=4.0).values[-1] == 4.0 and st.s_cell_case.sel(L=3.0).values[-1] < 3.0
    np.testing.assert_array_equal(st.s_case, st.z0)  # the reference cylinder: z0 = s
    assert float(summarize(st).chi_s_max.sel(L=4.0)) == pytest.approx(0.1, rel=1e-6)  # gamma, along each case's s
    assert not is_run(st.isel(L=1))  # no s to draw against: said, and study_case gives it
    assert study_case(st, L=4.0).s.values[-1] == 4.0


def test_per_case_numbers_words_and_units(tmp_path):
    """nu = 0.49 warns about its law: the warning was in the case's file only. Counts were floats, the per-case long
    names 'NAME of each case', omega_max_rad_s in s, and units_R a stray global attribute beside a varied R."""
    out = tmp_path / "nu.nc"
    st = mol_shell.study(mol_shell.TwistedCylinder(), {"nu": [0.3, 0.49, 0.6]}, output=out, **SMALL)  # 0.6 refused
    warning = st.material_warning.values.tolist()
    assert warning[0] == warning[2] == "" and warning[1].startswith('material = "svk" at nu = 0.49')
    assert st.n_steps.dtype == np.int32 and st.n_steps.values.tolist() == [10, 10, -1]
    assert st.complete.values.tolist() == [1, 1, 0] and st.complete.dtype == np.int32
    assert st.omega_max_rad_s.attrs["units"] == "rad s-1" and st.R.attrs["units"] == "m"
    for name in ("R", "complete", "n_steps", "omega_max_rad_s", "material_warning"):
        assert "of each case" not in st[name].attrs["long_name"] and len(st[name].attrs["long_name"]) > 15, name
    with netCDF4.Dataset(out) as nc:  # -1: none (the case did not run), as the file declares
        assert nc["n_steps"].dtype == np.int32 and nc["n_steps"]._FillValue == -1
        assert "_FillValue" not in nc["complete"].ncattrs()
        assert not [k for k in nc.ncattrs() if k.startswith("units_") and k.removeprefix("units_") not in nc.ncattrs()]
    back = mol_shell.read_netcdf(out)
    assert np.isnan(back.n_steps.values[2]) and back.n_steps.values[1] == 10  # CF decoding: NaN where none
    shared = mol_shell.study(mol_shell.TwistedCylinder(), {"gamma": [0.05, 0.1]}, **SMALL)  # nu = 0.49 in both
    assert shared.attrs["material_warning"].startswith('material = "svk" at nu = 0.49') and "material_warning" \
        not in shared.data_vars
    assert shared.n_steps.dtype == np.int32 and "_FillValue" not in shared.n_steps.encoding
    radii = mol_shell.study(mol_shell.TwistedCylinder(), {"R": [0.99, 1.0]}, **SMALL)
    assert "units_R" not in radii.attrs and "R_requested" not in radii.attrs and radii.R.attrs["units"] == "m"


def test_a_run_file_gives_omega_max_its_units():
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False)
    assert ds.attrs["units_omega_max_rad_s"] == "rad s-1"


def test_add_stresses_of_a_study_says_how_to_take_one_case():
    """It said "ds = 'Dataset' is not a mol_shell run; ... (missing z, r, chi, ...)" of a study, which holds them."""
    st = mol_shell.study(mol_shell.TwistedCylinder(), [{"nu": 0.3}, {"h": 0.004}], **SMALL)
    with pytest.raises(mol_shell.ParameterError, match=r"^ds = 'Dataset' is a parameter study \(mol-shell study\) "
                       r"over case, not one run; .*study_case\(ds, case=0\)"):
        add_stresses(st)
    with pytest.raises(mol_shell.ParameterError, match=r"^ds = 'Dataset' is a case of a parameter study taken with sel "
                       r".*study_case\(STUDY, case=1\) gives the case as its run"):
        add_stresses(st.sel(case=1))  # its h a coordinate: "missing attrs E, nu, h, ..." said the wrong thing
    case = study_case(st, case=1)
    assert case.attrs["h"] == 0.004 and "worker" not in case.attrs and "n_cases" not in case.attrs
    assert add_stresses(case).attrs["stresses"].startswith("included")
    with pytest.raises(mol_shell.ParameterError, match=r"^where = 'nothing' does not name one case"):
        study_case(st)
