"""Progress of long work on stderr: a tqdm bar on a terminal, plain lines at most once a minute elsewhere.

``progress=None`` (the default of ``simulate``, ``study`` and ``path``, and what the CLI passes) shows a bar when
stderr is a terminal and, when it is not (a batch job's ``2> log.txt``, a notebook), newline-terminated lines
every :data:`LOG_INTERVAL_S` s of wall time, and a last one when the work ends; work shorter than the interval
prints nothing. ``True`` is the bar wherever stderr goes, ``False`` nothing.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell._core.units import show_seconds

#: seconds of wall time between two progress lines when stderr is not a terminal (the first after as long)
LOG_INTERVAL_S = 60.0


def progress_mode(progress):
    """How progress is shown: ``"bar"`` (tqdm) for ``True`` or, for ``None``, when stderr is a terminal; ``"lines"``
    for ``None`` when stderr is something else; ``None`` (nothing) for ``False`` or when there is no stderr (under
    pythonw and some services). Anything else is refused by name."""
    if progress is None:
        if sys.stderr is None:
            return None
        isatty = getattr(sys.stderr, "isatty", None)
        return "bar" if isatty is not None and isatty() else "lines"
    if not isinstance(progress, (bool, np.bool_)):
        raise ParameterError.not_a("progress", progress, "a bool",
                                   "True, False, or None (a bar on a terminal, else a line a minute)")
    return "bar" if progress else None


def progress_meter(mode, desc, *, count, postfix="{}", total=None, initial=0, **bar):
    """What :func:`progress_mode`'s ``mode`` asks for: a tqdm bar (``desc``, ``total``, ``initial`` and ``bar``'s
    options), :class:`ProgressLines` (``desc``, ``count``, ``postfix``, ``total``, ``initial``), or ``None``. Both
    take ``update(n)``, ``set_postfix_str(text)`` and ``close()``."""
    if mode == "bar":
        from tqdm import tqdm  # loaded only where a bar is shown

        # without tqdm's monitor thread (it tunes bars that are not updated for 10 s): a study's workers are forked
        # only from a process without other threads (mol_shell.runs.worker_start)
        return type("Bar", (tqdm,), {"monitor_interval": 0})(desc=desc, total=total, initial=initial, **bar)
    if mode == "lines":
        return ProgressLines(desc, count, postfix=postfix, total=total, initial=initial)
    return None


def time_meter(mode, t_end, desc="simulating"):
    """:func:`progress_meter` of a run to ``t_end``: its simulated time, in seconds (``desc``: what runs)."""
    return progress_meter(mode, desc, count="t = {n:.4g} of {total:.4g} s", total=float(t_end), unit="s",
                          unit_scale=False, bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]")


class ProgressLines:
    """Progress as plain lines on stderr, at most one every ``interval`` s of wall time, with tqdm's ``update``,
    ``set_postfix_str`` and ``close``.

    A line says ``mol-shell: DESC: COUNT (P %), POSTFIX, E elapsed, about R left``: ``COUNT`` is ``count`` formatted
    with ``n`` (the progress so far) and ``total``, or ``count(n, total)``; the percentage and the time left (from the rate since the start,
    progress from ``initial`` on) only with a ``total``; ``POSTFIX`` is ``postfix`` formatted with the last
    :meth:`set_postfix_str`'s text. Nothing is written before ``interval`` s have passed; :meth:`close`, once a line
    was written, writes the last one (``..., ended after E``). ``interval`` defaults to :data:`LOG_INTERVAL_S`,
    ``clock`` (seconds) to :func:`time.perf_counter`, ``stream`` to ``sys.stderr`` at each line.
    """

    def __init__(self, desc, count, *, postfix="{}", total=None, initial=0, interval=None, clock=time.perf_counter,
                 stream=None):
        self.desc, self.count, self.postfix_format, self.total = desc, count, postfix, total
        self.n, self.initial, self.postfix = initial, initial, ""
        self.interval = LOG_INTERVAL_S if interval is None else float(interval)
        self.clock, self.stream = clock, stream
        self.start = self.last = clock()
        self.lines = 0
        self.closed = False

    def reset(self):
        """Back to ``initial``, the clock from now (tqdm's ``reset``): the work starts here, not at the meter."""
        self.n = self.initial
        self.start = self.last = self.clock()

    def update(self, n=1):
        """``n`` more done; a line when ``interval`` s have passed since the last one (or the start)."""
        self.n += n
        now = self.clock()
        if now - self.last >= self.interval:
            self.last = now
            self._write(self.text(now - self.start))

    def set_postfix_str(self, text="", refresh=True):
        """The text after the count (shown with the next line; ``refresh`` is tqdm's, unused)."""
        self.postfix = str(text)

    def close(self):
        """The last line, once a line was written or the interval has passed (work shorter than it stays silent; a
        study interrupted after a minute without a case finished says where it stopped)."""
        now = self.clock()
        if not self.closed and (self.lines or now - self.start >= self.interval):
            self._write(self.text(now - self.start, final=True))
        self.closed = True

    def text(self, elapsed, final=False):
        """One line's text (no ``mol-shell:`` and no newline) after ``elapsed`` s."""
        parts = [self.count(self.n, self.total) if callable(self.count) else self.count.format(n=self.n, total=self.total)]
        if self.total:
            parts[0] += f" ({100.0 * self.n / self.total:.0f} %)"
        if self.postfix:
            parts.append(self.postfix_format.format(self.postfix))
        if final:
            parts.append(f"ended after {show_seconds(elapsed)}")
        else:
            parts.append(f"{show_seconds(elapsed)} elapsed")
            done = self.n - self.initial
            if self.total and done > 0 and self.n < self.total:
                parts.append(f"about {show_seconds(elapsed * (self.total - self.n) / done)} left")
        return f"{self.desc}: {', '.join(parts)}"

    def _write(self, text):
        stream = sys.stderr if self.stream is None else self.stream
        if stream is not None:
            print(f"mol-shell: {text}", file=stream, flush=True)
        self.lines += 1
