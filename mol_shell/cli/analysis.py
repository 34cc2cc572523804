"""Commands of the analyses: compare (work-precision), stability, modes."""

from __future__ import annotations

import sys
import time

import numpy as np

from mol_shell._core.atomic import write_text
from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import beside, writable_path
from mol_shell.analysis.grid_modes import GRID_MODE_SHARE
from mol_shell.analysis.mode_zero import located_band
from mol_shell.analysis.modes import modes
from mol_shell.analysis.stability import FULL_SIZES, QUICK_SIZES, default_cases, report
from mol_shell.analysis.stability import markdown_table as stability_table
from mol_shell.analysis.workprecision import (
    MAX_REPEATS,
    PAPER_TIMES,
    check_integrators,
    markdown_table,
    reference_said,
    work_precision,
)
from mol_shell.cli.args import (
    NETCDF_SUFFIXES,
    SCENE_HELP,
    SCENE_METAVAR,
    as_stopped,
    integer_arg,
    interrupted_code,
    number_arg,
    plural,
    say_stand_ins,
    scene_and_run,
)
from mol_shell.cli.inputs import check_companions, check_outputs
from mol_shell.cli.path import add_start_options, not_an_equilibrium, say_start, start_of
from mol_shell.results.dataset import write_netcdf
from mol_shell.runs.building import parse_times
from mol_shell.views.figures import image_formats
from mol_shell.views.modes import plot_modes
from mol_shell.views.stability_plot import plot_report
from mol_shell.views.workprecision import companion_files, write_outputs


def register_compare(subparsers):
    parser = subparsers.add_parser("compare", help="work-precision: error against run time for integrators")
    parser.add_argument("scene", metavar=SCENE_METAVAR, help=SCENE_HELP)
    parser.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    parser.add_argument("--integrators", default=None,
                        help="comma-separated list (default: all but sksundae-cvode-bdf and sksundae-ida, 0.5.0's "
                        "Python-loop routes, which take minutes at tight tolerances, and for a scene with loads or "
                        "driven edges but those that cannot run them, said as they are left out)")
    parser.add_argument("--n", type=integer_arg("--n", 3), default=None,
                        help="nodes in s (default: a scene file's [run] n, else 40)")
    parser.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None,
                        help="final time, s; saved times then 0, t_end/4, ..., t_end (default: a scene file's [run] "
                        "times or t_end, else the paper's snapshots); leap-frog steps whose grid misses them are skipped")
    parser.add_argument("--repeats", type=integer_arg("--repeats", 1, MAX_REPEATS), default=3,
                        help=f"timed repeats per point, 1 to {MAX_REPEATS} (median; default 3)")
    parser.add_argument("--target", type=number_arg("--target"), default=1e-6,
                        help="error of the summary table (default 1e-6)")
    parser.add_argument("-o", "--output", required=True,
                        help="netCDF file, .nc; .png and .md written beside it (missing directories are created)")
    parser.set_defaults(func=cmd_compare, output_suffixes=NETCDF_SUFFIXES)


def cmd_compare(args):
    text = None if args.integrators is None else args.integrators.strip()
    names = None if text is None else check_integrators([s.strip() for s in text.split(",")] if text else [],
                                                        "--integrators")
    scene, run = scene_and_run(args.scene, args.set)
    t_end = args.t_end if args.t_end is not None else run.get("t_end")
    if args.t_end is None and run.get("times") is not None:  # the file's saved times (they were left out)
        times = [float(t) for t in run["times"]]
    else:
        # t_end checked as run checks it (1e-320 reached the reference runs, which failed at t = 0: exit 3)
        times = PAPER_TIMES if t_end is None else parse_times(None, t_end, intervals=4).tolist()
    check_companions(args, companion_files(args.output))
    start = time.perf_counter()
    ds = work_precision(scene, names, n=args.n or run.get("n", 40), times=times, repeats=args.repeats, progress=None)
    if ds.attrs.get("status") == "interrupted":  # by a SIGTERM: said so, as run's (it said "by the user")
        ds.attrs["message"] = as_stopped(str(ds.attrs["message"]))
    png, md = write_outputs(ds, args.output, args.target)
    say_stand_ins(scene)
    if ds.attrs.get("reference_check_status", "complete") != "complete":  # the reference kept: how well it is known
        print(f"mol-shell: note: {reference_said(ds.attrs, ds.attrs['reference_error'])}", file=sys.stderr)
    print(markdown_table(ds, args.target))
    if ds.attrs.get("status") == "interrupted":
        print(f"mol-shell: comparison stopped: {ds.attrs['message']}; wrote {args.output}, {png}, {md}",
              file=sys.stderr)
        return interrupted_code()
    print(f"wrote {args.output}, {png}, {md} in {time.perf_counter() - start:.0f} s")
    return 0


def register_stability(subparsers):
    parser = subparsers.add_parser("stability", help="stability report on stiff and extreme cases")
    parser.add_argument("scene", metavar=SCENE_METAVAR, help="base scene for the cases: " + SCENE_HELP)
    parser.add_argument("--set", action="append", metavar="NAME=VALUE", help="base scene parameter, repeatable")
    left_out = " and ".join(str(n) for n in FULL_SIZES if n not in QUICK_SIZES)
    parser.add_argument("--quick", action="store_true",
                        help=f"leave out the grid cases n = {left_out} (every other case, to n = {max(QUICK_SIZES)}, "
                        "runs as in the full report): for twisted-cylinder about 1 min on two idle cores with the "
                        "kernels cached, 1.5 min from an empty kernel cache, twice that or more on a busy machine (the "
                        "full report: 8 min)")
    parser.add_argument("--no-bisect", action="store_true", help="skip the leap-frog step bisection")
    parser.add_argument("-o", "--output", required=True, help="netCDF file, .nc; a .md table and .png plot beside it")
    parser.unknown_note = (f"the report runs its own cases, each with its own n (40; the grid cases n = "
                           f"{', '.join(map(str, FULL_SIZES))}, --quick to n = {max(QUICK_SIZES)}), times and "
                           "integrators; the base scene's parameters by --set NAME=VALUE")
    parser.set_defaults(func=cmd_stability, output_suffixes=NETCDF_SUFFIXES)


