"""Ctrl-C (SIGINT) where Python's own ``KeyboardInterrupt`` would do harm: held back while a file is written or
read, and noted, not raised, while a run steps.

Python raises ``KeyboardInterrupt`` wherever the main thread is when the signal arrives. Two kinds of place cannot
take it there:

* a netCDF file being written or read: xarray and netCDF4 hold process-wide locks (``threading.Lock``) around the C
  library's calls, and an interrupt between taking one and the ``try`` that gives it back leaves it taken; the
  clean-up that follows then waits for it forever (a study hung on Ctrl-C, SIGTERM ignored, a ``.NAME.*.part`` temporary
  left). :func:`held` lets such a block finish and raises ``KeyboardInterrupt`` after it.
* a run's steps, which call CasADi and ctypes many times a second: a ``KeyboardInterrupt`` could be lost on the
  way (2 of 24 interrupts of ``mol-shell run ... --option chunk=1`` 2.4-3.4 s after its start: the run went on
  to its end, the process then in a CasADi call; the call that dropped it was not pinned down), ctypes reports one
  raised while it converts an argument as an ``ArgumentError``, CasADi's ``DM.__array__`` as a ``SystemError``,
  its integrators as a failure of SUNDIALS. :func:`watched` notes the signal in a flag that the run's loop reads
  between its chunks.

Both act in the main thread only (the only one Python runs signal handlers in), and only where a Python handler
is in place: a process that ignores SIGINT, or that SIGINT kills, is left as it is. A signal noted is passed on to
the handler that was replaced (:func:`held`), or left to the caller (:func:`watched`). The command line watches a
whole command with a handler that raises as Python's does and notes the signal too, so that a run started after
an interrupt some call lost (in the run's set-up) stops at once.

The command line takes SIGTERM (what a cluster's scheduler sends at a job's wall-time limit, and ``kill`` by default)
over as well (:func:`watched` with ``terminating``): the watches note it as a Ctrl-C, so a run keeps its saved times
and writes them, and the command exits 143 (128 + SIGTERM) saying it was terminated (:func:`terminated`); where it
was the default action, SIGTERM ended the process at once, its run lost. Only the first: it puts SIGTERM's default
action back, so a second SIGTERM (or SIGKILL) ends the process as before.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading

#: the signals a :class:`Watch` takes: SIGINT (Ctrl-C), and SIGTERM where the command line has taken it over
#: (:func:`watched` with ``terminating``: what a cluster's scheduler sends at a job's wall-time limit)
SIGNALS = (signal.SIGINT, signal.SIGTERM)
#: ``[signal number]`` of the SIGTERM that ended this command, once one has arrived (:func:`terminated`)
_TERMINATED = []
#: the files this command has written whole (:func:`wrote`): how many, and the last :data:`NAMED` of them
_WRITTEN = [0, []]
#: the files named in what a command an interrupt stopped says it kept (:func:`kept_files`)
NAMED = 3


class Watch:
    """The SIGINT (and SIGTERM) handler while a block runs: ``caught`` once a signal arrived, ``signum`` which;
    ``raising``: also raise ``KeyboardInterrupt`` where it lands (for a block that waits in one long call which stops
    itself on one: CasADi's integrators run Python's signal handlers as they step). ``previous``: the handlers it
    replaced, ``{signal number: handler}``.

    A SIGTERM is taken as a Ctrl-C (the run stops, keeps its data and writes them), once: the first puts SIGTERM's
    default action back, so a second ends the process there and then (a scheduler's SIGKILL always does)."""

    def __init__(self, raising=False):
        self.caught, self.raising, self.previous, self.signum = False, raising, {}, None

    def __call__(self, signum, frame):
        self.caught, self.signum = True, signum
        if signum == signal.SIGTERM:
            signal.signal(signal.SIGTERM, signal.SIG_DFL)  # a second SIGTERM ends the process
            if _TERMINATED:  # a second one that arrived as this handler was put back: end it as asked
                os.kill(os.getpid(), signal.SIGTERM)
            _TERMINATED.append(signum)
        if self.raising:
            raise KeyboardInterrupt


def terminated():
    """Whether a SIGTERM stopped this command (:func:`watched` with ``terminating``): it exits as one it ended, 143,
    after keeping what it had, as Ctrl-C's 130."""
    return bool(_TERMINATED)


def wrote(path):
    """Note that ``path``, an output, has been written whole (renamed onto its name): a command that an interrupt stops
    after it says that it kept it (:func:`kept_files`), wherever the interrupt lands."""
    _WRITTEN[0] += 1
    _WRITTEN[1] = [*_WRITTEN[1], os.fspath(path)][-NAMED:]


def kept_files():
    """What this command has written whole (:func:`wrote`), as said after ``interrupted``: ``"after writing a.nc"``,
    ``"after writing a.nc and a.png"``, ``"after writing 12 files, the last a.nc, b.nc and c.nc"``; ``""`` for none."""
    count, names = _WRITTEN
    if not count:
        return ""
    listed = names[0] if len(names) == 1 else ", ".join(names[:-1]) + f" and {names[-1]}"
    return f"after writing {listed}" if count == len(names) else f"after writing {count} files, the last {listed}"


def _install(watch, terminating=False):
    """Put ``watch`` in place of SIGINT's handler, and of SIGTERM's where a watch has it (``terminating``: where its
    default action has it, which the watch takes over); False where neither can be (another thread than the main one)
    or should be (SIGINT ignored, or left to kill the process, and SIGTERM not the command line's)."""
    if threading.current_thread() is not threading.main_thread():
        return False
    for signum in SIGNALS:
        previous = signal.getsignal(signum)
        if signum == signal.SIGTERM:
            take = isinstance(previous, Watch) or (terminating and previous == signal.SIG_DFL)
        else:  # SIG_IGN, SIG_DFL, or a handler not set from Python (None): left as they are
            take = callable(previous)
        if take:
            watch.previous[signum] = previous
            signal.signal(signum, watch)  # runs the previous handler first for a signal already pending
    return bool(watch.previous)


def _restore(watch):
    """Put the replaced handlers back. A signal still pending is noted by ``watch`` first (``signal.signal`` runs the
    handlers of pending signals before it changes one), never raised: the handler would otherwise stay ``watch``.
    SIGTERM's is left as it is once a SIGTERM has arrived (its default action: a second one ends the process)."""
    watch.raising = False
    for signum, previous in watch.previous.items():
        if signal.getsignal(signum) is watch:
            signal.signal(signum, previous)


def _pass_on(watch, note=""):
    """Hand a signal that ``watch`` noted to the handler it replaced: Python's own, or an enclosing raising
    :class:`Watch`, raises ``KeyboardInterrupt`` (saying ``note``); an enclosing noting one notes it; another handler
    (the user's) is called as the signal would have called it."""
    if not watch.caught:
        return
    outer = watch.previous.get(watch.signum)
    if isinstance(outer, Watch):
        outer.caught, outer.signum = True, watch.signum
        if not outer.raising:
            return
    elif outer is not signal.default_int_handler and callable(outer):
        outer(watch.signum, None)
        return
    raise KeyboardInterrupt(*([note] if note else []))


@contextlib.contextmanager
def held(note=""):
    """Hold SIGINT (and the command line's SIGTERM) back while the block runs; once it has finished, raise
    ``KeyboardInterrupt`` (its message ``note``, e.g. what the block wrote) if one arrived meanwhile. The block is never
    interrupted halfway: for writing and reading files through libraries that hold locks (module docstring). A block
    that fails for its own reason raises that error, with the interrupt raised from within its handling (the error
    then its ``__context__``)."""
    watch = Watch()
    if not _install(watch):
        yield watch
        return
    try:
        yield watch
    except BaseException:
        _restore(watch)
        _pass_on(watch)
        raise
    _restore(watch)
    _pass_on(watch, note)


@contextlib.contextmanager
def watched(raising=False, terminating=False):
    """Note SIGINT (and the command line's SIGTERM) in the yielded :class:`Watch` (``caught``) while the block runs,
    for the block to act on where it can (a run's loop, between its chunks); ``raising``: also raise
    ``KeyboardInterrupt`` where the signal lands (the command line's, for a whole command: Python's behaviour, with
    the signal noted); ``terminating``: take SIGTERM over from its default action too, as a Ctrl-C (the command line:
    :func:`terminated` then says that one arrived). A signal that an enclosing watch noted already counts as caught
    (its ``KeyboardInterrupt`` was lost on the way: the command went on into this block). A signal noted is not passed
    on: the block has acted on it (a run ends ``"interrupted"``, keeping its data)."""
    if terminating:  # a new command (tests run many in one process)
        _TERMINATED.clear()
        _WRITTEN[:] = [0, []]
    watch = Watch(raising)
    installed = _install(watch, terminating)
    for outer in watch.previous.values():
        if isinstance(outer, Watch) and outer.caught:
            watch.caught, watch.signum = True, outer.signum
    try:
        yield watch
    finally:
        if installed:
            _restore(watch)


__all__ = ["Watch", "held", "kept_files", "terminated", "watched", "wrote"]


def started_as_command():
    """Whether this process is the command line (``mol-shell ...`` or ``python -m mol_shell ...``), whose Ctrl-C
    while the package is still being imported (about a second) exits as it does later: one line and code 130,
    where a script that imports the package gets its ``KeyboardInterrupt``. ``sys.orig_argv`` holds the ``-m``
    that ``sys.argv`` has lost while the package is imported."""
    argv = list(getattr(sys, "orig_argv", []))
    if "-m" in argv[:-1] and argv[argv.index("-m") + 1].split(".")[0] == "mol_shell":
        return True
    return bool(sys.argv) and os.path.basename(sys.argv[0]) in ("mol-shell", "mol-shell.exe")


def exit_if_command(exit_code=130):
    """For a ``KeyboardInterrupt`` caught while the package is imported: the command line's ``mol-shell:
    interrupted`` and ``exit_code``; anything else returns (the caller raises it again)."""
    if started_as_command():
        print("mol-shell: interrupted", file=sys.stderr)
        raise SystemExit(exit_code)
