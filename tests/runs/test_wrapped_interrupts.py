"""A Ctrl-C that a C extension reports in its own way (ctypes' ArgumentError, CasADi's RuntimeError) is a Ctrl-C:
the study command says so (a case's, which stops the study and resumes to the uninterrupted one, is
``tests/runs/test_study.py``'s interrupted study)."""

import ctypes
import importlib

import pytest
from wrapped_interrupts import WRAPPED

from mol_shell._core.errors import ModelLimitError, by_interrupt
from mol_shell.cli.main import main


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
