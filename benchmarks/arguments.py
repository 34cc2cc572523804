"""What the benchmarks' command lines share: a parser whose refusal is one line, and the ranged number types.

A script in benchmarks/ imports it as ``from arguments import ...`` (benchmarks/ is the script's folder, first on
``sys.path``). It imports nothing of mol_shell: the scripts that compare two trees measure each in its own process,
and must not depend on whichever mol_shell the interpreter finds. The messages read as the command line's
(``mol-shell: error: --n = 2 is outside integers >= 3``): ``benchmarks/leapfrog_paper.py: error: --repeats = 0 is
outside integers >= 1``, exit code 2, before anything is built or run. Without them ``--repeats 0`` ended in
``StatisticsError: no median for empty data`` (after the runs), ``--n 2`` in the child's traceback.
"""

import argparse
import math
import re
import sys
from pathlib import Path

#: the smallest grid a run takes (mol_shell's own bound, ``n = 2 is outside integers >= 3``)
MIN_NODES = 3


class Parser(argparse.ArgumentParser):
    """argparse's parser whose refusals are one line, ``benchmarks/SCRIPT.py: error: ...``, exit code 2."""

    def __init__(self, description=None, **kwargs):
        kwargs.setdefault("prog", f"benchmarks/{Path(sys.argv[0]).name}")
        kwargs.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(description=description, **kwargs)

    def error(self, message):
        # "argument --n: --n = 2 is outside ..." names the option twice: keep the type's own message
        found = re.match(r"argument (\S+?): (.*)", message, flags=re.DOTALL)
        if found and any(found.group(2).startswith(opt + " ") for opt in found.group(1).split("/")):
            message = found.group(2)
        self.exit(2, f"{self.prog}: error: {' '.join(message.split())}\n")


def integer(name, low):
    """An argparse ``type``: an integer ``>= low``, else a one-line refusal naming ``name`` and the range."""
    allowed = f"integers >= {low}"

    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is not an integer; allowed: {allowed}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{name} = {value} is outside {allowed}")
        return value

    return convert


def positive(name, unit=""):
    """An argparse ``type``: a finite number ``> 0``, else a one-line refusal naming ``name`` and the range."""
    allowed = "(0, inf)" + (f" {unit}" if unit else "")

    def convert(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is not a number; allowed: {allowed}") from None
        if not (math.isfinite(value) and value > 0):
            raise argparse.ArgumentTypeError(f"{name} = {text} is outside {allowed}")
        return value

    return convert
