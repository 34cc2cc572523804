"""Figures: the paper's figures 4-8 (r, theta, chi against s, one column per saved time)."""

from __future__ import annotations

import numpy as np

# Axis ranges of the paper's figures 4-8; used when the data fit inside them.
PAPER_LIMITS = {"r": (0.985, 1.005), "theta": (-0.02, 0.02), "chi": (-0.2, 0.2)}
LABELS = {"r": "r [m]", "theta": r"$\theta$ [rad]", "chi": r"$\chi$ [rad]"}


def _limits(values, name):
    lo, hi = PAPER_LIMITS[name]
    vmin, vmax = float(np.nanmin(values)), float(np.nanmax(values))
    if lo <= vmin and vmax <= hi:
        return lo, hi
    pad = 0.05 * max(vmax - vmin, 1e-12)
    return vmin - pad, vmax + pad


def plot_snapshots(ds, path, fields=("r", "theta", "chi"), max_times=8):
    """Plot ``fields`` against ``s`` at the saved times (at most ``max_times``, evenly picked).

    One column per time and one row per field, with the paper's axis ranges where the
    data fit them. Incomplete runs say so in the title.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    idx = np.unique(np.linspace(0, ds.sizes["time"] - 1, min(max_times, ds.sizes["time"])).round().astype(int))
    fig, axes = plt.subplots(len(fields), len(idx), figsize=(2.6 * len(idx) + 0.8, 1.9 * len(fields) + 0.9),
                             sharex=True, sharey="row", squeeze=False)
    s = ds["s"].values
    for row, name in enumerate(fields):
        limits = _limits(ds[name].values, name)
        for col, i in enumerate(idx):
            ax = axes[row, col]
            ax.plot(s, ds[name].values[i], "k.-", lw=1, ms=3)
            ax.set_ylim(*limits)
            ax.axhline(0.0 if name != "r" else 1.0, color="0.8", lw=0.6, zorder=0)
            if row == 0:
                ax.set_title(f"t = {float(ds['time'][i]):.4g} s", fontsize=10)
            if col == 0:
                ax.set_ylabel(LABELS[name])
            if row == len(fields) - 1:
                ax.set_xlabel("s [m]")
    attrs = ds.attrs
    title = (f"{attrs.get('scene', '')}: gamma = {attrs.get('gamma', float('nan')):g} rad/m, "
             f"R = {attrs.get('R', float('nan')):.6f} m, n = {attrs.get('n', '')}, {attrs.get('integrator', '')}")
    if not attrs.get("complete", 1):
        title += f"  [INCOMPLETE: {attrs.get('message', '')}]"
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
