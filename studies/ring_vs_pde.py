"""Section 5: the spinning ring, PDE (leap-frog, N nodes) against the reduced ODE (DOP853, rtol 1e-12).

Uniform data r = 1.01 m, chi_t = 20 rad/s, psi = 0.05 rad (mol_shell.SpinningRing) stay uniform in
the PDE, and every node follows the ODE of mol_shell.runs.ring; the discrepancy is leap-frog's error
and falls as dt^2. Both are saved every 40 us (SAMPLE_STEP, a multiple of every dt): psi carries the
transverse-shear oscillation, about 820 Hz here (sqrt(3 mu / rho) / h = 5,050 rad/s, 804 Hz, for the natural
cylinder; h the half-thickness), which 1 ms samples alias (to 178 Hz); 40 us gives 30 samples a period.
Writes OUT/ring_vs_pde.nc (the ODE on that time grid, and the discrepancies) and OUT/ring_vs_pde.png; prints a table. ``main`` returns the netCDF's Dataset.
Usage: python studies/ring_vs_pde.py [--n 10] [--t-end 0.1] [--quick] [--out out]
(--quick: t_end = 0.04 s and dt = 8, 4, 2 us, a few seconds.)
"""

import argparse
import math
import os

import numpy as np

import mol_shell
from mol_shell.cli.args import integer_arg, number_arg
from mol_shell.cli.scripts import MIN_NODES, finished, output_folder, run_script, script_parser, simulate
from mol_shell.runs.ring import simulate_ring

FIELDS = ("r", "chi", "psi", "r_t", "chi_t", "psi_t")
STEPS = (8e-6, 4e-6, 2e-6, 1e-6)
QUICK = {"t_end": 0.04, "steps": STEPS[:3]}
SAMPLE_STEP = 4e-5  # s: the saved times' spacing, at most (module docstring)


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--n", type=integer_arg("--n", MIN_NODES), default=10, help="nodes (default 10)")
    parser.add_argument("--t-end", type=t_end_arg, default=None,
                        help=f"a multiple of {SAMPLE_STEP:g} s, default 0.1 s ({QUICK['t_end']} s with --quick)")
    parser.add_argument("--quick", action="store_true",
                        help="small settings: " + ", ".join(f"{k} = {v}" for k, v in QUICK.items()))
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    t_end = args.t_end if args.t_end is not None else (QUICK["t_end"] if args.quick else 0.1)
    steps = QUICK["steps"] if args.quick else STEPS
    output_folder(args.out)
    scene = mol_shell.SpinningRing()
    times = sample_times(t_end)
    ring = finished(simulate_ring(scene, times))  # (a Ctrl-C raises in it today; checked as every run is)
    errors, uniform = {}, {}
    for dt in steps:
        pde = simulate(scene, n=args.n, times=times, dt=dt, progress=False)
        errors[dt] = [float(abs(pde[k] - ring[k]).max()) for k in FIELDS]
        uniform[dt] = max(float(abs(pde[k] - pde[k].mean("s")).max()) / max(1.0, float(abs(pde[k]).max()))
                          for k in FIELDS)
    out = ring.copy()
    for i, k in enumerate(FIELDS):  # one variable a field: each in its own units (m, rad, m s-1, rad s-1)
        out[f"discrepancy_{k}"] = (("dt",), [errors[dt][i] for dt in steps],
                                   {"long_name": f"max over s and t of |{k} of the PDE - {k} of the ODE|",
                                    "units": ring[k].attrs.get("units", "1")})
    out["nonuniformity"] = (("dt",), [uniform[dt] for dt in steps], {"long_name": "max over fields of max |x - mean_s x| / max(1, max |x|)", "units": "1"})
    out = out.assign_coords(dt=("dt", list(steps), {"units": "s", "long_name": "leap-frog time step"}))
    mol_shell.write_netcdf(out, os.path.join(args.out, "ring_vs_pde.nc"))
    e = ring.energy.values
    print(f"ODE: {ring.attrs['n_rhs']} RHS evaluations, {ring.attrs['wall_time_s']:.2f} s; relative energy change "
          f"{np.abs(e - e[0]).max() / e[0]:.1e}; r in {float(ring.r.min()):.5f} .. {float(ring.r.max()):.5f} m, "
          f"psi in {float(ring.psi.min()):+.4f} .. {float(ring.psi.max()):+.4f} rad, chi_t in "
          f"{float(ring.chi_t.min()):.3f} .. {float(ring.chi_t.max()):.3f} rad/s")
    print("| dt [s] | " + " | ".join(f"max abs(d{k})" for k in FIELDS) + " | ratio to the next larger dt (r) | max relative non-uniformity in s |")
    print("|---|" + "---|" * (len(FIELDS) + 2))
    for i, dt in enumerate(steps):
        ratio = f"{errors[steps[i - 1]][0] / errors[dt][0]:.3f}" if i else ""
        print(f"| {dt:g} | " + " | ".join(f"{x:.2e}" for x in errors[dt]) + f" | {ratio} | {uniform[dt]:.1e} |")
    _plot(ring, os.path.join(args.out, "ring_vs_pde.png"))
    print(f"wrote {args.out}/ring_vs_pde.nc, {args.out}/ring_vs_pde.png")
    return out


def t_end_arg(text):
    """``--t-end``: a positive multiple of :data:`SAMPLE_STEP`, so that the saved times (:func:`sample_times`, spaced
    ``SAMPLE_STEP``) are on the grid of every leap-frog step of :data:`STEPS`, which divide it (``--t-end 0.0001``
    saved every 33 us, which simulate refused naming ``times``; ``--t-end 1e-9`` too)."""
    value = number_arg("--t-end", unit="s")(text)
    k = value / SAMPLE_STEP
    if round(k) < 1 or abs(k - round(k)) > 1e-9 * k:
        raise argparse.ArgumentTypeError(
            f"--t-end = {text.strip()} is outside multiples of {SAMPLE_STEP:g} s (the saved times' spacing, which "
            f"every leap-frog step, {', '.join(f'{dt:g}' for dt in STEPS)} s, divides)")
    return value


def sample_times(t_end, step=SAMPLE_STEP):
    """Saved times: ``t_end`` in equal intervals of at most ``step`` (on every step grid when ``t_end`` is a multiple
    of ``step``), as typed (9 decimals)."""
    return np.round(np.linspace(0.0, t_end, math.ceil(t_end / step - 1e-9) + 1), 9)


def _plot(ring, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(11, 3.2))
    for ax, (name, label) in zip(axes, (("r", "r [m]"), ("psi", r"$\psi$ [rad]"), ("chi_t", r"$\chi_t$ [rad/s]"))):
        ax.plot(ring.time, ring[name], "k-", lw=0.5 if name == "psi" else 1)
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
    zoom = axes[1].inset_axes([0.5, 0.04, 0.47, 0.2])  # psi's shear oscillation (~820 Hz) over its first 5 ms
    first = ring.sel(time=slice(0.0, 0.005))
    zoom.plot(first.time * 1e3, first.psi, "r-", lw=0.8)
    zoom.set_yticks([])
    zoom.set_title("first 5 ms [ms]", fontsize=6, pad=2)
    zoom.tick_params(labelsize=5, pad=1)
    axes[1].set_ylim(-0.115, 0.055)  # room below the band for the zoom
    fig.suptitle("spinning ring (section 5): breathing, shearing, spin exchanged with the director", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
