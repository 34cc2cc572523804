"""The saved times a run asked for, kept in its file when it saved fewer (a limit, a failure, Ctrl-C): attr
``times_requested``, so that the run is written back as a scene file (``mol-shell scenes RUN.nc --toml``) that asks
for them again, not for the times it reached.

The attr is compact: ``"T0:T1:DT"`` (``--times``' range form, its values rounded to 12 significant digits as the
command line rounds them) where that gives the times back exactly, else the times listed, ``"t1,t2,..."``, each as
Python's shortest text that reads back as it.
"""

from __future__ import annotations

import numpy as np

#: the attr of a run file that holds the saved times asked for where it saved fewer
ATTR = "times_requested"


def times_text(times):
    """The compact text of ``times`` (see the module's docstring): it reads back (:func:`times_of`) as ``times``."""
    times = np.asarray(times, dtype=float)
    if len(times) >= 3:
        step = float(f"{(times[-1] - times[0]) / (len(times) - 1):.12g}")
        spec = f"{float(times[0])!r}:{float(times[-1])!r}:{step!r}"
        if step > 0 and np.array_equal(times_of(spec), times):
            return spec
    return ",".join(repr(float(t)) for t in times)


def times_of(text):
    """The times of ``text`` (:func:`times_text`'s form); ``ValueError`` where it is not of that form."""
    text = str(text).strip()
    if ":" in text:
        start, stop, step = (float(part) for part in text.split(":"))  # ValueError unless three numbers
        count = (stop - start) / step if step > 0 else -1.0
        if not (np.isfinite([start, stop, step]).all() and count >= 1 and count < 1e8):
            raise ValueError(text)
        return np.array([float(f"{start + k * step:.12g}") for k in range(round(count) + 1)])
    return np.array([float(part) for part in text.split(",")])
