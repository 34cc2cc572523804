"""SIGTERM, what a cluster's scheduler sends at a job's wall-time limit, ends a command as Ctrl-C does: a run keeps its
saved times and writes them, a study its finished cases, a path its steps; one line says it was terminated, and the
exit code is 143 (128 + SIGTERM). It ended the process at once (exit 143, no file, no word). A second SIGTERM still
ends it there and then.

Each test runs the command in a process of its own, which sends itself SIGTERM at a fixed point of the work (the
n-th call of a function, patched by the driver below), so the point does not depend on the machine's speed.
"""

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np

from mol_shell._core import interrupts
from mol_shell.results.dataset import read_netcdf

ROOT = Path(__file__).resolve().parents[2]

#: ``python -c DRIVER MODULE OWNER NAME CALLS KILLS ARGS...``: the command ``ARGS`` with ``MODULE.OWNER.NAME`` sending
#: SIGTERM ``KILLS`` times at its ``CALLS``-th call
DRIVER = """
import importlib, os, signal, sys
module, owner, name, calls, kills = sys.argv[1:6]
target = importlib.import_module(module)
if owner != "-":
    target = getattr(target, owner)
real, count = getattr(target, name), [0]
def patched(*args, **kwargs):
    count[0] += 1
    if count[0] == int(calls):
        for _ in range(int(kills)):
            os.kill(os.getpid(), signal.SIGTERM)
    return real(*args, **kwargs)
setattr(target, name, patched)
from mol_shell.cli.main import main
sys.exit(main(sys.argv[6:]))
"""

TIMES = np.round(np.arange(0, 0.0105, 0.001), 12)
RUN = ["run", "twisted-cylinder", "--n", "10", "--dt", "1e-5", "--option", "chunk=50", "--times", "0:0.01:0.001",
       "--no-stresses"]


def _default_sigterm():
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _command(patch, calls, args, kills=1):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.setdefault("OMP_NUM_THREADS", "1")
    proc = subprocess.run([sys.executable, "-c", DRIVER, *patch, str(calls), str(kills), *args], env=env,
                          capture_output=True, text=True, timeout=120, preexec_fn=_default_sigterm, check=False)
    err = [line for line in proc.stderr.splitlines() if not line.startswith("mol-shell: warning: ")]
    return proc.returncode, err


def test_sigterm_during_a_run_writes_its_saved_times_and_exits_143(tmp_path):
    """The leap-frog's fourth check of the limits (the start, the first step, two chunks): the run stops at the end of
    that chunk, as for Ctrl-C, and its file says it was terminated."""
    out = tmp_path / "run.nc"
    code, err = _command(("mol_shell.integrators.base", "Monitor", "check"), 4, [*RUN, "-o", str(out)])
    assert code == 143, err
    ds = read_netcdf(out)
    kept = ds.sizes["time"]
    assert 1 <= kept < len(TIMES)
    np.testing.assert_array_equal(ds.time.values, TIMES[:kept])
    assert ds.attrs["status"] == "interrupted" and ds.attrs["complete"] == 0
    stopped = float(ds.attrs["failure_time"])
    assert ds.attrs["message"] == f"terminated by SIGTERM at t = {stopped:.9g} s"
    assert err == [(f"mol-shell: run stopped: terminated by SIGTERM at t = {stopped:.9g} s; wrote {kept} saved "
                    f"time{'s' * (kept != 1)} to {out}")]


def test_a_second_sigterm_ends_the_run_at_once(tmp_path):
    out = tmp_path / "run.nc"
    code, err = _command(("mol_shell.integrators.base", "Monitor", "check"), 4, [*RUN, "-o", str(out)], kills=2)
    assert code == -signal.SIGTERM, err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_sigterm_during_a_study_keeps_its_finished_cases_and_exits_143(tmp_path):
    """The second case's run: the first case is kept for a rerun, as after Ctrl-C."""
    out = tmp_path / "study.nc"
    code, err = _command(("mol_shell.runs.study", "-", "run_scene"), 2, [
        "study", "twisted-cylinder", "--vary", "gamma=0.1,0.2,0.3", "--n", "5", "--t-end", "1e-6", "--workers", "1",
        "-o", str(out)])
    assert code == 143, err
    assert err == [(f"mol-shell: study terminated by SIGTERM; finished cases are kept in {tmp_path / 'study.cases'}; "
                    "run the same command again to resume")]
    assert len(list((tmp_path / "study.cases").glob("*.nc"))) == 1 and not out.exists()


def test_sigterm_during_a_path_writes_its_steps_and_exits_143(tmp_path):
    out = tmp_path / "path.nc"
    code, err = _command(("mol_shell.analysis.path", "_Path", "correct"), 6, [
        "path", "sphere", "--param", "pressure=0:-300", "--set", "nu=0.3", "--set", "material=svk-plane-stress",
        "--n", "10", "-o", str(out)])
    assert code == 143, err
    assert len(err) == 1 and re.match(r"mol-shell: path stopped: terminated by SIGTERM at pressure = ", err[0]), err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and ds.sizes["step"] >= 2
    assert ds.attrs["message"].startswith("terminated by SIGTERM at pressure = ")


def test_sigterm_is_left_alone_outside_the_command_line():
    """A script that calls mol_shell keeps SIGTERM as it set it: only the command line takes it over."""
    before = signal.getsignal(signal.SIGTERM)
    with interrupts.watched() as watch, interrupts.held():
        assert signal.getsignal(signal.SIGTERM) is before
    assert not watch.caught and not interrupts.terminated()


def test_the_command_lines_watch_takes_sigterm_once_and_gives_it_back(monkeypatch):
    """In the command line's watch SIGTERM is noted (and a nested watch gets it, as SIGINT); after the first, its
    default action is back, so a second ends the process."""
    previous = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        with interrupts.watched(terminating=True) as outer:
            with interrupts.watched() as inner:
                assert signal.getsignal(signal.SIGTERM) is inner
                signal.raise_signal(signal.SIGTERM)
                assert inner.caught and inner.signum == signal.SIGTERM and interrupts.terminated()
                assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL
            assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL and not outer.caught
        assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL
    finally:
        signal.signal(signal.SIGTERM, previous)
        interrupts._TERMINATED.clear()  # as the next command does
