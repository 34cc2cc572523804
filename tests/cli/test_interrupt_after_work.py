"""A Ctrl-C (or SIGTERM) that lands after the work is done keeps it: after a run's integration (in its ellipticity
check or its stresses), after a path's last step (as its Dataset is assembled), after an output was written (as the
command says what it wrote, or returns). Each was lost or misreported: the run or path with its file (exit 130, no
file), the written file unsaid (``mol-shell: interrupted``), the interrupt itself (exit 0). The signal is sent at that
point (``signal.raise_signal`` runs its handler at once), or its ``KeyboardInterrupt`` raised there."""

import importlib
import signal

import numpy as np
import pytest

from mol_shell import TwistedCylinder, simulate
from mol_shell._core import interrupts
from mol_shell.analysis import path as path_module
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf
from mol_shell.runs.post_run import ELLIPTICITY_INTERRUPTED, STRESSES_INTERRUPTED

simulate_module = importlib.import_module("mol_shell.runs.simulate")
cli_main = importlib.import_module("mol_shell.cli.main")
cli_analysis = importlib.import_module("mol_shell.cli.analysis")

T_END = 0.002
RUN = ["run", "twisted-cylinder", "--n", "10", "--t-end", str(T_END)]


@pytest.fixture
def sigint_python():
    """SIGINT as in a Python program (KeyboardInterrupt), whatever the test runner set."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def _signal_on_entry(monkeypatch, owner, name, signum=signal.SIGINT):
    """``owner.name`` sending ``signum`` to this process as it is entered, then running as before (if the handler
    lets it)."""
    original = getattr(owner, name)

    def wrapped(*args, **kwargs):
        signal.raise_signal(signum)
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, wrapped)


def _errors(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]


@pytest.mark.parametrize("signum, code, said", [(signal.SIGINT, 130, "interrupted by the user"),
                                                (signal.SIGTERM, 143, "terminated by SIGTERM")])
def test_an_interrupt_in_a_runs_ellipticity_check_keeps_the_run(monkeypatch, tmp_path, capsys, sigint_python, signum,
                                                                code, said):
    """Exit 130 (143) and no file: the run's states were complete. Now written, every saved time (11 evenly spaced to
    t_end, simulate's default), said interrupted after the run's end, the check and the stresses marked not done."""
    _signal_on_entry(monkeypatch, simulate_module, "check_ellipticity", signum)
    out = tmp_path / "run.nc"
    assert main([*RUN, "-o", str(out)]) == code
    ds = read_netcdf(out)
    line = (f"mol-shell: run stopped: {said} after the run reached its end, t = {T_END:g} s, before its ellipticity "
            f"check and its stresses; wrote 11 saved times to {out}")
    assert _errors(capsys) == [line]
    assert ds.attrs["status"] == "interrupted" and ds.attrs["complete"] == 0
    np.testing.assert_allclose(ds.time.values, np.linspace(0.0, T_END, 11), rtol=0, atol=1e-15)
    assert np.all(np.isfinite(ds.r.values)) and np.all(np.isnan(ds.ellipticity_margin.values))
    assert ds.attrs["ellipticity_note"] == ELLIPTICITY_INTERRUPTED and ds.attrs["stresses"] == STRESSES_INTERRUPTED
    assert "von_mises" not in ds and ds.attrs["failure_time"] == pytest.approx(T_END)


def test_an_interrupt_in_a_runs_stresses_cuts_them_short_and_keeps_the_run(monkeypatch, sigint_python):
    """In Python: the KeyboardInterrupt escaped simulate with the run. Now simulate returns it, its ellipticity
    checked, its stresses (where the signal landed: their computation stopped there) skipped and said so."""
    reached = []

    def add_stresses(ds, limit=None):
        signal.raise_signal(signal.SIGINT)
        reached.append(True)  # the computation went on past the signal
        return ds

    monkeypatch.setattr(simulate_module, "add_stresses", add_stresses)
    try:
        ds = simulate(TwistedCylinder(), n=10, t_end=T_END)
    except KeyboardInterrupt:
        pytest.fail("the interrupt was raised out of simulate, and the run with it")
    assert not reached and ds.attrs["status"] == "interrupted" and ds.sizes["time"] == 11
    assert ds.attrs["message"] == (f"interrupted by the user after the run reached its end, t = {T_END:g} s, before "
                                   "its stresses")
    assert ds.attrs["stresses"] == STRESSES_INTERRUPTED and np.all(ds.ellipticity_margin.values > 0)


def test_an_interrupt_as_a_path_is_assembled_keeps_its_steps(monkeypatch, tmp_path, capsys, sigint_python):
    """Exit 130 and no file, the path lost. Now written, all its steps to its stop, said interrupted after them."""
    _signal_on_entry(monkeypatch, path_module, "path_dataset")
    out = tmp_path / "p.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-300", "--set", "nu=0.3", "--set",
                 "material=svk-plane-stress", "--n", "10", "-o", str(out)])
    err = _errors(capsys)
    ds = read_netcdf(out)
    assert code == 130 and err[0].startswith(  # the critical points found follow, a line each
        "mol-shell: path stopped: interrupted by the user at pressure = -300 Pa, after the path's last step (reached "
        "pressure = -300 Pa)"), err
    assert ds.attrs["status"] == "interrupted" and float(ds.parameter[-1]) == -300.0 and ds.sizes["step"] >= 3


def test_an_interrupt_after_the_file_is_written_says_it_kept_it(monkeypatch, tmp_path, capsys, sigint_python):
    """``mol-shell: interrupted`` alone: the file written whole was not said."""
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_main, "say_stand_ins", interrupted)  # after write_netcdf
    out = tmp_path / "run.nc"
    assert main([*RUN, "--no-stresses", "-o", str(out)]) == 130
    assert _errors(capsys) == [f"mol-shell: interrupted after writing {out}"]
    assert read_netcdf(out).attrs["status"] == "complete"


def test_an_interrupt_noted_as_the_command_returns_is_not_lost(monkeypatch, tmp_path, capsys, sigint_python):
    """A signal the command line's watch noted but whose KeyboardInterrupt was lost (or that arrived as the watch was
    put back): the command exited 0 as if none had come. Now 130, saying what it kept."""
    def lost(*args, **kwargs):
        try:
            signal.raise_signal(signal.SIGINT)
        except KeyboardInterrupt:
            pass

    monkeypatch.setattr(cli_main, "say_stand_ins", lost)
    out = tmp_path / "run.nc"
    assert main([*RUN, "--no-stresses", "-o", str(out)]) == 130
    captured = capsys.readouterr()
    assert captured.out.startswith(f"wrote {out}: 11 times")
    assert [line for line in captured.err.splitlines() if "warning" not in line] == [
        f"mol-shell: interrupted after writing {out}"]


def test_modes_interrupted_between_its_file_and_its_figure_says_the_file(monkeypatch, tmp_path, capsys):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_analysis, "plot_modes", interrupted)
    out = tmp_path / "mm.nc"
    assert main(["modes", "sphere", "--n", "21", "--count", "4", "-o", str(out)]) == 130
    assert _errors(capsys) == [f"mol-shell: interrupted after writing {out}"]
    assert not (tmp_path / "mm.png").exists()


def test_what_an_interrupted_command_kept_is_said_in_one_line():
    with interrupts.watched(terminating=True):  # a new command: nothing written yet
        assert interrupts.kept_files() == ""
        interrupts.wrote("a.nc")
        assert interrupts.kept_files() == "after writing a.nc"
        interrupts.wrote("a.png")
        assert interrupts.kept_files() == "after writing a.nc and a.png"
        for name in ("b.nc", "c.nc"):
            interrupts.wrote(name)
        assert interrupts.kept_files() == "after writing 4 files, the last a.png, b.nc and c.nc"


def test_an_interrupt_as_the_unshearable_run_is_assembled_keeps_it(monkeypatch, sigint_python):
    """The unshearable scene's own steps after its integration (its observables, its Dataset) let a Ctrl-C escape with
    the whole run: now noted, the run returned whole and said interrupted after its end."""
    unshearable = importlib.import_module("mol_shell.runs.unshearable")
    _signal_on_entry(monkeypatch, unshearable, "build_dataset")
    ds = simulate("unshearable", "leapfrog", n=10, times=[0.0, 0.0005, 0.001], dt=1e-5, progress=False)
    assert ds.attrs["status"] == "interrupted" and ds.attrs["complete"] == 0
    assert ds.attrs["message"].startswith("interrupted by the user after the run reached its end, t = 0.001 s")
    np.testing.assert_array_equal(ds.time.values, [0.0, 0.0005, 0.001])
    assert np.all(np.isfinite(ds.r.values))  # its stresses follow, as after an interrupt while it stepped
