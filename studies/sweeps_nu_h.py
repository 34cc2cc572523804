"""Poisson's ratio and thickness sweeps of the paper's scene (section 6), with mol_shell.study.

nu in {0.3, 0.4, 0.45, 0.49, 0.499} at the paper's h, and h in {1/4, 1/2, 1, 2, 4} x 2 pi 1e-3 m
at nu = 0.49; gamma = 0.1 rad/m, R(gamma) computed per case, leap-frog with dt = 1e-6 s to
t = 0.143 s, on N = 40 and N = 160 nodes. max |r - R| falls as nu grows (the radial shift of the
twisted cylinder, 1 - R, is proportional to (lambda + 4 mu) / (lambda + 2 mu) for thin shells).
The leap-frog bound 1/max|eig| is set by the transverse-shear mode, whose frequency goes like
sqrt(mu/rho)/h (sqrt(3 mu/rho)/h = 5,050 rad/s for the natural cylinder at the paper's h), so
the bound is proportional to h up to the paper's h; at 4x that h the grid's axial wave, of
frequency about 2 sqrt((lambda + 2 mu)/rho)/ds, is the faster one. psi is tabulated with its
(-1)^i node pattern split off (mol_shell.results.study_store.grid_mode); psi is not pointwise converged
in N (see studies/paper_figures.py). Writes OUT/sweeps_nu_h.nc (amplitudes, dims grid x nu and grid x h),
the full fields in OUT/sweep_{nu,h}_n<N>.nc (cases kept for resuming) and OUT/sweeps_nu_h.png;
prints markdown tables. ``main`` returns the summaries of the two sweeps.
Usage: python studies/sweeps_nu_h.py [--grids 40,160] [--dt 1e-6] [--scheduler ADDRESS|serial] [--quick] [--out out]
(--quick: nu = 0.3, 0.45, 0.499 and h = 1/4, 1/2, 1 x 2 pi 1e-3 m on N = 40 with dt = 4e-6 s,
in this process; 10-20 s.)
"""

import math
import os

import numpy as np
import xarray as xr

import mol_shell
from mol_shell.cli.args import number_arg
from mol_shell.cli.scripts import integers_arg, output_folder, run_script, script_parser
from mol_shell.results.cf import described
from mol_shell.results.study_store import summarize
from mol_shell.runs.study import study

TIMES = np.round(np.arange(0.0, 0.1435, 0.001), 9)
H0 = 2 * math.pi * 1e-3
SWEEPS = {"nu": [0.3, 0.4, 0.45, 0.49, 0.499], "h": [H0 * f for f in (0.25, 0.5, 1.0, 2.0, 4.0)]}
DEFAULTS = {"grids": [40, 160], "dt": 1e-6, "scheduler": None}
QUICK = {"grids": [40], "dt": 4e-6, "scheduler": "serial"}
#: units and long_name of the variables of OUT/sweeps_nu_h.nc beside summarize's (which say their own), per sweep
EXTRAS = {"R": ("m", "equilibrium radius R(gamma)"), "status": (None, "how the case ended"),
          "wall_time_s": ("s", "wall time of the case's run"),
          "leapfrog_dt_bound_s": ("s", "leap-frog stability bound 1/max|eig J(y0)|"),
          "chi_end": ("rad", "chi at s = 0 at t = 0.143 s")}
MEANINGS = {"grid": ("1", "nodes in s"), "nu": ("1", "Poisson's ratio"), "h": ("m", "wall thickness"),
            **{f"{k}_{name}_sweep": (u, f"{n} ({name} sweep)") for k, (u, n) in EXTRAS.items() for name in SWEEPS}}
