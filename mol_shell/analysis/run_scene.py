"""A run file back as a scene file: its scene from the attrs and a ``[run]`` table as the run ran (``mol-shell scenes
RUN.nc --toml``), so ``mol-shell run`` of the file runs it again, to the bit.

The scene's parameters come from the attrs as a path's start takes them (:func:`~mol_shell.analysis.path_start.
scene_params`: those left to the code ``"auto"`` again); the ``[run]`` table holds ``n``, the integrator, ``t_end``
(or the saved ``times`` where they are not ``t_end``'s default) and the integrator's options that are not its
defaults (leap-frog's ``dt``, the tolerances ``rtol`` and ``atol`` always), from the attrs every run writes of them.
"""

from __future__ import annotations

import dataclasses
import os
import re
import shlex
import warnings

import numpy as np

from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import ParameterError, SceneWarning
from mol_shell._core.user_files import name_text
from mol_shell._core.version import __version__
from mol_shell.analysis.path_start import read_path, scene_params
from mol_shell.integrators import INTEGRATORS
from mol_shell.model.laws import MATERIALS
from mol_shell.model.layers import parse_layers
from mol_shell.results.dataset import RUN_FILE, holdings, read_run
from mol_shell.runs import asked_times
from mol_shell.runs.building import parse_times
from mol_shell.runs.simulate import integrator_options, leapfrog_times
from mol_shell.scenes import SCENES, get_scene
from mol_shell.scenes.file_writer import scene_toml
from mol_shell.scenes.files import _run_options

#: options written whatever their value: what a reader of the file looks for first
ALWAYS = ("dt", "rtol", "atol")
#: the built-in law a run's scene is made with in place of a law of one's own to write it as text (:func:`text_scene`:
#: no scene check depends on the law beyond the range of ``nu``, which is a law of one's own's too)
STAND_IN = "svk"
#: what ``mol-shell scenes FILE --toml`` reads (:func:`read_run_toml`): a path file is written back as its scene too
RUN_OR_PATH_FILE = "a netCDF file written by mol-shell run or mol-shell path"


def run_scene(ds, name="FILE"):
    """The scene of run ``ds`` as it was asked for (a value left to the code ``None`` again), refused naming ``name``
    where the file names no registered scene."""
    return get_scene(str(ds.attrs["scene"]), **_run_params(ds, name))


def _run_params(ds, name):
    """The parameters of :func:`run_scene` (the scene's name checked)."""
    scene = str(ds.attrs.get("scene", ""))
    if scene not in SCENES:
        raise ParameterError.invalid(name, str(ds.encoding.get("source", scene)), "names no registered scene in its "
                                     f"attribute scene = {scene!r}", RUN_FILE)
    params = scene_params(ds)
    for key in getattr(SCENES[scene], "initial", ()):  # a start given as fields (--from a path): the scene's values
        asked = ds.attrs.get(f"{key}_requested")
        if key in params and asked is not None and asked != "auto":
            params[key] = asked.item() if isinstance(asked, np.generic) else asked
    return params


def text_scene(ds, name="FILE"):
    """``(scene, values, notes)``: the scene of :func:`run_scene` made without importing its laws of one's own (each
    made :data:`STAND_IN` there, ``material_parameters`` empty), ``values`` what a scene file writes in their place
    (each law by its import path: a ``material = "my_laws:rubber"`` key, or the path a run of the Python API recorded
    in ``material_imports``; else its key, with a line of ``notes`` saying the law has no import path).
    ``mol-shell scenes RUN.nc --toml`` imported the law's module to write text, and refused a Python API run's law
    (stored by its name) as outside the built-in laws, "refused by this version"."""
    params = _run_params(ds, name)
    imports = dict(part.rpartition("=")[::2] for part in str(ds.attrs.get("material_imports", "")).split("; ")
                   if "=" in part)
    notes, values, layers = [], {}, []

    def written(key, where):
        path = key if ":" in key else imports.get(key)
        if path is None:
            notes.extend([f"# {where} {key!r} is a law of one's own the run recorded no import path for (made in a",
                          "# script's __main__ or a notebook, or run by an earlier version): to run this file, give it",
                          '# as "module:attr", a module that defines it at its top level.'])
        return path or key

    material = params.get("material")
    if isinstance(material, str) and material not in MATERIALS:
        values["material"], params["material"] = written(material, "material"), STAND_IN
    if params.get("layers"):
        for number, (_, law, _) in enumerate(parse_layers(str(params["layers"])), start=1):
            layers.append(law if law in MATERIALS else written(law, f"layer {number}'s material"))
        params["layers"] = "; ".join(_with_law(part, STAND_IN if law not in MATERIALS else law)
                                     for part, law in zip(str(params["layers"]).split(";"), layers))
    if values or any(law not in MATERIALS for law in layers):
        values["material_parameters"], params["material_parameters"] = params.get("material_parameters", ""), ""
    scene = get_scene(str(ds.attrs["scene"]), **params)
    if layers:
        values["layers"] = "; ".join(_with_law(part, law) for part, law in zip(scene.layers.split(";"), layers))
    return scene, values, notes


