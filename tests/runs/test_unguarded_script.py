"""A script that calls ``study`` with local workers but outside ``if __name__ == "__main__":``.

Python's spawned workers re-run such a script as they start; each then tried to start a study of its own, died
with multiprocessing's long RuntimeError, and the study went on spawning new workers (eleven tracebacks in one
run), finishing serially without a word. Now the worker stops with one line saying what to change, and the study
runs the remaining cases in the calling process, said once. A forked worker (the default on Linux where it is safe, or ``MOL_SHELL_START_METHOD=fork``,
Linux) does not run the script again: there such a script simply works.
"""

import multiprocessing
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

#: the environment of a script whose study spawns its workers (the default where forking is not safe: not Linux,
#: other threads)
SPAWNED = dict(os.environ, PYTHONPATH=str(Path(__file__).parents[2]), MOL_SHELL_START_METHOD="spawn")

SCRIPT = textwrap.dedent("""
    import mol_shell

    ds = mol_shell.study("twisted-cylinder", {"gamma": [0.05, 0.06, 0.07, 0.08]}, n=8, t_end=1e-4, workers=2,
                         progress=False)
    print("STATUS", sorted(set(ds.status.values.tolist())), ds.status.size, len(set(ds.worker.values.tolist())))
""")


@pytest.mark.timeout(120)
def test_unguarded_study_script_runs_its_cases_once_with_one_line_on_each_side(tmp_path):
    script = tmp_path / "sweep.py"
    script.write_text(SCRIPT)
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path,
                          env=SPAWNED, timeout=110, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "STATUS ['complete'] 4 1" in proc.stdout, (proc.stdout, proc.stderr[-3000:])  # all in this process
    assert proc.stdout.count("STATUS") == 1, proc.stdout  # the worker did not run the script's study
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
    assert proc.stderr.count('if __name__ == "__main__":') == 2, proc.stderr  # the worker's line, the warning
    assert "this process runs the study's remaining cases" in proc.stderr, proc.stderr


SLOW_WORKER = textwrap.dedent("""
    import time

    import mol_shell

    if __name__ == "__mp_main__":  # a worker that starts late (a busy machine): the cases are done and stored
        time.sleep(3)
    ds = mol_shell.study(mol_shell.TwistedCylinder(material="svk-plane-stress"), {"gamma": [0.05, 0.06]}, n=8,
                         t_end=1e-4, workers=2, progress=False, output="out/st.nc")
    print("STATUS", __name__, ds.status.size)
""")


@pytest.mark.timeout(120)
def test_a_late_worker_of_an_unguarded_script_stops_before_its_study_does_anything(tmp_path):
    """The worker's stop was reached only where the study spawns its own workers: a worker that started after
    every case was stored found nothing to run, never got there, and ran the user's whole script (its study, its
    prints, its output file written again). The studies now stop such a worker before anything else."""
    script = tmp_path / "sweep.py"
    script.write_text(SLOW_WORKER)
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path,
                          env=SPAWNED, timeout=110, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.count("STATUS") == 1 and "STATUS __main__ 2" in proc.stdout, (proc.stdout, proc.stderr)
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]


@pytest.mark.skipif("fork" not in multiprocessing.get_all_start_methods(), reason="no fork on this platform")
@pytest.mark.timeout(120)
def test_a_forked_worker_runs_an_unguarded_scripts_cases_without_running_the_script(tmp_path):
    script = tmp_path / "sweep.py"
    script.write_text(SCRIPT.replace("[0.05, 0.06, 0.07, 0.08]", "[0.05 + 0.01 * k for k in range(12)]").replace("1e-4", "1e-2"))
    env = {k: v for k, v in SPAWNED.items() if k != "MOL_SHELL_THREADS"}
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path,
                          env=dict(env, MOL_SHELL_START_METHOD="fork"), timeout=110, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.count("STATUS") == 1 and "STATUS ['complete'] 12 2" in proc.stdout, (proc.stdout, proc.stderr)
    assert "__main__" not in proc.stderr and "Traceback" not in proc.stderr, proc.stderr[-3000:]


@pytest.mark.timeout(120)
def test_a_script_read_from_stdin_starts_its_workers_without_a_traceback(tmp_path):
    """``python - < script.py``: the main module's ``__file__`` is ``'<stdin>'``, which each spawned worker tried to
    run again as it started (a traceback ending ``FileNotFoundError: ... '<stdin>'``, a RuntimeWarning, and every
    case in the calling process). The workers now start without it, as for ``python -c`` (forkserver's alike)."""
    proc = subprocess.run([sys.executable, "-"], input=SCRIPT, capture_output=True, text=True, cwd=tmp_path,
                          env=SPAWNED, timeout=110, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.count("STATUS") == 1 and "STATUS ['complete'] 4" in proc.stdout, (proc.stdout, proc.stderr)
    assert "Traceback" not in proc.stderr and "stopped before their first case" not in proc.stderr, proc.stderr
