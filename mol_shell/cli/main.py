"""Command line: ``mol-shell run | plot | ...`` (also ``python -m mol_shell``).

Errors in the user's input print one line naming the parameter and its allowed
range, and exit with code 2 (no traceback); they are found before anything is
computed where they can be. ``-o FILE`` of every subcommand is checked first: missing
directories are created, and a place that cannot be written, or a file the command reads (``FILE``, ``--from``),
is refused. A run that
stops at a model limit writes what it computed and exits with code 3; one interrupted by
Ctrl-C writes what it computed too and exits with code 130. Output cut short by its reader
(``mol-shell scenes | head -1``) ends quietly with code 141; output that cannot be written (``> /dev/full``) is
refused in one line with code 2, as an ``-o`` that cannot be. Warnings (a long run, a material law
out of its range) are one line each, ``mol-shell: warning: ...``; notes (a built-in stand-in for
data a user is expected to give) ``mol-shell: note: ...``.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import warnings

import numpy as np

from mol_shell._core.constants import RTOL_RANGE
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import writable_path
from mol_shell._core.user_files import not_regular
from mol_shell._core.version import __version__
from mol_shell.analysis.run_scene import read_run_toml, refuse_scene_file
from mol_shell.cli.analysis import register_compare, register_modes, register_stability
from mol_shell.cli.args import (
    EXIT_INCOMPLETE,
    NETCDF_SUFFIXES,
    RTOL_ALLOWED,
    SCENE_HELP,
    SCENE_METAVAR,
    Parser,
    as_stopped,
    checked_late,
    choice_arg,
    integer_arg,
    interrupted_code,
    max_step_arg,
    number_arg,
    parse_atol,
    plural,
    refuse_late,
    run_settings,
    say_stand_ins,
    unchecked_number_arg,
)
from mol_shell.cli.inputs import check_outputs
from mol_shell.cli.outcome import (
    OutputError,
    exits_after_its_exit_functions,
    guarded,
    missing_stdout,
    one_line_warnings,
    said,
    said_in_teardown,
    traceback_asked,
)
from mol_shell.cli.path import (
    add_start_options,
    cmd_plot_path,
    cmd_plot_path_study,
    looks_like_path,
    looks_like_path_study,
    register_path,
    say_off_equilibrium,
    say_start,
    start_of,
)
from mol_shell.cli.study import register_study
from mol_shell.cli.views import read_drawable, register_animate, register_export, said_as_options, said_incomplete
from mol_shell.discretization import kernel_cache
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.peers import SCIPY_RTOL_MIN
from mol_shell.integrators.tolerances import ATOL_RANGE, Tolerances
from mol_shell.results.dataset import write_netcdf
from mol_shell.results.stresses import nan_stresses
from mol_shell.runs.simulate import NO_SPACE_FOR_STRESSES, simulate
from mol_shell.scenes import SCENES, summary
from mol_shell.scenes.file_writer import scene_toml
from mol_shell.scenes.listing import parameter_listing
from mol_shell.views.fibres import MAX_FIBRES, plot_fibres
from mol_shell.views.figures import image_formats
from mol_shell.views.history import plot_history
from mol_shell.views.plotting import plot_meridian, plot_snapshots, shows_history


def cmd_run(args):
    scene, run, initial, info, source = start_of(args)  # a scene file's [run] table gives defaults, the options win
    times, t_end, integrator, options = run_settings(args, run, scene, args.n or run.get("n", 40))
    say_off_equilibrium(args, scene, args.n or run.get("n", 40), initial)
    ds = simulate(scene, integrator, n=args.n or run.get("n", 40), t_end=t_end, times=times, progress=None,
                  stresses=args.stresses, initial=initial, **options)
    say_start(args, ds, info, "the run starts from", source)
    if ds.attrs["status"] == "interrupted":  # by a SIGTERM (a scheduler's time limit): the file says so
        ds.attrs["message"] = as_stopped(str(ds.attrs["message"]))
    write_netcdf(ds, args.output)
    say_stand_ins(scene)
    if not ds.attrs["complete"]:
        print(f"mol-shell: run stopped: {ds.attrs['message']}; wrote {plural(ds.sizes['time'], 'saved time')} to "
              f"{args.output}",
              file=sys.stderr)
        return interrupted_code() if ds.attrs["status"] == "interrupted" else EXIT_INCOMPLETE
    print(f"wrote {args.output}: {plural(ds.sizes['time'], 'time')} x {ds.sizes['s']} nodes, "
          f"{plural(int(ds.attrs['n_steps']), 'step')} in {ds.attrs['wall_time_s']:.3g} s" + radius_said(ds, info))
    nan, total, why = nan_stresses(ds)
    if nan:  # NaN in a run file is never unflagged: attrs["stresses"] says why, and so does this line
        print(f"mol-shell: note: {nan} of {total} stress samples (saved time x cell x face) are NaN; "
              f"attrs['stresses'] of {args.output} says why: {why}", file=sys.stderr)
    why = str(ds.attrs.get("stresses", ""))
    if why.startswith("skipped") and not why.startswith(NO_SPACE_FOR_STRESSES):  # that one warned already
        print(f"stresses {why}" + (" (or run with --stresses)" if "exceed the limit" in why else ""))
    return 0


def radius_said(ds, given=None):
    """``, R = ... m`` of a run's summary: with what the start is where the code computed it (the static equilibrium
    under the loads, and where a spin or a drive was then set on it, that too, as ``attrs["initial_state"]`` says it)
    or a start was ``given`` (a path's state): ``R`` is then the start's radius, its mean where ``r(t = 0)`` is not
    one number."""
    R = ds.attrs.get("R")
    if not isinstance(R, (int, float, np.number)):
        return ""
    initial = str(ds.attrs.get("initial_state", ""))
    how = given or ("the static equilibrium under the loads" if initial.startswith("static") else "")
    moving = initial.partition("; then set moving")[2]  # a spin or a drive set on it: said as the file's attrs say
    if how and not given and moving:
        how += "; then set moving" + moving
    if not how or "R_requested" not in ds.attrs:
        return f", R = {R:.10g} m"
    r0 = ds.r.isel(time=0).values
    return f", R = {R:.10g} m (the start's {'radius' if np.all(r0 == r0[0]) else 'mean radius'}: {how})"


#: what ``plot`` reads, as its refusal of another file says
PLOT_FILES = "a netCDF file written by mol-shell run, mol-shell path or mol-shell study --path"
PLOT_WHAT = "a mol_shell run, path or path-study file"
#: options of ``plot`` and the figures that take them (``--at-s``: also the default figure of a shell that draws
#: its radius over time)
FIGURE_OPTIONS = {"time": ("fibres",), "at_s": ("fibres", "history"), "fibres": ("fibres",),
                  "thickness_scale": ("fibres",)}


def cmd_plot(args):
    if looks_like_path(args.file):
        return cmd_plot_path(args)
    if looks_like_path_study(args.file):
        return cmd_plot_path_study(args)
    if args.response is not None:
        raise ParameterError("--response", args.response, "an option of a path's figure (mol-shell path files)",
                             message="--response is an option of a path's figure (files of mol-shell path) only")
    ds = read_drawable(args.file, PLOT_FILES, PLOT_WHAT)
    history = shows_history(ds)
    for name, figures in FIGURE_OPTIONS.items():
        value = getattr(args, name)
        takes = args.figure in figures or (name == "at_s" and args.figure == "snapshots" and history)
        if value is not None and not takes:
            option = "--" + name.replace("_", "-")
            where = " or ".join(f"--figure {f}" for f in figures)
            only = (f"an option of {where} only" if name != "at_s" else "an option of --figure fibres, of --figure "
                    "history and of the default figure of a shell that is not an unloaded cylinder, not of the "
                    "paper's figures 4-8")
            raise ParameterError(option, value, f"options of {where}",
                                 message=f"{option} is {only} (options of --figure fibres: --time, --at-s, --fibres, "
                                 "--thickness-scale; of --figure history: --at-s)")
    refuse_late(args, FIGURE_OPTIONS)  # their values, once the figure is known to take them
    with said_as_options():
        if args.figure == "fibres":
            options = {"time": args.time, "s": args.at_s, "thickness_scale": args.thickness_scale}
            plot_fibres(ds, args.output, count=24 if args.fibres is None else args.fibres, **options)
        elif args.figure == "history":
            plot_history(ds, args.output, s=args.at_s)
        elif history:
            plot_meridian(ds, args.output, s=args.at_s)
        else:
            plot_snapshots(ds, args.output)
    print(f"wrote {args.output}{said_incomplete(ds)}")
    return 0


def cmd_scenes(args):

    if args.name is None:
        if args.toml:
            raise ParameterError.missing("name", "give mol-shell scenes NAME --toml, NAME a scene in {"
                                         + ", ".join(sorted(SCENES)) + "} or a run file RUN.nc")
        for name, cls in SCENES.items():
            print(f"{name:18s} {summary(cls)}")
        print("mol-shell scenes NAME lists a scene's parameters; set them with --set NAME=VALUE", file=sys.stderr)  # a hint: stdout lists scenes only
        return 0
    allowed = "a scene in {" + ", ".join(sorted(SCENES)) + "} or a run file RUN.nc (with --toml)"  # as docs/cli.md
    odd = not_regular(args.name) if args.name not in SCENES else None
    if odd is not None:  # a directory, a named pipe (never opened: reading one waited for a writer), a device
        raise ParameterError.invalid("FILE", args.name, odd, allowed)
    if args.name not in SCENES and (os.path.splitext(args.name)[1].lower().lstrip(".") in NETCDF_SUFFIXES
                                    or os.path.isfile(args.name)):  # a run file: a scene file that runs it again
        refuse_scene_file(args.name)  # a scene file FILE.toml, with --toml or without: said as one
        if not args.toml:
            raise ParameterError("--toml", False, "--toml with a run file", message=f"give mol-shell scenes "
                                 f"{args.name} --toml: a run file is written back as a scene file")
        print(read_run_toml(args.name), end="")
        return 0
    if args.name not in SCENES and (os.sep in args.name or os.path.splitext(args.name)[1]):  # a file, not there
        raise ParameterError.invalid("FILE", args.name, "does not exist", allowed)
    if args.name not in SCENES:
        raise ParameterError("scene", args.name, "{" + ", ".join(sorted(SCENES)) + "} (or a run file RUN.nc, "
                             "with --toml)")
    cls = SCENES[args.name]
    if args.toml:
        print(scene_toml(cls), end="")
        return 0
    print("\n".join(parameter_listing(cls)))
    return 0


def _image_formats():
    return image_formats()


def make_parser():
    parser = Parser(prog="mol-shell", description="Rotationally symmetric motions of Cosserat shells (Antman & Bourne 2010).")
    parser.add_argument("--version", action="version", version=f"mol-shell {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    run = sub.add_parser("run", help="run a scene and write netCDF",
                         description="Run a scene and write netCDF. A scene file's [run] table gives the defaults of "
                         "--integrator, --n, --t-end, --times, --dt, --rtol, --atol, --max-step and --option; the options win.")
    run.add_argument("scene", metavar=SCENE_METAVAR, nargs="?", default=None, help=SCENE_HELP)
    run.add_argument("--integrator", default=None, help="one of: " + ", ".join(INTEGRATORS)
                     + " (default: a scene file's [run] integrator, else leapfrog)")
    run.add_argument("--n", type=integer_arg("--n", 3), default=None,
                     help="nodes in s (default: a scene file's [run] n, else 40)")
    run.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None,
                     help="final time, s (default: a scene file's [run] t_end or times)")
    run.add_argument("--dt", type=checked_late("--dt", number_arg("--dt", unit="s")), default=None,
                     help="leap-frog step, s (default: a scene file's [run] dt, else 1e-6); adaptive integrators "
                     "refuse it")
    run.add_argument("--times", default=None, help="saved times: T0:T1:DT (T1 included) or t1,t2,...")
    run.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    # the integrator's options: their values checked once the integrator is known to take them (run_settings)
    run.add_argument("--rtol", type=checked_late("--rtol", unchecked_number_arg("--rtol", RTOL_ALLOWED)),
                     default=None,
                     help=f"relative tolerance in [{RTOL_RANGE[0]:g}, {RTOL_RANGE[1]:g}), default {Tolerances.rtol:g} "
                     f"(adaptive integrators; the scipy peers from {SCIPY_RTOL_MIN:.4g}, SciPy's floor)")
    run.add_argument("--atol", type=checked_late("--atol", parse_atol), default=None,
                     help=f"absolute tolerance in {ATOL_RANGE}, default {Tolerances.atol:g} (adaptive integrators): "
                     "absolute, in the state's units (m for z and r, rad for chi, theta and psi; their rates, m/s and "
                     "rad/s, for the momenta, which are scaled by their mass); one value, or per field as "
                     "r=1e-9,theta=1e-10")
    run.add_argument("--max-step", type=checked_late("--max-step", max_step_arg()), default=None,
                     help="largest step, s (adaptive; 0: unbounded, the default)")
    run.add_argument("--option", action="append", metavar="NAME=VALUE",
                     help="another option of the integrator, repeatable: restart=0 (leapfrog), jac_every=200, "
                     "linsolver=band, iteration=newton, ... (docs/integrators.md; as a scene file's [run] keys)")
    run.add_argument("--stresses", action=argparse.BooleanOptionalAction, default=None,
                     help="resultants and face stresses after the run (default: when cell samples x saved times "
                     "<= 4e6; --stresses always, --no-stresses never)")
    run.add_argument("-o", "--output", required=True,
                     help="netCDF file to write, .nc (missing directories are created)")
    add_start_options(run, perturb=True)
    run.set_defaults(func=cmd_run, output_suffixes=NETCDF_SUFFIXES)
    scenes = sub.add_parser("scenes", help="the built-in scenes, or one scene's parameters with units and defaults")
    scenes.add_argument("name", nargs="?", default=None,
                        help="a scene to describe, or a run or path file RUN.nc (with --toml)")
    scenes.add_argument("--toml", action="store_true", help="print the scene's defaults as a scene file to start from; "
                        "of a run file RUN.nc, a scene file whose run (mol-shell run FILE.toml) runs it again; of a "
                        "path file, its scene, with the mol-shell path command that traces it again")
    scenes.set_defaults(func=cmd_scenes)
    plot = sub.add_parser("plot", help="the paper's figures 4-8 (unloaded cylinders), the deformed meridian with the "
                          "radius and the energy-work balance over time (other shells, pressurised ones), figure 1 "
                          "(--figure fibres) or the radius and balance alone (--figure history) from a run")
    plot.add_argument("file", metavar="FILE", help=PLOT_FILES.replace("a netCDF", "netCDF"))
    plot.add_argument("--figure", type=choice_arg("--figure", ("snapshots", "fibres", "history")), default="snapshots",
                      help="snapshots (default): r, theta, chi against s (figures 4-8) for a cylinder without pressure, "
                      "else the deformed meridian, chi and psi against s, the radius at the equator against time and "
                      "the energy-work balance; fibres: a section with its material fibres in the reference state "
                      "and at --time (figure 1); history: the radius against time and the energy-work balance")
    plot.add_argument("--time", type=checked_late("--time", number_arg("--time", 0.0, low_closed=True, unit="s")), default=None,
                      help="fibres: the saved time nearest to this (default the last)")
    plot.add_argument("--at-s", type=checked_late("--at-s", number_arg("--at-s", -np.inf, unit="m")), default=None,
                      help="fibres: the section at the node nearest to this s (default the first node, or on a shell with a "
                      "pole there the widest section); history and "
                      "the meridian figure: the radius drawn over time at the node nearest to this s (default the "
                      "equator: the node of largest reference radius, the middle one where several have it, as on "
                      "a vessel's cylinder)")
    plot.add_argument("--fibres", type=checked_late("--fibres", integer_arg("--fibres", 1, MAX_FIBRES)), default=None,
                      help=f"fibres: how many, 1 to {MAX_FIBRES} (default 24)")
    plot.add_argument("--thickness-scale", type=checked_late("--thickness-scale", number_arg("--thickness-scale")), default=None,
                      help="fibres: magnification of the drawn thickness, up to the section's radius over the wall's "
                      "thickness (the drawn wall at most as thick as the radius; default: 0.2 of the radius)")
    plot.add_argument("--response", default=None, help="a path file (mol-shell path): the response the load is drawn "
                      "against, a variable along step (default load_conjugate) or FIELD@S (a field at the node "
                      "nearest S, S in [0, L] m: the meridian's arc length)")
    plot.add_argument("-o", "--output", required=True, help="image to write (.png, .pdf, .svg, ...)")
    plot.set_defaults(func=cmd_plot, output_suffixes=_image_formats)
    for register in (register_compare, register_stability, register_study, register_modes, register_export,
                     register_animate, register_path):
        register(sub)
    return parser


#: a negative number as argparse does not know it (``-1e-6``, ``-inf``: its own pattern takes ``-1`` and ``-.5`` only)
_NEGATIVE = re.compile(r"-(?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?|-inf|-nan", re.IGNORECASE)


def negative_values_attached(argv):
    """``--dt -1e-6`` as ``--dt=-1e-6``: argparse would read ``-1e-6`` as an option and refuse ``--dt`` for want of
    a value, naming no range; attached, the value reaches the option's own check."""
    out = []
    for token in argv:
        if out and _NEGATIVE.fullmatch(token) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv=None):
    return guarded(_command, argv)


