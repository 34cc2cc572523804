"""How a study's local workers start: forked only where no thread but OpenBLAS's can hold a lock, else spawned.

Each check of a process's threads runs in a fresh interpreter: a pytest-xdist worker has threads of its own."""

import os
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell._core.progress import progress_meter
from mol_shell.runs import worker_start

ROOT = Path(__file__).resolve().parents[2]
LINUX = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the fork rule reads /proc/self/task")


def _python(code, **env):
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(ROOT), **env}, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


@LINUX
def test_openblas_stops_its_threads_across_a_fork():
    """The rule's premise, held against the OpenBLAS that numpy loads: a pool of two threads holds one besides the
    calling thread, and in the parent, just after a fork, that one is gone (OpenBLAS's ``pthread_atfork`` handler
    stopped it); the next product starts it again."""
    out = _python("""
        import os
        import numpy as np
        from mol_shell.runs.worker_start import TASKS, openblas_threads
        a = np.random.default_rng(0).random((300, 300)); a @ a
        tasks = lambda: len(os.listdir(TASKS))
        print(openblas_threads(), tasks())
        pid = os.fork()
        if pid == 0:
            os._exit(0)
        print(tasks())
        os.waitpid(pid, 0)
        a @ a
        print(tasks())
    """, OPENBLAS_NUM_THREADS="2", OMP_NUM_THREADS="2")
    assert out == ["1", "2", "1", "2"]


@LINUX
def test_fork_is_chosen_only_where_every_other_thread_is_openblas_s():
    """In a fresh interpreter: fork with no other thread, and with OpenBLAS's (counted as it loaded them); spawn with
    a Python thread running, with an OS thread that is not OpenBLAS's (the allowance given as 0), and with kernels on
    two threads (OpenMP's pool does not survive a fork)."""
    out = _python("""
        import os, threading
        from mol_shell.runs.worker_start import fork_is_safe, start_method
        print(start_method(), fork_is_safe(), fork_is_safe(blas_threads=0))
        stop = threading.Event()
        thread = threading.Thread(target=stop.wait)
        thread.start()
        print(start_method())
        stop.set(); thread.join()
        os.environ["MOL_SHELL_THREADS"] = "2"
        print(start_method())
    """, OPENBLAS_NUM_THREADS="2", OMP_NUM_THREADS="1")
    assert out == ["fork", "True", "False", "spawn", "spawn"]
    out = _python("""
        from mol_shell.runs.worker_start import TASKS, fork_is_safe, start_method
        import os
        print(len(os.listdir(TASKS)), start_method(), fork_is_safe(blas_threads=0))
    """, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    assert out == ["1", "fork", "True"]


def test_a_process_with_another_python_thread_spawns():
    """Here too (a test process): a Python thread besides this one means spawn, whatever the OS threads."""
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert not worker_start.fork_is_safe(blas_threads=10**6)
        assert worker_start.start_method(10**6) in ("spawn", os.environ.get(worker_start.START_VARIABLE))
    finally:
        stop.set()
        thread.join()


def test_a_progress_bar_starts_no_thread():
    """tqdm's monitor thread would make every study shown with a bar (a terminal) spawn its workers."""
    before = threading.active_count()
    with open(os.devnull, "w") as sink:
        bar = progress_meter("bar", "cases", count="{n}", total=3, file=sink)
        try:
            bar.update(1)
            assert threading.active_count() == before
        finally:
            bar.close()


@LINUX
def test_a_command_line_study_forks_its_workers_and_gives_the_serial_bits(tmp_path):
    """``mol-shell study`` on two local processes in a fresh interpreter forks its worker (the file says so) and
    computes every case to the bits of the serial study; a serial study records no worker start. OpenBLAS on two
    threads: its pool's thread is counted as loaded, before the study limits the pool to one (read after, its size
    says 1 and the study spawned)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "2"}
    env.pop(worker_start.START_VARIABLE, None)
    args = ["study", "twisted-cylinder", "--vary", "gamma=0.02:0.12:0.02", "--n", "10", "--t-end", "0.005"]
    for name, more in (("local", ["--workers", "2"]), ("serial", ["--scheduler", "serial"])):
        done = subprocess.run([sys.executable, "-m", "mol_shell", *args, *more, "-o", str(tmp_path / f"{name}.nc")],
                              capture_output=True, text=True, timeout=240, env=env, check=False)
        assert done.returncode == 0, done.stderr
    local, serial = (mol_shell.read_netcdf(tmp_path / f"{name}.nc") for name in ("local", "serial"))
    assert local.attrs["worker_start"] == "fork" and "worker_start" not in serial.attrs
    assert (local.status == "complete").all()
    for name in ("r", "theta", "psi", "energy", "angular_momentum"):
        np.testing.assert_array_equal(local[name].values, serial[name].values, err_msg=name)
