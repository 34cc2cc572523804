"""Run files are CF-1.8 clean: the IOOS compliance-checker reports only the two calendar items of the
deliberate epoch-less model time (docs/netcdf.md), and xarray reads that time as plain numbers."""

import json

import netCDF4
import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.results.stresses import add_stresses

#: what CF's time rules say about ``units = "s"`` without ``since <epoch>``: the one departure
CALENDAR_ITEMS = {
    ("§3.1 Units", "time must be in a valid units format <unit> since <epoch> not s"),
    ("§4.4 Time Coordinate", "time does not have correct time units"),
}


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """A small viscous run with its stresses (every kind of variable a run file can hold)."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(eta_mu=10.0, eta_lambda=20.0), n=8, t_end=1e-5, progress=False)
    path = tmp_path_factory.mktemp("cf") / "run.nc"
    mol_shell.write_netcdf(add_stresses(ds), path)
    return path


def checker_report(path, out):
    """Every message of ``compliance-checker --test=cf:1.8`` (errors, warnings and notes) as (section, text)."""
    from compliance_checker.runner import CheckSuite, ComplianceChecker

    CheckSuite.load_all_available_checkers()
    ComplianceChecker.run_checker(str(path), ["cf:1.8"], verbose=0, criteria="lenient", output_filename=str(out),
                                  output_format="json_new")
    report = json.loads(out.read_text())[str(path)]["cf:1.8"]
    assert not report.get("errors"), report["errors"]  # the checker itself ran through
    items = set()
    for level in ("high_priorities", "medium_priorities", "low_priorities"):
        for check in report[level]:
            items.update((check["name"], msg) for msg in check["msgs"])
    return items


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # the checker's own (its ioos_sos plugin)
def test_compliance_checker_reports_only_the_epoch_less_time(run_file, tmp_path):
    items = checker_report(run_file, tmp_path / "report.json")
    assert items == CALENDAR_ITEMS


def test_coordinates_have_no_fill_value_and_time_stays_numbers(run_file):
    with netCDF4.Dataset(run_file) as nc:
        for name in ("time", "s", "s_cell", "zeta"):
            assert "_FillValue" not in nc[name].ncattrs(), name
        assert nc["time"].standard_name == "time" and nc["time"].axis == "T" and nc.dimensions["time"].isunlimited()
        for key in ("Conventions", "title", "source", "history", "references", "comment"):
            assert nc.getncattr(key), key
    with xr.open_dataset(run_file) as ds:  # xarray's default decoding
        assert ds.time.dtype == np.float64 and float(ds.time[-1]) == pytest.approx(1e-5)
        assert ds.r.dims == ("time", "s")


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_study_file_reports_only_the_epoch_less_time(tmp_path):
    """A study of h (its faces differ between cases: ``zeta_case``) with a refused case (NaN in its grid, -1 in its
    counts): its integers are 32-bit (CF 1.8 has no 64-bit ones; they were floats), and the checker reports only the
    time (run from the command line it also warns that ``R``, the radius each case used, stands beside ``r``:
    docs/netcdf.md)."""
    path = tmp_path / "study.nc"
    mol_shell.study(mol_shell.TwistedCylinder(), {"h": [0.004, 0.008, -1.0]}, n=8, t_end=1e-5, scheduler="serial",
                    progress=False, output=path)
    with netCDF4.Dataset(path) as nc:
        assert nc["n_steps"].dtype == np.int32 and nc["zeta_case"].dimensions == ("h", "zeta")
    items = checker_report(path, tmp_path / "report.json")
    assert items == CALENDAR_ITEMS, items


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_ring_file_has_the_runs_time_coordinate(tmp_path):
    """The reduced ODE's ``time`` had units and a long name only: no ``standard_name = "time"`` nor ``axis = "T"``
    (docs/netcdf.md promises both; the checker said so under CF 5.1)."""
    path = tmp_path / "ring.nc"
    mol_shell.write_netcdf(mol_shell.simulate_ring(mol_shell.SpinningRing(), t_end=0.01), path)
    with netCDF4.Dataset(path) as nc:
        assert nc["time"].standard_name == "time" and nc["time"].axis == "T"
    assert checker_report(path, tmp_path / "report.json") == CALENDAR_ITEMS
