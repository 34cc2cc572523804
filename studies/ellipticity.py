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

import argparse
import math
import os
import warnings

import numpy as np
import xarray as xr

import mol_shell

GRIDS = (40, 80, 160, 320)
QUICK_GRIDS = (21, 41)
NU = 0.49


def run(material, n, t_end):
    """One release: the Dataset (warnings of the run are recorded in its attrs)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mol_shell.simulate(mol_shell.Sphere(R=1.05, material=material, nu=NU), "cvode-bdf", n=n,
                                  times=np.linspace(0.0, t_end, int(round(t_end / 2.5e-4)) + 1), stresses=False)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two grids (and one for the plane-stress law)")
    parser.add_argument("--out", default="out", help="output directory")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
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
    out = xr.Dataset(
        {key: (("case",), [row[key] for row in rows], attrs) for key, attrs in (
            ("material", {"long_name": "material law"}),
            ("n", {"units": "1", "long_name": "nodes"}),
            ("status", {"long_name": "how the run ended"}),
            ("lost", {"units": "s", "long_name": "first saved time past the loss of ellipticity (NaN: none)"}),
            ("stop", {"units": "s", "long_name": "time the run stopped at a limit of the model (NaN: it did not)"}),
            ("end", {"units": "s", "long_name": "last saved time"}),
            ("stretch_min", {"units": "1", "long_name": "smallest hoop stretch at the equator"}),
            ("margin_min", {"units": "1", "long_name": "smallest ellipticity margin over the saved states"}))},
        coords={"case": np.arange(len(rows))},
        attrs={"title": "breathing sphere: the loss of ellipticity and the grid", "critical_stretch": critical,
               "nu": NU, "R": 1.05})
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
    main()
