"""``mol-shell path``: an equilibrium path in one load, its stability and critical points, to netCDF."""

from __future__ import annotations

import math
import sys

from mol_shell._core.errors import ParameterError, show
from mol_shell.analysis.equilibria import PATH_LOADS
from mol_shell.analysis.path import path
from mol_shell.cli.args import (
    EXIT_INCOMPLETE,
    NETCDF_SUFFIXES,
    SCENE_HELP,
    SCENE_METAVAR,
    integer_arg,
    say_stand_ins,
    scene_and_run,
)
from mol_shell.results.dataset import write_netcdf

PARAM_FORM = "NAME=START:STOP with NAME in {" + ", ".join(PATH_LOADS) + "}, START and STOP numbers, START != STOP"


def parse_param(text):
    """``NAME=START:STOP`` into ``(name, start, stop)``; anything else is refused naming ``--param``."""
    name, sep, span = str(text).partition("=")
    name = name.strip()
    if not sep or name not in PATH_LOADS:
        raise ParameterError("--param", text, PARAM_FORM)
    parts = span.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        start, stop = (float(x) for x in parts)
    except ValueError:
        raise ParameterError("--param", text, PARAM_FORM) from None
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise ParameterError("--param", text, PARAM_FORM)
    return name, start, stop


def cmd_path(args):
    name, start, stop = parse_param(args.param)
    scene, run = scene_and_run(args.scene, args.set)  # a scene file's [run] n is the default of --n
    n = args.n or run.get("n", 40)
    try:
        ds = path(scene, name, start, stop, n=n, max_steps=args.max_steps)
    except ParameterError as exc:
        if exc.name in ("parameter", "start", "stop"):  # said by the option --param
            raise ParameterError("--param", args.param, exc.allowed, message=f"--param = {show(args.param)}: {exc}") \
                from None
        raise
    write_netcdf(ds, args.output)
    say_stand_ins(scene)
    summary = (f"{ds.sizes['step']} steps from {name} = {start:g} to {float(ds.parameter[-1]):.6g} "
               f"{ds.parameter.attrs['units']}, {ds.sizes['point']} critical points")
    points = "".join(f"\n  {kind} at {name} = {value:.6g} ({family})" for kind, value, family in
                     zip(ds.point_kind.values, ds.point_parameter.values, ds.point_family.values))
    if ds.attrs["status"] in ("failed", "limit"):
        print(f"mol-shell: path stopped: {ds.attrs['message']}; wrote {summary} to {args.output}{points}",
              file=sys.stderr)
        return EXIT_INCOMPLETE
    print(f"wrote {args.output}: {summary} ({ds.attrs['message']}){points}")
    return 0


def register_path(sub):
    p = sub.add_parser("path", help="equilibrium path in one load through limit points, with stability and "
                       "critical points")
    p.add_argument("scene", metavar=SCENE_METAVAR, help=SCENE_HELP)
    p.add_argument("--param", required=True, metavar="NAME=START:STOP",
                   help="the continued load and its range, NAME in {" + ", ".join(PATH_LOADS) + "}")
    p.add_argument("--n", type=integer_arg("--n", 3), default=None, help="nodes in s (default 40)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    p.add_argument("--max-steps", type=integer_arg("--max-steps", 1), default=200,
                   help="the path ends after this many steps (default 200)")
    p.add_argument("-o", "--output", required=True,
                   help="netCDF file to write, .nc (missing directories are created)")
    p.set_defaults(func=cmd_path, output_suffixes=NETCDF_SUFFIXES)
