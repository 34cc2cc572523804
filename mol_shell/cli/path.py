"""``mol-shell path``: an equilibrium path in one load, its stability and critical points, to netCDF."""

from __future__ import annotations

import math
import os
import shlex
import sys

import numpy as np

from mol_shell._core.errors import ParameterError, show
from mol_shell.analysis.equilibria import PATH_PARAMETERS
from mol_shell.analysis.modes import off_equilibrium
from mol_shell.analysis.path import path
from mol_shell.analysis.path_continue import continue_named
from mol_shell.analysis.path_inputs import STEPS_MAX
from mol_shell.analysis.path_start import ALLOWED, FLAGS, is_path, path_start, read_path
from mol_shell.cli.args import (
    EXIT_INCOMPLETE,
    NETCDF_SUFFIXES,
    SCENE_HELP,
    SCENE_METAVAR,
    Once,
    as_stopped,
    checked_late,
    integer_arg,
    interrupted_code,
    number_arg,
    parse_sets,
    plural,
    refuse_late,
    say_stand_ins,
    scene_and_run,
)
from mol_shell.cli.views import said_as_options
from mol_shell.results.dataset import read_netcdf, write_netcdf
from mol_shell.runs.building import build, resolve
from mol_shell.runs.simulate import starting_state
from mol_shell.scenes import DISPLACEMENTS, with_params
from mol_shell.views.figures import path_note
from mol_shell.views.path_plot import check_response, plot_path, response_values
from mol_shell.views.path_study_plot import is_path_study, plot_path_study

PARAM_FORM = "NAME=START:STOP with NAME in {" + ", ".join(PATH_PARAMETERS) + "}, START and STOP numbers, START != STOP"


class _OneParameter(Once):
    """``--param`` given at most once: a path follows one parameter (a second ``--param`` replaced the first)."""

    why = "a path follows one parameter; vary the others with study"


def parse_param(text, option="--param"):
    """``NAME=START:STOP`` into ``(name, start, stop)``; anything else is refused naming ``option``."""
    name, sep, span = str(text).partition("=")
    name = name.strip()
    if not sep or name not in PATH_PARAMETERS:
        raise ParameterError(option, text, PARAM_FORM)
    parts = span.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        start, stop = (float(x) for x in parts)
    except ValueError:
        raise ParameterError(option, text, PARAM_FORM) from None
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise ParameterError(option, text, PARAM_FORM)
    return name, start, stop


#: the keywords of :func:`mol_shell.analysis.path.path` (and of ``path_study``), as their refusals name them, and the
#: options of ``mol-shell path`` (and ``study --path``) that set them
PATH_OPTIONS = {"steps": "--steps", "max_steps": "--max-steps", "branch": "--branch"}


def as_path_option(exc, args, param="--param"):
    """``exc``, a refusal of :func:`~mol_shell.analysis.path.path` or ``path_study``, said by the command line's option
    that set the value it names (``max_steps = ...`` as ``--max-steps = ...``; the range by ``param``, ``--param`` or
    ``--path``); else ``exc`` (``n``, which a scene file's ``[run] n`` may set, is said as every command says it)."""
    if exc.name in ("parameter", "start", "stop"):  # said by the option --param
        text = getattr(args, param.lstrip("-"))
        return ParameterError(param, text, exc.allowed, message=f"{param} = {show(text)}: {exc}")
    option = PATH_OPTIONS.get(exc.name)
    if option is None:
        return exc
    text = str(exc)
    said = option + text[len(exc.name):] if text.startswith(exc.name + " ") else f"{option}: {text}"
    return ParameterError(option, exc.value, exc.range or exc.allowed, message=said)


def not_located(step):
    """How a point the secant did not close on (``point_located = 0``) is marked: where its estimate lies."""
    return f"; not located: the search's last estimate, between steps {step} and {step + 1}"


