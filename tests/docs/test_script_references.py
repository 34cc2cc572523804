"""Every dotted ``mol_shell.x.y`` name that the scripts of studies/ and benchmarks/ mention (docstrings, comments,
imports, probe code) resolves: a module, or an attribute of one.

studies/*.py headers named mol_shell.stability.default_cases, mol_shell.study_data.grid_mode,
mol_shell.unshearable.Unshearable, mol_shell.ring and mol_shell.workprecision, none of which exists (the
modules had moved); a reader following them got an ImportError. Names are only imported, no script is run.
"""

import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted([*(ROOT / "studies").glob("*.py"), *(ROOT / "benchmarks").glob("*.py")])
DOTTED = re.compile(r"(?<![\w.])mol_shell(?:\.[A-Za-z_]\w*)+")


def resolves(dotted):
    """Whether ``dotted`` is a module, or an attribute (at any depth) of the longest module it starts with."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        name = ".".join(parts[:cut])
        try:
            obj = importlib.import_module(name)
        except ModuleNotFoundError as error:
            if error.name is None or not (name == error.name or name.startswith(error.name + ".")):
                raise  # the module exists but needs another that is missing: not this test's business to hide
            continue
        try:
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return False
        return True
    return False


def test_the_scripts_are_found():
    assert {p.parent.name for p in SCRIPTS} == {"studies", "benchmarks"} and len(SCRIPTS) > 10


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_mol_shell_name_a_script_mentions_resolves(script):
    names = sorted(set(DOTTED.findall(script.read_text())))
    missing = [name for name in names if not resolves(name)]
    assert not missing, f"{script.parent.name}/{script.name} names {missing}, which do not resolve"
