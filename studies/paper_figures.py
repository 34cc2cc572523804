"""The paper's figures 4-8: r, theta, chi against s at t = 0, 0.02, 0.07, 0.106, 0.143 s.

The scene of section 6 (N = 40 nodes, leap-frog, dt = 1e-6 s, gamma = 0.1 rad/m, R computed),
saved every millisecond as well, so psi's small rapid oscillation can be shown too.
Writes out/paper_figures.nc, out/fig4.png .. out/fig8.png (one per paper time, as the paper)
and out/paper_psi.png; prints the numbers. A second run on a finer grid (--check-n, default 160)
shows which part of psi is resolved: at N = 40 most of it is a (-1)^i node pattern (see
mol_shell.study_data.grid_mode), a spurious soft mode of the one-point cell rule.
Usage: python studies/paper_figures.py [--n 40] [--dt 1e-6] [--check-n 160]
"""

import argparse
import os

import numpy as np

import mol_shell
from mol_shell.plotting import plot_snapshots
from mol_shell.study_data import summarize

PAPER_TIMES = (0.0, 0.02, 0.07, 0.106, 0.143)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=40)
    parser.add_argument("--dt", type=float, default=1e-6)
    parser.add_argument("--check-n", type=int, default=160, help="finer grid for the psi check (0: skip)")
    args = parser.parse_args()
    os.makedirs("out", exist_ok=True)
    times = np.unique(np.round(np.r_[np.arange(0.0, 0.1435, 0.001), PAPER_TIMES], 9))
    scene = mol_shell.TwistedCylinder()
    ds = mol_shell.simulate(scene, n=args.n, times=times, dt=args.dt, progress=False)
    mol_shell.write_netcdf(ds, "out/paper_figures.nc")
    for number, t in zip(range(4, 9), PAPER_TIMES):
        snap = ds.sel(time=[t], method="nearest")
        plot_snapshots(snap, f"out/fig{number}.png")
    _plot_psi(ds, "out/paper_psi.png")
    e = ds.energy.values
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
          f"{float(abs(ds.theta).max()):.4f}, max |psi| = {float(abs(ds.psi).max()):.4f} rad; "
          f"relative energy change {np.abs(e - e[0]).max() / e[0]:.2e}; psi at s = L/2 oscillates at about "
          f"{peak:.0f} Hz (FFT peak; resolution {1 / 0.143:.0f} Hz)")
    grids = {args.n: ds}
    if args.check_n:
        grids[args.check_n] = mol_shell.simulate(scene, n=args.check_n, times=times, dt=args.dt, progress=False)
    print("| N | max abs(r - R) [m] | max abs(theta) | max abs(psi) | psi: (-1)^i node pattern | psi: the rest | max abs(chi_s) |")
    print("|---|---|---|---|---|---|---|")
    for n, run in grids.items():
        m = summarize(run)
        print(f"| {n} | {float(m.dr_max):.5f} | {float(m.theta_max):.4f} | {float(m.psi_max):.2e} | "
              f"{float(m.psi_grid_mode_max):.2e} | {float(m.psi_smooth_max):.2e} | {float(m.chi_s_max):.4f} |")
    print("wrote out/paper_figures.nc, out/fig4.png .. out/fig8.png, out/paper_psi.png")


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
    main()