def _continued(args):
    """``(scene, name, start, stop, ds)`` of ``mol-shell path --from OLD.nc --stop X [--step K]``: the path of the
    file followed on from its step (:func:`~mol_shell.analysis.path_continue.continue_path`)."""
    for option, value, why in (("SCENE_OR_FILE", args.scene, "the path's scene is the file's"),
                               ("--param", args.param, "the load and its start are the path's (STOP: --stop)"),
                               ("--set", args.set, ("the path's scene is the file's (a changed scene's equilibria "
                                                    "are not the path's)"))):
        if value is not None:
            raise ParameterError(option, value, "nothing with --from", message=f"{option} is not taken with --from "
                                 f"PATH.nc: {why}")
    refuse_late(args, ("step", "stop"))  # their values, once the options are known to be taken
    if args.stop is None:
        raise ParameterError.missing("--stop", "give --stop X with --from PATH.nc (where the continued load goes)")
    source = read_path(args.from_path)
    if args.n is not None and args.n != source.sizes["s"]:
        raise ParameterError("--n", args.n, f"{{{source.sizes['s']}}} with --from (the path's nodes)")
    try:
        ds = continue_named(source, args.stop, FLAGS, step=args.step, steps=args.steps, max_steps=args.max_steps,
                            branch=args.branch)
    except ParameterError as exc:
        if exc.name == "initial" or getattr(exc, "residual", None):  # the file's state at the step, Newton's start
            step = source.sizes["step"] - 1 if args.step is None else args.step  # (out of equilibrium under its
            said = getattr(exc, "residual", None) or str(exc).partition(': ')[2]  # scene): the file is what is wrong
            raise ParameterError.invalid("--from", args.from_path, f"holds a state at step {step} that is no "
                                         f"equilibrium under its scene ({said})", ALLOWED) from None
        if exc.name == "parameter":  # the file's continued load, which no --param named
            raise ParameterError.invalid("--from", args.from_path, f"continues {exc.value!r}, which this scene "
                                         f"cannot ({exc.allowed})", ALLOWED) from None
        if exc.name in ("stop", "start"):  # start is the step's load: a stop equal to it is --stop's
            allowed = str(exc.allowed).replace("start", "the step's load")
            raise ParameterError("--stop", args.stop, allowed, message=f"--stop = {args.stop:.10g} is outside "
                                 f"{allowed}") from None
        raise as_path_option(exc, args) from None
    ds.attrs["continued_from"] = ds.attrs["continued_from"].replace("<xarray.Dataset>", os.path.abspath(args.from_path))
    return source.attrs["scene"], str(source.attrs["parameter"]), float(ds.parameter.values[0]), args.stop, ds


