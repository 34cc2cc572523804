"""Figure and tables of a work-precision Dataset: error against wall time, one line per integrator."""

from __future__ import annotations

import numpy as np

from mol_shell._core.atomic import write_text
from mol_shell.analysis.workprecision import full_table, markdown_table
from mol_shell.results.dataset import write_netcdf
from mol_shell.views.figures import save_figure


def plot(ds, path, target=1e-6):
    """Log-log error against wall time, one line per integrator."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    markers = "osD^v<>phX*"
    for k, name in enumerate(ds.integrator.values):
        row = ds.sel(integrator=name)
        ok = np.isfinite(row.error.values) & (row.status.values == "complete")
        ax.loglog(row.wall_time_s.values[ok], np.maximum(row.error.values[ok], 1e-16), marker=markers[k % len(markers)],
                  label=str(name), linestyle="--" if str(name).startswith(("scipy", "casadi")) else "-")
    ax.axhline(target, color="grey", lw=0.8, ls=":")
    ax.axhline(ds.attrs["reference_error"], color="k", lw=0.6, ls="-.", label="reference converged to")
    ax.set_xlabel("wall time [s] (median of repeats)")
    ax.set_ylabel("max relative error of r, theta, chi")
    ax.set_title(f"work-precision, {ds.attrs['scene']}, n = {ds.attrs['n']}, t = 0..{ds.attrs['times'].split(',')[-1]} s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def companion_files(path):
    """``(png, md)``: the figure and the tables written beside ``path`` (its stem)."""
    stem = str(path).rsplit(".", 1)[0]
    return stem + ".png", stem + ".md"


def write_outputs(ds, path, target=1e-6):
    """``path`` (netCDF), and beside it :func:`companion_files`: ``.png`` and ``.md`` with the same stem."""
    write_netcdf(ds, path)
    png, md = companion_files(path)
    plot(ds, png, target)
    write_text(md, markdown_table(ds, target) + "\n\nAll runs:\n\n" + full_table(ds) + "\n")
    return png, md
