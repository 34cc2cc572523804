"""How a study's local worker processes start: forked where no other thread can hold a lock, else spawned.

A forked worker is a copy of this process with its imports done (and whatever graphs and kernels it had loaded),
so it starts its first case at once; a spawned one first starts an interpreter and imports the package (0.5 s on a
fast machine, 1.5 s on a slow one), while this process already computes. POSIX forks only the calling thread: a lock
another thread held at that moment (malloc's, a library's) stays locked in the copy, which may then hang. So
:func:`start_method` forks only where every thread but this one is known to be safe across a fork, and spawns
elsewhere; :data:`START_VARIABLE` chooses a start method outright.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import threading

from threadpoolctl import threadpool_info

from mol_shell._core.errors import ParameterError

#: the environment variable that says how local worker processes start (a start method of ``multiprocessing``;
#: unset: :func:`start_method` chooses)
START_VARIABLE = "MOL_SHELL_START_METHOD"

#: where this process's threads are listed, one entry each (Linux)
TASKS = "/proc/self/task"


def kernels_threaded():
    """Whether ``MOL_SHELL_THREADS`` asks for the kernels on more than one thread (anything but 1; unset reads 1, as a
    study sets it): OpenMP's thread pool does not survive a fork."""
    return os.environ.get("MOL_SHELL_THREADS", "1").strip() != "1"


def openblas_threads():
    """The threads of the OpenBLAS pools loaded here besides the calling one (a pool of k threads holds k - 1):
    OpenBLAS stops them before a fork (its ``pthread_atfork`` handler) and starts them again when next used, so they
    are safe across one. Read before a study limits the pools to one thread (their sizes then read 1)."""
    return sum(max(0, int(info.get("num_threads") or 1) - 1) for info in threadpool_info()
               if info.get("internal_api") == "openblas" and info.get("threading_layer") == "pthreads")


def fork_is_safe(blas_threads=None):
    """Whether a forked worker is safe here: Linux, the kernels on one thread (``MOL_SHELL_THREADS`` 1, which a study
    sets where it is unset; OpenMP's pool does not survive a fork), no Python thread but this one (a notebook's,
    dask's, a progress monitor's, the user's), and no more other threads in the process than OpenBLAS's pools hold
    (``blas_threads``, else :func:`openblas_threads`; a count: a native thread of another library in place of an
    OpenBLAS thread that was never started would pass). Anything unknown (no ``/proc``) says no."""
    if not sys.platform.startswith("linux") or "fork" not in multiprocessing.get_all_start_methods():
        return False
    if kernels_threaded() or threading.active_count() != 1:
        return False
    try:
        others = len(os.listdir(TASKS)) - 1
    except OSError:
        return False
    return others <= 0 or others <= (openblas_threads() if blas_threads is None else blas_threads)


def start_method(blas_threads=None):
    """How a study's local worker processes start: the start method :data:`START_VARIABLE` names, else ``fork``
    where :func:`fork_is_safe` (``blas_threads`` passed on), else ``spawn``.

    Measured on the benchmark's 100-case study (December 8, a slow 2-core AMD EPYC, the fastest parallel studies
    10.2-14.6 s, an interpreter importing the package 1.5 s): over 14 rounds forked workers gave 1.75-2.17x the
    serial throughput (median 1.85) and beat the spawned study of the same round in 13 (docs/performance.md).
    ``fork`` asked where the kernels run on more than one thread (``MOL_SHELL_THREADS``) is refused: OpenMP's thread
    pool is not safe across a fork. Raises
    :class:`ParameterError` for a method this platform lacks."""
    methods = multiprocessing.get_all_start_methods()
    threaded = kernels_threaded()
    allowed = [m for m in methods if not (m == "fork" and threaded)]
    asked = os.environ.get(START_VARIABLE, "").strip()
    if not asked:
        return "fork" if fork_is_safe(blas_threads) else "spawn"
    if asked not in allowed:
        raise ParameterError(START_VARIABLE, asked, "{" + ", ".join(allowed) + "}", hint=(
            "the environment variable that says how a study's local worker processes start; unset, fork where it "
            "is safe, else spawn" + (
                "; fork only with MOL_SHELL_THREADS = 1: OpenMP's threads are not safe across a fork"
                if threaded and asked == "fork" else "")))
    return asked
