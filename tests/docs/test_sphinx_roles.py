"""The API reference rendered the docstrings' Sphinx roles as text (``:func:`` and a code span, ~1,160 of them, none a
link): docs/_hooks/sphinx_roles.py, a griffe extension of mkdocs.yml, makes each an optional autorefs reference
(a link where the object is on a page of the site, else its title as code) or, naming nothing known, code."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
griffe = pytest.importorskip("griffe")
_spec = importlib.util.spec_from_file_location("sphinx_roles", ROOT / "docs" / "_hooks" / "sphinx_roles.py")
roles = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(roles)

KNOWN = {"mol_shell.runs.simulate.simulate", "mol_shell.SCENES", "mol_shell.runs.simulate.DEFAULT_DT"}


def _resolve(name):
    """A scope where ``DEFAULT_DT`` is ``mol_shell.runs.simulate``'s and the full paths of :data:`KNOWN` exist."""
    name = {"DEFAULT_DT": "mol_shell.runs.simulate.DEFAULT_DT"}.get(name, name)
    return name if name in KNOWN else None


def ref(path, title):
    return f'<autoref identifier="{path}" optional>`{title}`</autoref>'


@pytest.mark.parametrize(("text", "expected"), [
    (":func:`~mol_shell.runs.simulate.simulate`", ref("mol_shell.runs.simulate.simulate", "simulate")),
    ("any of :data:`mol_shell.SCENES`' classes", f"any of {ref('mol_shell.SCENES', 'mol_shell.SCENES')}' classes"),
    ("default :data:`DEFAULT_DT` (1e-6)", f"default {ref('mol_shell.runs.simulate.DEFAULT_DT', 'DEFAULT_DT')} (1e-6)"),
    (":func:`run <mol_shell.runs.simulate.simulate>`", ref("mol_shell.runs.simulate.simulate", "run")),
    # a role broken over lines
    (":func:`~mol_shell.runs.\n    simulate.simulate`", ref("mol_shell.runs.simulate.simulate", "simulate")),
    (":class:`xarray.Dataset` and :meth:`~a.b.gone`", "`xarray.Dataset` and `gone`"),  # unresolvable: code
    ("``:func:`simulate``` and `x`:y: and :math:`x`", "``:func:`simulate``` and `x`:y: and :math:`x`"),  # untouched
])
def test_a_role_becomes_a_reference_or_code(text, expected):
    assert roles.rewrite(text, _resolve) == expected


def test_the_extension_resolves_names_in_each_docstrings_scope():
    modules = {
        "__init__.py": '"""The package: :func:`~pkg.mod.run` and :func:`pkg.nothing`."""\nfrom pkg.mod import run\n',
        "mod.py": ('LIMIT = 1\n"""A limit."""\n\n\ndef run():\n    """Runs to :data:`LIMIT`, as :class:`Box.size` and '
                   ':func:`unknown` say."""\n\n\nclass Box:\n    size = 2\n'),
    }
    extensions = griffe.load_extensions(roles.SphinxRoles())
    with griffe.temporary_visited_package("pkg", modules, extensions=extensions) as pkg:
        assert pkg.docstring.value == f"The package: {ref('pkg.mod.run', 'run')} and `pkg.nothing`."
        assert pkg["mod.run"].docstring.value == (f"Runs to {ref('pkg.mod.LIMIT', 'LIMIT')}, as "
                                                  f"{ref('pkg.mod.Box.size', 'Box.size')} and `unknown` say.")
