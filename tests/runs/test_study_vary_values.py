"""What a study varies over: a list of real numbers (words for a parameter that takes words), checked before any case
runs, in Python and on the command line."""

import importlib

import pandas as pd
import pytest
import xarray as xr

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.cli.study import _integer_options, parse_vary
from mol_shell.runs.study_design import design

study_module = importlib.import_module("mol_shell.runs.study")  # the module, even if mol_shell exports a function study

LIST = "allowed: a list of numbers or words, one per case"


@pytest.mark.parametrize("values, words", [
    # a set was one case, refused as it ran; then xarray failed on the coordinate and the file was not written
    ({0.1, 0.2}, r"vary\['gamma'\] = \{0\.1, 0\.2\} is a set, not a list of values; " + LIST),
    ((g for g in [0.1, 0.2]), r"vary\['gamma'\] = '<generator>' is a generator, not a list of values; " + LIST),
    ({"a": 1}, r"vary\['gamma'\] = \{'a': 1\} is a dict, not a list of values; " + LIST),
    ([{"a": 1}], r"vary\['gamma'\] = \[\{'a': 1\}\] holds \{'a': 1\}, a dict, not a real number or a word; " + LIST),
    ([1j], r"vary\['gamma'\] = \[1j\] holds 1j, a complex, not a real number or a word; " + LIST),
    ([True, 0.1], r"vary\['gamma'\] = \[True, 0\.1\] holds True, a flag, not a number; " + LIST),
    # None stood in the file's coordinate as NaN, its case refused (NaN itself is refused up front)
    ([None, 0.1], r"vary\['gamma'\] = \[None, 0\.1\] holds None, not a value of gamma; allowed: finite values"),
    ([None], r"vary\['gamma'\] = \[None\] holds None, not a value of gamma; allowed: finite values"),
])
def test_a_value_that_is_not_a_list_of_real_numbers_is_refused_before_any_case(values, words, tmp_path, monkeypatch):
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    out = tmp_path / "t.nc"
    with pytest.raises(ParameterError, match="^" + words):
        mol_shell.study(mol_shell.TwistedCylinder(nu=0.3), {"gamma": values}, "leapfrog", t_end=5e-4,
                        scheduler="serial", output=str(out))
    assert not out.exists()


@pytest.mark.parametrize("case, words", [
    ({"gamma": {0.1}}, r"vary\[1\]\['gamma'\] = \{0\.1\} is a set, not a real number or a word"),
    ({"gamma": None}, r"vary\[1\]\['gamma'\] = None is None, not a value of gamma; allowed: finite values"),
])
def test_a_list_of_cases_refuses_a_value_that_is_not_one_number(case, words, monkeypatch):
    monkeypatch.setattr(study_module, "run_task", None)
    with pytest.raises(ParameterError, match="^" + words):
        mol_shell.study("twisted-cylinder", [{"gamma": 0.1}, case], t_end=5e-4, scheduler="serial")


@pytest.mark.parametrize("kind", ["DataArray", "Series", "Index"])
def test_an_array_like_of_values_is_its_values_in_order(kind):
    """A DataArray (a study's own coordinate ds.gamma), a Series, an Index: two values, two cases (they ran so, then
    were refused as 'is a DataArray, not a list of values')."""
    values = {"DataArray": xr.DataArray, "Series": pd.Series, "Index": pd.Index}[kind]([0.2, 0.1])
    dims, coords, cases = design(mol_shell.TwistedCylinder(), {"gamma": values})
    assert dims == ["gamma"] and coords == {"gamma": [0.2, 0.1]}
    assert [case for _, case in cases] == [{"gamma": 0.2}, {"gamma": 0.1}]


def test_a_one_value_range_is_its_value():
    """START = STOP satisfies "STOP included, STEP > 0, (STOP - START)/STEP whole" and was refused by it."""
    assert parse_vary(["gamma=0.1:0.1:0.1"]) == parse_vary(["gamma=0.1"]) == {"gamma": [0.1]}
    with pytest.raises(ParameterError, match="outside START:STOP:STEP"):
        parse_vary(["gamma=0.2:0.1:0.1"])


