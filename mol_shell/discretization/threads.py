"""Threads for the compiled kernels (the OpenMP maps of the right-hand side, the leap-frog stencil's blocks):
``$MOL_SHELL_THREADS`` or ``threads=``, from 1 to :data:`THREADS_PER_CPU` per logical CPU."""

from __future__ import annotations

import os

import numpy as np

from mol_shell._core.errors import ParameterError

#: at most this many threads per logical CPU (:func:`max_threads`): one per CPU is all that runs at once, a few
#: more only oversubscribe. At n = 600 on 2 CPUs a leap-frog step took 2x as long on 16 threads as on 2, 500x on
#: 10,000; 100,000 crashed libgomp (a segmentation fault) and 2**31 wrapped round a C int
THREADS_PER_CPU = 8


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


def default_threads():
    """Threads for the compiled right-hand side: ``$MOL_SHELL_THREADS`` (1 .. :func:`max_threads`), else all
    the cores this process may run on."""
    text = os.environ.get("MOL_SHELL_THREADS", "").strip()
    if text:
        try:
            value = int(text)
        except ValueError:
            value = None
        return checked_threads("MOL_SHELL_THREADS", value, text)
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
