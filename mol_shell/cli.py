"""Command line: ``mol-shell run | plot | ...`` (also ``python -m mol_shell``).

Errors in the user's input print one line naming the parameter and its allowed
range, and exit with code 2 (no traceback); they are found before anything is
computed where they can be. ``-o FILE`` of every subcommand is checked first: missing
directories are created, and a place that cannot be written is refused. A run that
stops at a model limit writes what it computed and exits with code 3; one interrupted by
Ctrl-C writes what it computed too and exits with code 130.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys
import warnings

import numpy as np

from .version import __version__
from .errors import ParameterError, show

EXIT_INTERNAL, EXIT_USAGE, EXIT_INCOMPLETE, EXIT_INTERRUPTED = 1, 2, 3, 130

# Subcommands contributed by other modules: each module has ``register(subparsers)``
# that adds its parser with ``set_defaults(func=...)``.
EXTENSIONS = ("mol_shell.workprecision", "mol_shell.stability", "mol_shell.study", "mol_shell.analysis.modes",
              "mol_shell.io.export", "mol_shell.io.animate")

#: integrator options the command line offers (as --dt, --rtol, --atol, --max-step)
CLI_OPTIONS = {"dt", "rtol", "atol", "max_step"}


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        # "argument --dt: --dt = 0 is outside ..." names the option twice: keep our own message
        found = re.match(r"argument (\S+?): (.*)", message, flags=re.S)
        if found and any(found.group(2).startswith(opt + " ") for opt in found.group(1).split("/")):
            message = found.group(2)
        self.exit(EXIT_USAGE, f"mol-shell: error: {message}\n")


def parse_range_or_list(text, name, words=("T0", "T1", "DT"), item="t", count_check=None):
    """``A:B:STEP`` (``B`` included; ``(B - A)/STEP`` a whole number) or ``v1,v2,...`` into a list of floats.

    Generated values are rounded to 12 significant digits, so ``0:0.009:0.003`` gives values that
    ``ds.sel`` finds as typed. Empty entries are refused. ``count_check(count)``, if given, is called
    with the number of values before a range is expanded (``0:1:1e-12`` would be 1e12 of them).
    """
    a, b, d = words
    form = f"{a}:{b}:{d} ({b} included, {d} > 0, ({b} - {a})/{d} whole) or {item}1,{item}2,..."
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        try:
            if len(parts) != 3:
                raise ValueError
            start, stop, step = (float(x) for x in parts)
        except ValueError:
            raise ParameterError(name, text, form) from None
        if not (np.isfinite([start, stop, step]).all() and step > 0 and stop > start):
            raise ParameterError(name, text, form)
        count = (stop - start) / step
        if not np.isfinite(count):
            raise ParameterError.invalid(name, text, f"has more values than can be counted (({b} - {a})/{d} = "
                                         f"{count:g})", form)
        whole = round(count)
        if abs(count - whole) > 1e-9 * max(1.0, count):
            raise ParameterError.invalid(name, text, f"does not end on its grid: ({b} - {a})/{d} = {count:.4g} "
                                         f"is not whole ({b} is included)", form)
        if count_check is not None:
            count_check(whole + 1)
        return [float(f"{start + k * step:.12g}") for k in range(whole + 1)]
    items = [x.strip() for x in text.split(",")]
    if not text or any(not x for x in items):
        raise ParameterError.invalid(name, text, "has an empty entry" if text else "is empty", form)
    try:
        return [float(x) for x in items]
    except ValueError:
        raise ParameterError(name, text, form) from None


def parse_times_arg(text, name="--times", n=None):
    """``T0:T1:DT`` (T1 included) or ``t1,t2,...`` into an array of times.

    With ``n`` (nodes), a range whose output would not fit in memory is refused before it is expanded.
    """
    from .resources import check_saved_times

    check = (lambda count: check_saved_times(count, n, name=name, value=str(text))) if n is not None else None
    return np.array(parse_range_or_list(text, name, count_check=check))


def parse_sets(items, name="--set"):
    params = {}
    for item in items or []:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ParameterError(name, item, "NAME=VALUE")
        if key in params:
            raise ParameterError.invalid(name, item, f"sets {key} a second time", "each parameter once")
        params[key] = value.strip()
    return params


def _number_text(text):
    """A number as typed, for messages (``0``, not ``'0'``); anything else quoted."""
    try:
        float(text)
        return str(text).strip()
    except ValueError:
        return show(text)


def number_arg(name, low=0.0, high=np.inf, *, low_closed=False, high_closed=False, unit=""):
    """An argparse ``type``: a float in the interval, or a one-line error naming ``name`` and the interval."""
    allowed = f"{'[' if low_closed else '('}{low:g}, {high:g}{']' if high_closed else ')'}" + (f" {unit}" if unit else "")

    def convert(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not a number; allowed: {allowed}") from None
        above = value >= low if low_closed else value > low
        below = value <= high if high_closed else value < high
        if not (np.isfinite(value) and above and below):
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is outside {allowed}")
        return value

    return convert


def integer_arg(name, low=1):
    """An argparse ``type``: an integer ``>= low``."""
    allowed = f"integers >= {low}"

    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {_number_text(text)} is not an integer; allowed: {allowed}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{name} = {value} is outside {allowed}")
        return value

    return convert


def choice_arg(name, options):
    """An argparse ``type``: one of ``options``, or a one-line error naming ``name`` and the options."""

    def convert(text):
        if text not in options:
            raise argparse.ArgumentTypeError(f"{name} = {show(text)} is outside {{{', '.join(options)}}}")
        return text

    return convert


def parse_atol(text):
    """``--atol``: one number, or ``FIELD=VALUE,...`` per field (the others keep the default 1e-9)."""
    from .model.kinematics import FIELDS

    allowed = f"(0, inf), or FIELD=VALUE,... with FIELD in {{{', '.join(FIELDS)}}}"
    if "=" not in text:
        try:
            return number_arg("--atol")(text)
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(f"--atol = {_number_text(text)} is outside {allowed}") from None
    out = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        name = name.strip()
        try:
            number = float(value)
        except ValueError:
            number = float("nan")
        if name not in FIELDS or name in out or not (np.isfinite(number) and number > 0):
            raise argparse.ArgumentTypeError(f"--atol = {text!r} is outside {allowed}, each field once")
        out[name] = number
    return out


def integrator_option_args(args):
    """``--dt/--rtol/--atol/--max-step`` given on the command line, as options."""
    return {k: getattr(args, k) for k in ("dt", "rtol", "atol", "max_step") if getattr(args, k, None) is not None}


def cmd_run(args):
    from .output import write_netcdf
    from .scenes import get_scene
    from .simulate import check_options, simulate

    run = {}
    if args.scene.endswith(".toml"):  # a scene file: its [run] table gives defaults, the options win
        from .scenes import with_params
        from .scenes.files import load_scene

        scene, run = load_scene(args.scene, with_run=True)
        scene = with_params(scene, parse_sets(args.set))
    else:
        scene = get_scene(args.scene, **parse_sets(args.set))
    times = parse_times_arg(args.times, n=args.n or run.get("n", 40)) if args.times else None
    if args.t_end is None and times is None:  # --t-end or --times replace both of the file's
        times = run.get("times")
    t_end = args.t_end if args.t_end is not None or args.times else run.get("t_end")
    integrator = args.integrator or run.get("integrator", "leapfrog")
    options = {k: run[k] for k in ("dt", "rtol", "atol", "max_step") if k in run} | integrator_option_args(args)
    check_options(scene, integrator, options, offered=CLI_OPTIONS)
    ds = simulate(scene, integrator, n=args.n or run.get("n", 40), t_end=t_end, times=times, progress=None,
                  stresses=args.stresses, **options)
    write_netcdf(ds, args.output)
    if not ds.attrs["complete"]:
        print(f"mol-shell: run stopped: {ds.attrs['message']}; wrote {ds.sizes['time']} saved times to {args.output}",
              file=sys.stderr)
        return EXIT_INTERRUPTED if ds.attrs["status"] == "interrupted" else EXIT_INCOMPLETE
    print(f"wrote {args.output}: {ds.sizes['time']} times x {ds.sizes['s']} nodes, "
          f"{ds.attrs['n_steps']} steps in {ds.attrs['wall_time_s']:.3g} s"
          + (f", R = {ds.attrs['R']:.10g} m" if isinstance(ds.attrs.get("R"), (int, float, np.number)) else ""))
    if str(ds.attrs.get("stresses", "")).startswith("skipped"):
        print(f"stresses {ds.attrs['stresses']} (or run with --stresses)")
    return 0


#: options of ``plot --figure fibres`` only
FIBRE_OPTIONS = ("time", "at_s", "fibres", "thickness_scale")


def cmd_plot(args):
    from .output import read_run

    given = [name for name in FIBRE_OPTIONS if getattr(args, name) is not None]
    if args.figure != "fibres" and given:
        option = "--" + given[0].replace("_", "-")
        raise ParameterError(option, getattr(args, given[0]), "options of --figure fibres only",
                             message=f"{option} is an option of --figure fibres only (its options: --time, --at-s, "
                             "--fibres, --thickness-scale)")
    ds = read_run(args.file)
    if args.figure == "fibres":
        from .io.figures import plot_fibres

        options = {"time": args.time, "s": args.at_s, "thickness_scale": args.thickness_scale}
        plot_fibres(ds, args.output, count=24 if args.fibres is None else args.fibres, **options)
    else:
        from .plotting import is_cylinder, plot_meridian, plot_snapshots

        (plot_snapshots if is_cylinder(ds) else plot_meridian)(ds, args.output)
    print(f"wrote {args.output}")
    return 0


def cmd_scenes(args):
    import dataclasses

    from .scenes import DESCRIPTIONS, SCENES, UNITS

    if args.name is None:
        if args.toml:
            raise ParameterError.missing("NAME", "give mol-shell scenes NAME --toml, NAME in {" + ", ".join(sorted(SCENES)) + "}")
        for name, cls in SCENES.items():
            print(f"{name:18s} {(cls.__doc__ or '').strip().splitlines()[0]}")
        print("mol-shell scenes NAME lists a scene's parameters; set them with --set NAME=VALUE")
        return 0
    if args.name not in SCENES:
        raise ParameterError("scene", args.name, "{" + ", ".join(sorted(SCENES)) + "}")
    cls = SCENES[args.name]
    if args.toml:
        from .scenes.files import scene_toml

        print(scene_toml(cls), end="")
        return 0
    print(f"{args.name}: {(cls.__doc__ or '').strip().splitlines()[0]}")
    for f in dataclasses.fields(cls):
        default = f.default if f.default is not dataclasses.MISSING else "(required)"
        default = "auto" if default is None else default
        print(f"  {f.name:11s} {str(default):>22s}  {UNITS.get(f.name, '1'):8s} {DESCRIPTIONS.get(f.name, '')}")
    return 0


def _image_formats():
    from .plotting import image_formats

    return image_formats()


def make_parser():
    from .integrators import INTEGRATORS
    from .scenes import SCENES

    parser = _Parser(prog="mol-shell", description="Rotationally symmetric motions of Cosserat shells (Antman & Bourne 2010).")
    parser.add_argument("--version", action="version", version=f"mol-shell {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("run", help="run a scene and write netCDF")
    run.add_argument("scene", metavar="SCENE_OR_FILE", help="one of: " + ", ".join(SCENES) + "; or a scene file FILE.toml")
    run.add_argument("--integrator", default=None, help="one of: " + ", ".join(INTEGRATORS) + " (default leapfrog)")
    run.add_argument("--n", type=integer_arg("--n", 3), default=None, help="nodes in s (default 40)")
    run.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None, help="final time, s")
    run.add_argument("--dt", type=number_arg("--dt", unit="s"), default=None,
                     help="leap-frog step, s (default 1e-6); adaptive integrators refuse it")
    run.add_argument("--times", default=None, help="saved times: T0:T1:DT (T1 included) or t1,t2,...")
    run.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    run.add_argument("--rtol", type=number_arg("--rtol", 1e-14, 1.0, low_closed=True), default=None,
                     help="relative tolerance in [1e-14, 1) (adaptive integrators)")
    run.add_argument("--atol", type=parse_atol, default=None,
                     help="absolute tolerance (adaptive integrators): one value, or per field as r=1e-9,theta=1e-10")
    run.add_argument("--max-step", type=number_arg("--max-step", unit="s"), default=None, help="largest step, s (adaptive)")
    run.add_argument("--stresses", action=argparse.BooleanOptionalAction, default=None,
                     help="resultants and face stresses after the run (default: when cell samples x saved times "
                     "<= 4e6; --stresses always, --no-stresses never)")
    run.add_argument("-o", "--output", required=True, help="netCDF file to write (missing directories are created)")
    run.set_defaults(func=cmd_run)
    scenes = sub.add_parser("scenes", help="the built-in scenes, or one scene's parameters with units and defaults")
    scenes.add_argument("name", nargs="?", default=None, help="a scene to describe")
    scenes.add_argument("--toml", action="store_true", help="print the scene's defaults as a scene file to start from")
    scenes.set_defaults(func=cmd_scenes)
    plot = sub.add_parser("plot", help="the paper's figures 4-8 (cylinders), the deformed meridian (other shells) "
                          "or figure 1 (--figure fibres) from a run")
    plot.add_argument("file", metavar="FILE", help="netCDF file written by mol-shell run")
    plot.add_argument("--figure", type=choice_arg("--figure", ("snapshots", "fibres")), default="snapshots",
                      help="snapshots: r, theta, chi against s (figures 4-8, default); fibres: a section with its "
                      "material fibres in the reference state and at --time (figure 1)")
    plot.add_argument("--time", type=number_arg("--time", 0.0, low_closed=True, unit="s"), default=None,
                      help="fibres: the saved time nearest to this (default the last)")
    plot.add_argument("--at-s", type=number_arg("--at-s", -np.inf, unit="m"), default=None,
                      help="fibres: the section at the node nearest to this s (default the first node)")
    plot.add_argument("--fibres", type=integer_arg("--fibres", 1), default=None, help="fibres: how many (default 24)")
    plot.add_argument("--thickness-scale", type=number_arg("--thickness-scale"), default=None,
                      help="fibres: magnification of the drawn thickness (default: 0.2 of the radius)")
    plot.add_argument("-o", "--output", required=True, help="image to write (.png, .pdf, .svg, ...)")
    plot.set_defaults(func=cmd_plot, output_suffixes=_image_formats)
    for module in EXTENSIONS:
        try:
            importlib.import_module(module).register(sub)
        except ModuleNotFoundError as exc:  # an extension not written yet
            if exc.name != module:
                raise
    return parser


def _remove_empty(folders):
    """Remove the directories this command created, deepest first, if nothing was written into them."""
    import os

    for folder in reversed(folders):
        try:
            os.rmdir(folder)
        except OSError:
            return


def main(argv=None):
    parser = make_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (code 2), --help and --version (code 0)
        return exc.code
    created = []  # directories made for -o: removed again if the command is refused
    try:
        with warnings.catch_warnings():
            from .resources import LongRunWarning

            # the command line reports a stopped run in its own one line (and in the file's attrs); warnings
            # about a run's projected time are one line each, as errors are
            warnings.simplefilter("ignore", RuntimeWarning)
            warnings.simplefilter("always", LongRunWarning)
            warnings.showwarning = _one_line_warning
            if getattr(args, "output", None) is not None:  # every subcommand: before anything is computed
                from .output import writable_path

                suffixes = getattr(args, "output_suffixes", None)
                writable_path(args.output, "-o", suffixes=suffixes() if callable(suffixes) else suffixes, created=created)
            return args.func(args)
    except ParameterError as exc:
        _remove_empty(created)
        print(f"mol-shell: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("mol-shell: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # noqa: BLE001 - the last resort: one line, never a traceback (unless asked for)
        import os

        if os.environ.get("MOL_SHELL_TRACEBACK"):
            raise
        text = " ".join(str(exc).split())[:300]
        print(f"mol-shell: internal error: {type(exc).__name__}: {text} (a bug of mol_shell: please report it with "
              "the command; MOL_SHELL_TRACEBACK=1 shows where it happened)", file=sys.stderr)
        return EXIT_INTERNAL


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    print(f"mol-shell: warning: {message}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
