"""Where a breathing sphere's equations stop being elliptic, and what the grid does after it.

The default sphere (``svk`` at ``nu = 0.49``, ``h/a = 0.0063``) released 5 % stretched breathes through about 5 %
compression. Under the inextensible director its equations stop being elliptic in ``s`` at 1 % equibiaxial
compression (docs/materials.md): every grid reports that loss at the same time, and what follows is the grid's
(finer grids stop sooner, on SVK's turning point next to a pole). The same release with ``svk-plane-stress`` stays
elliptic and moves the same on every grid. Runs ``cvode-bdf`` to 0.02 s (the plane-stress law, which breathes more
slowly, to 0.1 s), saved every 0.25 ms.
Writes OUT/ellipticity.nc (per case: loss and stop times, smallest equator stretch and margin) and
OUT/ellipticity.png (the equator's stretch and the smallest margin against time); prints a markdown table.
``main`` returns the netCDF's Dataset.
Usage: python studies/ellipticity.py [--quick] [--out out]
(--quick: n = 21 and 41, and 21 for the plane-stress law; about 10 s.)
"""

import math
import os
import warnings

import numpy as np
import xarray as xr

import mol_shell
from mol_shell.cli.scripts import output_folder, run_script, script_parser, simulate
from mol_shell.results.cf import described

GRIDS = (40, 80, 160, 320)
QUICK_GRIDS = (21, 41)
NU = 0.49
#: units and long_name of every variable of OUT/ellipticity.nc
MEANINGS = {
    "case": ("1", "case number"), "material": (None, "material law"), "n": ("1", "nodes"),
    "status": (None, "how the run ended"),
    "lost": ("s", "first saved time past the loss of ellipticity (NaN: none)"),
    "stop": ("s", "time the run stopped at a limit of the model (NaN: it did not)"),
    "end": ("s", "last saved time"), "stretch_min": ("1", "smallest hoop stretch at the equator"),
    "margin_min": ("1", "smallest ellipticity margin over the saved states"),
}


def run(material, n, t_end):
    """One release: the Dataset (warnings of the run are recorded in its attrs)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(mol_shell.Sphere(R=1.05, material=material, nu=NU), "cvode-bdf", n=n,
                                  times=np.linspace(0.0, t_end, int(round(t_end / 2.5e-4)) + 1), stresses=False)


def summary(rows, critical):
    """The Dataset of OUT/ellipticity.nc: one case per row of ``rows`` (material, n, status, lost, stop, end,
    stretch_min, margin_min); ``critical``, the equator's stretch at the closed-form loss of ellipticity."""
    out = xr.Dataset({key: (("case",), [row[key] for row in rows]) for key in MEANINGS if key != "case"},
                     coords={"case": np.arange(len(rows))})
    return described(out, "mol_shell: breathing sphere, the loss of ellipticity and the grid", MEANINGS,
                     critical_stretch=critical, nu=NU, R=1.05, units_R="m")


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--quick", action="store_true", help="two grids (and one for the plane-stress law)")
    parser.add_argument("--out", default="out", help="output directory")
    args = parser.parse_args(argv)
    output_folder(args.out)
    grids = QUICK_GRIDS if args.quick else GRIDS
    cases = [("svk", n, 0.02) for n in grids] + [("svk-plane-stress", n, 0.1) for n in grids[: 1 if args.quick else 2]]
    runs = {(m, n): run(m, n, t) for m, n, t in cases}
    lam = 2 * NU / (1 - 2 * NU)  # Lame's l / mu
    critical = math.sqrt((lam + 1) / (lam + 2))  # the hoop polarisation's loss under equibiaxial compression
    rows = []
    for (material, n), ds in runs.items():
        stretch = (ds.r / ds.r0).isel(s=n // 2).values
        rows.append({"material": material, "n": n, "status": ds.attrs["status"],
                     "lost": ds.attrs.get("ellipticity_lost_time", np.nan),
                     "stop": ds.attrs.get("failure_time", np.nan) if ds.attrs["status"] == "limit" else np.nan,
                     "end": float(ds.time[-1]), "stretch_min": float(stretch.min()),
                     "margin_min": float(np.nanmin(ds.ellipticity_margin.values))})
    out = summary(rows, critical)
    mol_shell.write_netcdf(out, os.path.join(args.out, "ellipticity.nc"))
    print(f"closed form: the equator's stretch {critical:.5f} (hoop polarisation)")
    print("| material | n | status | loss at [ms] | stopped at [ms] | smallest equator stretch | smallest margin |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        print(f"| {row['material']} | {row['n']} | {row['status']} | {row['lost'] * 1e3:.3f} | {row['stop'] * 1e3:.2f} "
              f"| {row['stretch_min']:.4f} | {row['margin_min']:.3f} |")
    _plot(runs, critical, os.path.join(args.out, "ellipticity.png"))
    print(f"wrote {args.out}/ellipticity.nc, {args.out}/ellipticity.png")
    return out


def _plot(runs, critical, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), sharex=True)
    for (material, n), ds in runs.items():
        if material != "svk":
            continue
        t = ds.time.values * 1e3
        line, = axes[0].plot(t, (ds.r / ds.r0).isel(s=n // 2).values, label=f"n = {n}")
        margin = ds.ellipticity_margin.values
        checked = np.isfinite(margin)  # at large n x saved states, every k-th state is checked
        axes[1].plot(t[checked], margin[checked], color=line.get_color(), label=f"n = {n}")
        if ds.attrs["status"] == "limit":
            axes[0].plot(t[-1], float((ds.r / ds.r0).isel(s=n // 2, time=-1)), "x", color=line.get_color(), ms=8)
    lost = min(ds.attrs.get("ellipticity_lost_time", np.inf) for ds in runs.values()) * 1e3
    for ax in axes:
        if math.isfinite(lost):
            ax.axvline(lost, color="0.5", ls=":", lw=1)
        ax.set_xlabel("t [ms]")
    axes[0].axhline(critical, color="k", ls="--", lw=0.8, label="closed form: loss of ellipticity")
    axes[0].set_ylabel("hoop stretch at the equator")
    axes[0].set_title("svk, nu = 0.49: x = stopped (SVK's turning point)", fontsize=9)
    axes[1].axhline(0.0, color="k", lw=0.8)
    axes[1].set_ylabel("ellipticity margin (smallest over cells)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    run_script(main)