def cmd_path(args):
    if args.from_path is not None:
        scene, name, start, stop, ds = _continued(args)
    else:
        for option, value in (("--stop", args.stop), ("--step", args.step)):
            if value is not None:
                raise ParameterError(option, value, "an option with --from PATH.nc",
                                     message=f"{option} is an option with --from PATH.nc only")
        refuse_late(args, ("step", "stop"))
        if args.scene is None or args.param is None:
            missing = "SCENE_OR_FILE" if args.scene is None else "--param"
            raise ParameterError.missing(missing, "give a scene (or a scene file) and --param NAME=START:STOP, or "
                                         "--from PATH.nc and --stop X")
        name, start, stop = parse_param(args.param)
        scene, run = scene_and_run(args.scene, args.set)  # a scene file's [run] n is the default of --n
        n = args.n or run.get("n", 40)
        try:
            ds = path(scene, name, start, stop, n=n, steps=args.steps, max_steps=args.max_steps, branch=args.branch)
        except ParameterError as exc:
            raise as_path_option(exc, args) from None
    if ds.attrs["status"] == "interrupted":  # by a SIGTERM (a scheduler's time limit): the file says so
        ds.attrs["message"] = as_stopped(str(ds.attrs["message"]))
    write_netcdf(ds, args.output)
    if args.from_path is None:
        say_stand_ins(scene)
    if "parameter_replaced" in ds.attrs:  # --param pressure=... on a scene that sets a pressure of its own
        print(f"mol-shell: note: {ds.attrs['parameter_replaced']}", file=sys.stderr)
    for note in str(ds.attrs.get("loads_at_rest", "")).splitlines():  # another load on a history: taken at t = 0
        print(f"mol-shell: note: {note}", file=sys.stderr)
    states = ds.sizes["step"]  # the start is the first of them
    summary = (f"{plural(states, 'state')} ({plural(states - 1, 'step')}) from {name} = {start:g} to {float(ds.parameter[-1]):.6g} "
               f"{ds.parameter.attrs['units']}, {plural(ds.sizes['point'], 'critical point')}")
    past = "; past the loss of ellipticity: the grid's"
    edge, _, moved = name.partition("_")  # an edge displacement (end2_dz): its reaction beside each point
    held = f"point_{edge}_reaction_{'force' if moved == 'dz' else 'torque'}"
    reactions = ds[held].values if name in DISPLACEMENTS and held in ds else [None] * ds.sizes["point"]
    points = "".join(f"\n  {kind} at {name} = {value:.6g} ({family}"
                     + ("" if reaction is None else f"; reaction {reaction:.6g} {ds[held].attrs['units']}")
                     + f"{past if margin <= 0 else ''}{'' if located else not_located(step)})"
                     for kind, value, family, margin, reaction, located, step in zip(
                         ds.point_kind.values, ds.point_parameter.values, ds.point_family.values,
                         ds.point_ellipticity_margin.values, reactions, ds.point_located.values,
                         ds.point_step.values))
    if ds.attrs["status"] in ("failed", "limit", "interrupted"):
        print(f"mol-shell: path stopped: {ds.attrs['message']}; wrote {summary} to {args.output}{points}",
              file=sys.stderr)
        return interrupted_code() if ds.attrs["status"] == "interrupted" else EXIT_INCOMPLETE
    print(f"wrote {args.output}: {summary} ({ds.attrs['message']}){points}")
    if "; no switch: " in ds.attrs["message"]:  # --branch asked for what the path could not do
        print(f"mol-shell: note: --branch {args.branch}: {ds.attrs['message'].partition('; no switch: ')[2]}",
              file=sys.stderr)
    if ds.attrs["status"] in ("max_steps", "returned"):  # what was asked for, but short of STOP: exit 0, said
        print(f"mol-shell: note: the path did not reach {name} = {stop:g}: {ds.attrs['message']}"
              + (f" (to go on from its last step: mol-shell path --from {shlex.quote(str(args.output))} --stop "
                 f"{stop!r})"
                 if ds.attrs["status"] == "max_steps" else ""), file=sys.stderr)
    return 0


def register_path(sub):
    p = sub.add_parser("path", help="equilibrium path in one load through limit points, with stability and "
                       "critical points")
    p.add_argument("scene", metavar=SCENE_METAVAR, help=SCENE_HELP + " (or --from PATH.nc)", nargs="?")
    p.add_argument("--param", metavar="NAME=START:STOP", action=_OneParameter,
                   help="the continued load or edge displacement and its range, NAME in {"
                   + ", ".join(PATH_PARAMETERS) + "}")
    p.add_argument("--n", type=integer_arg("--n", 3), default=None,
                   help="nodes in s (default: a scene file's [run] n, else 40)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    p.add_argument("--steps", type=integer_arg("--steps", 1, STEPS_MAX), default=20,
                   help="the first step covers 1/STEPS of the range (default 20; the later ones adapt): more for a "
                   "path whose start the first step overshoots")
    p.add_argument("--max-steps", type=integer_arg("--max-steps", 1), default=200,
                   help="the path ends after this many steps (default 200); short of STOP it says so in a note on "
                   "stderr and in attrs status = max_steps, complete = 0, and exits 0")
    p.add_argument("--branch", type=integer_arg("--branch", 0), default=None, metavar="K",
                   help="switch onto the branch leaving bifurcation point K (numbered from 0 as found) and follow it")
    p.add_argument("--from", dest="from_path", metavar="PATH.nc", default=None,
                   help="go on along a path written by mol-shell path, from its last step (or --step K) to --stop X, "
                   "in place of SCENE_OR_FILE and --param: the path's scene and load")
    p.add_argument("--step", type=checked_late("--step", integer_arg("--step", 0)), default=None,
                   help="with --from: the step to go on from (default: the last)")
    p.add_argument("--stop", type=checked_late("--stop", number_arg("--stop", -np.inf)), default=None,
                   help="with --from: where the continued load goes (in the path's units)")
    p.add_argument("-o", "--output", required=True,
                   help="netCDF file to write, .nc (missing directories are created)")
    p.set_defaults(func=cmd_path, output_suffixes=NETCDF_SUFFIXES)


