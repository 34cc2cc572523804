"""Scene files: one TOML file composing a scene and the defaults of its run.

A scene file names a registered scene and sets any of its parameters, each in the table it belongs to::

    scene = "sphere"            # a key of mol_shell.scenes.SCENES

    [geometry]                  # the meridian: L, a, b, alpha1, alpha2, r1, r2, H, points
    a = 1.0
    [material]                  # h, E, nu, rho, material, n_quad, zeta1, eta_lambda, eta_mu, fibre_*, h_profile, ...
    E = 1e6
    [[layer]]                   # a layered wall, from the lower face (mol_shell.model.layers): thickness, material, ...
    thickness = 0.0126
    material = "svk"
    [edges]                     # end1, end2 and the driven edges (end1_spin, ..., end_omega, with *_history)
    end1 = "auto"
    [loads]                     # pressure, gravity, drag, end forces and torques (with *_history)
    pressure = 1e3
    pressure_history = {kind = "ramp", t1 = 0.01}     # or "ramp 0.01"
    [initial]                   # the scene's initial data (its ``initial`` tuple: R, gamma, omega, ...)
    R = "auto"
    [run]                       # defaults of ``mol-shell run FILE.toml`` (command-line options win)
    integrator = "leapfrog"
    n = 41
    t_end = 0.01

Which table a parameter belongs to follows from its name (:func:`table_of`), so new scenes and fields
need no code here. Parameters left out keep the scene's defaults; ``"auto"`` is ``None`` (computed).
A history is its string form (:mod:`mol_shell.model.loads`) or an inline table ``{kind = "constant"}``,
``{kind = "step", t0 = T0}``, ``{kind = "ramp", t1 = T1}``, ``{kind = "sine", f = F}``,
``{kind = "table", t = [...], h = [...]}``. ``points`` is a path relative to the file's folder.

Every refusal is a :class:`~mol_shell._core.errors.ParameterError` of one line that starts with the file
(and the table): ``sphere.toml: [material] nu = 0.7 is outside (-1, 0.5)``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import sys
from pathlib import Path

from mol_shell._core.constants import ATOL_MIN, FIELDS, RTOL_RANGE
from mol_shell._core.errors import ParameterError, flag, is_number, show
from mol_shell._core.user_files import MAX_USER_FILE_TEXT, UserFileError, name_from_text, read_user_file
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.loop import declared, real, refusal, typed_value
from mol_shell.integrators.tolerances import MAX_STEP_NOTE
from mol_shell.model.edges import EDGE_PARAMETERS
from mol_shell.model.layers import LAYER_KEYS
from mol_shell.model.loads import HISTORY_ALLOWED, parse_history
from mol_shell.scenes import SCENES
from mol_shell.scenes.base import DISPLACEMENTS, DRIVES, LOADS, ShellScene
from mol_shell.scenes.file_layers import layer_sum_refusal, layer_tables
from mol_shell.scenes.file_values import FLOAT_MAX, respelled, toml_value, too_large
from mol_shell.scenes.file_values import fail as _fail
from mol_shell.scenes.setting import with_params
from mol_shell.scenes.unshearable import UNSHEARABLE_DAE_OPTIONS, UNSHEARABLE_INTEGRATORS, Unshearable

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

#: the tables of a scene file, in the order they are written
TABLES = ("geometry", "material", "edges", "loads", "initial", "run")
MATERIAL = ("h", "h_profile", "layers", "E", "nu", "rho", "material", "material_parameters", "c10", "c01", "fibre_E", "fibre_angle", "fibre_families",
            "fibre_compression", "law_limit", "ellipticity_limit", "n_quad", "zeta1", "eta_lambda", "eta_mu")
EDGES = ("end1", "end2") + DRIVES + DISPLACEMENTS + ("end_omega",)
#: the true/false parameters (the scenes' bool fields): TOML booleans in a scene file
FLAGS = tuple(f.name for f in dataclasses.fields(ShellScene) if f.type in (bool, "bool"))
#: the keys of ``[run]``: defaults of ``mol-shell run`` (``simulate``'s keywords)
RUN = ("integrator", "n", "t_end", "times", "dt", "rtol", "atol", "max_step")
#: the keys whose value names a file (read relative to the scene file's folder): the only strings taken as paths
FILE_KEYS = ("points",)
#: the keys of ``[run]`` and every integrator's options: said to belong in ``[run]`` where a file puts them elsewhere
RUN_KEYS = frozenset(RUN).union(*(declared(cls) for cls in INTEGRATORS.values()))
HISTORY_FORMS = {"constant": (), "step": ("t0",), "ramp": ("t1",), "sine": ("f",), "table": ("t", "h")}
HISTORY_TABLES = ('{kind = "constant"}, {kind = "step", t0 = T0}, {kind = "ramp", t1 = T1}, {kind = "sine", f = F}, '
                  '{kind = "table", t = [t0, t1, ...], h = [h0, h1, ...]}, or the strings ' + HISTORY_ALLOWED)


def table_of(cls, name):
    """The table of a scene file that parameter ``name`` of scene class ``cls`` belongs to.

    ``NAME_history`` goes with ``NAME``; then material, edges (and driven edges), loads, the scene's
    ``initial`` parameters, and everything else is geometry.
    """
    base = name.removesuffix("_history")
    for table, names in (("material", MATERIAL), ("edges", EDGES), ("loads", LOADS), ("initial", cls.initial)):
        if base in names:
            return table
    return "geometry"


def history_text(name, value):
    """A history as the scenes take it: the string form as it is, an inline table converted to it."""
    if not isinstance(value, (dict, str)):  # a number, a list: the file's forms said, its inline tables with them
        raise ParameterError.not_a(name, value, "a string or an inline table", HISTORY_TABLES)
    if not isinstance(value, dict):
        return value  # the scene's check names a string that is not a valid history
    kind = value.get("kind")

    def bad(why):
        """The refusal: the form of this kind (all the forms for an unknown kind) and what is wrong."""
        forms = [form for form in HISTORY_TABLES.split("}, ") if f'kind = "{kind}"' in form]
        allowed = forms[0].rstrip("}") + "}" if forms else HISTORY_TABLES
        return ParameterError(name, value, allowed, message=f"{name} = {toml_value(value)} is outside {allowed} ({why})")

    if kind not in HISTORY_FORMS:
        raise bad(f"kind = {toml_value(kind)} is not one of {', '.join(HISTORY_FORMS)}" if "kind" in value
                  else "it has no kind")
    keys = HISTORY_FORMS[kind]
    missing, extra = [k for k in keys if k not in value], sorted(set(value) - {"kind", *keys})
    if missing or extra:
        said = ([f"{', '.join(missing)} missing"] if missing else []) + ([f"not {', '.join(extra)}"] if extra else [])
        raise bad(f"{kind} takes {', '.join(keys) or 'no other key'}; " + ", ".join(said))
    args = [value[key] for key in keys]
    if kind == "table":
        t, h = args
        if not (isinstance(t, list) and isinstance(h, list) and all(map(is_number, t + h))):
            raise bad("t and h are lists of numbers")
        if len(t) != len(h):
            raise bad(f"t has {len(t)} values and h {len(h)}: one h for each t")
        text = "table " + " ".join(f"{float(a)!r}:{float(b)!r}" for a, b in zip(t, h))
    elif all(map(is_number, args)):
        text = " ".join([kind] + [repr(float(a)) for a in args])
    else:
        raise bad(f"{', '.join(keys)} {'is a number' if len(keys) == 1 else 'are numbers'}")
    try:
        parse_history(name, text)
    except ParameterError as exc:  # a value out of its range: the string form's rule for this kind says which
        forms, start = str(exc.allowed), str(exc.allowed).find(f"'{kind}")
        ends = [i for i in (forms.find(", '", start + 1), forms.find(" or '", start + 1)) if i > 0]
        hint = f"; {exc.hint}" if exc.hint else ""  # what is wrong: a table's points too close, say
        raise bad(f"as {forms[start:min(ends, default=len(forms))]}{hint}" if start >= 0 else str(exc)) from None
    return text


def _flag_of_file(source, table, name, value):
    """A true/false key of a scene file: a TOML boolean (``true``/``false``), nothing else (not 0/1, not a string)."""
    if not isinstance(value, bool):
        raise _fail(source, table, ParameterError.not_a(name, value, "a TOML boolean", "{true, false}"))
    return value


def _convert(cls, field, value, folder):
    """A file's value as the scene wants it: ``"auto"`` is None, integers are floats where floats are wanted,
    histories from inline tables, ``points`` relative to the file's folder."""
    kind = str(field.type)
    words = ("auto",) if field.name in EDGE_PARAMETERS else ("auto", "none")  # an edge's "none": free or auto? refused
    if isinstance(value, str) and value.strip().lower() in words and "None" in kind:
        return None
    if field.name.endswith("_history"):
        return history_text(field.name, value)
    if field.name in FILE_KEYS and isinstance(value, str) and value.strip():
        try:
            path = Path(value).expanduser()
        except RuntimeError:  # ~nosuchuser/p.txt
            raise ParameterError.invalid(field.name, value, f"starts with {value.split('/')[0]}, which is no user's "
                                         "home directory", "a file path, relative to the scene file's folder, or "
                                         "~/... in your home directory") from None
        return name_from_text(str(path if path.is_absolute() else folder / path))  # a name not UTF-8: escaped
    if field.name == "material_parameters" and isinstance(value, dict):  # numbers, as E = "1e6" is refused
        for key, number in value.items():
            if not is_number(number):
                raise ParameterError(field.name, value, "finite numbers", message=f"{field.name}.{key} = "
                                     f"{show(number) if isinstance(number, str) else toml_value(number)} is not a "
                                     "number; allowed: finite numbers")
    if "float" in kind and is_number(value) and not isinstance(value, float):
        return float(value)
    return value