def _with_law(part, law):
    """One layer of a ``layers`` string with its law (its second word) ``law``."""
    words = part.split()
    return " ".join([words[0], law, *words[2:]])


def _option(value, default):
    """An option's value as the attrs hold it, as the integrator takes it: netCDF's 0/1 as a bool, ``'none'`` as
    None, a per-field ``atol`` (``"z=1e-09,r=1e-08,..."``) as a table."""
    value = value.item() if isinstance(value, np.generic) else value
    if isinstance(default, bool):
        return bool(value)
    if default is None and isinstance(value, str) and value.lower() == "none":
        return None
    if isinstance(value, str) and "=" in value and all(part.partition("=")[0] in FIELDS for part in value.split(",")):
        return {key: float(number) for key, _, number in (part.partition("=") for part in value.split(","))}
    return value


def run_table(ds, scene, name="FILE", source=None):
    """``{key: value}`` of the ``[run]`` table that runs ``ds`` again (see the module's docstring; a value the file
    holds that is not a run's refused naming ``name``)."""
    integrator = str(ds.attrs["integrator"])
    table = {"integrator": integrator, "n": int(ds.attrs.get("n", ds.sizes["s"]))}
    defaults = {f.name: f.default for f in dataclasses.fields(INTEGRATORS[integrator])} \
        if integrator in INTEGRATORS else {}
    options = {}
    for key in sorted(integrator_options(scene, integrator), key=lambda k: (k not in ALWAYS, k)):
        value = ds.attrs.get(f"{key}_option", ds.attrs.get(key))  # linsolver: as given ("auto"), not as chosen
        if value is None:
            continue
        value = _option(value, defaults.get(key))
        if key in ALWAYS or key not in defaults or value != defaults[key]:
            options[key] = value
    times = [float(t) for t in ds.time.values]
    asked = _asked_times(ds, name, source) if _stopped(ds) else None
    if asked is not None:  # a run that stopped early: the times it asked for, those it saved their prefix
        times = [float(t) for t in asked]
    elif not (times[0] == 0.0 and (len(times) >= 2 or _stopped(ds)) and np.all(np.diff(times) > 0)):
        # a selection of a run's times (ds.isel(time=...)), or times reordered by hand: no run saves those
        raise ParameterError.invalid(name, str(source or ds.encoding.get("source", "<xarray.Dataset>")),
                                     f"holds the saved times {_shown(', '.join(f'{t:g}' for t in times))[1:-1]} s, not "
                                     "increasing times from 0 as a run saves them (a part of a run?), which no scene "
                                     "file runs again", RUN_FILE)
    # a run of an earlier version that stopped early saved a prefix of the times asked: t_end asked where they are
    # its default times
    t_end = float(ds.attrs.get("t_end_requested", times[-1])) if _stopped(ds) else times[-1]
    try:
        default = (leapfrog_times(t_end, options.get("dt", defaults.get("dt"))) if integrator == "leapfrog"
                   else parse_times(None, t_end))
    except ParameterError:
        default = None
    if default is not None and len(default) >= len(times) and np.array_equal(default[:len(times)], times) \
            and (len(default) == len(times) or _stopped(ds)):
        table["t_end"] = t_end
    else:
        table["times"] = times
    return {**table, **options}


