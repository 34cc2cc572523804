"""Scenes: frozen dataclasses holding every physical parameter of a run, and their registry.

Vary a scene with :func:`dataclasses.replace` (or :func:`with_params` from strings, as the CLI
does); a bad value raises :class:`~mol_shell._core.errors.ParameterError` naming the parameter and its
allowed range.
"""

from __future__ import annotations

from mol_shell._core.errors import ParameterError
from mol_shell.scenes.base import (
    DESCRIPTIONS,
    DISPLACEMENTS,
    DRIVES,
    LOADS,
    N_QUAD_RANGE,
    UNITS,
    ShellScene,
    _check,
    describe,
    zeta1_used,
)
from mol_shell.scenes.cylinder import Axisymmetric, CylinderScene, SpinningRing, TwistedCylinder, check_radius
from mol_shell.scenes.segments import Vessel
from mol_shell.scenes.setting import _coerce, with_params
from mol_shell.scenes.shells import Cone, MeridianShell, Sphere, Torus
from mol_shell.scenes.unshearable import UNSHEARABLE_INTEGRATORS, Unshearable

SCENES = {cls.name: cls for cls in (TwistedCylinder, SpinningRing, Axisymmetric, Sphere, Cone, Torus, MeridianShell,
                                  Unshearable, Vessel)}
"""The registered scenes: name -> scene class (a frozen dataclass of the scene's parameters).
``list(mol_shell.SCENES)`` gives the names (``mol-shell scenes`` lists them, ``mol-shell scenes NAME`` one's
parameters with units and defaults); ``mol_shell.SCENES["sphere"](E=2e6)`` or ``mol_shell.get_scene("sphere",
E=2e6)`` makes one, and :func:`mol_shell.simulate` takes a name for the scene with its defaults."""


def get_scene(name, **params):
    """The scene registered as ``name`` with parameters replaced by ``params``: all of them at once, checked together
    (the ``meridian`` scene's ``points`` was read first, with the default ``h``, and a file that only the given ``h``
    fits was refused)."""
    if not isinstance(name, str) or name not in SCENES:  # (a list is not even hashable)
        raise ParameterError("scene", name, "{" + ", ".join(sorted(SCENES)) + "}")
    return with_params(SCENES[name](), params)


#: the longest summary of a scene in ``mol-shell scenes`` (beyond it, cut at a clause, parentheses kept whole)
SUMMARY_WIDTH = 100


def _plain(text):
    """Docstring text for a terminal: one line, without the double backticks of reStructuredText literals."""
    return " ".join(text.replace("``", "").split())


def _depth_zero(text, marks):
    """Indices ``i`` where ``text[i:]`` starts with one of ``marks`` outside every parenthesis."""
    depth, found = 0, []
    for i, char in enumerate(text):
        depth += (char == "(") - (char == ")")
        if depth == 0 and any(text.startswith(mark, i) for mark in marks):
            found.append(i)
    return found


def _drop_parentheses(text):
    """``text`` without its outermost parenthesised remarks (and the space before each)."""
    out, depth = [], 0
    for char in text:
        depth += char == "("
        if depth == 0:
            out.append(char)
        depth -= char == ")" and depth > 0
    return " ".join("".join(out).replace(" ,", ",").replace(" ;", ";").split())


def description(cls):
    """What a scene is: the first paragraph of its docstring, in one line without reStructuredText markup."""
    return _plain((cls.__doc__ or "").strip().split("\n\n")[0])


def summary(cls, width=SUMMARY_WIDTH):
    """What a scene is in one line of at most about ``width`` characters, for ``mol-shell scenes``: the first
    sentence of its docstring without markup; a longer one loses its parenthesised remarks, and then its last
    clauses (cut at a comma or semicolon outside parentheses, ``...`` said), never a parenthesis in its middle."""
    text = description(cls)
    ends = [i for i in _depth_zero(text, (". ",)) if i + 2 < len(text) and text[i + 2].isupper()]
    sentence = text[: ends[0] + 1] if ends else text
    if len(sentence) <= width:
        return sentence
    sentence = _drop_parentheses(sentence)
    if len(sentence) <= width:
        return sentence
    cuts = [i for i in _depth_zero(sentence, (", ", "; ")) if i <= width - 4]
    return sentence[: cuts[-1]] + " ..." if cuts else sentence


__all__ = [
    "DESCRIPTIONS", "DISPLACEMENTS", "DRIVES", "LOADS", "N_QUAD_RANGE", "SCENES", "UNITS", "Axisymmetric", "Cone", "CylinderScene", "MeridianShell",
    "ShellScene", "SpinningRing", "Sphere", "Torus", "TwistedCylinder", "UNSHEARABLE_INTEGRATORS", "Unshearable", "Vessel", "check_radius", "describe", "description", "get_scene", "summary", "with_params",
    "zeta1_used", "_check", "_coerce",
]