def _type_ok(field, value):
    """Whether a value the scene accepted has the field's type (a fallback for fields the scene does not check)."""
    kind = str(field.type)
    return ((value is None and "None" in kind) or ("float" in kind and is_number(value))
            or ("int" in kind and is_number(value) and float(value).is_integer())
            or ("str" in kind and isinstance(value, str)) or (kind == "bool" and isinstance(value, bool)))


def _run_options(source, run, together=True, cls=None):
    """The ``[run]`` table checked: ``{name: value}`` with ``simulate``'s keyword names; ``together``: also the
    integrator's checks across its options (the command line makes them after its own options are applied); ``cls``:
    the scene class, whose parameters are said to belong in their tables."""
    out = {}
    fields = {f.name for f in dataclasses.fields(cls)} if cls is not None else set()

    def positive(key, value, low=0.0, high=math.inf, closed=False, unit=" s"):
        allowed = f"{'[' if closed else '('}{low:g}, {high:g}){unit}"
        if not is_number(value):
            raise _fail(source, "run", ParameterError.not_a(key, value, "a number", allowed))
        number = real(value)  # an integer beyond the floats' range as inf (math.isfinite raised on it)
        if isinstance(value, int) and not math.isfinite(number):
            raise _fail(source, "run", ParameterError.invalid(key, value, "is beyond the floats' range (magnitude up "
                                                              f"to {FLOAT_MAX:.4g})", allowed))
        if not (math.isfinite(number) and (number >= low if closed else number > low) and number < high):
            raise _fail(source, "run", ParameterError(key, value, allowed))
        return number

    integrator = run.get("integrator", "leapfrog")
    extra = declared(INTEGRATORS[integrator]) if integrator in INTEGRATORS else {}
    taken = _taken(integrator, cls)
    if together and taken is None and integrator in INTEGRATORS:  # the unshearable scene: ida, its DAE, or leapfrog
        raise _fail(source, "run", ParameterError("integrator", integrator, "{" + ", ".join(UNSHEARABLE_INTEGRATORS)
                    + "}", hint="ida solves the unshearable DAE, leapfrog the free shell from the same state"))
    for key, value in run.items():
        if together and taken is not None and key not in taken and key not in RUN[:4] and (key in RUN or key in extra):
            # not an option of the integrator, said before its value is checked (atol = -1 on leapfrog); apart
            # (the command line, whose --integrator may replace the file's), every value is checked in the file's
            # order and the caller leaves out or refuses what its integrator does not take
            raise _fail(source, "run", ParameterError.not_an_option(key, integrator, taken))
        if key not in RUN and key in extra:  # an option of the integrator beyond the tolerances: its declared range
            value = typed_value(extra[key], value)  # "none" (any case) where the option takes None
            if not extra[key].check(value):
                raise _fail(source, "run", refusal(key, value, extra[key]))
            out[key] = value
            continue
        if key not in RUN and key in fields:
            raise _fail(source, "run", f"{key} belongs in [{table_of(cls, key)}], not [run]", key, value)
        if key not in RUN:
            others = f", and the options of {integrator}: {', '.join(sorted(set(extra) - set(RUN)))}" if extra else ""
            raise _fail(source, "run", f"{key} is not a key of [run]; allowed: {', '.join(RUN)}{others}", key, value)
        if key == "integrator":
            if value not in INTEGRATORS:
                raise _fail(source, "run", ParameterError(key, value, "{" + ", ".join(INTEGRATORS) + "}"))
        elif key == "n":
            if not (is_number(value) and isinstance(value, int)):
                raise _fail(source, "run", ParameterError.not_a(key, value, "an integer", "integers >= 3"))
            if value < 3:
                raise _fail(source, "run", ParameterError(key, value, "integers >= 3"))
        elif key == "times":
            allowed = "increasing finite times starting at 0 (s), at least two"
            if not (isinstance(value, list) and all(map(is_number, value))):
                raise _fail(source, "run", ParameterError.not_a(key, value, "a list of numbers", allowed))
            given, value = value, [real(v) for v in value]  # an integer beyond the floats' range: inf, not finite
            if len(value) < 2 or value[0] != 0 or not all(map(math.isfinite, value)) or any(
                    b <= a for a, b in zip(value, value[1:])):
                huge = [v for v in given if isinstance(v, int) and abs(v) > FLOAT_MAX]
                raise _fail(source, "run", ParameterError.invalid(key, given, f"holds {show(huge[0])}, beyond the "
                                                                  f"floats' range", allowed) if huge else
                            ParameterError(key, value, allowed))
        elif key == "rtol":
            value = positive(key, value, *RTOL_RANGE, closed=True, unit="")
        elif key == "atol" and isinstance(value, dict):
            for name, tol in value.items():
                if name not in FIELDS:
                    raise _fail(source, "run", ParameterError("atol", name, "{" + ", ".join(FIELDS) + "}"))
                positive(f"atol.{name}", tol, ATOL_MIN, closed=True, unit="")
            value = {name: real(tol) for name, tol in value.items()}
        elif key == "atol":
            value = positive(key, value, ATOL_MIN, closed=True, unit="")
        elif key == "max_step":  # 0: unbounded, as the integrators take it
            value = positive(key, value, closed=True, unit=" s" + MAX_STEP_NOTE)
        else:  # t_end, dt
            value = positive(key, value)
        out[key] = value
    if together:  # an option the integrator does not take: refused above, before its value
        check_run_together(source, integrator, out)
    return out


