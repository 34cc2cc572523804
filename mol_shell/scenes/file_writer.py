"""Scene files written: a scene (an instance, or a class for its defaults) as a commented TOML file that
:func:`mol_shell.scenes.files.load_scene` reads back (``mol-shell scenes NAME --toml``, a run's or a path's scene file).
"""

from __future__ import annotations

import dataclasses

from mol_shell._core.user_files import name_text
from mol_shell.scenes import summary
from mol_shell.scenes.base import DESCRIPTIONS, UNITS, describe
from mol_shell.scenes.file_values import toml_value
from mol_shell.scenes.files import FILE_KEYS, RUN, TABLES, table_of


def _comment(name, cls=None):
    unit = UNITS.get(name, "1")
    text = describe(name, cls) if cls is not None else DESCRIPTIONS.get(name, "")
    return f"{unit}: {text}" if unit != "1" else text


#: comments under a table's header in a printed scene file
NOTES = {
    "edges": ["# edges: magnet, clamped, pinned, free, or auto; driven edges (*_spin, *_axial_speed) take histories"],
    "loads": ['# histories (a factor on the load): "constant", "step T0", "ramp T1", "sine F" (Hz),',
              '# "table t0:h0 t1:h1 ...", or inline tables: {kind = "ramp", t1 = 0.01},',
              '# {kind = "table", t = [0, 0.01], h = [0, 1]}, {kind = "step", t0 = 0.01}, {kind = "sine", f = 50}'],
    "run": ["# defaults of mol-shell run (its options win); any of: " + ", ".join(RUN)],
}


def comment_text(text):
    """``text`` as one line of a TOML comment in UTF-8: a character that is not printable escaped as Python writes it
    (a newline ``\\n``: a run file's name ``r\\nnu = 0.3`` set a key), a byte of a file name that is not UTF-8 (held
    as a surrogate, ``'\\udce9'``, which no UTF-8 file can hold) as ``\\xe9``."""
    return "".join(c if c.isprintable() else f"\\x{ord(c) - 0xDC00:02x}" if 0xDC80 <= ord(c) <= 0xDCFF
                   else repr(c)[1:-1] for c in str(text))


def scene_toml(scene, run=None, notes=(), values=None):
    """A scene (an instance, or a class for its defaults) as a commented scene file that
    :func:`~mol_shell.scenes.files.load_scene` reads back.

    Values are written as TOML (``None`` as ``"auto"``), each with its unit and description as a comment; a
    ``[run]`` table holds ``run`` (``{key: value}``: a run file's, :func:`mol_shell.analysis.run_scene.run_table`) or
    the command line's defaults (leap-frog, 40 nodes, ``t_end`` = 0.01 s: a run of a second or two), so the file runs
    as its header says. ``notes``: comment lines after the header; ``values``: ``{name: value}`` written in place of
    the scene's (a run's laws of one's own by their import paths, the scene made without importing them).
    """
    cls = scene if isinstance(scene, type) else type(scene)
    fields = dataclasses.fields(cls)
    if isinstance(scene, type):
        value = {f.name: f.default if f.default is not dataclasses.MISSING else "" for f in fields}
    else:
        value = {f.name: getattr(scene, f.name) for f in fields}
    value.update(values or {})
    doc = summary(cls)  # the package's summary: one clause, no markup
    lines = [f"# {cls.name}: {doc}",
             "# A mol_shell scene file: mol-shell run THIS.toml -o out.nc (--set NAME=VALUE on top). Units: SI.",
             '# "auto" is computed (an edge: from the geometry; R, dilation: the equilibrium under the loads',
             "# at t = 0).", *map(comment_text, notes),
             f'scene = "{cls.name}"']
    points = ["# points: a file of two columns r z (m), relative to this file"] if "points" in value else []
    comments = dict(NOTES, geometry=points)
    for table in TABLES[:-1]:
        names = [f.name for f in fields if table_of(cls, f.name) == table]
        if names:
            lines += ["", f"[{table}]", *comments.get(table, [])]
        for name in names:
            text = name_text(value[name]) if name in FILE_KEYS and isinstance(value[name], str) else value[name]
            entry = f"{name} = {toml_value(text)}"  # a file name not UTF-8: escaped (\xfc), as TOML holds UTF-8
            note = _comment(name, cls) if not name.endswith("_history") else ""
            lines.append(f"{entry:34s} # {note}" if note else entry)
    if run is not None:
        return "\n".join([*lines, "", "[run]", *comments["run"], *[f"{key} = {toml_value(value)}" for key, value in run.items()]]) + "\n"
    lines += ["", "[run]", *comments["run"], 'integrator = "leapfrog"', "n = 40",
              f"{'t_end = 0.01':34s} # s: final time (or times = [0, 0.005, 0.01] in its place)"]
    return "\n".join(lines) + "\n"
