"""Twist amplitude: gamma against the largest radius change and the psi amplitude (section 6 scene).

A study over gamma = 0.02 .. 0.2 rad/m (the paper's figures fit 0.1) with mol_shell.study, on
the paper's grid (N = 40) and a finer one (N = 160). Every case starts from its own equilibrium
radius R(gamma) and runs to t = 0.143 s with leap-frog, dt = 1e-6 s. Log-log slopes are fitted.
Both R(gamma) - 1 and max |r - R| are even in gamma (the energy is), so they grow like gamma^2
for small twists. psi is tabulated too, with its (-1)^i node pattern split off
(mol_shell.results.study_store.grid_mode): since the cell energy samples psi at the nodes that pattern
is no soft mode and stays a small part of psi (3e-6 .. 5e-6 rad at gamma = 0.1 on N = 40 .. 320);
psi itself is small but not pointwise converged in N (see studies/paper_figures.py), so its
slope is a property of each grid.
Writes OUT/twist_amplitude.nc (amplitudes; dims grid, gamma), the full fields in
OUT/twist_amplitude_n<N>.nc (finished cases kept in OUT/twist_amplitude_n<N>.cases/, so a rerun
resumes) and OUT/twist_amplitude.png. ``main`` returns the amplitudes and the slopes.
Usage: python studies/twist_amplitude.py [--grids 40,160] [--gammas 0.02:0.2:0.02] [--dt 1e-6]
                                         [--scheduler ADDRESS|serial] [--quick] [--out out]
(--quick: gamma = 0.025, 0.05, 0.1 on N = 40 with dt = 4e-6 s, in this process; a few seconds.)
"""

import os

import numpy as np
import xarray as xr

import mol_shell
from mol_shell.cli.args import number_arg
from mol_shell.cli.scripts import integers_arg, output_folder, run_script, script_parser
from mol_shell.cli.study import parse_vary
from mol_shell.results.cf import described
from mol_shell.results.study_store import summarize
from mol_shell.runs.study import study

TIMES = np.round(np.arange(0.0, 0.1435, 0.001), 9)
DEFAULTS = {"grids": [40, 160], "gammas": "0.02:0.2:0.02", "dt": 1e-6, "scheduler": None}
#: units and long_name of the variables of OUT/twist_amplitude.nc beside summarize's (which say their own)
MEANINGS = {"grid": ("1", "nodes in s"), "gamma": ("rad m-1", "twist gamma"), "R": ("m", "equilibrium radius R(gamma)"),
            "status": (None, "how the case ended"), "wall_time_s": ("s", "wall time of the case's run")}
QUICK = {"grids": [40], "gammas": "0.025,0.05,0.1", "dt": 4e-6, "scheduler": "serial"}


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--grids", type=integers_arg("--grids"),
                        help=f"nodes, N1,N2,... (default {','.join(map(str, DEFAULTS['grids']))})")
    parser.add_argument("--gammas", help=f"START:STOP:STEP or V1,V2,... (default {DEFAULTS['gammas']})")
    parser.add_argument("--dt", type=number_arg("--dt", unit="s"), help=f"leap-frog step, s (default {DEFAULTS['dt']:g})")
    parser.add_argument("--scheduler", help="dask scheduler address, or serial (default: local processes)")
    parser.add_argument("--quick", action="store_true",
                        help="small settings: " + ", ".join(f"{k} = {v}" for k, v in QUICK.items()))
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else DEFAULTS).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    out_dir = args.out
    output_folder(out_dir)
    gammas = parse_vary([f"gamma={args.gammas}"])["gamma"]
    grids = args.grids
    summaries = []
    for n in grids:
        ds = study(mol_shell.TwistedCylinder(), {"gamma": gammas}, n=n, times=TIMES, dt=args.dt,
                   scheduler=args.scheduler, output=os.path.join(out_dir, f"twist_amplitude_n{n}.nc"))
        m = summarize(ds)
        m["R"] = ds.R
        m["status"] = ds.status
        m["wall_time_s"] = ds.wall_time_s
        summaries.append(m.expand_dims(grid=[n]))
        print(f"N = {n}: {ds.attrs['n_executed']} cases run, {ds.attrs['n_reused']} reused, "
              f"{ds.attrs['study_wall_time_s']:.1f} s")
    out = summary(summaries, args.dt)
    mol_shell.write_netcdf(out, os.path.join(out_dir, "twist_amplitude.nc"))
    slopes = {}
    g = np.log(np.asarray(gammas))
    for n in grids:
        for name in ("dr_max", "theta_max", "psi_max", "psi_smooth_max"):
            slopes[n, name] = np.polyfit(g, np.log(out[name].sel(grid=n).values), 1)[0]
    print("| gamma [rad/m] | R [m] | " + " | ".join(f"max abs(r - R), N = {n} [m] | max abs(psi), N = {n} [rad] "
                                                   f"| psi without node pattern, N = {n}" for n in grids) + " |")
    print("|---|---|" + "---|---|---|" * len(grids))
    for i, gamma in enumerate(gammas):
        row = f"| {gamma:g} | {float(out.R.isel(grid=0, gamma=i)):.6f} |"
        for n in grids:
            x = out.sel(grid=n).isel(gamma=i)
            row += f" {float(x.dr_max):.3e} | {float(x.psi_max):.3e} | {float(x.psi_smooth_max):.3e} |"
        print(row)
    for n in grids:
        print(f"N = {n}: log-log slopes against gamma: max|r - R| {slopes[n, 'dr_max']:.2f}, max|theta| "
              f"{slopes[n, 'theta_max']:.2f}, max|psi| {slopes[n, 'psi_max']:.2f}, psi without node pattern "
              f"{slopes[n, 'psi_smooth_max']:.2f}")
    _plot(out, gammas, grids, os.path.join(out_dir, "twist_amplitude.png"))
    print(f"wrote {out_dir}/twist_amplitude.nc, {out_dir}/twist_amplitude_n*.nc, {out_dir}/twist_amplitude.png")
    return out, slopes


def summary(per_grid, dt):
    """The Dataset of OUT/twist_amplitude.nc: the grids' amplitudes (summarize's, with R, status and wall_time_s of
    the cases), each with its ``grid`` dimension, and the leap-frog step ``dt``."""
    return described(xr.concat(per_grid, "grid"), "mol_shell: twist amplitude gamma against radius change and psi "
                     "amplitude", MEANINGS, t_end=float(TIMES[-1]), units_t_end="s", dt=dt, units_dt="s")


def _plot(out, gammas, grids, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    g = np.asarray(gammas)
    for n, style in zip(grids, ("o-", "s--", "^:")):
        axes[0].loglog(g, out.dr_max.sel(grid=n), style, label=f"N = {n}")
        axes[1].loglog(g, out.psi_max.sel(grid=n), style, label=f"max |psi|, N = {n}")
        axes[1].loglog(g, out.psi_smooth_max.sel(grid=n), style, alpha=0.5, label=f"without node pattern, N = {n}")
    ref = out.dr_max.sel(grid=grids[-1]).values[-1] * (g / g[-1]) ** 2
    axes[0].loglog(g, ref, "k:", lw=0.8, label=r"$\propto\gamma^2$")
    axes[0].set_xlabel(r"$\gamma$ [rad/m]")
    axes[0].set_ylabel(r"max $|r - R|$ over s and t [m]")
    axes[1].set_xlabel(r"$\gamma$ [rad/m]")
    axes[1].set_ylabel(r"max $|\psi|$ [rad]")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    fig.suptitle("twisted cylinder, t <= 0.143 s", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