def _from_command(ds):
    """The ``mol-shell run --from`` command that starts where run ``ds`` started (its ``started_from``: a path file,
    a step or a critical point), for the header of its scene file; ``""`` for a file without it (an earlier
    version's)."""
    origin, _, where = str(ds.attrs.get("started_from", "")).rpartition(", step ")
    flag = "--step"
    if not origin:
        origin, _, where = str(ds.attrs.get("started_from", "")).rpartition(", critical point ")
        flag = "--point"
    if not origin:
        return ""
    perturb = re.search(r", perturbed by (\S+) x its critical mode$", where)
    return (f"# mol-shell run --from {shlex.quote(origin)} {flag} {where.split()[0]}"
            + (f" --perturb {perturb[1]}" if perturb else "") + " (the [run] table below as options: --integrator, "
            "--n, --t-end or --times, ...) starts from it.")


def _asked_times(ds, name, source=None):
    """The saved times run ``ds`` asked for (attr ``times_requested``, kept where it saved fewer), ``None`` where the
    file has none (a run of an earlier version); a value that is not of its form, or not a run's times that go on
    from those saved, is refused naming ``name`` and the attribute."""
    if asked_times.ATTR not in ds.attrs:
        return None
    text, saved = str(ds.attrs[asked_times.ATTR]), ds.time.values
    try:
        times = asked_times.times_of(text)
    except ValueError:
        times = None
    if times is None or len(times) < max(2, len(saved)) or not np.all(np.isfinite(times)) or times[0] != 0 \
            or np.any(np.diff(times) <= 0) or not np.array_equal(times[:len(saved)], saved):
        raise ParameterError.invalid(name, str(source or ds.encoding.get("source", "<xarray.Dataset>")), f"holds "
                                     f"{asked_times.ATTR} = {_shown(text)}, not increasing times from 0 that begin "
                                     "with the times it saved", RUN_FILE)
    return times


def _shown(text, most=60):
    """``text`` quoted, cut to ``most`` characters."""
    return repr(text if len(text) <= most else text[:most] + "...")


def _stopped(ds):
    """Whether run ``ds`` stopped before its end (a limit, a failure, Ctrl-C)."""
    return not int(ds.attrs.get("complete", 1))


def run_toml(ds, name="FILE", source=None):
    """A scene file (:func:`~mol_shell.scenes.file_writer.scene_toml`) that runs run ``ds`` again: its scene and a
    ``[run]`` table as it ran; ``source``, the file's name for the header."""
    scene, values, laws = text_scene(ds, name)
    version = str(ds.attrs.get("mol_shell_version", "?"))
    shown = source or ds.encoding.get("source", "")
    run = checked_run(ds, run_table(ds, scene, name, shown), scene, name, shown)
    notes = [f"# Written from the run {shown} (mol_shell {version}): mol-shell run THIS.toml runs it again.", *laws]
    if version != __version__:
        said = other_version_note(version)
        warnings.warn(f"{name} = {shown!r}: {said}", SceneWarning, stacklevel=2)
        notes.append(f"# {said[0].upper()}{said[1:]}.")
    if _stopped(ds):
        asked = "t_end is the one it asked" if "t_end" in run else "times are those it asked for" \
            if asked_times.ATTR in ds.attrs else "times are those it saved (its file does not record those it asked for)"
        notes.append(f"# That run stopped ({ds.attrs.get('message', '')}): {asked}.")
    start = str(ds.attrs.get("initial_state", ""))
    if start.startswith("equilibrium path"):
        notes.append(f"# That run started from {start}: this file starts from the scene's own initial data, not "
                     "the path's state.")
        notes += [command for command in [_from_command(ds)] if command]
    then, now = str(ds.attrs.get("meridian", "")), scene.meridian().describe() if hasattr(scene, "meridian") else ""
    _check_points(ds, then, now, name, source)
    if then and now and then != name_text(now):  # a file name not UTF-8: the attrs hold it escaped
        notes.append(f"# The meridian differs now (the run's: {then}; now: {now}).")
    return scene_toml(scene, run=run, notes=notes, values=values)


def other_version_note(version):
    """What a scene file written from a run of mol_shell ``version`` (not this one) says of running it again."""
    return (f"the run was computed by mol_shell {version}, this is {__version__}: its scene file runs it again with "
            "this version's code, whose states may differ from the run's (by up to the solver's tolerance on an "
            "adaptive integrator, more where a model or a default changed since), not to the bit")


