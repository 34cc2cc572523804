"""The paper's figures 4-8: r, theta, chi against s at t = 0, 0.02, 0.07, 0.106, 0.143 s.

The scene of section 6 (N = 40 nodes, leap-frog, dt = 1e-6 s, gamma = 0.1 rad/m, R computed),
saved every millisecond as well, so psi's small rapid oscillation can be shown too.
Writes OUT/paper_figures.nc, OUT/fig4.png .. OUT/fig8.png (one per paper time, as the paper)
and OUT/paper_psi.png; prints the numbers. ``main`` returns the run, its relative energy change,
the per-grid summaries and the files written.

A second run on a finer grid (--check-n, default 160) compares psi across grids. The cell energy
samples psi at the cell's two nodes, so the (-1)^i node pattern has the full transverse-shear
stiffness (a mode at 5,063 rad/s on 40 nodes, just above the uniform shear mode at 5,050 rad/s)
and stays at 3e-6 .. 5e-6 rad on every grid (column "(-1)^i node pattern", from
mol_shell.results.study_store.grid_mode). psi itself is small (max |psi| over the run: 5.8e-5 rad at
N = 40, 8.2e-5 at 80, 1.0e-4 at 160, 1.6e-4 at 320) but is not pointwise converged: it is
short-wave content radiated at the torsional fronts, which are as sharp as the grid because
the initial data make chi_s jump at the free ends (its dominant frequency at s = L/2 rises with
the grid: about 35, 62, 118, 264 Hz at N = 40, 80, 160, 320). r, theta and chi converge
(max |r - R| = 0.01126, 0.01112, 0.01108, 0.01107 m on the same grids).
Usage: python studies/paper_figures.py [--n 40] [--dt 1e-6] [--check-n 160] [--quick] [--out out]
(--quick: the paper run only, without the finer grid; about 10 s.)
"""

import os

import numpy as np

import mol_shell
from mol_shell.cli.args import integer_arg, number_arg
from mol_shell.cli.scripts import MIN_NODES, output_folder, run_script, script_parser
from mol_shell.views.plotting import plot_snapshots
from mol_shell.results.study_store import summarize

PAPER_TIMES = (0.0, 0.02, 0.07, 0.106, 0.143)
QUICK = {"check_n": 0}  # --quick: no finer grid


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--n", type=integer_arg("--n", MIN_NODES), default=40, help="nodes (default 40)")
    parser.add_argument("--dt", type=number_arg("--dt", unit="s"), default=1e-6, help="leap-frog step, s (default 1e-6)")
    parser.add_argument("--check-n", type=integer_arg("--check-n", 0), default=None,
                        help="finer grid for the psi comparison (default 160; 0: skip, as with --quick)")
    parser.add_argument("--quick", action="store_true", help="the paper run only (no finer grid): a few seconds")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    check_n = args.check_n if args.check_n is not None else (QUICK["check_n"] if args.quick else 160)
    out = args.out
    output_folder(out)
    times = np.unique(np.round(np.r_[np.arange(0.0, 0.1435, 0.001), PAPER_TIMES], 9))
    scene = mol_shell.TwistedCylinder()
    ds = mol_shell.simulate(scene, n=args.n, times=times, dt=args.dt, progress=False)
    files = [os.path.join(out, "paper_figures.nc")]
    mol_shell.write_netcdf(ds, files[0])
    for number, t in zip(range(4, 9), PAPER_TIMES):
        snap = ds.sel(time=[t], method="nearest")
        files.append(os.path.join(out, f"fig{number}.png"))
        plot_snapshots(snap, files[-1])
    files.append(os.path.join(out, "paper_psi.png"))
    _plot_psi(ds, files[-1])
    e = ds.energy.values
    drift = float(np.abs(e - e[0]).max() / e[0])
    mid = ds.sizes["s"] // 2
    print(f"R = {ds.attrs['R']:.10f} m, n = {args.n}, dt = {args.dt:g} s, {ds.attrs['n_steps']} steps in "
          f"{ds.attrs['wall_time_s']:.2f} s, status {ds.attrs['status']}")
    print("| t [s] | r min .. max [m] | max abs(theta) [rad] | chi min .. max [rad] | max abs(psi) [rad] |")
    print("|---|---|---|---|---|")
    for t in PAPER_TIMES:
        x = ds.sel(time=t, method="nearest")
        print(f"| {t:g} | {float(x.r.min()):.5f} .. {float(x.r.max()):.5f} | {float(abs(x.theta).max()):.4f} "
              f"| {float(x.chi.min()):+.4f} .. {float(x.chi.max()):+.4f} | {float(abs(x.psi).max()):.2e} |")
    grid = ds.sel(time=np.arange(0.0, 0.1435, 0.001), method="nearest")
    psi = grid.psi.isel(s=mid).values
    spectrum = np.abs(np.fft.rfft(psi - psi.mean()))
    peak = np.fft.rfftfreq(psi.size, 0.001)[np.argmax(spectrum)]
    print(f"whole run (1 ms samples): r in {float(ds.r.min()):.5f} .. {float(ds.r.max()):.5f} m, max |theta| = "
          f"{float(abs(ds.theta).max()):.4f}, max |psi| = {float(abs(ds.psi).max()):.2e} rad; "
          f"relative energy change {drift:.2e}; psi at s = L/2 oscillates at about "
          f"{peak:.0f} Hz (FFT peak; resolution {1 / 0.143:.0f} Hz)")
    grids = {args.n: ds}
    if check_n:
        grids[check_n] = mol_shell.simulate(scene, n=check_n, times=times, dt=args.dt, progress=False)
    print("| N | max abs(r - R) [m] | max abs(theta) | max abs(psi) | psi: (-1)^i node pattern | psi: the rest | max abs(chi_s) |")
    print("|---|---|---|---|---|---|---|")
    summaries = {}
    for n, run in grids.items():
        m = summaries[n] = summarize(run)
        print(f"| {n} | {float(m.dr_max):.5f} | {float(m.theta_max):.4f} | {float(m.psi_max):.2e} | "
              f"{float(m.psi_grid_mode_max):.2e} | {float(m.psi_smooth_max):.2e} | {float(m.chi_s_max):.4f} |")
    print("wrote " + ", ".join(files))
    return {"ds": ds, "energy_drift": drift, "summaries": summaries, "files": files}


def _plot_psi(ds, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.4))
    for frac in (0.0, 0.25, 0.5):
        i = int(round(frac * (ds.sizes["s"] - 1)))
        axes[0].plot(ds.time, ds.psi.isel(s=i), lw=0.8, label=f"s = {float(ds.s[i]):.2f} m")
    axes[0].set_xlabel("t [s]")
    axes[0].set_ylabel(r"$\psi$ [rad] (1 ms samples)")
    axes[0].legend(fontsize=8)
    axes[1].plot(ds.s, ds.psi.sel(time=0.143, method="nearest"), "k.-", ms=3)
    axes[1].set_xlabel("s [m]")
    axes[1].set_ylabel(r"$\psi$ at t = 0.143 s [rad]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
