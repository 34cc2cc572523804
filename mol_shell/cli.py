"""Command line: ``mol-shell run | plot | ...`` (also ``python -m mol_shell``).

Errors in the user's input print one line naming the parameter and its allowed
range, and exit with code 2 (no traceback). A run that stops at a model limit
writes what it computed and exits with code 3.
"""

from __future__ import annotations

import argparse
import importlib
import sys

import numpy as np

from .errors import ParameterError

EXIT_USAGE, EXIT_INCOMPLETE = 2, 3

# Subcommands contributed by other modules: each module has ``register(subparsers)``
# that adds its parser with ``set_defaults(func=...)``.
EXTENSIONS = ("mol_shell.workprecision", "mol_shell.stability", "mol_shell.study")


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(EXIT_USAGE, f"mol-shell: error: {message}\n")


def parse_times_arg(text):
    """``T0:T1:DT`` (T1 included) or ``t1,t2,...`` into an array of times."""
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            if len(parts) != 3 or parts[2] <= 0 or parts[1] < parts[0]:
                raise ValueError
            t0, t1, step = parts
            count = int(np.floor((t1 - t0) / step + 1e-9)) + 1
            return t0 + step * np.arange(count)
        return np.array([float(x) for x in text.split(",") if x.strip()])
    except ValueError:
        raise ParameterError("--times", text, "T0:T1:DT with DT > 0 and T1 >= T0, or a list t1,t2,...") from None


def parse_sets(items):
    params = {}
    for item in items or []:
        if "=" not in item:
            raise ParameterError("--set", item, "NAME=VALUE")
        name, value = item.split("=", 1)
        params[name.strip()] = value.strip()
    return params


def cmd_run(args):
    from .output import write_netcdf
    from .scenes import get_scene
    from .simulate import simulate

    scene = get_scene(args.scene, **parse_sets(args.set))
    times = parse_times_arg(args.times) if args.times else None
    options = {}
    for name in ("rtol", "atol", "max_step"):
        value = getattr(args, name)
        if value is not None:
            options[name] = value
    ds = simulate(
        scene, args.integrator, n=args.n, t_end=args.t_end, times=times, dt=args.dt, progress=None, **options
    )
    write_netcdf(ds, args.output)
    if not ds.attrs["complete"]:
        print(f"mol-shell: run stopped: {ds.attrs['message']}; wrote {ds.sizes['time']} saved times to {args.output}",
              file=sys.stderr)
        return EXIT_INCOMPLETE
    print(f"wrote {args.output}: {ds.sizes['time']} times x {ds.sizes['s']} nodes, "
          f"{ds.attrs['n_steps']} steps in {ds.attrs['wall_time_s']:.3g} s, R = {ds.attrs['R']:.10g} m")
    return 0


def cmd_plot(args):
    from .output import read_netcdf
    from .plotting import plot_snapshots

    ds = read_netcdf(args.file)
    plot_snapshots(ds, args.output)
    print(f"wrote {args.output}")
    return 0


def _positive_float(name):
    def convert(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is outside (0, inf)") from None
        if not (np.isfinite(value) and value > 0):
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is outside (0, inf)")
        return value

    return convert


def parse_atol(text):
    """``--atol``: one number, or ``FIELD=VALUE,...`` per field (the others keep the default 1e-9)."""
    from .model.kinematics import FIELDS

    allowed = f"(0, inf), or FIELD=VALUE,... with FIELD in {{{', '.join(FIELDS)}}}"
    if "=" not in text:
        try:
            return _positive_float("--atol")(text)
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(f"--atol = {text!r} is outside {allowed}") from None
    out = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        name = name.strip()
        try:
            number = float(value)
        except ValueError:
            number = float("nan")
        if name not in FIELDS or not (np.isfinite(number) and number > 0):
            raise argparse.ArgumentTypeError(f"--atol = {text!r} is outside {allowed}")
        out[name] = number
    return out


def make_parser():
    from .integrators import INTEGRATORS
    from .scenes import SCENES

    parser = _Parser(prog="mol-shell", description="Rotationally symmetric motions of Cosserat shells (Antman & Bourne 2010).")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("run", help="run a scene and write netCDF")
    run.add_argument("scene", help="one of: " + ", ".join(SCENES))
    run.add_argument("--integrator", default="leapfrog", help="one of: " + ", ".join(INTEGRATORS))
    run.add_argument("--n", type=int, default=40, help="nodes in s (default 40)")
    run.add_argument("--t-end", type=_positive_float("--t-end"), default=None, help="final time, s")
    run.add_argument("--dt", type=_positive_float("--dt"), default=1e-6, help="leap-frog step, s (default 1e-6)")
    run.add_argument("--times", default=None, help="saved times: T0:T1:DT (T1 included) or t1,t2,...")
    run.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    run.add_argument("--rtol", type=_positive_float("--rtol"), default=None, help="relative tolerance (adaptive integrators)")
    run.add_argument("--atol", type=parse_atol, default=None,
                     help="absolute tolerance (adaptive integrators): one value, or per field as r=1e-9,theta=1e-10")
    run.add_argument("--max-step", type=_positive_float("--max-step"), default=None, help="largest step, s (adaptive)")
    run.add_argument("-o", "--output", required=True, help="netCDF file to write")
    run.set_defaults(func=cmd_run)
    plot = sub.add_parser("plot", help="the paper's figures 4-8 from a run's netCDF file")
    plot.add_argument("file")
    plot.add_argument("-o", "--output", required=True, help="PNG to write")
    plot.set_defaults(func=cmd_plot)
    for module in EXTENSIONS:
        try:
            importlib.import_module(module).register(sub)
        except ModuleNotFoundError as exc:  # an extension not written yet
            if exc.name != module:
                raise
    return parser


def main(argv=None):
    parser = make_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (code 2) and --help (code 0)
        return exc.code
    try:
        return args.func(args)
    except ParameterError as exc:
        print(f"mol-shell: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("mol-shell: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
