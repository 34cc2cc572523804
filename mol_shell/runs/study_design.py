"""The design of a parameter study: which cases its varied parameters make, each value typed as its parameter wants
it, and the units and long names of the varied coordinates (:func:`mol_shell.runs.study.study` and
:func:`mol_shell.analysis.path_study.path_study` share it)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.leapfrog import DEFAULT_RESTART
from mol_shell.integrators.loop import declared, refusal
from mol_shell.model.laws import Material, resolve_material
from mol_shell.model.wall_parameters import wall_parameter, wall_parameter_names
from mol_shell.runs.simulate import DEFAULT_DT, integrator_options
from mol_shell.scenes import DESCRIPTIONS, UNITS, _coerce, with_params


def design(scene, vary, integrator="leapfrog", options=None):
    """``(dims, coords, cases)`` of a study: a grid for a dict of lists, a ``case`` dim for a list of dicts.

    Each case is ``(index, {name: value})``; names are scene parameters or integrator options (none with
    ``integrator=None``: a study of paths). A case of a list
    that leaves a name out has the base scene's value, or for an option the study's (``options``), else the
    integrator's default.
    """
    allowed = set(scene_fields(scene)) | material_names(scene)  # integrator None: a study of paths, no options
    allowed |= _option_names(scene, integrator) if integrator is not None else set()
    if isinstance(vary, dict):
        if not vary:
            raise ParameterError("vary", vary, "at least one parameter with values")
        names = list(vary)
        given = {}
        for name in names:  # a name first: its values are typed as the name wants them
            _check_name(name, allowed, scene, integrator)
            given[name] = _listed(scene, name, vary[name], integrator)
        values = [[_typed(scene, k, v, integrator) for v in given[k]] for k in names]
        for name, vals in zip(names, values):
            if not vals or len(set(map(repr, vals))) != len(vals):
                raise ParameterError(f"vary[{name!r}]", vals, "distinct values, at least one")
        cases = [(idx, dict(zip(names, (values[d][i] for d, i in enumerate(idx)))))
                 for idx in itertools.product(*(range(len(v)) for v in values))]
        return names, {k: v for k, v in zip(names, values)}, cases
    cases = [dict(c) for c in vary]
    if not cases:
        raise ParameterError("vary", vary, "at least one case")
    names = sorted({k for c in cases for k in c})
    for name in names:
        _check_name(name, allowed, scene, integrator)
    for i, case in enumerate(cases):
        for name, value in case.items():
            _check_scalar(scene, f"vary[{i}][{name!r}]", value, name, value, integrator)
    coords = {k: [_typed(scene, k, c[k], integrator) if k in c else
                  _typed(scene, k, _default(scene, k, integrator, options or {}), integrator, left_out=True)
                  for c in cases] for k in names}
    return ["case"], coords, [((i,), {k: coords[k][i] for k in names}) for i in range(len(cases))]


def scene_fields(scene):
    """The names of ``scene``'s parameters (its dataclass fields)."""
    return [f.name for f in dataclasses.fields(scene)]


def text_parameters(scene):
    """The names of ``scene``'s string parameters (``h_profile``, ``layers``, ``material``, a history, ``end1``,
    ``points``, ...): the command line's ``--vary`` keeps their values as typed, as ``--set`` does."""
    return {f.name for f in dataclasses.fields(scene) if "str" in str(f.type).split(" | ")}


def material_names(scene):
    """``material.NAME`` for each parameter of the scene's law of one's own (a layered wall's: of its layers' laws;
    none for built-in laws)."""
    return {f"material.{k}" for k in (wall_parameter_names(scene) if hasattr(scene, "material_parameters") else ())}


def _option_type(integrator, name):
    """The declared type of option ``name`` of ``integrator`` as text (``"int"``, ``"str"``, ...), ``""`` if none."""
    fields = {f.name: f for f in dataclasses.fields(INTEGRATORS[integrator])} if integrator in INTEGRATORS else {}
    return str(fields[name].type) if name in fields else ""


def _option_names(scene, integrator):
    return integrator_options(scene, integrator)


def label_coords(ds, coords, dims):
    """Units and long names of the varied parameters (and of the ``case`` index)."""
    for name in coords:
        if name not in ds.coords:
            continue
        attrs = {"long_name": f"{DESCRIPTIONS.get(name, name)} (varied)"}
        if name.startswith("material."):  # a Material's parameter: its units are the law's author's
            attrs["long_name"] = f"parameter {name.removeprefix('material.')} of the material (varied)"
        elif ds[name].dtype.kind in "iuf":
            attrs["units"] = UNITS.get(name, "1")
        ds[name].attrs.update(attrs)
    if "case" in dims and "case" in ds.coords:
        ds["case"].attrs.update({"units": "1", "long_name": "index of the case in the list of cases"})


#: what a varied parameter takes, said by a refusal of a value that is not one
VALUES = "a list of numbers or words, one per case"
#: what a case of a list of cases gives a parameter
ONE_VALUE = "a number or a word"