def _taken(integrator, cls=None):
    """The options ``integrator`` takes for scenes of class ``cls`` as ``simulate`` and ``mol-shell run`` do
    (:func:`mol_shell.runs.simulate.integrator_options`; the unshearable scene: ``ida``, its DAE, or leapfrog); ``None``
    for an integrator that runs none of them."""
    dae = cls is not None and issubclass(cls, Unshearable)
    if integrator not in INTEGRATORS or dae and integrator not in UNSHEARABLE_INTEGRATORS:
        return None
    return set(UNSHEARABLE_DAE_OPTIONS) if dae and integrator == "ida" else {
        f.name for f in dataclasses.fields(INTEGRATORS[integrator])}


def check_run_together(source, integrator, run, given=()):
    """The integrator's checks across its options of ``run`` (max_order 9 on BDF, jac_every with a fixed-point
    iteration): refused naming the file ``source`` and ``[run]`` when the option blamed is the file's (not in
    ``given``, the command line's), else as the integrator says."""
    extra = declared(INTEGRATORS[integrator]) if integrator in INTEGRATORS else {}
    own = {key: value for key, value in run.items() if key in extra and key not in RUN}
    # with the run's own keys it declares (leap-frog's restart is at least 100 steps of dt): those refused where
    # they are checked, and the integrator's options then checked without them
    together = {key: value for key, value in run.items() if key in extra}
    for options in (together, own) if own else ():
        try:
            INTEGRATORS[integrator](**options)
            return
        except ParameterError as exc:
            if exc.name in own:
                raise (exc if exc.name in given else _fail(source, "run", exc)) from None


