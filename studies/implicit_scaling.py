"""Cost of the implicit integrators against the grid size n, up to n = 10,240.

Two cases of the paper scene, saved at [0, t_end]:

* ``viscous`` (eta_mu = 1000 Pa s, eta_lambda = 2000 Pa s, t_end = 0.01 s): the twist front is
  smoothed by viscosity, so the number of BDF steps hardly depends on n, while the explicit bound
  shrinks like ds^2 (leap-frog is refused: its parasitic root grows the damped modes);
* ``elastic`` (the paper's material, t_end = 0.002 s): the front released at the free ends stays
  as sharp as the grid, so accuracy asks for steps ~ 1/ds, as for leap-frog's CFL bound.

For each: steps, Jacobian evaluations, wall time of the integration (graph built, compiled code
cached), time per step and per simulated second, the fitted exponent of cost against n, and
leap-frog at half its stability bound (elastic case) for comparison. Each point is timed as the best of
its repeats: at least --repeats of them (default 1; 3 with --quick), and more until they add up to 50 ms, so
that runs of a millisecond are not timed once; the exponents are given with their spread (fitted to the
fastest and the slowest repeats). Writes OUT/implicit_scaling.nc, .png and .md. ``main`` returns the Dataset.
Usage: python studies/implicit_scaling.py [--sizes 40,160,640,2560,10240] [--integrators cvode-bdf,ida]
                                          [--repeats 1] [--quick] [--out out] [--output FILE.nc]
(--quick: n = 40, 80 and CVODE-BDF only; about 20 s once the Jacobians are compiled and cached. Its exponents,
from two sizes and runs of milliseconds, say little: the spread printed beside them says how little.)
"""

import os
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

import mol_shell  # noqa: E402
from mol_shell._core.paths import beside
from mol_shell.cli.args import integer_arg
from mol_shell.cli.scripts import (
    MIN_NODES,
    integers_arg,
    output_file,
    output_folder,
    run_script,
    script_parser,
    simulate,
)
from mol_shell.results.cf import described

CASES = {
    "viscous": (mol_shell.TwistedCylinder(eta_mu=1000.0, eta_lambda=2000.0), 0.01),
    "elastic": (mol_shell.TwistedCylinder(), 0.002),
}
QUICK = {"sizes": [40, 80], "integrators": "cvode-bdf", "repeats": 3}
SIZES = [40, 160, 640, 2560, 10240]
STATS = ("n_steps", "n_jac", "wall_time_s", "wall_per_step_s", "wall_per_sim_second_s", "dt_bound_s",
         "wall_time_max_s", "n_repeats")
#: a point's repeats go on until their wall times add up to this (s), so that a run of 1 ms is not timed once
TIMED_S = 0.05
#: at most this many repeats of a point
MAX_REPEATS = 200
#: units and long_name of every variable of OUT/implicit_scaling.nc
MEANINGS = {
    "case": (None, "scene: viscous or elastic paper scene"), "integrator": (None, "integrator"),
    "n": ("1", "nodes in s"), "n_steps": ("1", "steps taken"), "n_jac": ("1", "Jacobian evaluations"),
    "wall_time_s": ("s", "wall time of the integration, best of the repeats"),
    "wall_time_max_s": ("s", "wall time of the integration, slowest of the repeats"),
    "n_repeats": ("1", "timed repeats of the run"),
    "wall_per_step_s": ("s", "wall time per step (best of the repeats)"),
    "wall_per_sim_second_s": ("s", "wall time per simulated second (best of the repeats)"),
    "dt_bound_s": ("s", "leap-frog stability bound 1/max|eig J(y0)|"),
}