def checked_run(ds, run, scene, name, source):
    """``run`` (:func:`run_table`) checked as ``mol-shell run`` checks a scene file's ``[run]`` table (its ``n``
    against the nodes of the file's ``s`` too): a hand-edited attribute of run ``ds`` is refused naming ``name`` (the
    file ``source``) and the attribute, not written into a scene file that the run refuses later."""
    nodes = int(ds.sizes["s"])
    if run["n"] != nodes:
        raise ParameterError.invalid(name, source, f"holds attribute n = {run['n']}, but its coordinate s has "
                                     f"{nodes} nodes", f"a run file as mol-shell run wrote it (n = {nodes})")
    try:
        _run_options(f"{name} = {source!r}, attribute", run, cls=type(scene))
    except ParameterError as exc:
        said = str(exc).replace(", attribute: ", ", attribute ", 1).replace("[run] ", "", 1)
        if exc.name.endswith("times"):  # the saved times are the file's coordinate, not an attribute
            said = f"{name} = {source!r} holds the saved times {exc.value}, not {exc.allowed}"
        raise ParameterError(name, source, exc.allowed, message=said) from None
    return run


def _check_points(ds, then, now, name, source):
    """Refuse, naming ``name`` (the run file ``source``) and its points file, a run on a points meridian whose file
    was edited since (its digest, in the run's ``meridian``, differs now): the scene file would run another shell,
    as ``mol-shell run --from`` of a path on it refuses to."""
    digests = [re.search(r", sha256 ([0-9a-f]+)\)$", text) for text in (then, now)]
    if "points" in ds.attrs and all(digests) and digests[0][1] != digests[1][1]:
        raise ParameterError.invalid(name, str(source or ds.encoding.get("source", "<xarray.Dataset>")),
                                     f"was run on the points file {str(ds.attrs['points'])!r}, edited since the run "
                                     f"(digest {digests[0][1]} then, {digests[1][1]} now)",
                                     "a run file whose points file is as it ran (the scene file would run another "
                                     "shell)", hint=f"the run's meridian: {then}; now: {name_text(now)}")


#: the attributes of a run file without which :func:`run_toml` cannot write it back (its scene, its integrator)
RUN_ATTRS = ("scene", "integrator")


def read_run_toml(filename, name="FILE"):
    """:func:`run_toml` of the run file ``filename`` (:func:`path_toml` of a path file), refused naming ``name`` where
    it is neither (a scene file ``FILE.toml`` said as one: :func:`refuse_scene_file`)."""
    refuse_scene_file(filename, name)
    try:
        return path_toml(read_path(filename, name), str(filename))
    except ParameterError:  # not a path (of a registered scene): read as a run, and refused as one
        pass
    what = "a mol_shell run or path file"
    ds = read_run(filename, name=name, allowed=RUN_OR_PATH_FILE, what=what)
    if str(ds.attrs.get("integrator", "")).startswith("ring-ode/"):  # simulate_ring(..., n=21): on (time, s), no run
        raise ParameterError.invalid(name, str(filename), f"is not {what}", RUN_OR_PATH_FILE,
                                     hint=f"it holds {holdings(ds)}")
    missing = [key for key in RUN_ATTRS if key not in ds.attrs]
    try:
        if missing:
            raise KeyError(missing[0])
        return run_toml(ds, name, str(filename))
    except KeyError as exc:  # attrs dropped (a file saved again without them): KeyError 'integrator', a bug
        missing = [key for key in RUN_ATTRS if key not in ds.attrs] or [str(exc.args[0] if exc.args else exc)]
        them = "them" if len(missing) > 1 else "it"
        raise ParameterError.invalid(name, str(filename), f"has no attribute {' or '.join(map(repr, missing))}: a run "
                                     f"file without {them} cannot be written back as a scene file (saved again without "
                                     "its attributes?)", RUN_OR_PATH_FILE) from None
    except ParameterError as exc:  # a run of an earlier version whose scene this one refuses: said with the file
        if exc.name == name:  # the file refused as it is (an attribute, its points file edited since): as said
            raise
        version = ds.attrs.get("mol_shell_version")
        if version is not None and str(version) == __version__:  # this version wrote it: the scene is refused as run
            raise ParameterError(exc.name, exc.value, exc.allowed, message=f"{name} = {str(filename)!r}: the run's "
                                 f"scene cannot run again: {exc}") from None
        who = f"{version} wrote it" if version is not None else "the file has no attribute 'mol_shell_version'"
        raise ParameterError(exc.name, exc.value, exc.allowed, message=f"{name} = {str(filename)!r}: the run's scene is "
                             f"refused by this version ({who}): {exc}") from None