def scene_from_dict(data, source="<scene file>", folder=".", together=True, overrides=None):
    """The scene (and the ``[run]`` options) of a parsed scene file; see the module's docstring. ``overrides``
    (``--set NAME=VALUE``, as :func:`~mol_shell.scenes.with_params` takes them) replace the file's values before
    the scene is made: a file's value they replace is not read (a law that fails to import, say)."""
    overrides = dict(overrides or {})
    folder = Path(folder)
    names = "{" + ", ".join(sorted(SCENES)) + "}"
    if "scene" not in data:
        raise _fail(source, None, ParameterError.missing("scene", f"give scene = NAME with NAME in {names}"))
    name = data["scene"]
    if not isinstance(name, str) or name not in SCENES:
        raise _fail(source, None, ParameterError("scene", name, names))
    cls = SCENES[name]
    fields = {f.name: f for f in dataclasses.fields(cls)}
    tables = ", ".join(f"[{t}]" for t in TABLES)
    given, where = {}, {}
    too_large(source, cls, data, TABLES)
    if "layer" in data and "layers" in fields:  # [[layer]] tables: a layered wall (mol_shell.model.layers)
        data = dict(data)
        if isinstance(data.get("material"), dict) and "layers" in data["material"]:
            raise _fail(source, "material", "layers is given twice, as [material] layers and as [[layer]] tables; "
                        "allowed: one of them", "layers", data["material"]["layers"])
        given["layers"], where["layers"] = layer_tables(source, data.pop("layer"), FLAGS), "layer"
    for key, table in data.items():
        if key == "scene":
            continue
        if key == "layers" and isinstance(table, list) and all(isinstance(x, dict) for x in table):  # [[layers]]
            raise _fail(source, None, "[[layers]] tables are not read; allowed: [[layer]] tables, one per layer "
                        "(or layers = 'T MATERIAL ...; ...' in [material])", key, table)
        if key in TABLES and isinstance(table, list) and table and all(isinstance(x, dict) for x in table):
            raise _fail(source, None, f"{key} is an array of tables ([[{key}]]); allowed: [{key}], one table (a "
                        f"single [{key}] header, its keys under it)", key, table)
        if key in RUN_KEYS and key not in fields:
            raise _fail(source, None, f"{key} = {toml_value(table)} belongs in [run]", key, table)
        if key in fields and not (key in TABLES and isinstance(table, dict)):  # material is both
            raise _fail(source, None, f"{key} = {toml_value(table)} belongs in [{table_of(cls, key)}]", key, table)
        if key not in TABLES:
            what = f"[{key}] is not a table" if isinstance(table, dict) else f"{key} is not a key"
            raise _fail(source, None, f"{what} of a scene file; allowed: scene = NAME and {tables}", key, table)
        if not isinstance(table, dict):
            raise _fail(source, None, f"{key} = {toml_value(table)} is not a table; allowed: [{key}] with its keys",
                        key, table)
        if key == "run":
            continue
        takes = [f for f in fields if table_of(cls, f) == key]
        for param, value in table.items():
            if param in RUN_KEYS and param not in fields:
                raise _fail(source, key, f"{param} belongs in [run], not [{key}]", param, value)
            if param not in fields:
                raise _fail(source, key, f"{param} is not a parameter of scene {name}; allowed: "
                            + (", ".join(takes) or f"none ([{key}] of {name} is empty)"), param, value)
            if table_of(cls, param) != key:
                raise _fail(source, key, f"{param} belongs in [{table_of(cls, param)}], not [{key}]", param, value)
            if param in overrides:  # replaced: not read
                where[param] = key
                continue
            if param in FLAGS:
                _flag_of_file(source, key, param, value)
            try:
                given[param] = _convert(cls, fields[param], value, folder)
            except ParameterError as exc:
                raise _fail(source, key, exc) from None
            where[param] = key
    run = _run_options(source, data.get("run", {}), together, cls)
    try:
        scene = with_params(cls(), {**given, **overrides}) if overrides else cls(**given)
    except ParameterError as exc:
        said = layer_sum_refusal(exc, source, given.get("layers") if where.get("layers") == "layer" else None,
                                 overrides.get("h", given.get("h", cls.h)), overrides, where.get("h"))
        if said is not None:  # layers not adding up to 2h: said by the [[layer]] tables, or by the --set h that did
            raise said from None
        if exc.name in overrides or exc.name == "parameter":  # the command line's own: said as it says it
            raise
        entry = re.match(r"layer (\d+):? (.*)", exc.hint or "") if where.get(exc.name) == "layer" else None
        if entry:  # a [[layer]] table's value: said by the table, not by the layers text made of them
            number, why = entry.groups()
            keys = ("" if "allowed:" in why else  # a value's own range said already: not a second "allowed:"
                    f"; allowed: thickness (m, a positive finite number), material and {', '.join(LAYER_KEYS)}")
            raise ParameterError(exc.name, exc.value, exc.range or exc.allowed, message=f"{source}: [[layer]] "
                                 f"{number} (from the lower face): {'it ' if why.startswith('has ') else ''}{why}"
                                 f"{keys}") from None
        raise _fail(source, where.get(exc.name, table_of(cls, exc.name) if exc.name in fields else None), exc) from None
    for param, value in given.items():
        if param not in overrides and not _type_ok(fields[param], getattr(scene, param)):
            raise _fail(source, where[param], ParameterError.not_a(param, value, f"of type {fields[param].type}",
                                                                    f"values of type {fields[param].type}"))
    return scene, run


