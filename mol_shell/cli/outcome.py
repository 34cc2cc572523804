"""How a command ends: its one-line errors and exit codes (:func:`said`), its warnings in one line each
(:func:`one_line_warnings`), and its standard streams guarded while it runs (:func:`guarded`): bad input 2, a model
limit 3, Ctrl-C 130 (SIGTERM 143), a reader gone 141, an output that cannot be written 2, a bug 1.

The command line (:mod:`mol_shell.cli.main`) and the studies' scripts (:mod:`mol_shell.cli.scripts`) end so.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import os
import signal
import sys
import warnings

from mol_shell._core import interrupts
from mol_shell._core.atomic import NoSpaceError
from mol_shell._core.errors import ModelLimitError, MolShellWarning, ParameterError, by_interrupt, show
from mol_shell.cli.args import (
    EXIT_INCOMPLETE,
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    EXIT_PIPE,
    EXIT_TERMINATED,
    EXIT_USAGE,
    interrupted_code,
)
from mol_shell.cli.inputs import said_with_the_file


def remove_empty(folders):
    """Remove the directories this command created, deepest first, if nothing was written into them."""
    for folder in reversed(folders):
        try:
            os.rmdir(folder)
        except OSError:
            return


class OutputError(Exception):
    """Standard output or error could not be written (a full disk, a terminal gone): not a bug, said in one line."""

    def __init__(self, stream, error):
        self.stream = stream
        super().__init__(f"cannot write to {stream}: {error}")


class _Guarded:
    """``sys.stdout`` or ``sys.stderr`` while a command runs: an ``OSError`` writing it is an :class:`OutputError`
    naming the stream (a reader gone, ``BrokenPipeError``, stays one: it ends quietly)."""

    def __init__(self, stream, name):
        self._stream, self._name = stream, name

    def write(self, text):
        try:
            return self._guard(self._stream.write, text)
        except UnicodeEncodeError:  # a file name's bytes that are not UTF-8 ('\udce9') on a strict stream: as repr
            encoding = getattr(self._stream, "encoding", None) or "utf-8"
            return self._guard(self._stream.write, text.encode(encoding, "backslashreplace").decode(encoding))

    def flush(self):
        return self._guard(self._stream.flush)

    def _guard(self, method, *args):
        try:
            return method(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise OutputError(self._name, exc) from None

    def __getattr__(self, name):
        return getattr(self._stream, name)


class Missing:
    """A standard stream the process does not have (``>&-``, ``2>&-``: Python's ``sys.stdout`` or ``sys.stderr`` is
    ``None``): what is written to it goes nowhere, as the user asked (a run still writes its file and exits 0); a
    command whose product is its standard output (``mol-shell scenes``) refuses to run (:func:`missing_stdout`)."""

    missing = True

    def write(self, text):
        return len(text)

    def flush(self):
        return None

    def isatty(self):
        return False


def _absent(stream):
    """``True`` for a standard stream that is not there: ``None`` (Python found its descriptor closed), or one whose
    descriptor cannot be written at all (``EBADF``: closed since, or taken by a file opened for reading, as a launcher
    script such as pyenv's shim leaves a closed ``2>&-``). A stream without a descriptor (captured) is there."""
    if stream is None:
        return True
    try:
        os.write(stream.fileno(), b"")
    except OSError as exc:
        return exc.errno == errno.EBADF
    except (ValueError, AttributeError):  # io.UnsupportedOperation (a ValueError): a stream in memory
        return False
    return False


def missing_stdout():
    """``True`` while a command runs without a standard output (``>&-``: :class:`Missing`)."""
    return getattr(sys.stdout, "missing", False) is True


def guarded(command, *args, prog="mol-shell"):
    """``command(*args)`` with the command line's watch on Ctrl-C and SIGTERM, and its standard streams guarded: an
    output that cannot be written is one line, exit code 2 (:func:`_unwritable`). The studies' scripts run so too
    (:mod:`mol_shell.cli.scripts`).

    A Ctrl-C (or SIGTERM) that arrives at any point before the command returns ends it 130 (143) with one line saying
    what it kept (:func:`_interrupted_late`): also one that lands as the command returns, after its own handling (it
    escaped, or was noted as the watch was put back and the command exited 0 with its file written)."""
    streams = sys.stdout, sys.stderr
    present = tuple(Missing() if _absent(stream) else stream for stream in streams)  # a closed one: nowhere
    sys.stdout, sys.stderr = (_Guarded(stream, name) for stream, name in zip(present, ("standard output",
                                                                                         "standard error")))
    watch = None
    try:
        # Ctrl-C raises as usual, and is noted where a C call loses it; a SIGTERM (a scheduler's time limit) too
        with interrupts.watched(raising=True, terminating=True) as watch:
            code = command(*args)
    except OutputError as exc:
        return _unwritable(exc, prog, present)
    except KeyboardInterrupt as exc:  # landed after the command's own handling, as it returned
        code = _interrupted_late(exc, prog, present)
    else:
        if watch.caught and code not in (EXIT_INTERRUPTED, EXIT_TERMINATED):  # noted, not raised: as it returned
            code = _interrupted_late(KeyboardInterrupt(), prog, present)
    finally:
        sys.stdout, sys.stderr = streams
    return code


def _interrupted_late(exc, prog, streams):
    """:func:`said` of an interrupt that arrived as a command returned, on the command's own standard error."""
    sys.stdout, sys.stderr = streams
    return said(exc, prog=prog)


def said(exc, args=None, created=(), prog="mol-shell"):
    """The exit code of a command (or a study's script, ``prog``) that ``exc`` stopped, having said why in one line on
    stderr: bad input 2, a model limit 3, Ctrl-C 130 (SIGTERM 143), a reader gone 141, a bug 1 (its traceback with
    ``MOL_SHELL_TRACEBACK=1``). ``created``: directories made for ``-o``, removed again if the input is refused."""
    if isinstance(exc, BrokenPipeError):
        return _reader_gone()
    if isinstance(exc, ParameterError):
        remove_empty(created)
        print(f"{prog}: error: {said_as_typed(args, said_with_the_file(args, exc))}", file=sys.stderr)
        return EXIT_USAGE
    if isinstance(exc, KeyboardInterrupt):  # what was kept ("after writing run.nc": a write is never cut short)
        print(f"{prog}: {_interrupted()}{_kept(exc)}", file=sys.stderr)
        return interrupted_code()
    if isinstance(exc, NoSpaceError):  # a full disk: not a bug, and nothing half-written (mol_shell._core.atomic.staged)
        remove_empty(created)
        print(f"{prog}: error: {_no_space(args, exc)}", file=sys.stderr)
        return EXIT_USAGE
    if isinstance(exc, ModelLimitError):  # a run a command needs stopped at a limit (compare's reference)
        print(f"{prog}: stopped: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    if isinstance(exc, OutputError):  # said by main, once the streams are the command's own again
        raise exc
    if by_interrupt(exc):  # a Ctrl-C that arrived inside a C extension's call
        print(f"{prog}: {_interrupted()}{_kept(KeyboardInterrupt())}", file=sys.stderr)
        return interrupted_code()
    if traceback_asked(refuse=False):
        raise exc
    text = " ".join(str(exc).split())[:300]
    print(f"{prog}: internal error: {type(exc).__name__}: {text} (a bug of mol_shell: please report it with "
          "the command; MOL_SHELL_TRACEBACK=1 shows where it happened)", file=sys.stderr)
    return EXIT_INTERNAL


#: the parameters a command's option of the same name sets whose refusals, found past the option's own check, named
#: the parameter (``t_end = 1e-300``, ``n = 99999999999``, ``max_step = 1e-300``, ``count = 41``)
TYPED_NAMES = frozenset({"t_end", "n", "max_step", "count"})


def said_as_typed(args, exc):
    """``exc`` naming the option the command line set its value with where it names the Python parameter (``t_end =
    1e-300 is outside ...``, after ``--t-end = 0 is outside ...``; ``n``, ``max_step``, ``count``): the options given
    are in ``args._given`` (:class:`~mol_shell.cli.args.Once`), each by its ``dest``."""
    given = getattr(args, "_given", None) or {}
    text = str(exc)
    if not (exc.name in TYPED_NAMES and exc.name in given and text.startswith(f"{exc.name} = ")):
        return exc
    option = given[exc.name][0]
    if not (isinstance(option, str) and option.startswith("-")):
        return exc
    return ParameterError(option, exc.value, exc.range or exc.allowed, message=option + text[len(exc.name):])


#: the environment variable that asks for a bug's traceback, and the values it takes
TRACEBACK_VARIABLE = "MOL_SHELL_TRACEBACK"
_OFF, _ON = ("", "0", "false", "no", "off"), ("1", "true", "yes", "on")


def traceback_asked(refuse=True):
    """Whether ``MOL_SHELL_TRACEBACK`` asks for a bug's traceback: ``1``, ``true``, ``yes``, ``on`` (any case) do;
    unset, empty, ``0``, ``false``, ``no``, ``off`` do not (``0`` asked for one: any value that was not empty did).
    Another value is refused (:class:`ParameterError`, as a command starts), or with ``refuse=False`` read as off."""
    text = os.environ.get(TRACEBACK_VARIABLE, "").strip().lower()
    if text in _OFF or text in _ON:
        return text in _ON
    if refuse:
        raise ParameterError.invalid(TRACEBACK_VARIABLE, os.environ[TRACEBACK_VARIABLE], "is not a switch",
                                     "1, true, yes or on (a bug's traceback); 0, false, no, off or empty (one line)")
    return False


def _interrupted():
    """What stopped a command: ``interrupted`` (Ctrl-C), or ``terminated (SIGTERM)``."""
    return "terminated (SIGTERM)" if interrupts.terminated() else "interrupted"


def _kept(exc):
    """`` after writing a.nc``: what a command that ``exc`` (a ``KeyboardInterrupt``) stopped kept, the files it had
    written whole (:func:`mol_shell._core.interrupts.kept_files`; else the interrupt's own text), ``""`` for none."""
    text = interrupts.kept_files() or str(exc)
    return f" {text}" if text else ""


def _no_space(args, exc):
    """A write that failed for want of space (:class:`~mol_shell._core.atomic.NoSpaceError`), in one line naming
    ``-o``: the output itself, or the file written for it (a figure beside it, a study's case)."""
    output = getattr(args, "output", None)
    if output is None:
        return f"cannot write {show(str(exc.filename))}: {exc.strerror}"
    if os.path.abspath(os.path.expanduser(str(output))) == os.path.abspath(str(exc.filename)):
        return f"-o = {show(str(output))} cannot be written: {exc.strerror}"
    return f"-o = {show(str(output))}: cannot write {show(str(exc.filename))} for it: {exc.strerror}"


def _reader_gone():
    """The reader of stdout has gone (``mol-shell scenes | head -1``): exit quietly, as command-line tools do."""
    _to_devnull(sys.stdout)
    return EXIT_PIPE


def _unwritable(exc, prog="mol-shell", streams=None):
    """Standard output or error could not be written (``> /dev/full``): one line on stderr, when that is not the
    stream that failed, and exit code 2, as for an ``-o`` that cannot be written (``streams``: the command's own
    ``stdout, stderr``, put back first)."""
    if streams is not None:
        sys.stdout, sys.stderr = streams
    if exc.stream == "standard error":
        _to_devnull(sys.stderr)
        return EXIT_USAGE
    _to_devnull(sys.stdout)
    try:
        print(f"{prog}: error: {exc}", file=sys.stderr)
    except OSError:  # stderr too: nowhere to say it
        _to_devnull(sys.stderr)
    return EXIT_USAGE


def _to_devnull(stream):
    """Point ``stream``'s file descriptor at /dev/null, so the interpreter's own flush at exit, of what the stream
    still holds, finds nowhere to fail."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())
    except (OSError, ValueError, AttributeError):  # a stream without a file descriptor (captured): nothing to flush
        pass


#: the warnings said by this command: each once (a stability report's twenty runs of one law warned twenty times)
_SAID = set()


def one_line_warnings(prog="mol-shell"):
    """Within a ``warnings.catch_warnings()`` block: the package's warnings (:class:`~mol_shell.MolShellWarning`: a
    run's projected time, the material, the scene, an unstable start, grid modes, ...) said in one line each, as errors
    are, ``prog: warning: ...`` on stderr, each once per command (or script), whatever ``python -W`` asks (``-W
    error`` made them errors that ended the command and lost its result). A missing stderr (``2>&-``): nothing said."""
    warnings.simplefilter("always", MolShellWarning)
    _SAID.clear()  # once per command (tests call main many times in one process)

    def one_line(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())  # one line, whatever the warning's author wrapped
        if text not in _SAID and sys.stderr is not None:
            _SAID.add(text)
            print(f"{prog}: warning: {text}", file=sys.stderr)

    warnings.showwarning = one_line


def said_in_teardown(code, prog="mol-shell"):
    """After a command that returned ``code`` (its output written and said), until the process exits: a Ctrl-C or
    SIGTERM in the interpreter's own teardown (about a second after a large run) ended it 130 with nothing said, or 0.
    Now one line saying what the command kept, and exit 130 (143), at once (what is left of the teardown frees
    memory only: the files are closed and the streams flushed). A command that an interrupt already ended exits
    with its code, quietly. Only for a process that is the command (:func:`mol_shell.cli.main.entry`): tests call
    :func:`mol_shell.cli.main.main` in their own process."""

    def late(signum, frame):
        stopped = EXIT_TERMINATED if signum == signal.SIGTERM else EXIT_INTERRUPTED
        if code not in (EXIT_INTERRUPTED, EXIT_TERMINATED):
            with contextlib.suppress(Exception):
                sys.stdout.flush()
            kept = interrupts.kept_files()
            what = "terminated (SIGTERM)" if stopped == EXIT_TERMINATED else "interrupted"
            with contextlib.suppress(OSError):
                os.write(2, f"{prog}: {what}{' ' + kept if kept else ''}\n".encode(errors="backslashreplace"))
        os._exit(code if code in (EXIT_INTERRUPTED, EXIT_TERMINATED) else stopped)

    for signum in (signal.SIGINT, signal.SIGTERM):
        with contextlib.suppress(ValueError, OSError):  # not the main thread: nothing to put in place
            signal.signal(signum, late)
    return code


def exits_after_its_exit_functions(code):
    """End the process that is the command, ``code`` its exit status, as soon as the interpreter has joined its threads
    and called its exit functions (:mod:`atexit`: multiprocessing's, logging's), where its teardown (0.5 s after a
    run: modules and arrays freed) would follow. That teardown first puts SIGINT's and SIGTERM's default actions back:
    a Ctrl-C or SIGTERM in it killed the process (-2, -15) with nothing said, however the command ended, after
    ``wrote ...`` too. Without it the handlers of :func:`said_in_teardown` are in place until the process exits.
    What the teardown did besides is done already or not needed: the command's files are written and closed, the
    standard streams are flushed here, the memory goes with the process. Only for a process that is the command
    (:func:`mol_shell.cli.main.entry`); returns ``code``, for ``sys.exit``, which then ends as usual up to here."""
    if code is not None and not isinstance(code, int):  # an argparse message (never, but Python would print it)
        return code

    def at_once():
        atexit.unregister(at_once)  # registered last, called first: the others, in their order, then the exit
        atexit._run_exitfuncs()  # Python's own call of them (private, in CPython since 3.0), as its exit makes it
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):  # a reader gone, a closed stream: nothing more to say anyway
                stream.flush()
        os._exit(code or 0)

    atexit.register(at_once)
    return code

