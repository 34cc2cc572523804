"""What the benchmarks that compare this tree with a baseline tree share: the check of ``--baseline``.

A script in benchmarks/ imports it as ``from baselines import ...`` (benchmarks/ is the script's folder, first on
``sys.path``). Without the check a path that is no checkout of mol_shell ends in a traceback from the first probe,
or worse, lets the probe import whatever mol_shell the interpreter finds and report a ratio of this tree to itself.
"""

import sys
from pathlib import Path


def is_checkout(path):
    """Whether ``path`` is a checkout of mol_shell: a folder holding the package ``mol_shell``."""
    return (Path(path) / "mol_shell" / "__init__.py").is_file()


def refuse_baseline(script, path):
    """``True`` after one line on stderr naming ``script`` and ``path`` unless ``path`` is a checkout of
    mol_shell (then ``False``, silently); the caller exits with code 2."""
    if is_checkout(path):
        return False
    print(f"{script}: --baseline {str(path)!r}: not a checkout of mol_shell (no mol_shell/__init__.py there)",
          file=sys.stderr)
    return True