def _listed(scene, name, given, integrator):
    """The values of ``vary[name]`` as a list: a list, tuple, range or 1-D array of them (or anything with an array of
    them: a DataArray, a Series, an Index), or one number or word (one case); each a number, a word, a flag where the parameter is one, or a :class:`Material` for ``material``.
    Refused by ``vary['NAME']``, before any case runs: a set or a generator (no order to make a grid's axis of: a set
    was one case, its value refused as it ran, and the file was not written), a dict, a nested list, a complex
    number."""
    label = f"vary[{name!r}]"
    if isinstance(given, np.ndarray) and given.ndim > 1:
        raise ParameterError.invalid(label, given.tolist(), "nests lists (the grid's values must be scalars)", VALUES)
    if isinstance(given, np.ndarray):
        values = given.ravel().tolist()
    elif isinstance(given, (list, tuple, range)):
        values = list(given)
    elif _scalar(given):  # one value: one case
        values = [given]
    elif hasattr(given, "__array__") and not isinstance(given, (set, frozenset, dict)):
        # a DataArray, a Series, an Index (a study's own coordinate): its values as an array, in its order
        return _listed(scene, name, np.asarray(given), integrator)
    else:
        raise ParameterError.invalid(label, _shown(given), f"is a {type(given).__name__}, not a list of values",
                                     VALUES)
    for value in values:
        _check_scalar(scene, label, given, name, value, integrator)
    return values


def _scalar(value):
    """Whether ``value`` can be one value of a study's coordinate (as typed: a field's own check says more)."""
    return value is None or isinstance(value, (str, bool, np.bool_, Material)) or is_number(value)


def _check_scalar(scene, label, given, name, value, integrator):
    """Refuse, by ``label`` (its values ``given``; ``value`` itself for a case of a list of cases), a value of ``name``
    that is no number, word or flag (a set, a dict, a complex number, a list); a flag (``True``) where ``name`` is not
    one."""
    one = value is given  # a case's value in a list of cases
    said, allowed = ("is", ONE_VALUE) if one else (f"holds {_shown(value)},", VALUES)
    if not one and (isinstance(value, (list, tuple)) or isinstance(value, np.ndarray) and value.ndim):
        raise ParameterError.invalid(label, _shown(given), "nests lists (the grid's values must be scalars)", VALUES)
    if isinstance(value, np.ndarray) and not value.ndim or isinstance(value, np.generic):
        value = value.item()
    if value is None and not _takes_none(scene, name):  # it wrote NaN in the coordinate, the case refused
        raise ParameterError.invalid(label, _shown(given), f"{'is' if one else 'holds'} None, not a value of {name}",
                                     _allowed(scene, name, integrator), hint=f"leave {name} out of vary for its default")
    if not _scalar(value):
        raise ParameterError.invalid(label, _shown(given), f"{said} a {type(value).__name__}, not a real number or a "
                                     "word", allowed)
    if isinstance(value, (bool, np.bool_)) and not _is_flag(scene, name, integrator):
        raise ParameterError.invalid(label, _shown(given), f"{said} a flag, not a number", allowed)


def _takes_none(scene, name):
    """Whether ``None`` is a value of the scene parameter ``name`` (an edge left to the code, the word ``"auto"`` in
    the coordinate; a numeric one left to the code, refused by :func:`_auto_refused`); never of an option."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    return name in fields and "None" in str(fields[name].type)


def _allowed(scene, name, integrator):
    """The allowed values of ``name`` as its own check says them (``finite values (rad/m)``), or as the option of
    ``integrator`` declares them; else "a number or a word"."""
    spec = declared(INTEGRATORS[integrator]).get(name) if integrator in INTEGRATORS else None
    if spec is not None:
        return spec.allowed
    try:
        if name in scene_fields(scene) or name.startswith("material."):
            with_params(scene, {name: None})
    except ParameterError as exc:
        return exc.allowed
    except (TypeError, ValueError):
        pass
    return ONE_VALUE


def _is_flag(scene, name, integrator):
    """Whether ``name`` (a scene parameter or an option of ``integrator``) is a flag (True or False)."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    return "bool" in (str(fields[name].type) if name in fields else _option_type(integrator, name))


