"""A Ctrl-C that a C extension reports in its own way (ctypes' ArgumentError, CasADi's RuntimeError) is a Ctrl-C:
a study stops there, the case is not stored as an error, and the resumed study equals an uninterrupted one."""

import ctypes
import importlib

import numpy as np
import pytest
from wrapped_interrupts import WRAPPED

from mol_shell._core.errors import ModelLimitError, by_interrupt
from mol_shell.cli.main import main
from mol_shell.runs.study import study

study_module = importlib.import_module("mol_shell.runs.study")

SMALL = {"n": 10, "t_end": 0.002}


@pytest.mark.parametrize("kind", ["ctypes", "casadi"])
def test_every_wrapper_of_a_ctrl_c_is_one_and_errors_that_only_mention_one_are_not(kind):
    exc = WRAPPED[kind]()
    assert by_interrupt(exc)
    try:  # and as the cause or context of another error
        raise ValueError("while handling it") from exc
    except ValueError as outer:
        assert by_interrupt(outer)
    assert not by_interrupt(ctypes.ArgumentError("argument 1: TypeError: wrong type"))
    assert not by_interrupt(RuntimeError("Error in Function::call for 'F':\nKeyboardInterrupt handling is off"))
    assert not by_interrupt(ModelLimitError("a limit at t = 1 s, after a KeyboardInterrupt", 1.0, "s = 0 m"))
    assert not by_interrupt(ValueError("KeyboardInterrupt"))


@pytest.mark.parametrize("kind", ["ctypes", "casadi"])
def test_a_case_interrupted_inside_a_c_call_stops_the_study_and_is_run_again(tmp_path, monkeypatch, kind):
    """The tester's study: an interrupt landing in a ctypes argument's conversion became the case's ``error``
    ("ArgumentError: argument 1: KeyboardInterrupt: "), stored in the cases folder and reused on every resume, and
    the study went on and exited 3."""
    out = tmp_path / "study.nc"
    vary = {"gamma": [0.05, 0.1], "psi0": [0.0, 0.02]}
    calls = []
    real = study_module.run_scene

    def interrupt_third(*args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            raise WRAPPED[kind]()
        return real(*args, **kwargs)

    monkeypatch.setattr(study_module, "run_scene", interrupt_third)
    with pytest.raises(KeyboardInterrupt):
        study("twisted-cylinder", vary, **SMALL, scheduler="serial", output=out)
    assert len(calls) == 3 and len(list((tmp_path / "study.cases").glob("*.nc"))) == 2 and not out.exists()
    monkeypatch.setattr(study_module, "run_scene", real)
    resumed = study("twisted-cylinder", vary, **SMALL, scheduler="serial", output=out)
    assert (resumed.attrs["n_executed"], resumed.attrs["n_reused"]) == (2, 2)
    assert (resumed.status == "complete").all()
    whole = study("twisted-cylinder", vary, **SMALL, scheduler="serial")
    np.testing.assert_array_equal(resumed.r.values, whole.r.values)


@pytest.mark.parametrize("kind", ["ctypes", "casadi"])
def test_the_study_command_says_where_the_finished_cases_are_kept(tmp_path, monkeypatch, capsys, kind):
    """A wrapped interrupt out of the study (in this process, outside its cases) is the study's interruption: its
    line says where the finished cases are kept and how to resume, exit 130 (it was an internal error, exit 1)."""
    cli_study = importlib.import_module("mol_shell.cli.study")

    def interrupted(*args, **kwargs):
        raise WRAPPED[kind]()

    monkeypatch.setattr(cli_study, "study", interrupted)
    code = main(["study", "twisted-cylinder", "--vary", "gamma=0.05,0.1", "--n", "10", "--t-end", "0.002",
                 "--scheduler", "serial", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 130 and "mol-shell: study interrupted; finished cases are kept in" in err, err
