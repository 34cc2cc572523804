"""Scene parameters set by name: from strings (``--set NAME=VALUE``, scene files, studies), unknown names refused."""

from __future__ import annotations

import dataclasses

from mol_shell._core.errors import UnknownParameterError
from mol_shell._core.ranges import Choice
from mol_shell.model.edges import EDGE_PARAMETERS
from mol_shell.model.laws import parameter_values
from mol_shell.scenes.base import DRIVES, LOADS


def with_params(scene, params):
    """``dataclasses.replace`` that accepts strings (as from ``--set NAME=VALUE``) and names unknown parameters."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    changes = {}
    # a law of one's own: material_parameters given replaces the scene's, and each material.NAME sets one
    # parameter on top of that, whatever their order (either one was dropped when both were given)
    given = params.get("material_parameters") if "material_parameters" in fields else None
    own = parameter_values((getattr(scene, "material_parameters", "") if given is None else given) or "")
    for name, value in params.items():
        if name.startswith("material.") and "material_parameters" in fields:  # one parameter of a law of one's own
            own[name.removeprefix("material.")] = value
            changes["material_parameters"] = own
            continue
        if name == "material_parameters" and name in fields:
            changes.setdefault(name, own)
            continue
        if name not in fields:
            raise UnknownParameterError("parameter", name, Choice(tuple(fields)), hint=f"for scene {scene.name}")
        changes[name] = _coerce(name, value, fields[name].type)
    return dataclasses.replace(scene, **changes)


def _coerce(name, value, annotation):
    """A string from the command line as the field wants it; what does not convert is passed on unchanged,
    so the scene's own check names the parameter and its allowed range."""
    if not isinstance(value, str) or annotation in (str, "str", bool, "bool"):  # a flag: true/false as typed
        return value
    text = value.strip()
    if (text.lower() == "auto" or text.lower() == "none" and name not in EDGE_PARAMETERS) and "None" in str(annotation):
        return None
    try:
        number = float(text)
    except ValueError:
        return value
    if "int" in str(annotation) and number.is_integer():
        return int(number)
    return number


def unused_histories(scene):
    """One line for each load or drive of ``scene`` whose ``NAME_history`` is set (not constant) while ``NAME`` is 0:
    the history then multiplies nothing (a load meant for it mistyped, say)."""
    out = []
    for name in LOADS + DRIVES:
        history = getattr(scene, f"{name}_history", "constant")
        if isinstance(history, str) and history.strip() != "constant" and getattr(scene, name, 0.0) == 0:
            out.append(f"{name}_history = {history!r} is unused: {name} = 0; set {name} to the magnitude the history "
                       "multiplies")
    return out


__all__ = ["unused_histories", "with_params"]
