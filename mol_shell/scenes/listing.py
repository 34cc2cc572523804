"""A scene's parameters as ``mol-shell scenes NAME`` lists them: its description, a table of every parameter with its
default, units and what it is (with the choices its check declares), and what ``auto`` and ``''`` stand for."""

from __future__ import annotations

import dataclasses
import textwrap

from mol_shell._core.ranges import Choice
from mol_shell.scenes import description
from mol_shell.scenes.descriptions import BEYOND_CHOICES, UNITS, default_meaning, describe, is_numeric
from mol_shell.scenes.ranges import parameter_range

#: the width the description and the notes are wrapped to
WIDTH = 118


def shown_default(field):
    """A field's default as listed: ``auto`` for None, ``''`` for the empty string."""
    default = field.default if field.default is not dataclasses.MISSING else "(required)"
    return "auto" if default is None else "''" if default == "" else str(default)


def shown_units(field):
    """The units column: a number's CF units (``1``: dimensionless); ``-`` for a parameter that is no number (a name,
    a flag, a history, a file) unless its text is in units (``h_profile``, m)."""
    units = UNITS.get(field.name, "1")
    return units if is_numeric(field) or units != "1" else "-"


def what_it_is(scene, field):
    """What a parameter is, and for one that is no number the choices its check declares (``end1``: the edge kinds;
    ``material``: the laws; a flag: true or false)."""
    text = describe(field.name, scene).replace("``", "")
    allowed = None if is_numeric(field) or field.name.endswith("_history") else parameter_range(scene, field.name)
    if isinstance(allowed, Choice):
        beyond = BEYOND_CHOICES.get(field.name)
        text += f"; one of {allowed.text()}" + (f", {beyond}" if beyond else "")
    return text


def defaults_note(scene):
    """What ``auto`` and ``''`` stand for in this scene, parameter by parameter (the lines under the table)."""
    groups = {}
    for f in dataclasses.fields(scene):
        meaning = default_meaning(f.name, scene)
        if not meaning:
            continue
        shown = "''" if f.default == "" else "auto"
        if f.default in (None, "") or "None" in str(f.type):
            groups.setdefault((shown, meaning), []).append(f.name)
    parts = [f"{', '.join(names)} = {shown}: {meaning}" for (shown, meaning), names in groups.items()]
    text = "auto: left to the code, computed from the other parameters; '': nothing given. Here " + "; ".join(parts)
    return textwrap.wrap(text + ".", WIDTH, initial_indent="  ", subsequent_indent="    ", break_on_hyphens=False)


def parameter_listing(cls):
    """The lines of ``mol-shell scenes NAME`` for the scene class ``cls``."""
    scene = cls()
    head = textwrap.wrap(f"{cls.name}: {description(cls)}", WIDTH, subsequent_indent="  ", break_on_hyphens=False)
    rows = [("parameter", "default", "units", "what it is")]
    rows += [(f.name, shown_default(f), shown_units(f), what_it_is(scene, f)) for f in dataclasses.fields(cls)]
    widths = [max(len(row[k]) for row in rows) for k in range(3)]  # from the content: every column lines up
    table = [f"  {name:<{widths[0]}}  {default:>{widths[1]}}  {units:<{widths[2]}}  {text}".rstrip()
             for name, default, units, text in rows]
    return [*head, *table, "", *defaults_note(scene)]


__all__ = ["WIDTH", "defaults_note", "parameter_listing", "shown_default", "shown_units", "what_it_is"]