QUICK_SWEEPS = {"nu": [0.3, 0.45, 0.499], "h": [H0 * f for f in (0.25, 0.5, 1.0)]}


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--grids", type=integers_arg("--grids"),
                        help=f"nodes, N1,N2,... (default {','.join(map(str, DEFAULTS['grids']))})")
    parser.add_argument("--dt", type=number_arg("--dt", unit="s"), help=f"leap-frog step, s (default {DEFAULTS['dt']:g})")
    parser.add_argument("--scheduler", help="dask scheduler address, or serial (default: local processes)")
    parser.add_argument("--quick", action="store_true",
                        help="small settings: " + ", ".join(f"{k} = {v}" for k, v in QUICK.items())
                        + "; nu = 0.3, 0.45, 0.499 and h = 1/4, 1/2, 1 x 2 pi 1e-3 m")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else DEFAULTS).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    sweeps = QUICK_SWEEPS if args.quick else SWEEPS
    out_dir = args.out
    output_folder(out_dir)
    grids = args.grids
    summaries = {}
    for name, values in sweeps.items():
        per_grid = []
        for n in grids:
            ds = study(mol_shell.TwistedCylinder(), {name: values}, n=n, times=TIMES, dt=args.dt,
                       scheduler=args.scheduler, output=os.path.join(out_dir, f"sweep_{name}_n{n}.nc"))
            m = summarize(ds)
            for extra in ("R", "status", "wall_time_s", "leapfrog_dt_bound_s"):
                m[extra] = ds[extra]
            m["chi_end"] = ds.chi.isel(time=-1, s=0)  # chi at s = 0 (an end) at t = 0.143 s
            per_grid.append(m.expand_dims(grid=[n]))
            print(f"{name} sweep, N = {n}: {ds.attrs['n_executed']} run, {ds.attrs['n_reused']} reused, "
                  f"{ds.attrs['study_wall_time_s']:.1f} s")
        summaries[name] = xr.concat(per_grid, "grid")
    out = summary(summaries, args.dt)
    mol_shell.write_netcdf(out, os.path.join(out_dir, "sweeps_nu_h.nc"))
    for name, m in summaries.items():
        print(f"\n| {name} | N | R [m] | max abs(r - R) [m] | max abs(theta) [rad] | max abs(psi) [rad] "
              "| psi without node pattern | chi(s=0) at 0.143 s | leap-frog dt bound [s] | status |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for value in sweeps[name]:
            for n in grids:
                x = m.sel(grid=n, **{name: value})
                print(f"| {value:.4g} | {n} | {float(x.R):.6f} | {float(x.dr_max):.3e} | {float(x.theta_max):.4f} "
                      f"| {float(x.psi_max):.2e} | {float(x.psi_smooth_max):.2e} | {float(x.chi_end):+.4f} "
                      f"| {float(x.leapfrog_dt_bound_s):.3g} | {str(x.status.values)} |")
    _plot(summaries, grids, os.path.join(out_dir, "sweeps_nu_h.png"))
    print(f"\nwrote {out_dir}/sweeps_nu_h.nc, {out_dir}/sweep_*_n*.nc, {out_dir}/sweeps_nu_h.png")
    return summaries


def summary(summaries, dt):
    """The Dataset of OUT/sweeps_nu_h.nc: ``summaries[name]`` (dims grid x name: summarize's amplitudes and the
    cases' R, status, wall_time_s, leapfrog_dt_bound_s and chi_end), each variable named after its sweep."""
    out = xr.merge([m.rename({k: f"{k}_{name}_sweep" for k in m.data_vars}) for name, m in summaries.items()],
                   compat="no_conflicts", join="outer")
    return described(out, "mol_shell: nu and h sweeps of the twisted cylinder", MEANINGS, gamma=0.1,
                     units_gamma="rad m-1", t_end=float(TIMES[-1]), units_t_end="s", dt=dt, units_dt="s")


def _plot(summaries, grids, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(2, 3, figsize=(12, 6.4))
    for row, (name, m) in enumerate(summaries.items()):
        x = np.asarray(m[name])
        for n, style in zip(grids, ("o-", "s--")):
            sel = m.sel(grid=n)
            axes[row, 0].plot(x, sel.dr_max, style, label=f"N = {n}")
            axes[row, 1].plot(x, sel.theta_max, style, label=f"N = {n}")
            axes[row, 2].plot(x, sel.psi_max, style, label=f"max |psi|, N = {n}")
            axes[row, 2].plot(x, sel.psi_smooth_max, style, alpha=0.5, label=f"without node pattern, N = {n}")
        label = "nu" if name == "nu" else "h [m]"
        for col, ylabel in enumerate(("max |r - R| [m]", "max |theta| [rad]", "max |psi| [rad]")):
            axes[row, col].set_xlabel(label)
            axes[row, col].set_ylabel(ylabel)
            axes[row, col].legend(fontsize=7)
            if name == "h":
                # the h values span less than a decade: a log axis labels none of them (or one power of ten), so
                # each value is a labelled tick
                axes[row, col].set_xscale("log")
                axes[row, col].xaxis.set_major_locator(matplotlib.ticker.FixedLocator(x))
                axes[row, col].xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%.3g"))
                axes[row, col].xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    fig.suptitle("twisted cylinder, gamma = 0.1 rad/m, t <= 0.143 s", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