def measure(scene, integrator, n, t_end, repeats=1):
    """One point: the run timed at least ``repeats`` times, and until the times add up to :data:`TIMED_S`; the
    best of them is its wall time (``wall_time_max_s``: the slowest)."""
    options = {"rtol": 1e-6, "atol": 1e-9} if integrator != "leapfrog" else {}
    if integrator == "leapfrog":  # half the bound, the step count rounded up
        ds0 = simulate(scene, "cvode-bdf", n=n, times=[0.0, 1e-9], progress=False)
        dt = 0.5 * ds0.attrs["leapfrog_dt_bound_s"]
        options["dt"] = t_end / np.ceil(t_end / dt)
    walls = []
    while len(walls) < min(repeats, MAX_REPEATS) or (sum(walls) < TIMED_S and len(walls) < MAX_REPEATS):
        ds = simulate(scene, integrator, n=n, times=[0.0, t_end], progress=False, **options)
        a = ds.attrs
        if a["status"] != "complete":
            raise RuntimeError(f"{integrator} n={n}: {a['message']}")
        walls.append(a["wall_time_s"])
    best = min(walls)
    return {"n_steps": a["n_steps"], "n_jac": a.get("n_jac", 0), "wall_time_s": best,
            "wall_per_step_s": best / a["n_steps"], "wall_per_sim_second_s": best / t_end,
            "dt_bound_s": a["leapfrog_dt_bound_s"], "wall_time_max_s": max(walls), "n_repeats": len(walls)}


def slope(n, cost):
    ok = np.isfinite(cost)
    return float(np.polyfit(np.log(n[ok]), np.log(cost[ok]), 1)[0]) if ok.sum() >= 2 else float("nan")


def slope_spread(n, best, slowest):
    """The exponent of ``best`` against ``n``, and the range of the exponents the repeats allow: fitted with the
    slowest repeats on the small grids and the fastest on the large ones, and the other way round."""
    small = n <= np.median(n)
    low = slope(n, np.where(small, slowest, best))
    high = slope(n, np.where(small, best, slowest))
    return slope(n, best), min(low, high), max(low, high)


def exponent(n, best, slowest):
    """An exponent as the table gives it: ``1.02 (0.95 .. 1.10)``, the range from the repeats' spread."""
    value, low, high = slope_spread(n, best, slowest)
    return f"{value:.2f} ({low:.2f} .. {high:.2f})" if np.isfinite(value) else "nan"


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--sizes", type=integers_arg("--sizes", MIN_NODES), default=None,
                        help=f"nodes, N1,N2,... (default {','.join(map(str, SIZES))})")
    parser.add_argument("--integrators", default=None,
                        help="default cvode-bdf,ida (leap-frog is added on the elastic case)")
    parser.add_argument("--repeats", type=integer_arg("--repeats", 1, MAX_REPEATS), default=None,
                        help=f"least timed repeats of a point, more until {TIMED_S * 1e3:g} ms (default 1; 3 with --quick)")
    parser.add_argument("--quick", action="store_true",
                        help="small settings: " + ", ".join(f"{k} = {v}" for k, v in QUICK.items()))
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    parser.add_argument("--output", default=None, help="netCDF file (default: OUT/implicit_scaling.nc)")
    args = parser.parse_args(argv)
    sizes = args.sizes or (QUICK["sizes"] if args.quick else SIZES)
    repeats = args.repeats or (QUICK["repeats"] if args.quick else 1)
    args.integrators = args.integrators or (QUICK["integrators"] if args.quick else "cvode-bdf,ida")
    args.output = output_file(args.output) if args.output else os.path.join(output_folder(args.out),
                                                                           "implicit_scaling.nc")
    runs = {"viscous": args.integrators.split(","), "elastic": args.integrators.split(",") + ["leapfrog"]}
    methods = list(dict.fromkeys(m for ms in runs.values() for m in ms))
    data = {k: np.full((len(CASES), len(methods), len(sizes)), np.nan) for k in STATS}
    for c, (case, (scene, t_end)) in enumerate(CASES.items()):
        for m, method in enumerate(methods):
            if method not in runs[case]:
                continue
            for k, n in enumerate(sizes):
                start = time.perf_counter()
                row = measure(scene, method, n, t_end, repeats)
                for key, value in row.items():
                    data[key][c, m, k] = value
                print(f"{case:8s} {method:10s} n={n:6d} steps={row['n_steps']:7d} wall={row['wall_time_s']:8.3f} s "
                      f"({1e3 * row['wall_per_step_s']:.3f} ms/step; best of {row['n_repeats']}; "
                      f"{time.perf_counter() - start:.1f} s with set-up)", flush=True)
    ds = summary(data, methods, sizes)
    mol_shell.write_netcdf(ds, args.output)
    table = markdown(ds)
    with open(beside(args.output, ".md"), "w") as fh:  # beside the name typed (a link's too)
        fh.write(table + "\n")
    plot(ds, beside(args.output, ".png"))
    print(table)
    return ds


