"""Threads for the compiled kernels (the OpenMP maps of the right-hand side, the leap-frog stencil's blocks):
``threads=``, else ``$MOL_SHELL_THREADS``, else ``$OMP_NUM_THREADS``, else every usable CPU; from 1 to
:data:`THREADS_PER_CPU` per logical CPU."""

from __future__ import annotations

import os

import numpy as np

from mol_shell._core.errors import ParameterError

#: at most this many threads per logical CPU (:func:`max_threads`): one per CPU is all that runs at once, a few
#: more only oversubscribe. At n = 600 on 2 CPUs a leap-frog step took 2x as long on 16 threads as on 2, 500x on
#: 10,000; 100,000 crashed libgomp (a segmentation fault) and 2**31 wrapped round a C int
THREADS_PER_CPU = 8

#: ``$OMP_NUM_THREADS`` as this process was started (None: unset), read before the line below gives it the default
#: of 1 that SUNDIALS' SuperLU_MT needs (it spins otherwise: 70x slower on 2 cores); the first import of the
#: package runs this (mol_shell.integrators.sundials imports this module before its solvers)
OMP_NUM_THREADS_GIVEN = os.environ.get("OMP_NUM_THREADS")
os.environ.setdefault("OMP_NUM_THREADS", "1")


def max_threads():
    """The most threads the compiled kernels take: :data:`THREADS_PER_CPU` x this machine's logical CPUs."""
    return THREADS_PER_CPU * (os.cpu_count() or 1)


def checked_threads(name, value, shown=None):
    """``value`` as a thread count (an integer 1 .. :func:`max_threads`), else a ParameterError naming ``name`` (and
    ``shown``, the text it was read from, when there is one)."""
    top = max_threads()
    ok = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    if not (ok and 1 <= value <= top):
        raise ParameterError(name, value if shown is None else shown, f"integers 1 .. {top}",
                             hint=f"{THREADS_PER_CPU} x this machine's {top // THREADS_PER_CPU} logical CPUs; "
                                  "more threads than CPUs only oversubscribe them")
    return int(value)


def omp_threads(text):
    """The thread count ``text`` (a value of ``$OMP_NUM_THREADS``) gives as OpenMP reads it: the first entry of a
    comma list (the outermost level), a positive integer, at most :func:`max_threads`; None for a value OpenMP
    ignores (not a positive integer: libgomp falls back to its default then, and so does :func:`default_threads`)."""
    first = (text or "").split(",")[0].strip()
    if not first.isdigit() or int(first) < 1:
        return None
    return min(int(first), max_threads())


def default_threads():
    """Threads for the compiled right-hand side: ``$MOL_SHELL_THREADS`` (1 .. :func:`max_threads`, else refused),
    else ``$OMP_NUM_THREADS`` as the process was started (:func:`omp_threads`: what cluster job scripts set; a value
    OpenMP would ignore is ignored), else all the cores this process may run on."""
    text = os.environ.get("MOL_SHELL_THREADS", "").strip()
    if text:
        try:
            value = int(text)
        except ValueError:
            value = None
        return checked_threads("MOL_SHELL_THREADS", value, text)
    omp = omp_threads(OMP_NUM_THREADS_GIVEN)
    if omp is not None:
        return omp
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
