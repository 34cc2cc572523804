"""The entry of the scripts in ``studies/``: the command line's rules for their options and for how they end.

Every script's ``if __name__ == "__main__":`` is ``run_script(main)``, and its ``main`` parses its options with
:func:`script_parser` and the ranged types (:func:`~mol_shell.cli.args.number_arg`,
:func:`~mol_shell.cli.args.integer_arg`, :func:`integers_arg`). So a script ends as a ``mol-shell`` command does
(:func:`mol_shell.cli.outcome.said`): bad input (an option out of its range, a
:class:`~mol_shell._core.errors.ParameterError`, a study whose every case was refused) is one line naming the option
and its range, exit code 2; a run stopped at a model limit 3; Ctrl-C 130 (SIGTERM 143), what was saved kept (a
study's finished cases); an output folder that cannot be made (:func:`output_folder`) one line naming ``--out``.
Never a traceback, unless ``MOL_SHELL_TRACEBACK=1`` asks for a bug's.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from pathlib import Path

from mol_shell._core import interrupts
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import writable_path
from mol_shell.cli.args import Parser, as_stopped, integer_arg, interrupted_code
from mol_shell.cli.main import negative_values_attached
from mol_shell.cli.outcome import (
    exits_after_its_exit_functions,
    guarded,
    one_line_warnings,
    said,
    said_in_teardown,
    traceback_asked,
)
from mol_shell.runs.simulate import simulate as run_simulate
from mol_shell.runs.unshearable import simulate_unshearable as run_unshearable

#: the smallest grid a run takes (``n = 2 is outside integers >= 3``)
MIN_NODES = 3


def script_name():
    """The running script's file name (``twist_amplitude.py``), which its messages begin with."""
    return Path(sys.argv[0]).name or "study"


def script_parser(doc, prog=None):
    """An argparse parser with the command line's rules (:class:`~mol_shell.cli.args.Parser`: options spelt in full,
    given once, a refusal in one line, exit code 2) whose messages begin with the script's name; ``doc``, the
    script's docstring, is its help."""
    parser = Parser(prog=prog or script_name(), description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.said_as = parser.prog
    return parser


def integers_arg(name, low=MIN_NODES):
    """An argparse ``type``: comma-separated integers ``>= low`` (``--grids 40,160``), as a list."""
    one = integer_arg(name, low)

    def convert(text):
        return [one(item.strip()) for item in str(text).split(",")]

    return convert


def output_folder(path, name="--out"):
    """``path``, a folder the script writes into, made if missing; one that cannot be made or written is a
    :class:`ParameterError` naming ``name``, before anything is computed."""
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        raise ParameterError.invalid(name, str(path), f"cannot be made a folder: {exc.strerror or exc}",
                                     "a folder that exists or can be made, and can be written") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise ParameterError.invalid(name, str(path), "cannot be written", "a folder that can be written")
    return path


def output_file(path, name="--output", suffixes=("nc",)):
    """``path``, a file the script writes, checked as ``-o`` is (:func:`~mol_shell._core.paths.writable_path`), as
    given (``~`` expanded): a symbolic link stays one, written through, and the files the script writes beside it
    (its ``.md``, ``.png``) go beside the link (:func:`~mol_shell._core.paths.beside`), as the command line's do."""
    writable_path(path, name, suffixes=set(suffixes))
    return str(Path(os.fspath(path)).expanduser())


class Stopped(KeyboardInterrupt):
    """A run (or report) of a script that Ctrl-C or SIGTERM stopped, its Dataset ``ds`` kept as it is: the script
    ends 130 (143) with one line, ``what`` stopped, the run's own message (``interrupted by the user at t = ...``),
    ``note`` (what the script left out for it) and the files written."""

    def __init__(self, ds, what="run", note=""):
        super().__init__(ds.attrs.get("message") or "interrupted by the user")
        self.ds, self.what, self.note = ds, what, note

    def line(self, prog):
        kept = interrupts.kept_files().replace("after writing", "wrote", 1) or "nothing written"
        note = f"; {self.note}" if self.note else ""
        return f"{prog}: {self.what} stopped: {as_stopped(str(self))}{note}; {kept}"


def finished(ds, what="run"):
    """``ds``, a run's or a report's Dataset, if it ran to its end; :class:`Stopped` where an interrupt stopped it
    (``attrs["status"] == "interrupted"``). Other ends (a model limit) are the script's to read."""
    if ds.attrs.get("status") == "interrupted":
        raise Stopped(ds, what)
    return ds


def simulate(*args, **kwargs):
    """``mol_shell.simulate`` for a script: its run, :func:`finished` (a Ctrl-C stops the script, exit 130)."""
    return finished(run_simulate(*args, **kwargs))


def simulate_unshearable(*args, **kwargs):
    """``mol_shell.runs.unshearable.simulate_unshearable`` for a script, as :func:`simulate` (it too returns a run a
    Ctrl-C stopped as data: ``unshearable_vs_free.py`` compared it and went on)."""
    return finished(run_unshearable(*args, **kwargs))


def exit_code(main, argv=None, prog=None):
    """Run a script's ``main(argv)`` and return its exit code, having said in one line why it ended short."""
    prog = prog or script_name()
    os.environ.setdefault("MPLBACKEND", "Agg")  # the scripts draw into files only
    argv = negative_values_attached(sys.argv[1:] if argv is None else list(argv))  # --dt -1e-6 reaches its check
    return guarded(_run, main, argv, prog, prog=prog)


def _run(main, argv, prog):
    try:
        with warnings.catch_warnings():
            one_line_warnings(prog)  # a study's cases warn once each, in one line, as the command line does
            # a run a Ctrl-C stopped: said once, as the script stops (Stopped), not also as the run's warning
            warnings.filterwarnings("ignore", "run incomplete: interrupted by the user", RuntimeWarning)
            traceback_asked()  # a value it does not take: refused in one line
            main(argv)
        sys.stdout.flush()
    except SystemExit as exc:  # the parser's refusal (2, said in one line), --help (0)
        return exc.code
    except Stopped as exc:  # a run kept as data: what stopped it and what was written
        print(exc.line(prog), file=sys.stderr)
        return interrupted_code()
    except (Exception, KeyboardInterrupt) as exc:  # noqa: BLE001 - said in one line (a bug too), never a traceback
        return said(exc, prog=prog)
    return 0


def run_script(main):
    """The ``if __name__ == "__main__":`` of a study's script: :func:`exit_code` of ``main`` as the process's, ended
    as the ``mol-shell`` program ends (:func:`mol_shell.cli.main.entry`): a Ctrl-C or SIGTERM after ``main`` returned
    is said in one line, exit 130 (143) (:func:`~mol_shell.cli.outcome.said_in_teardown`), and the process exits once
    Python has called its exit functions, without the teardown in which such a signal killed it (-2, -15, nothing
    said: :func:`~mol_shell.cli.outcome.exits_after_its_exit_functions`)."""
    sys.exit(exits_after_its_exit_functions(said_in_teardown(exit_code(main), prog=script_name())))