def entry():
    """The ``mol-shell`` program (and ``python -m mol_shell``): :func:`main`, then a Ctrl-C or SIGTERM until the
    process exits said as one that stopped the command (:func:`~mol_shell.cli.outcome.said_in_teardown`), which
    exits once Python has called its exit functions, without the teardown in which those signals killed it
    (:func:`~mol_shell.cli.outcome.exits_after_its_exit_functions`). Standard descriptors the caller closed are held
    first (:func:`hold_closed_descriptors`)."""
    hold_closed_descriptors()
    return exits_after_its_exit_functions(said_in_teardown(main()))


def hold_closed_descriptors():
    """Open ``/dev/null`` on each of the descriptors 0, 1, 2 that the caller closed (``2>&-``), so that no file this
    command opens takes its number: C libraries (netCDF, HDF5, SUNDIALS) write their messages to descriptor 2, which
    would then be the middle of a netCDF file being written. ``sys.stderr`` stays ``None`` (Python's own sign that the
    stream is closed, which the command's output follows)."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            null = os.open(os.devnull, os.O_RDWR)  # the lowest free number: the closed one, or one below it
            if null != fd:
                os.dup2(null, fd)
                os.close(null)


def _command(argv):
    # the command line draws into files only; matplotlib reads this when (and if) a command imports it, so a
    # run does not pay matplotlib's import (0.1 s)
    os.environ["MPLBACKEND"] = "Agg"
    parser = make_parser()
    try:
        args = parser.parse_args(negative_values_attached(sys.argv[1:] if argv is None else list(argv)))
    except SystemExit as exc:  # usage errors (code 2), --help and --version (code 0)
        return exc.code
    created = []  # directories made for -o: removed again if the command is refused
    try:
        with warnings.catch_warnings():
            # the command line reports a stopped run in its own one line (and in the file's attrs)
            warnings.simplefilter("ignore", RuntimeWarning)
            one_line_warnings()
            traceback_asked()  # its value refused in one line as the command starts, not where a bug would read it
            kernel_cache.check_opt_level()  # as the command starts, not where a right-hand side is first built
            if getattr(args, "output", None) is None and missing_stdout():  # scenes: its product is what it prints
                raise OutputError("standard output", f"it is closed, and mol-shell {args.command} prints what it "
                                  "lists there")
            if getattr(args, "output", None) is not None:  # every subcommand: before anything is computed
                suffixes = getattr(args, "output_suffixes", None)
                writable_path(args.output, "-o", suffixes=suffixes() if callable(suffixes) else suffixes, created=created)
                check_outputs(args)  # not over the command's input (the files beside it: where the command knows them)
            code = args.func(args)
            sys.stdout.flush()  # here, where a reader that has gone (| head -1) can be told from a bug
            return code
    except (Exception, KeyboardInterrupt) as exc:  # noqa: BLE001 - said in one line (a bug too), never a traceback
        return said(exc, args, created)




if __name__ == "__main__":
    sys.exit(main())