def refuse_scene_file(filename, name="FILE"):
    """Refuse, naming ``name``, a scene file ``FILE.toml`` given where a run file is wanted (``mol-shell scenes
    FILE.toml --toml``, which writes a run file back as a scene file): it was said as "not a mol_shell run file (not
    a netCDF file)", naming the usage line's placeholder ``NAME``. Anything else passes (a run file is read as one)."""
    text = str(filename)
    if text.lower().endswith(".toml") and os.path.isfile(os.path.expanduser(text)):
        raise ParameterError.invalid(name, text, "is a scene file (TOML), not a run file", RUN_OR_PATH_FILE,
                                     hint=f"--toml writes a run file back as a scene file; mol-shell run {text} "
                                     "runs a scene file")


def path_toml(ds, source=None):
    """A scene file (:func:`~mol_shell.scenes.file_writer.scene_toml`) of the scene of path ``ds`` (``mol-shell path``'s:
    its parameters from the attrs, the continued one at the scene's own value where it gave one, else left out) with
    ``[run] n`` the path's, and comments that give the ``mol-shell path`` command tracing it again (its ``--param``
    range; where it ended short, how to go on); ``source``, the file's name for the header."""
    params, parameter = scene_params(ds), str(ds.attrs["parameter"])
    if "parameter_scene_value" in ds.attrs:
        params[parameter] = float(ds.attrs["parameter_scene_value"])
    scene = get_scene(str(ds.attrs["scene"]), **params)
    units = str(ds.attrs.get("parameter_units", ""))
    span = f"{parameter}={_exact(ds.attrs['start'])}:{_exact(ds.attrs['stop'])}"
    steps, last = ds.sizes["step"] - 1, float(ds.parameter.values[-1])
    branch = int(ds.attrs.get("branch_point", -1))
    command = f"mol-shell path THIS.toml --param {span}" + (f" --branch {branch}" if branch >= 0 else "")
    written = (f"# Written from the equilibrium path {source or ds.encoding.get('source', '')} (mol_shell "
               f"{ds.attrs.get('mol_shell_version', '?')}) in {parameter} from {float(ds.attrs['start']):g} to "
               f"{float(ds.attrs['stop']):g} {units}, {steps} steps:")
    again = f"# {command} -o PATH.nc traces it again (--steps, --max-steps as it was traced: the file does not record them)."
    if "continued_from" in ds.attrs:  # its start is a step of another path: from this scene's state a path at that
        # load may lie on another branch (a continuation past a fold)
        origin, _, where = str(ds.attrs["continued_from"]).rpartition(", step ")
        again = (f"# It was continued from {origin}, step {where}: mol-shell path --from {shlex.quote(origin)} --step "
                 f"{where.split()[0]} --stop {_exact(ds.attrs['stop'])} -o PATH.nc traces it again; {command} "
                 f"starts from this scene's state at {float(ds.attrs['start']):g} {units}, which may lie on another branch.")
    notes = [written, again]
    if not int(ds.attrs.get("complete", 1)):
        notes.append(f"# That path ended at {parameter} = {last:.6g} {units} ({ds.attrs.get('message', '')})"
                     + (f": mol-shell path --from PATH.nc --stop {_exact(ds.attrs['stop'])} goes on from its last step."
                        if ds.attrs.get("status") == "max_steps" else "."))
    if "parameter_scene_value" in ds.attrs:
        notes.append(f"# {parameter} below is the scene's own; the path's --param values replace it.")
    return scene_toml(scene, run={"n": int(ds.attrs.get("n", ds.sizes["s"]))}, notes=notes)


def _exact(value):
    """``value`` as a short number that reads back as it (``-1000``, ``-775.0123456789``)."""
    short = f"{float(value):g}"
    return short if float(short) == float(value) else repr(float(value))
