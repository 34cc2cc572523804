"""Figure of a natural-modes Dataset: the lowest shapes along s, with each field's share of kinetic energy."""

from __future__ import annotations

import numpy as np

from mol_shell._core.constants import FIELDS
from mol_shell.views.figures import save_figure


def plot_modes(ds, path, count=6):
    """The lowest ``count`` mode shapes against ``s``, one panel each, with frequency and dominant field."""
    import matplotlib.pyplot as plt

    count = min(count, ds.sizes["mode"])
    cols = 3 if count > 4 else count
    rows = -(-count // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 2.8 * rows), squeeze=False, sharex=True)
    colors = dict(zip(FIELDS, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")))
    for m, ax in enumerate(axes.ravel()):
        if m >= count:
            ax.axis("off")
            continue
        mode = ds.isel(mode=m)
        share = mode.energy_fraction.values
        for k, name in enumerate(FIELDS):
            if np.abs(mode[name]).max() > 1e-3:
                ax.plot(ds.s, mode[name], color=colors[name], label=f"{name} ({share[k]:.0%})")
        dom = FIELDS[int(np.argmax(share))]
        ax.set_title(f"mode {m + 1}: {float(mode.frequency):.5g} rad/s ({dom})", fontsize=9)
        ax.axhline(0, color="0.8", lw=0.5)
        ax.legend(fontsize=7, loc="best")
    for ax in axes[-1]:
        ax.set_xlabel("s (m)")
    fig.suptitle(f"{ds.attrs['scene']}: lowest modes (n = {ds.attrs['n']}, {ds.attrs['zero_modes']} rigid motions "
                 "not shown); shapes scaled to 1, share of kinetic energy per field", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
