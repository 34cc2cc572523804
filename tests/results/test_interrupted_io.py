"""Ctrl-C while a netCDF file is written or read: the file is finished (or read) whole, then the interrupt is
raised; nothing hangs, no ``.part`` file is left.

xarray takes process-wide locks around netCDF4's calls; a KeyboardInterrupt that lands just after one is taken (its
``CombinedLock.acquire`` between two locks) leaves it taken, and the clean-up that follows (``store.close()``) waits
for it forever: a study interrupted while it stored a case hung, SIGTERM ignored. The signal is sent here at exactly
that point, from inside xarray's ``acquire``.
"""

import signal

import numpy as np
import pytest
from xarray.backends import locks

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf, write_netcdf
from mol_shell.runs.study import study

GLOBAL_LOCKS = (locks.HDF5_LOCK, locks.NETCDFC_LOCK)


@pytest.fixture
def sigint_python():
    """SIGINT as in a Python program (KeyboardInterrupt), whatever the test runner set; the xarray locks an
    interrupt left taken are given back afterwards (before the fix: the hang was then ended by the timeout), so
    that the other tests can write."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
    for lock in GLOBAL_LOCKS:
        if lock.locked():
            lock.release()


#: the lock a run's file is written under when the signal arrives: in the middle of its variables (before the fix,
#: the interrupt left it taken and the write's clean-up hung there, as the tester's study did)
AMID_THE_VARIABLES = 10


def signal_at_acquire(monkeypatch, which=AMID_THE_VARIABLES):
    """SIGINT sent to this process just after xarray takes its ``which``-th lock; returns the list of its calls."""
    real, calls = locks.acquire, []

    def acquire_then_signal(lock, blocking=True):
        taken = real(lock, blocking)
        calls.append(lock)
        if len(calls) == which:
            signal.raise_signal(signal.SIGINT)  # Python runs the handler here, the lock taken
        return taken

    monkeypatch.setattr(locks, "acquire", acquire_then_signal)
    return calls


@pytest.fixture(scope="module")
def run():
    return mol_shell.simulate("twisted-cylinder", n=10, t_end=0.002, progress=False)


@pytest.mark.timeout(30)
def test_a_ctrl_c_while_a_file_is_written_lets_it_finish_then_interrupts(tmp_path, monkeypatch, sigint_python, run):
    out = tmp_path / "run.nc"
    calls = signal_at_acquire(monkeypatch)
    with pytest.raises(KeyboardInterrupt, match="after writing"):
        write_netcdf(run, out)
    assert len(calls) >= AMID_THE_VARIABLES, "the signal was not sent"
    monkeypatch.undo()
    assert not any(lock.locked() for lock in GLOBAL_LOCKS)
    np.testing.assert_array_equal(read_netcdf(out).r.values, run.r.values)
    assert not list(tmp_path.glob(".*.part"))


@pytest.mark.timeout(30)
def test_a_ctrl_c_while_a_file_is_read_is_raised_once_it_is_closed(tmp_path, monkeypatch, sigint_python, run):
    """Reading too: the interrupt left xarray's locks taken, and the next read or write waited for them forever."""
    out = tmp_path / "run.nc"
    write_netcdf(run, out)
    signal_at_acquire(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        read_netcdf(out)
    monkeypatch.undo()
    assert not any(lock.locked() for lock in GLOBAL_LOCKS)
    np.testing.assert_array_equal(read_netcdf(out).r.values, run.r.values)


@pytest.mark.timeout(30)
def test_a_study_interrupted_while_it_stores_a_case_stops_and_resumes(tmp_path, monkeypatch, sigint_python):
    """The tester's hang (``study ... --scheduler serial``, Ctrl-C at 5 s or 9 s): the first case is stored whole,
    the study stops, and resuming it gives the uninterrupted study."""
    out, vary, small = tmp_path / "s.nc", {"gamma": [0.05, 0.1], "psi0": [0.0, 0.02]}, {"n": 10, "t_end": 0.002}
    signal_at_acquire(monkeypatch)  # the study's first lock: its first case's file (the runs write nothing)
    with pytest.raises(KeyboardInterrupt):
        study("twisted-cylinder", vary, **small, scheduler="serial", output=out)
    monkeypatch.undo()
    assert len(list((tmp_path / "s.cases").glob("*.nc"))) == 1 and not list(tmp_path.rglob(".*.part"))
    resumed = study("twisted-cylinder", vary, **small, scheduler="serial", output=out)
    assert (resumed.attrs["n_executed"], resumed.attrs["n_reused"]) == (3, 1)
    whole = study("twisted-cylinder", vary, **small, scheduler="serial")
    np.testing.assert_array_equal(resumed.r.values, whole.r.values)


@pytest.mark.timeout(30)
def test_the_run_command_interrupted_while_it_writes_says_the_file_was_written(tmp_path, monkeypatch, capsys,
                                                                              sigint_python):
    out = tmp_path / "run.nc"
    signal_at_acquire(monkeypatch)
    code = main(["run", "twisted-cylinder", "--n", "10", "--t-end", "0.002", "--no-stresses", "-o", str(out)])
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert code == 130 and err == [f"mol-shell: interrupted after writing {out}"], err
    monkeypatch.undo()
    assert read_netcdf(out).attrs["status"] == "complete" and not list(tmp_path.glob(".*.part"))