def _shown(value):
    """``value`` for a message: a generator or another object as ``<its kind>`` (its text is an address)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple, set, frozenset, dict, range, complex, str)) or _scalar(value):
        return value
    return f"<{type(value).__name__}>"


def _check_name(name, allowed, scene, integrator=None):
    if name not in allowed:
        hint = f"parameters of scene {scene.name}" + (f" and options of {integrator}" if integrator else "")
        if name in ("integrator", "n"):  # one per study
            hint += f"; {name} is one per study (integrators are compared by mol-shell compare)"
        raise ParameterError("vary", name, "{" + ", ".join(sorted(allowed)) + "}", hint=hint)


def _default(scene, name, integrator, options):
    """The value of ``name`` in a case that leaves it out: the scene's, the study's option, the integrator's
    default; refused by name when there is none to show (an option whose default is left to the solver)."""
    if hasattr(scene, name):
        return getattr(scene, name)
    if name.startswith("material.") and hasattr(scene, "material_parameters"):  # the law's value in this scene
        return wall_parameter(scene, name.split(".", 1)[1])
    if name in options:
        return options[name]
    fields = {f.name: f for f in dataclasses.fields(INTEGRATORS[integrator])} if integrator in INTEGRATORS else {}
    value = fields[name].default if name in fields else None
    if name == "dt" and value is None:  # the unshearable scene's leap-frog
        value = DEFAULT_DT
    if name == "restart" and value is None:  # the leap-frog's default, as its run records it (at least 100 steps)
        value = DEFAULT_RESTART
    if value is None or value is dataclasses.MISSING:
        raise ParameterError("vary", f"<{name} missing from a case>", f"cases that each give {name}",
                             hint=f"{integrator} has no value of {name} to record for a case without it")
    return value


def _typed(scene, name, value, integrator=None, left_out=False):
    """A value as the scene field's type wants it, or the integrator option's (strings from the command line are
    converted: ``jac_every=20`` an integer, ``linsolver=band`` a word).

    Refused here, for every case at once: a string that is not a number, for a numeric parameter; NaN, and an
    infinity the parameter refuses (with its own message); ``"auto"`` (``None``) for a numeric parameter left to the
    code (``R``, ``zeta1``, ...: its coordinate holds numbers, :func:`_auto_refused`). An edge left to the code
    (``end1``, ``end2``) is the word ``"auto"`` in the coordinate. ``left_out``: the value is the base scene's, for a
    case of a list that leaves ``name`` out.
    """
    if isinstance(value, np.generic):
        value = value.item()
    fields = {f.name: f for f in dataclasses.fields(scene)}
    if name not in fields:
        kind = _option_type(integrator, name)
        if isinstance(value, str) and ("str" in kind or "bool" in kind):
            words = {"true": True, "false": False}
            return words.get(value.strip().lower(), value) if "bool" in kind else value
        if isinstance(value, str):
            try:
                value = int(value) if "int" in kind and "float" not in kind else float(value)
            except ValueError:
                try:
                    value = float(value)  # "2e3" for an integer option: refused below as not an integer
                except ValueError:
                    raise ParameterError.not_a(f"vary[{name!r}]", value, "a number", "numbers") from None
        if "int" in kind and "float" not in kind and isinstance(value, float):
            # refused as simulate(chunk=2000.0) refuses it ("is not an integer ... write it as the integer 2000");
            # the command line's --vary gives an integer option's values as integers (mol_shell.cli.study)
            raise refusal(name, value, declared(INTEGRATORS[integrator])[name])
        _refuse_non_finite(scene, name, value, integrator)
        return value
    annotation = str(fields[name].type)
    if name == "material" and isinstance(value, Material):  # its key in the coordinate, as the case's scene stores
        value = resolve_material(value)  # it (a netCDF file holds no Material; two laws of one name are two keys)
    value = _coerce(name, value, fields[name].type)
    if isinstance(value, str) and annotation != "str":
        dataclasses.replace(scene, **{name: value})  # raises: "gamma = 'abc' is not a number; allowed: ..."
    if name.endswith("_history") and isinstance(value, str):  # as the case's scene stores it (one normal form)
        value = getattr(dataclasses.replace(scene, **{name: value}), name)
    if value is None and "str" in annotation and "None" in annotation:  # an edge left to the code: a word among
        return "auto"  # the edge kinds
    if value is None and "None" in annotation:
        raise _auto_refused(name, left_out)
    if "int" in annotation and isinstance(value, float) and value.is_integer():
        return int(value)
    _refuse_non_finite(scene, name, value, integrator)
    return value


def _refuse_non_finite(scene, name, value, integrator):
    """Refuse NaN, and an infinity where the parameter refuses it anyway, before any case runs (each case refused it
    as it ran, and NaN stood in the study's coordinate): with the parameter's own message where it has one (the
    scene's check, a law's, the integrator's), else as not a number."""
    if not is_number(value) or math.isfinite(value):
        return
    try:
        if name in scene_fields(scene) or name.startswith("material."):
            with_params(scene, {name: value})
        elif integrator in INTEGRATORS:
            INTEGRATORS[integrator](**{name: value})
    except ParameterError:
        raise
    except (TypeError, ValueError):
        pass  # no check of its own said why: NaN is refused below
    if math.isnan(value):
        raise ParameterError.not_a(name, value, "a number", "numbers", hint="a study varies over values it can run")


def _auto_refused(name, left_out):
    """The refusal of ``"auto"`` (``None``: left to the code) among the values of a numeric parameter: the coordinate
    holds numbers (NaN stood there, and the value the code chose was recorded nowhere)."""
    how = (f"a case that leaves {name} out has the base scene's {name} = auto: give {name} in every case of the list, "
           "or in none; " if left_out else "")
    return ParameterError.invalid(
        name, "auto", "cannot be varied: a study's coordinate holds numbers", "numbers",
        hint=f"{how}to compare with {name} left to the code, run that case alone or in a study that does not vary "
        f"{name}: its Dataset holds the {name} each case used")