# -- starting a run or modes from a path ------------------------------------------------------------------------
#: the options of a start from a path (their values checked once the command knows it starts from one)
START_OPTIONS = ("step", "point", "perturb")


def add_start_options(p, perturb=False):
    """``--from PATH.nc`` with ``--step K`` or ``--point K`` (and ``--perturb A`` for a run) on command ``p``."""
    p.add_argument("--from", dest="from_path", metavar="PATH.nc", default=None,
                   help="start from an equilibrium path written by mol-shell path (in place of SCENE_OR_FILE: the "
                   "path's scene, its load at the state's value, --set on top)")
    p.add_argument("--step", type=checked_late("--step", integer_arg("--step", 0)), default=None,
                   help="with --from: the path's step K")
    p.add_argument("--point", type=checked_late("--point", integer_arg("--point", 0)), default=None,
                   help="with --from: the path's critical point K")
    if perturb:
        p.add_argument("--perturb", type=checked_late("--perturb", number_arg("--perturb", -math.inf)), default=None,
                       help="with --from and --point: add this amplitude times the critical mode (its largest "
                       "entry 1, m or rad)")


def start_of(args):
    """``(scene, run, initial, info, source)`` of a command with :func:`add_start_options`: a scene (file) and its
    ``[run]`` table as usual (``initial``, ``info`` and ``source`` None), or a path's state with ``{"n": the path's
    n}`` and ``source``, the path as read (once: :func:`say_start` and :func:`not_an_equilibrium` take it)."""
    perturb = getattr(args, "perturb", None)
    if args.from_path is None:
        for option, value in (("--step", args.step), ("--point", args.point), ("--perturb", perturb)):
            if value is not None:
                raise ParameterError(option, value, "an option with --from PATH.nc",
                                     message=f"{option} is an option with --from PATH.nc only")
        refuse_late(args, START_OPTIONS)
        if args.scene is None:
            raise ParameterError.missing("SCENE_OR_FILE", "give a scene, a scene file or --from PATH.nc")
        scene, run = scene_and_run(args.scene, args.set)
        return scene, run, None, None, None
    if args.scene is not None:
        raise ParameterError("--from", args.from_path, "a path file in place of SCENE_OR_FILE",
                             message=f"give SCENE_OR_FILE ({args.scene}) or --from PATH.nc, not both")
    refuse_late(args, START_OPTIONS)
    ds = read_path(args.from_path)
    scene, n, fields, info = path_start(ds, step=args.step, point=args.point, perturb=perturb or 0.0, names=FLAGS)
    if args.n is not None and args.n != n:
        raise ParameterError("--n", args.n, f"{{{n}}} with --from (the path's nodes)")
    return with_params(scene, parse_sets(args.set)), {"n": n}, fields, info, ds


