"""Figure of the stability report: predicted vs measured leap-frog steps, and wall times."""

from __future__ import annotations

import numpy as np

from mol_shell.views.figures import save_figure


def plot_report(ds, path):
    """Two panels over the cases: leap-frog step (bound from eigenvalues vs bisection), wall times."""
    import matplotlib.pyplot as plt

    labels = [str(c) for c in ds.case.values]
    x = np.arange(len(labels))
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(max(8, 0.55 * len(labels)), 7), sharex=True)
    top.semilogy(x, ds["leapfrog_dt_bound"], "o", mfc="none", label="bound 1/max|eig J|")
    if "leapfrog_dt_stable" in ds:
        top.semilogy(x, ds["leapfrog_dt_stable"], "k.", label="largest stable step (bisection)")
    top.set_ylabel("leap-frog step [s]")
    top.legend(fontsize=8)
    for name, marker in (("leapfrog", "s"), ("cvode_bdf", "^"), ("ida", "v")):
        key = f"{name}_wall_s"
        if key in ds:
            ok = np.array([str(s) == "complete" for s in ds[f"{name}_status"].values])
            wall = ds[key].values.astype(float)
            bottom.semilogy(x[ok], wall[ok], marker, label=name)
    bottom.set_ylabel("wall time [s]")
    bottom.legend(fontsize=8)
    bottom.set_xticks(x, labels, rotation=60, ha="right", fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    return path