def load_scene(path, *, with_run=False, together=True, overrides=None):
    """The scene a TOML scene file describes (see :mod:`mol_shell.scenes.files` for the layout).

    Parameters
    ----------
    path : str or Path
        The file. ``points`` (meridian scene) is read relative to its folder.
    with_run : bool
        Also return the ``[run]`` table as checked options: ``{"integrator", "n", "t_end", "times",
        "dt", "rtol", "atol", "max_step"}`` and any other option of the integrator (those given), so
        ``simulate(scene, **run)`` runs it as
        ``mol-shell run FILE.toml`` does.
    together : bool
        Check the ``[run]`` options against the integrator as ``simulate`` does (an option it does not take:
        ``rtol`` on leap-frog, ``dt`` on an adaptive one) and across each other as the integrator does (False: the
        caller does, after options of its own replace some: the command line's ``--integrator`` and ``--option``),
        ``with_run`` or not: a ``[run]`` table ``mol-shell run`` refuses is refused here too.
    overrides : dict, optional
        Parameters over the file's (the command line's ``--set``), applied before the scene is made.

    Returns
    -------
    ShellScene, or ``(ShellScene, dict)`` with ``with_run``

    Raises
    ------
    ParameterError
        One line starting with the file (and ``[table]``): a missing or unreadable file, a TOML syntax
        error (with its line), ``scene`` missing or unknown, an unknown table or key, a key in the wrong
        table, a value of the wrong type or outside its range.
    """
    with_run, together = flag("with_run", with_run), flag("together", together)  # "no" was taken as True
    try:
        path = Path(os.fspath(path))
    except TypeError:
        raise ParameterError.not_a("scene file", path, "a file path", "a readable TOML file") from None
    try:
        path = path.expanduser()
    except RuntimeError:  # ~nosuchuser/s.toml
        raise ParameterError("scene file", str(path), "a readable TOML file", message=f"{path}: cannot read the scene "
                             f"file ({str(path).split(os.sep)[0]} is no user's home directory)") from None
    try:
        text = read_user_file(path).decode("utf-8-sig")  # a byte-order mark (Windows editors write one) is not TOML
    except UserFileError as exc:  # a device, a named pipe (not opened), a file larger than a scene file may be
        raise ParameterError("scene file", str(path), "a readable TOML file", message=f"{path}: the scene file "
                             f"{exc.problem}; allowed: a TOML file of at most {MAX_USER_FILE_TEXT}") from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ParameterError("scene file", str(path), "a readable TOML file",
                             message=f"{path}: cannot read the scene file ({reason})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError("scene file", str(path), "TOML", message=f"{path}: not valid TOML: {exc}") from None
    try:
        scene, run = scene_from_dict(data, str(path), path.parent, together, overrides)
    except ParameterError as exc:  # its value as the file writes it: nu = 7e-1, not 0.7
        raise respelled(exc, text, str(path)) from None
    return (scene, run) if with_run else scene
