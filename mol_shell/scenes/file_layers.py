"""A scene file's ``[[layer]]`` tables: their keys checked, and the refusal of their thicknesses against the wall
said by the tables as written (``[[layer]]``, not the ``layers`` text made of them), or by the ``--set h`` that made
them disagree."""

from __future__ import annotations

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.model.layers import LAYER_KEYS
from mol_shell.scenes.base import LAYERS_RTOL
from mol_shell.scenes.file_values import toml_spelled, toml_value

#: the start of the hint of the scene's refusal of layers that do not add up to the wall (ShellScene._check_layers)
SUM_HINT = "they add up to "


def layer_tables(source, layers, flags):
    """``[[layer]]`` tables as given, their keys known, ``material`` a string and their true/false keys (``flags``)
    TOML booleans, each refused naming the table (``[[layer]] N``, from the lower face); the values: the scene's
    check."""
    for number, layer in enumerate(layers if isinstance(layers, list) else (), start=1):
        where = f"{source}: [[layer]] {number} (from the lower face): "
        for key, value in (layer.items() if isinstance(layer, dict) else ()):
            if key not in ("thickness", "material", *LAYER_KEYS):
                own = (" (a law of one's own takes the parameters of its Material in a layer, not the file's)"
                       if key == "material_parameters" else "")
                raise ParameterError(key, value, "", message=f"{where}unknown key {key}; allowed: thickness, "
                                     f"material, {', '.join(LAYER_KEYS)}{own}")
            try:
                if key == "material" and not isinstance(value, str):
                    raise ParameterError.not_a("material", value, "a string", "a law's name or import path")
                if key in flags and not isinstance(value, bool):
                    raise ParameterError.not_a(key, value, "a TOML boolean", "{true, false}")
            except ParameterError as exc:
                raise ParameterError(exc.name, exc.value, exc.range or exc.allowed,
                                     message=where + toml_spelled(exc)) from None
    return layers


def layer_sum_refusal(exc, source, tables, h, overrides, h_table):
    """The scene's refusal ``exc`` of a layered wall whose thicknesses do not add up to ``2h``, said by what the user
    wrote, or ``None`` where ``exc`` is another refusal or the layers are not the file's ``[[layer]]`` tables nor ``h``
    the command line's: ``--set h = 0.011`` (in ``overrides``) where it made the file's layers disagree, else the
    ``[[layer]]`` tables (``tables``, as parsed) and the file's ``h`` (in table ``h_table``, None: the scene's
    default) they disagree with."""
    if exc.name != "layers" or not str(exc.hint or "").startswith(SUM_HINT) or "layers" in overrides:
        return None
    total = str(exc.hint)[len(SUM_HINT):]
    written = [t.get("thickness") for t in tables if isinstance(t, dict)] if isinstance(tables, list) else []
    parts = " + ".join(toml_value(t) if is_number(t) else str(t) for t in written)
    what = f"[[layer]] thicknesses {parts} = {total}" if tables is not None and parts else f"layers adding up to {total}"
    tolerance = f"to {LAYERS_RTOL:g} of it"
    if "h" in overrides:  # as typed (--set's text) or as given (a number)
        try:
            typed, h = h, float(h)
        except (TypeError, ValueError):  # refused by the scene as h
            return None
        return ParameterError("h", typed, f"h = half the layers' sum, {tolerance}", message=(
            f"--set h = {typed} makes the wall 2h = {2 * h:.10g} m, which {source}'s {what} do not add up to; allowed: h "
            f"= half their sum, {tolerance} (or layers adding up to 2h)"))
    if tables is None:
        return None
    h_said = f"[{h_table}] h = {h!r}" if h_table else f"the scene's default h = {h!r}"
    return ParameterError("layers", exc.value, exc.range or exc.allowed, message=(
        f"{source}: {what}; allowed: thicknesses adding up to the wall, 2h = {2 * h:.10g} m ({h_said}), {tolerance}"))
