"""The command line as a tool in scripts: its warnings whatever ``python -W`` says, closed standard streams, stdout
that carries only what a command lists, an unknown option named first, and its environment variables refused in
one line."""

import os
import sys
import warnings

import pytest

from mol_shell._core.errors import MaterialWarning, MolShellWarning, ParameterError, RunWarning, SceneWarning
from mol_shell.cli import outcome
from mol_shell.cli.main import main
from mol_shell.discretization import sundials_driver as drv
from mol_shell.runs.resources import LongRunWarning
from mol_shell.scenes import SCENES

#: a sphere of a plane-stress law just past its classical buckling pressure, p_cr = 2 E (2h/a)^2 / sqrt(3 (1 - nu^2))
#: = 758.6 Pa (a = 1 m, 2h = 0.025034 m, E = 1 MPa): the start computed as its static equilibrium is unstable, warned
UNSTABLE = ["sphere", "--set", "h=0.012517", "--set", "nu=0.3", "--set", "material=svk-plane-stress", "--set",
            "pressure=-760", "--n", "21", "--t-end", "0.0005", "--integrator", "cvode-bdf"]


@pytest.mark.parametrize("category", [MolShellWarning, MaterialWarning, SceneWarning, RunWarning, LongRunWarning])
def test_every_package_warning_is_one_line_under_W_error(category, capsys):
    """``python -W error`` made the package's plain UserWarnings exceptions: the command ended 'internal error'."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # as -W error
        outcome.one_line_warnings()
        warnings.warn("the start is unstable", category)
    assert capsys.readouterr().err == "mol-shell: warning: the start is unstable\n"
    assert issubclass(category, UserWarning)  # Python users keep a real warning, filtered as ever


def test_an_unstable_start_warned_and_written_under_W_error(tmp_path, capsys):
    out = tmp_path / "us.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(["run", *UNSTABLE, "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 0 and out.exists(), err
    assert "mol-shell: warning: the start computed as a static equilibrium (R or dilation auto) is unstable" in err
    assert "internal error" not in err


def test_closed_stdout_writes_the_file_and_exits_0(tmp_path, monkeypatch, capsys):
    """``>&-``: sys.stdout is None; the run's file was written, then 'internal error: AttributeError ... flush'."""
    out = tmp_path / "cl.nc"
    monkeypatch.setattr(sys, "stdout", None)
    assert main(["run", "twisted-cylinder", "--t-end", "0.001", "--n", "11", "-o", str(out)]) == 0
    assert out.exists() and "error" not in capsys.readouterr().err
    assert main(["scenes"]) == 2  # its product is what it prints: refused in one line
    assert capsys.readouterr().err == ("mol-shell: error: cannot write to standard output: it is closed, and "
                                       "mol-shell scenes prints what it lists there\n")


def test_closed_stderr_says_nothing_on_stdout(tmp_path, monkeypatch, capsys):
    """``2>&-``: the warning (nu = 0.49 of the default svk law) went to stdout, print's file=None."""
    monkeypatch.setattr(sys, "stderr", None)
    out = tmp_path / "cl.nc"
    assert main(["run", "twisted-cylinder", "--t-end", "0.001", "--n", "11", "-o", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"wrote {out}: ")


def test_a_descriptor_that_cannot_be_written_is_absent(tmp_path):
    """A closed ``2>&-`` behind a launcher script (pyenv's shim) is fd 2 open for reading: EBADF, not a full disk."""
    with open(os.devnull) as reading, open(os.devnull, "w") as writing:
        assert outcome._absent(reading) and not outcome._absent(writing) and outcome._absent(None)


def test_scenes_lists_scenes_only_on_stdout(capsys):
    assert main(["scenes"]) == 0
    said = capsys.readouterr()
    assert [line.split()[0] for line in said.out.splitlines()] == list(SCENES)  # | awk '{print $1}'
    assert said.err.startswith("mol-shell scenes NAME lists")


def test_an_unknown_option_is_named_before_a_missing_one(capsys):
    assert main(["run", "--bogus"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mol-shell: error: --bogus is not an option of mol-shell run; allowed: ") and "-o" in err


def test_sundials_libs_that_do_not_hold_them_are_refused(tmp_path, monkeypatch):
    monkeypatch.setenv("MOL_SHELL_SUNDIALS_LIBS", str(tmp_path / "nonexistent"))
    with pytest.raises(ParameterError, match=r"^MOL_SHELL_SUNDIALS_LIBS = '.*nonexistent' is not a folder; allowed"):
        drv.driver()
    monkeypatch.setenv("MOL_SHELL_SUNDIALS_LIBS", str(tmp_path))
    with pytest.raises(ParameterError, match=r"^MOL_SHELL_SUNDIALS_LIBS = '.*' holds no libsundials_core; allowed"):
        drv.driver()


@pytest.mark.parametrize(("value", "asked"), [("0", False), ("off", False), ("", False), ("False", False),
                                              ("1", True), ("yes", True), ("ON", True)])
def test_traceback_switch(value, asked, monkeypatch):
    """``MOL_SHELL_TRACEBACK=0`` turned tracebacks on (any value that was not empty did)."""
    monkeypatch.setenv("MOL_SHELL_TRACEBACK", value)
    assert outcome.traceback_asked() is asked


def test_traceback_switch_refuses_another_value(monkeypatch, capsys):
    monkeypatch.setenv("MOL_SHELL_TRACEBACK", "maybe")
    assert main(["scenes"]) == 2
    assert capsys.readouterr().err.startswith("mol-shell: error: MOL_SHELL_TRACEBACK = 'maybe' is not a switch; "
                                              "allowed: 1, true, yes or on")


def test_a_sundials_folder_name_too_long_is_refused_by_its_variable(monkeypatch):
    """A name longer than the file system takes made Path.is_dir raise (an internal error): refused by name."""
    from mol_shell._core.errors import ParameterError
    from mol_shell.discretization.sundials_driver import LIBS_VARIABLE, library_folder

    monkeypatch.setenv(LIBS_VARIABLE, "/" + "z" * 300)
    with pytest.raises(ParameterError) as refused:
        library_folder()
    assert refused.value.name == LIBS_VARIABLE and "too long" in str(refused.value)
