"""Section 4: a spinning azimuthally unshearable shell moves axisymmetrically; the free shell does not.

Initial state (mol_shell.scenes.unshearable.Unshearable): r = 1 + 0.01 cos(2 pi s / L) m, theta =
arctan(r_s) (no transverse shear), chi = psi = 0, spin chi_t = 20 rad/s. The constrained shell
(chi_s = 0, psi = 0 with Lagrange multipliers; DAE, IDA) and the free shell (the PDE, leap-frog)
start from it on N = 81 nodes. The free shell's twist is converged there (max |chi_s| over
t <= 0.1 s: 1.556e-2, 1.562e-2, 1.563e-2 rad/m on N = 41, 81, 161) and its shear nearly so (max
|psi|: 1.8e-5, 5.4e-6, 6.0e-6 rad). A second part varies the spin with mol_shell.study
(integrator "ida") and runs the free shell at the same spins. Without spin the motion is
axisymmetric by symmetry, so the multipliers vanish. Writes OUT/unshearable_{constrained,free}.nc,
OUT/unshearable_omega.nc and OUT/unshearable.png; prints the numbers. ``main`` returns the runs.
Usage: python studies/unshearable_vs_free.py [--n 81] [--t-end 0.1] [--dt 1e-6] [--scheduler ADDRESS|serial]
                                             [--quick] [--out out]
(--quick: N = 21 to t = 0.02 s, dt = 2e-6 s, spins 0, 10, 20 rad/s, in this process; about 10 s.)
"""

import os

import numpy as np

import mol_shell
from mol_shell.cli.args import integer_arg, number_arg
from mol_shell.cli.scripts import MIN_NODES, output_folder, run_script, script_parser, simulate_unshearable
from mol_shell.runs.study import study
from mol_shell.runs.unshearable import defects
from mol_shell.scenes import Unshearable

OMEGAS = (0.0, 5.0, 10.0, 20.0)
DEFAULTS = {"n": 81, "t_end": 0.1, "dt": 1e-6, "omegas": OMEGAS, "scheduler": None}
QUICK = {"n": 21, "t_end": 0.02, "dt": 2e-6, "omegas": (0.0, 10.0, 20.0), "scheduler": "serial"}


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--n", type=integer_arg("--n", MIN_NODES), help=f"nodes (default {DEFAULTS['n']})")
    parser.add_argument("--t-end", type=number_arg("--t-end", unit="s"), help=f"s (default {DEFAULTS['t_end']:g})")
    parser.add_argument("--dt", type=number_arg("--dt", unit="s"), help=f"leap-frog step of the free shell, s (default {DEFAULTS['dt']:g})")
    parser.add_argument("--scheduler", help="dask scheduler address, or serial (default: local processes)")
    parser.add_argument("--quick", action="store_true",
                        help="small settings: " + ", ".join(f"{k} = {v}" for k, v in QUICK.items()))
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    parser.set_defaults(omegas=None)
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else DEFAULTS).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    out = args.out
    output_folder(out)
    times = np.round(np.arange(0.0, args.t_end + 1e-12, 0.001), 9)
    scene = Unshearable()
    con = simulate_unshearable(scene, n=args.n, times=times)
    free = simulate_unshearable(scene, n=args.n, times=times, constrained=False, dt=args.dt)
    mol_shell.write_netcdf(con, os.path.join(out, "unshearable_constrained.nc"))
    mol_shell.write_netcdf(free, os.path.join(out, "unshearable_free.nc"))
    e = con.energy.values
    print(f"omega = {scene.omega} rad/s, dR = {scene.dR} m, N = {args.n}, t_end = {args.t_end} s")
    print(f"constrained (IDA, rtol {con.attrs['rtol']:g}): {con.attrs['n_steps']} steps, {con.attrs['wall_time_s']:.1f} s; "
          f"max|chi_s| = {defects(con)[0]:.1e} rad/m, max|psi| = {defects(con)[1]:.1e} rad; energy change "
          f"{np.abs(e - e[0]).max() / e[0]:.1e}; max|lambda_chi| = {float(abs(con.lambda_chi).max()):.1f} N "
          f"(torque 2 pi lambda_chi = {2 * np.pi * float(abs(con.lambda_chi).max()):.0f} N m), "
          f"max|lambda_psi| = {float(abs(con.lambda_psi).max()):.2e} N/m")
    print(f"free (leap-frog, dt {args.dt:g}): max|chi_s| = {defects(free)[0]:.2e} rad/m, max|psi| = "
          f"{defects(free)[1]:.2e} rad, spread of chi_t over s up to "
          f"{float((free.chi_t.max('s') - free.chi_t.min('s')).max()):.3f} rad/s")
    print(f"same radius history? max |r_free - r_constrained| = {float(abs(free.r - con.r).max()):.2e} m "
          f"(r moves by {float(abs(con.r - con.r.isel(time=0)).max()):.3f} m)")
    spins = study(scene, {"omega": list(args.omegas)}, "ida", n=args.n, times=times, scheduler=args.scheduler,
                  output=os.path.join(out, "unshearable_omega.nc"))
    print("| omega [rad/s] | constrained: max abs(lambda_chi) [N] | max abs(lambda_psi) [N/m] | max abs(chi_s), max abs(psi) "
          "| free: max abs(chi_s) [rad/m] | free: max abs(psi) [rad] |")
    print("|---|---|---|---|---|---|")
    free_spins = {}
    for omega in args.omegas:
        c = spins.sel(omega=omega)
        f = free_spins[omega] = simulate_unshearable(Unshearable(omega=omega), n=args.n, times=times, constrained=False,
                                                     dt=args.dt)
        print(f"| {omega:g} | {float(abs(c.lambda_chi).max()):.3g} | {float(abs(c.lambda_psi).max()):.3g} "
              f"| {float(c.chi_s_max.max()):.1e}, {float(c.psi_max.max()):.1e} | {defects(f)[0]:.3e} | {defects(f)[1]:.3e} |")
    _plot(con, free, os.path.join(out, "unshearable.png"))
    print(f"wrote {out}/unshearable_constrained.nc, {out}/unshearable_free.nc, {out}/unshearable_omega.nc, "
          f"{out}/unshearable.png")
    return {"constrained": con, "free": free, "spins": spins, "free_spins": free_spins}