def cmd_stability(args):
    scene, run = scene_and_run(args.scene, args.set)
    png, md = companion_files(args.output)  # as compare's: the figure and the table beside the file
    check_companions(args, [png, md])
    ds = report(default_cases(scene, quick=args.quick), bisect=not args.no_bisect)
    ds.attrs["quick"] = int(args.quick)  # what was run: the grid cases left out (--quick) or not
    if ds.attrs.get("status") == "interrupted":  # by a SIGTERM: said so, as run's (it said "by the user")
        ds.attrs["message"] = as_stopped(str(ds.attrs["message"]))
    say_stand_ins(scene)
    if run:  # the file's [run] n = 12 was dropped without a word: the report's cases set their own
        print(f"mol-shell: note: the stability report runs its own cases (each with its own n, times and "
              f"integrators); {args.scene}'s [run] table ({', '.join(sorted(run))}) is not used", file=sys.stderr)
    write_netcdf(ds, args.output)
    write_text(md, stability_table(ds) + "\n")
    plot_report(ds, png)
    print(stability_table(ds))
    if ds.attrs.get("status") == "interrupted":
        print(f"mol-shell: stability report stopped: {ds.attrs['message']}; wrote {args.output}, {png}, {md}",
              file=sys.stderr)
        return interrupted_code()
    skipped = int(ds.attrs.get("cases_not_measured", 0))
    print(f"wrote {args.output}, {png}, {md}" + (f" ({plural(skipped, 'case')} not measured: why, under the table)"
                                                 if skipped else ""))
    return 0


def cmd_modes(args):
    scene, run, initial, info, source = start_of(args)
    given = args.png is not None  # --png '' is refused as empty (it was the default figure)
    png = writable_path(args.png if given else beside(args.output, ".png"), "--png",
                        suffixes=image_formats())
    if given:  # the figure is not the --from file either
        check_outputs(args, name="--png", value=png)
    else:
        check_outputs(args, [png])
    try:
        band = located_band(source, args.point) if source is not None and args.point is not None else 0.0
        ds = modes(scene, n=args.n or run.get("n", 40), count=args.count, initial=initial, zero_band=band)
    except ParameterError as exc:
        if hasattr(exc, "residual") and initial is not None:  # a path's state, named by --point, --set or --from
            raise not_an_equilibrium(args, exc, source) from None
        raise
    say_start(args, ds, info, "the modes are about", source)
    for note in str(ds.attrs.get("loads_at_rest", "")).splitlines():  # a load on a history: taken at t = 0
        print(f"mol-shell: note: {note}", file=sys.stderr)
    say_stand_ins(scene)
    write_netcdf(ds, args.output)
    plot_modes(ds, png)
    print(f"wrote {args.output} and {png}: {plural(ds.sizes['mode'], 'mode')}, "
          f"{plural(int(ds.attrs['zero_modes']), 'rigid motion')}; lowest {_frequency(ds, 0).strip()}")
    for m in range(ds.sizes["mode"]):  # every mode the file holds (--count asked for them)
        share = ds.energy_fraction.isel(mode=m).values
        grid = float(ds.grid_mode_share[m]) if "grid_mode_share" in ds else 0.0  # a file of before it: none
        mark = f"; grid mode (-1)^i: {grid:.2f}" if grid >= GRID_MODE_SHARE else ""
        print(f"  mode {m + 1:2d}: {_frequency(ds, m)}  ({FIELDS[int(np.argmax(share))]}, "
              f"{share.max():.0%} of the kinetic energy{mark})")
    return 0


def _frequency(ds, m):
    """Mode ``m``'s frequency in rad/s, or, unstable (omega^2 < 0, frequency NaN), its omega^2 and growth rate."""
    if np.isfinite(float(ds.frequency[m])) or "omega_squared" not in ds:
        return f"{float(ds.frequency[m]):14.8g} rad/s"
    w2 = float(ds.omega_squared[m])
    return f"unstable: omega^2 = {w2:.6g} s-2 (grows as exp({np.sqrt(-w2):.6g} t / s))"


def register_modes(sub):
    p = sub.add_parser("modes", help="natural frequencies and mode shapes about a scene's initial state")
    p.add_argument("scene", metavar=SCENE_METAVAR, nargs="?", default=None,
                   help=SCENE_HELP + "; its initial state must be at rest and in equilibrium")
    add_start_options(p)
    p.add_argument("--n", type=integer_arg("--n", 3), default=None,
                   help="nodes in s (default: a scene file's [run] n, else 40)")
    p.add_argument("--count", type=integer_arg("--count", 1), default=10, help="lowest nonzero modes (default 10)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="scene parameter, repeatable")
    p.add_argument("--png", default=None, help="figure of the lowest shapes (default: beside -o, .png)")
    p.add_argument("-o", "--output", required=True, help="netCDF file to write, .nc")
    p.set_defaults(func=cmd_modes, output_suffixes=NETCDF_SUFFIXES)