def _unlocated(args, source):
    """``(ds, k)`` when the command starts from a critical point ``k`` the path ``source`` (``--from``, as
    :func:`start_of` read it) did not locate (``--point K``, ``point_located = 0``; a file written before that
    variable: every point located), else ``(None, None)``."""
    if source is None or args.point is None:
        return None, None
    located = source["point_located"].values[args.point] if "point_located" in source else 1
    return (None, None) if int(located) else (source, args.point)


def unlocated_note(args, source, subject="the modes are about"):
    """A note for modes (or a run: ``subject``) about a critical point the path ``source`` did not locate (an
    equilibrium, but not a critical one), else ``""``."""
    ds, k = _unlocated(args, source)
    if ds is None:
        return ""
    step = int(ds.point_step.values[k])
    return (f"critical point {k} was not located (point_located = 0): {subject} the search's last estimate, "
            f"an equilibrium at {ds.attrs['parameter']} = {float(ds.point_parameter[k]):.6g} "
            f"{ds.attrs.get('parameter_units', '')} between steps {step} and {step + 1} whose crossing eigenvalue is "
            f"{float(ds.point_eigenvalue[k]):.3g} s-2 (0 at a located point; --step {step} or --step {step + 1} for a step's)")


def say_start(args, ds, info, subject, source=None):
    """What ``run`` or ``modes`` (``subject``: "the run starts from", "the modes are about") tell of a start from a
    path (``source``, as :func:`start_of` read it): ``info`` into ``initial_state`` (with "not located" at a point
    the path did not locate), and a note for that point and for initial data the path's state stands in for
    (``initial_data_note``)."""
    note = unlocated_note(args, source, subject)
    if info:
        ds.attrs["initial_state"] = info + ("; not located (point_located = 0): the search's last estimate"
                                            if note else "")
    if source is not None and args.from_path is not None:  # the path file, as a continued path's continued_from
        ds.attrs["started_from"] = started_from(args, source)
    for said in (note, ds.attrs.get("initial_data_note")):
        if said:
            print(f"mol-shell: note: {said}", file=sys.stderr)


def say_off_equilibrium(args, scene, n, initial):
    """A note on stderr where a run ``--from`` a path's step or critical point (``initial``, its fields) starts out
    of equilibrium under its scene (``scene``: the path's, ``--set`` on top), with the residual modes would refuse it
    by: a file edited since, or loads moved by ``--set`` (a dynamic run from there is legitimate: it starts moving).
    Not for a state perturbed on purpose (``--perturb``)."""
    if initial is None or getattr(args, "perturb", None):
        return
    try:
        scene = resolve(scene)  # as the run takes it (R = auto computed)
        system, _ = build(scene, n)
        where = off_equilibrium(system, starting_state(scene, system, n, initial=initial)[0])
    except ParameterError:  # refused by the run, which says it as it does
        return
    if where:
        print(f"mol-shell: note: the state at {_where(args)} of {args.from_path} is out of equilibrium under the run's "
              f"scene ({where}): the run starts moving from it", file=sys.stderr)


def _where(args):
    return f"step {args.step}" if args.step is not None else f"critical point {args.point}"


def started_from(args, source):
    """``started_from`` of a run or modes analysis ``--from`` the path ``source`` (the file ``args.from_path``): its
    absolute name, the step (or critical point) and its load, ``"/abs/p.nc, step 6 of 21 (pressure = 1251.4 Pa)"``."""
    if args.step is not None:
        where, count, value = f"step {args.step}", source.sizes["step"], float(source.parameter.values[args.step])
    else:
        where, count = f"critical point {args.point}", source.sizes.get("point", 0)
        value = float(source.point_parameter.values[args.point])
    perturbed = f", perturbed by {float(args.perturb):g} x its critical mode" if getattr(args, "perturb", None) else ""
    return (f"{os.path.abspath(args.from_path)}, {where} of {count} ({source.attrs['parameter']} = {value:.10g} "
            f"{source.attrs.get('parameter_units', '')}){perturbed}")