def summary(data, methods, sizes):
    """The Dataset of OUT/implicit_scaling.nc: ``data[stat]``, arrays over case x integrator x n."""
    ds = xr.Dataset({k: (("case", "integrator", "n"), v) for k, v in data.items()},
                    coords={"case": list(CASES), "integrator": methods, "n": sizes})
    return described(ds, "mol_shell: cost of the integrators against n", MEANINGS,
                     t_end_viscous=CASES["viscous"][1], units_t_end_viscous="s", t_end_elastic=CASES["elastic"][1],
                     units_t_end_elastic="s", rtol=1e-6, atol=1e-9, timed_s=TIMED_S,
                     source=f"mol_shell {mol_shell.__version__}, studies/implicit_scaling.py")


def markdown(ds):
    n = ds.n.values
    lines = ["| case | integrator | " + " | ".join(f"n={v}" for v in n) + " | exponent of cost per sim. s | exponent of cost per step |",
             "|---|---|" + "---|" * len(n) + "---|---|"]
    for case in ds.case.values:
        for method in ds.integrator.values:
            x = ds.sel(case=case, integrator=method)
            cost = x.wall_per_sim_second_s.values
            if np.all(np.isnan(cost)):
                continue
            cells = [f"{c:.3g} s ({int(s)} steps)" if np.isfinite(c) else "" for c, s in zip(cost, x.n_steps.values)]
            slowest = x.wall_time_max_s.values / x.wall_time_s.values
            lines.append(f"| {case} | {method} | " + " | ".join(cells)
                         + f" | {exponent(n, cost, cost * slowest)} "
                         f"| {exponent(n, x.wall_per_step_s.values, x.wall_per_step_s.values * slowest)} |")
    lines.append("")
    lines.append("Cells: wall time per simulated second, best of the repeats (steps taken). Exponent: least-squares "
                 "slope of log cost against log n; in brackets, the range the repeats' spread allows (the slowest "
                 "repeats on the small grids and the fastest on the large ones, and the other way round).")
    if n.max() < 10 * n.min():
        lines.append(f"The sizes span less than a decade (n = {n.min()} .. {n.max()}): the exponents say little.")
    return "\n".join(lines)


def plot(ds, path):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    n = ds.n.values.astype(float)
    for ax, case in zip(axes, ds.case.values):
        for method in ds.integrator.values:
            cost = ds.wall_per_sim_second_s.sel(case=case, integrator=method).values
            if np.any(np.isfinite(cost)):
                ax.loglog(n, cost, "o-", label=method)
        ref = ds.wall_per_sim_second_s.sel(case=case).values
        base = np.nanmin(ref[:, 0]) if np.any(np.isfinite(ref[:, 0])) else 1.0
        ax.loglog(n, base * n / n[0], "k:", label="~ n")
        ax.loglog(n, base * (n / n[0]) ** 2, "k--", label="~ n^2")
        ax.set_title(f"{case} (t_end = {ds.attrs['t_end_' + str(case)]} s)")
        ax.set_xlabel("nodes n")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    axes[0].set_ylabel("wall time per simulated second [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
