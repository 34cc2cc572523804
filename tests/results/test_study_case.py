"""``study_case``: a case of a study is its run's Dataset, the variables and attributes its run has and no others
(docs/netcdf.md, "Study files")."""

import math

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.study_dataset import study_case

RUN = {"n": 11, "t_end": 0.002, "progress": False}
#: what differs between a case and its run whatever the case: when and how fast it ran, and its file's header
TIMED = {"title", "history", "wall_time_s", "setup_time_s", "build_time_s", "jacobian_build_s"}


def _as_its_run(tmp_path, integrator, name, values):
    """Each case of a study of ``name`` read back, beside its run read back (as ``mol-shell plot`` reads them)."""
    out = tmp_path / f"{name}.nc"
    mol_shell.study(mol_shell.Sphere(), {name: values}, integrator, output=out, scheduler="serial", **RUN)
    st = mol_shell.read_netcdf(out)
    for value in values:
        case_path, run_path = tmp_path / f"{name}{value}c.nc", tmp_path / f"{name}{value}r.nc"
        mol_shell.write_netcdf(study_case(st, **{name: value}), case_path)
        mol_shell.write_netcdf(mol_shell.simulate(mol_shell.Sphere(**{name: value}), integrator, **RUN), run_path)
        yield value, case_path, mol_shell.read_netcdf(case_path), mol_shell.read_netcdf(run_path)


@pytest.mark.parametrize("integrator, name, values, only", [
    ("leapfrog", "pressure", [0.0, 100.0], {"work", "dissipated"}),
    ("cvode-bdf", "eta_mu", [0.0, 50.0], {"dissipation", "von_mises_stress_viscous"}),
])
def test_a_case_that_differs_in_loads_or_viscosity_is_its_run(tmp_path, integrator, name, values, only):
    """The case without loads (without viscosity) had the loaded (viscous) case's ``work`` and ``dissipated``
    (``dissipation`` and 13 ``*_viscous`` stresses) all NaN, and ``energy_balance_error`` NaN for its run's
    ``'n/a (no loads)'``: ``mol-shell plot`` refused it (work is not finite at t = 0 s); and the cases' ``units_NAME``
    of per-case numbers (``max_damping_rate``) were missing."""
    for value, path, case, run in _as_its_run(tmp_path, integrator, name, values):
        assert set(case.variables) == set(run.variables), value
        assert (only <= set(run.variables)) == bool(value)
        for var in run.variables:
            assert case[var].variable.identical(run[var].variable), (value, var)
        assert set(case.attrs) == set(run.attrs), value
        for key in set(run.attrs) - TIMED:
            a, b = case.attrs[key], run.attrs[key]
            assert a == b or (isinstance(a, float) and math.isnan(a) and math.isnan(b)), (value, key, a, b)
        assert main(["plot", str(path), "-o", str(tmp_path / f"{value}.png")]) == 0


def test_a_case_that_lost_ellipticity_keeps_its_units_and_one_that_did_not_has_none():
    """``units_ellipticity_lost_time`` and ``units_ellipticity_lost_position`` were left out of the case that lost
    ellipticity, and the case that did not had ``ellipticity_lost_time = nan`` and ``ellipticity_warning = ''``, which
    its run has not."""
    st = mol_shell.study(mol_shell.TwistedCylinder(), {"psi0": [0.0, 1.5]}, n=11, t_end=0.01, scheduler="serial",
                         progress=False)
    lost, kept = study_case(st, psi0=1.5).attrs, study_case(st, psi0=0.0).attrs
    assert lost["units_ellipticity_lost_time"] == "s" and lost["units_ellipticity_lost_position"] == "m"
    assert not {k for k in kept if k.startswith("ellipticity_lost") or k == "ellipticity_warning"}
    assert "case_wall_time_s" not in kept and kept["comment"].startswith("time: ")


@pytest.mark.parametrize("where, words", [
    ({"gamma": [0.1], "nu": 0.3}, r"^gamma = \[0\.1\] is not one value; allowed: one of 0\.05, 0\.1$"),
    ({"gamma": 0.1, "nu": (0.3,)}, r"^nu = \(0\.3,\) is not one value; allowed: one of 0\.3, 0\.4$"),
])
def test_a_case_named_by_a_list_is_refused_naming_the_study_s_values(where, words):
    """A list kept the study's dimension: ``StopIteration`` from deep inside, no case named."""
    st = mol_shell.study(mol_shell.TwistedCylinder(material="svk-plane-stress"), {"gamma": [0.05, 0.1],
                         "nu": [0.3, 0.4]}, n=8, t_end=1e-5, scheduler="serial", progress=False)
    with pytest.raises(mol_shell.ParameterError, match=words):
        study_case(st, **where)


def test_a_grid_of_nested_lists_is_refused_naming_its_parameter():
    """``{'gamma': [[0.1, 0.2]]}`` ran every case and then failed in xarray on the coordinate's dimensions."""
    with pytest.raises(mol_shell.ParameterError, match=r"^vary\['gamma'\] = \[\[0\.1, 0\.2\]\] nests lists \(the "
                       r"grid's values must be scalars\); allowed: a list of numbers or words, one per case$"):
        mol_shell.study("twisted-cylinder", {"gamma": [[0.1, 0.2]]}, t_end=0.001, scheduler="serial")