def not_an_equilibrium(args, exc, source=None):
    """The refusal of a ``--from`` state that modes found out of equilibrium (``exc``, named ``initial``), named by
    what chose the state: ``--point`` (a point the path ``source``, as :func:`start_of` read it, did not locate: its
    last estimate, from a path written before the search kept only equilibria), ``--set`` (loads moved off the
    path's), or the file."""
    residual = exc.residual
    ds, k = _unlocated(args, source)
    if ds is not None:
        step = int(ds.point_step.values[k])
        return ParameterError.invalid(
            "--point", k, f"is a critical point the path did not locate (point_located = 0): its state, the search's "
            f"last estimate between steps {step} and {step + 1}, is no equilibrium ({residual})",
            f"a located critical point, or a step: --step {step} or --step {step + 1} (the steps around it)")
    where = f"step {args.step}" if args.step is not None else f"critical point {args.point}"
    if args.set:
        return ParameterError.invalid("--set", " ".join(args.set), f"takes the path's state at {where} out of "
                                      f"equilibrium ({residual})", "settings that keep the path's loads (the modes "
                                      "are taken about an equilibrium)")
    return ParameterError.invalid("--from", args.from_path, f"holds a state at {where} that is no equilibrium under "
                                  f"its scene ({residual})", ALLOWED)


# -- the figure of a path ---------------------------------------------------------------------------------------
def looks_like_path(filename):
    """Whether ``filename`` is a readable path file (anything else goes to the run figures and their checks)."""
    try:
        return is_path(read_netcdf(filename))
    except Exception:  # noqa: BLE001 - not a readable netCDF file: the run reader refuses it by name
        return False


def looks_like_path_study(filename):
    """Whether ``filename`` is a readable study of paths (``mol-shell study ... --path``)."""
    try:
        return is_path_study(read_netcdf(filename))
    except Exception:  # noqa: BLE001 - not a readable netCDF file: the run reader refuses it by name
        return False


def _refuse_run_options(args, theirs):
    for option, value in (("--figure", None if args.figure == "snapshots" else args.figure), ("--time", args.time),
                          ("--at-s", args.at_s), ("--fibres", args.fibres),
                          ("--thickness-scale", args.thickness_scale)):
        if value is not None:
            raise ParameterError(option, value, "options of run files",
                                 message=f"{option} is an option of a run's figures; {theirs}")


def cmd_plot_path_study(args):
    """``mol-shell plot STUDY.nc`` of a study of paths: critical loads against the varied parameter."""
    _refuse_run_options(args, "a study of paths' figure takes none")
    if args.response is not None:
        raise ParameterError("--response", args.response, "an option of a path's figure (mol-shell path files)",
                             message="--response is an option of a path's figure; a study of paths' figure takes none")
    ds = read_netcdf(args.file)
    plot_path_study(ds, args.output)
    short = int(sum(str(v) not in ("complete", "") for v in np.ravel(ds["status"].values))) if "status" in ds else 0
    print(f"wrote {args.output}" + (f" [ENDED SHORT: {short} of {ds['status'].size} paths (marked)]" if short else ""))
    return 0


def cmd_plot_path(args):
    _refuse_run_options(args, "a path's: --response")
    ds = read_path(args.file, "FILE")
    response = "load_conjugate" if args.response is None else args.response  # '' refused, not the default
    with said_as_options():
        check_response(ds, response)
        response_values(ds, response)
        plot_path(ds, args.output, response)
    states = ds.sizes["step"]  # the start and its steps, counted as mol-shell path counts them
    note = path_note(ds.attrs, float(ds.parameter.values[-1]))
    print(f"wrote {args.output}: {ds.attrs['parameter']} against {response}, {plural(states, 'state')} "
          f"({plural(states - 1, 'step')}), {plural(ds.sizes['point'], 'critical point')}"
          + (f" [{note}]" if note else ""))
    return 0
