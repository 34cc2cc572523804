"""Ctrl-C of ``mol-shell study`` on local processes: a real SIGINT to the whole process group, as a terminal sends it.

A sitecustomize (run by Python before anything else, in the study's process and in its spawned workers) sends the
signal from inside a worker at a chosen moment, so the timing is deterministic: while the worker imports the package
(its first second), or halfway through writing a case's result back to the study's process."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from child_process import sigint_default

#: fault drills: real signals to subprocesses (each a few seconds)
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]

#: in a spawned worker only (its command line says --multiprocessing-fork): SIGINT to the process group once, when
#: the worker imports INTERRUPT_IMPORT, or once it has written half of its INTERRUPT_SEND-th result (a message of a
#: 16 kB or more: its first kB) into the pool's pipe; the rest follows after 0.1 s, as a worker that goes on would send
#: it, and no result after it (one would fill the bytes still missing, whatever they hold)
HOOK = textwrap.dedent("""
    import os, signal, sys, time

    if "--multiprocessing-fork" in sys.orig_argv:
        def _interrupt():
            with open(os.environ["INTERRUPT_STAMP"], "w") as stamp:
                stamp.write(repr(time.time()))
            os.killpg(0, signal.SIGINT)
            time.sleep(0.1)

        class _AtImport:
            fired = False

            def find_spec(self, name, path=None, target=None):
                if name == os.environ.get("INTERRUPT_IMPORT") and not self.fired:
                    self.fired = True
                    _interrupt()
                return None

        sys.meta_path.insert(0, _AtImport())

        if os.environ.get("INTERRUPT_SEND"):
            import multiprocessing.connection as connection

            _send, _sent = connection.Connection._send, []

            def _halved(self, buf, *args):
                if len(buf) < 16384:
                    return _send(self, buf, *args)
                _sent.append(len(buf))
                if len(_sent) > int(os.environ["INTERRUPT_SEND"]):  # no result after it (a long case, say)
                    time.sleep(600)
                if len(_sent) != int(os.environ["INTERRUPT_SEND"]):
                    return _send(self, buf, *args)
                half = 1024  # the rest, more than a KeyboardInterrupt sent after it, is what the pool waits for
                _send(self, bytes(buf[:half]), *args)
                _interrupt()
                _send(self, bytes(buf[half:]), *args)

            connection.Connection._send = _halved
""")

STUDY = ["-m", "mol_shell", "study", "twisted-cylinder", "--vary", "gamma=0.02:0.12:0.02", "--n", "21",
         "--t-end", "0.02", "--workers", "2"]


def _study(tmp_path, out, timeout=60, **hook):
    """Run the study in a session of its own; ``(exit code, stdout + stderr, seconds from the hook's SIGINT to
    the exit)``, or a failure after ``timeout`` s."""
    (tmp_path / "sitecustomize.py").write_text(HOOK)
    stamp = tmp_path / "interrupted-at"
    stamp.unlink(missing_ok=True)
    env = {**os.environ, **hook, "INTERRUPT_STAMP": str(stamp), "MOL_SHELL_START_METHOD": "spawn", "OMP_NUM_THREADS": "1",
           "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    env.pop("PYTHONSTARTUP", None)
    proc = subprocess.Popen([sys.executable, *STUDY, "-o", str(out)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=sigint_default)  # noqa: PLW1509 - this test's threads take no locks
    try:
        text, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
        pytest.fail(f"the study hung after Ctrl-C (killed after {timeout} s); stderr:\n{err}")
    ended = time.time()
    return proc.returncode, text + err, ended - float(stamp.read_text()) if stamp.exists() else None


def _one_line(err, out):
    return [line for line in err.splitlines() if not line.startswith("mol-shell: warning:")] == [
        (f"mol-shell: study interrupted; finished cases are kept in {out.with_suffix('.cases')}; "
         "run the same command again to resume")]


@pytest.mark.timeout(120)
def test_ctrl_c_while_the_workers_start_exits_130_in_one_line_without_a_workers_traceback(tmp_path):
    """SIGINT to the process group while the spawned worker imports xarray: the worker printed its
    KeyboardInterrupt traceback (17-41 lines through multiprocessing/spawn.py and mol_shell/__init__.py) before the
    study's line. Now the worker ignores SIGINT from its start: the study's one line, exit 130."""
    out = tmp_path / "s.nc"
    code, err, seconds = _study(tmp_path, out, INTERRUPT_IMPORT="xarray")
    assert code == 130 and seconds < 10 and "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert _one_line(err, out), err
    assert not out.exists()


@pytest.mark.timeout(180)
def test_ctrl_c_while_a_worker_sends_a_result_exits_130_and_a_rerun_reuses_the_kept_cases(tmp_path):
    """SIGINT to the process group halfway through the worker's writing of its second result: the worker's
    KeyboardInterrupt cut the message off, and the study waited forever for the rest of it (a study hung on Ctrl-C
    about once in 40). Now the worker finishes the message (it ignores SIGINT), the study stops its workers instead
    of waiting for them, and exits 130 at once with its one line; a rerun reuses every case file kept and runs
    the other cases of the six."""
    out = tmp_path / "s.nc"
    code, err, seconds = _study(tmp_path, out, timeout=45, INTERRUPT_SEND="2")
    assert code == 130 and "Traceback" not in err and _one_line(err, out), err
    assert seconds < 10  # 0.3 s here: the running cases are not waited for
    kept = len(list(out.with_suffix(".cases").glob("*.nc")))
    assert 1 <= kept < 6, kept  # the worker's first result at least, stored before the interrupt
    code, err, _ = _study(tmp_path, out)  # no hook: the rerun
    assert code == 0, err
    assert f"wrote {out}: 6 cases (6 complete); ran {6 - kept}, reused {kept}, in " in err, err