@pytest.mark.parametrize("extra, message", [
    # ran, with chunk 2000 in the coordinate, where --option chunk=2e3 is refused
    (["--vary", "chunk=100,2e3"], "--vary chunk = 2e3 is not an integer; allowed: integers in [1, "),
    (["--vary", "chunk=100:2e3:100"], "--vary chunk = 2e3 is not an integer; allowed: integers in [1, "),
    # the varied values won, silently (--set nu with --vary nu is refused)
    (["--dt", "1e-6", "--vary", "dt=1e-6,2e-6"], ("--dt = 1e-06 sets dt, which --vary varies; allowed: options not "
                                                  "in --vary")),
    (["--option", "chunk=100", "--vary", "chunk=100,200"], "--option = 'chunk=100' sets chunk, which --vary varies"),
])
def test_the_command_line_reads_varied_options_as_it_reads_them_set(extra, message, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    code = main(["study", "twisted-cylinder", *extra, "--t-end", "0.001", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: " + message), err
    assert len(err.splitlines()) == 1
    if "2e3" in message:  # as --option says it
        assert err.rstrip().endswith("(a float: write it as the integer 2000)")


def test_integer_options_typed_as_integers_are_varied():
    """A range of integers, and a list, give integers (the coordinate of chunk)."""
    for item in ("chunk=100:300:100", "chunk=100,200,300"):
        vary = _integer_options([item], "leapfrog", parse_vary([item]))
        _, coords, _ = design(mol_shell.TwistedCylinder(), vary, "leapfrog")
        assert coords["chunk"] == [100, 200, 300] and all(type(v) is int for v in coords["chunk"])


@pytest.mark.parametrize("values", [[2000.0], [100, 2e3], ["2e3"]])
def test_python_refuses_a_float_for_an_integer_option_as_simulate_does(values, monkeypatch):
    """``mol_shell.study(..., {"chunk": [2000.0]})`` ran with chunk 2000, where ``simulate(chunk=2000.0)`` and
    ``--vary chunk=2e3`` are refused; the same one line now, before any case."""
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    with pytest.raises(ParameterError) as refused:
        mol_shell.study("twisted-cylinder", {"chunk": values}, t_end=5e-4, scheduler="serial")
    with pytest.raises(ParameterError) as by_simulate:
        mol_shell.simulate("twisted-cylinder", n=9, t_end=5e-4, chunk=2000.0)
    assert str(refused.value) == str(by_simulate.value) == (
        "chunk = 2000.0 is not an integer; allowed: integers in [1, 9223372036854775807] (a float: write it as the "
        "integer 2000)")
    _, coords, _ = design(mol_shell.TwistedCylinder(), {"chunk": [2000, "3000"]}, "leapfrog")  # integers: taken
    assert coords["chunk"] == [2000, 3000] and all(type(v) is int for v in coords["chunk"])


def test_a_keyword_that_vary_also_varies_is_refused_as_the_command_line_refuses_it():
    """``study(..., {"dt": [...]}, dt=4e-6)`` ran the varied values and dropped the keyword without a word."""
    with pytest.raises(mol_shell.ParameterError, match=r"^dt = 4e-06 is set while vary\['dt'\] varies it"):
        mol_shell.study(mol_shell.TwistedCylinder(), {"dt": [1e-6, 2e-6]}, "leapfrog", n=21, t_end=0.002,
                        dt=4e-6, scheduler="serial")
    with pytest.raises(mol_shell.ParameterError, match=r"^rtol = 1e-06 is set while vary\['rtol'\] varies it"):
        mol_shell.study(mol_shell.TwistedCylinder(), {"rtol": [1e-8]}, "dop853-c", n=21, t_end=0.002,
                        rtol=1e-6, scheduler="serial")
    # a list of cases: the keyword is the value of the cases that leave it out (tests/runs/test_study.py)