def _plot(con, free, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10.5, 6.6))
    floor = 1e-17
    for ds, label, style in ((free, "free shell", "-"), (con, "unshearable (DAE)", "--")):
        axes[0, 0].semilogy(ds.time, np.maximum(ds.chi_s_max, floor), style, label=label)
        axes[0, 1].semilogy(ds.time, np.maximum(ds.psi_max, floor), style, label=label)
    axes[0, 0].set_ylabel(r"max$_s\ |\chi_s|$ [rad/m]")
    axes[0, 1].set_ylabel(r"max$_s\ |\psi|$ [rad]  (constrained: exactly 0)")
    for t in np.round(np.array([0.1, 0.3, 0.6]) * float(free.time[-1]), 9):  # 0.01, 0.03, 0.06 s for t_end = 0.1 s
        x = free.sel(time=t, method="nearest")
        axes[1, 0].plot(x.s, x.chi_t, label=f"free, t = {t:g} s")
        axes[1, 0].plot(x.s, con.chi_t.sel(time=t, method="nearest"), "k:", lw=0.8)
    axes[1, 0].set_xlabel("s [m]")
    axes[1, 0].set_ylabel(r"$\chi_t$ [rad/s] (dotted: unshearable)")
    mesh = axes[1, 1].pcolormesh(con.s_cell, con.time, con.lambda_chi, shading="auto", cmap="RdBu_r")
    fig.colorbar(mesh, ax=axes[1, 1], label=r"$\lambda_\chi$ [N]")
    axes[1, 1].set_xlabel("s [m]")
    axes[1, 1].set_ylabel("t [s]")
    for ax in axes[0]:
        ax.set_xlabel("t [s]")
        ax.legend(fontsize=8)
    axes[1, 0].legend(fontsize=7)
    fig.suptitle("spinning shell with a bulge: unshearable (chi_s = psi = 0) vs free", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
