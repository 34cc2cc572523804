"""Values of a scene file (:mod:`mol_shell.scenes.files`) as TOML spells them, and the refusals that name them so:
the file and the table first, the value as written (``E = true``, not ``True``), integers beyond the floats' range
(TOML's are unbounded) refused by key before anything takes them as floats."""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
import re
import sys

from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell.scenes.ranges import parameter_range

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

#: the largest float: an integer beyond it (TOML's integers are unbounded) is no number a run can take
FLOAT_MAX = sys.float_info.max


def toml_value(value):
    """``value`` as TOML text: ``"auto"`` for ``None``, strings, booleans, numbers, flat lists and inline tables."""
    if value is None:
        return '"auto"'
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (datetime.date, datetime.time)):  # TOML's dates and times (RFC 3339)
        return value.isoformat()
    if is_number(value):
        value = value.item() if hasattr(value, "item") else value
        if isinstance(value, float) and not math.isfinite(value):
            return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
        return repr(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return show(value)


def fail(source, table, exc_or_message, name=None, value=None):
    """A ParameterError whose message is prefixed with the file and the table (its value as TOML spells it)."""
    where = f"{source}: " + (f"[{table}] " if table else "")
    if isinstance(exc_or_message, ParameterError):
        exc = exc_or_message
        return ParameterError(exc.name, exc.value, exc.range or exc.allowed, message=where + toml_spelled(exc))
    return ParameterError(name, value, "", message=where + exc_or_message)


def _tomlish(value):
    """Whether ``value`` holds a TOML value Python spells otherwise: a boolean (``true``), a date or a time."""
    if isinstance(value, (bool, datetime.date, datetime.time)):
        return True
    items = value.values() if isinstance(value, dict) else value if isinstance(value, list) else ()
    return any(map(_tomlish, items))


def toml_shown(value):
    """``value`` as TOML spells it (:func:`toml_value`) on a message's line: a list or a table cut after six items, a
    long integer in its middle (as :func:`~mol_shell._core.errors.show` cuts it)."""
    if isinstance(value, dict):
        items = [f"{k} = {toml_shown(v)}" for k, v in list(value.items())[:6]]
        return "{" + ", ".join(items + ["..."] * (len(value) > 6)) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join([toml_shown(v) for v in value[:6]] + ["..."] * (len(value) > 6)) + "]"
    return show(value) if isinstance(value, int) and not isinstance(value, bool) else toml_value(value)  # 1000...000


def toml_spelled(exc):
    """The message of ``exc`` with its value as TOML spells it (``E = true``, ``E = 1979-05-27``, ``end1 = ["r",
    "theta"]``, ``E = {value = 1e6, unit = "Pa"}``), not as Python does (``E = True``, ``E = datetime.date(1979, 5,
    27)``, ``['r', 'theta']``, ``{'unit': 'Pa', ...}``). A string alone keeps Python's quotes (``end1 = 'clamped'``)."""
    text = str(exc)
    if not (isinstance(exc.name, str) and (_tomlish(exc.value) or isinstance(exc.value, (dict, list)))):
        return text
    return text.replace(f"{exc.name} = {show(exc.value)}", f"{exc.name} = {toml_shown(exc.value)}", 1)


def _same(read, value):
    """Whether TOML value ``read`` is ``value`` as a scene file's check holds it (an integer taken as a float)."""
    if isinstance(read, bool) or isinstance(value, bool):
        return isinstance(read, bool) and isinstance(value, bool) and read == value
    if is_number(read) and is_number(value):
        try:
            return float(read) == float(value)
        except OverflowError:  # an integer beyond the floats' range
            return read == value
    if isinstance(read, dict) and isinstance(value, dict):
        return read.keys() == value.keys() and all(_same(read[k], value[k]) for k in read)
    if isinstance(read, list) and isinstance(value, list):
        return len(read) == len(value) and all(map(_same, read, value))
    return type(read) is type(value) and read == value


def _written(text, table, key, value):
    """The text of ``key = ...`` under ``[table]`` in scene file ``text`` (without its comment) where it reads back
    as ``value`` on one line (``7e-1``); ``None`` where it cannot be found so."""
    current = None
    for line in text.splitlines():
        header = re.match(r"\s*(\[\[?)\s*([A-Za-z0-9_-]+)\s*\]", line)
        if header:
            current = header.group(2) if header.group(1) == "[" else None
            continue
        found = re.match(rf"\s*{re.escape(key)}\s*=\s*(.*?)\s*$", line) if current == table else None
        if found is None:
            continue
        said = found.group(1)
        for end in [*(i for i, c in enumerate(said) if c == "#"), len(said)]:  # the comment off: the shortest that reads
            try:
                read = tomllib.loads(f"v = {said[:end]}")["v"]
            except tomllib.TOMLDecodeError:
                continue
            return said[:end].rstrip() if _same(read, value) else None
    return None


#: the longest value a refusal writes as the file does (a longer one is shortened as Python shows it)
SPELLED_MAX = 120


def respelled(exc, text, source):
    """``exc`` (a refusal of scene file ``source``, whose text is ``text``) with its value as the file writes it:
    ``[material] nu = 7e-1``, not ``nu = 0.7``; ``exc`` itself where the value is a string (said with Python's
    quotes, as every refusal says one), is not written on one line of its table or is longer than
    :data:`SPELLED_MAX`."""
    message, head = str(exc), f"{source}: ["
    table = message[len(head):].partition("] ")[0] if message.startswith(head) else ""
    if not (isinstance(exc.name, str) and table and not isinstance(exc.value, str)):
        return exc
    start = f"{head}{table}] {exc.name} = "
    written = _written(text, table, exc.name, exc.value)
    if written is not None and len(written) > SPELLED_MAX:  # 1 and 400 zeros: said shortened, as it was
        return exc
    for shown in (toml_shown(exc.value), show(exc.value)):
        if written is not None and message.startswith(start + shown):
            said = start + written + message[len(start + shown):]
            return type(exc)(exc.name, exc.value, exc.range or exc.allowed, message=said)
    return exc


def _huge(value, path):
    """``(path, number, in_list)`` of the first integer beyond the floats' range in ``value`` (a key's value, an
    inline table's, an array's: ``path`` as TOML's dotted keys spell it), or ``None``."""
    if isinstance(value, dict):
        return next(filter(None, (_huge(v, f"{path}.{k}") for k, v in value.items())), None)
    if isinstance(value, list):
        found = next(filter(None, (_huge(v, path) for v in value)), None)
        return found and (found[0], found[1], found[0] == path)
    return (path, value, False) if isinstance(value, int) and not isinstance(value, bool) and abs(value) > FLOAT_MAX \
        else None


def too_large(source, cls, data, tables):
    """Refuse an integer beyond the floats' range (``E = 1`` and 400 zeros: TOML's integers are unbounded; ``float``
    raised an OverflowError) in a scene's table (an inline table or array there too) or a ``[[layer]]`` table, naming
    the file, the table and the key with the allowed range (the scene's, for a parameter). Integer parameters
    (``n_quad``) are left to their own checks, ``[run]`` to its own; ``tables``: the scene file's tables."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    places = [(f"[{name}]", table, True) for name, table in data.items()
              if name in tables and name != "run" and isinstance(table, dict)]
    layers = data.get("layer") if isinstance(data.get("layer"), list) else []
    places += [(f"[[layer]] {number} (from the lower face):", layer, False)
               for number, layer in enumerate(layers, start=1) if isinstance(layer, dict)]
    for where, table, scenes in places:
        for key, value in table.items():
            field = fields.get(key) if scenes else None
            if field is not None and "int" in str(field.type) and "float" not in str(field.type):
                continue
            found = _huge(value, key)
            if found is None:
                continue
            path, number, in_list = found
            floats = f"finite numbers, of magnitude up to {FLOAT_MAX:.4g}"
            declared_range = parameter_range(cls(), key) if field is not None and path == key else None
            allowed = declared_range.text() if declared_range is not None else floats
            said = f"holds {show(number)}," if in_list else f"= {show(number)} is"
            raise ParameterError(key, value, allowed, message=f"{source}: {where} {path} {said} beyond the floats' "
                                 f"range (magnitude up to {FLOAT_MAX:.4g}); allowed: {allowed}")
