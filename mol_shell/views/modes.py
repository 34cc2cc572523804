"""Figure of a natural-modes Dataset: the lowest shapes along s, with each field's share of kinetic energy.

Each mode has two panels sharing ``s``: the displacements ``z, r`` above, the angles ``chi, theta, psi`` below,
each on its own axis (a shape is scaled so that its entry of largest magnitude over all fields is +1, so metres
and radians are drawn to their own scales, never on one). The shapes have no units of their own (a mode's amplitude is arbitrary): the
axes say "shape of z, r (scaled)", not metres.
"""

from __future__ import annotations

import os

import numpy as np
import xarray as xr

from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import ParameterError, kind_of
from mol_shell.results.dataset import holdings, is_run, read_netcdf
from mol_shell.views.figures import save_figure

#: the fields drawn in each of a mode's two panels, and the unit of their entries before the shape was scaled
PANELS = ((("z", "r"), "m"), (("chi", "theta", "psi"), "rad"))
COLORS = dict(zip(FIELDS, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")))


def modes_of(ds):
    """The modes a figure draws: ``ds`` (checked: natural modes, as :func:`mol_shell.modes` returns), or the file at
    ``ds``; anything else refused naming ``ds``."""
    shown = str(ds) if isinstance(ds, (str, os.PathLike)) else f"<{kind_of(ds)}>"
    if isinstance(ds, (str, os.PathLike)):
        ds = read_netcdf(ds)
    if not (isinstance(ds, xr.Dataset) and "mode" in ds.dims and all(ds[f].dims[0] == "mode" for f in FIELDS
                                                                      if f in ds) and all(f in ds for f in FIELDS)):
        what = ("a run (mol-shell run)" if is_run(ds) else holdings(ds)) if isinstance(ds, xr.Dataset) else "not a Dataset"
        raise ParameterError.invalid("ds", shown, f"is {what}, not natural modes",
                                     "the Dataset of mol_shell.modes, or its netCDF file")
    return ds


def modes_figure(ds, count=6):
    """The lowest ``count`` mode shapes against ``s`` (a matplotlib ``Figure``, not saved): per mode, lengths and
    angles on their own axes, with the frequency, the dominant field and each field's share of the kinetic energy.
    A field below 1e-3 of the mode's largest entry is left out of its panel."""
    import matplotlib.pyplot as plt

    ds = modes_of(ds)
    count = min(count, ds.sizes["mode"])
    cols = 3 if count > 4 else count
    rows = -(-count // cols)
    fig, axes = plt.subplots(2 * rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False, sharex=True)
    for m in range(rows * cols):
        row, col = divmod(m, cols)
        pair = axes[2 * row : 2 * row + 2, col]
        if m >= count:
            for ax in pair:
                ax.axis("off")
            continue
        mode = ds.isel(mode=m)
        share = mode.energy_fraction.values
        for ax, (names, unit) in zip(pair, PANELS):
            drawn = [name for name in names if np.abs(mode[name]).max() > 1e-3]
            for name in drawn:
                ax.plot(ds.s, mode[name], color=COLORS[name], label=f"{name} ({share[FIELDS.index(name)]:.0%})")
            ax.axhline(0, color="0.8", lw=0.5)
            ax.set_ylabel(f"shape of {', '.join(names)}\n(scaled)", fontsize=8)
            if drawn:
                ax.legend(fontsize=7, loc="best")
        dom = FIELDS[int(np.argmax(share))]
        what = (f"{float(mode.frequency):.5g} rad/s" if np.isfinite(float(mode.frequency)) or "omega_squared" not in mode
                else f"unstable, omega^2 = {float(mode.omega_squared):.5g} s-2")
        pair[0].set_title(f"mode {m + 1}: {what} ({dom})", fontsize=9)
    for ax in axes[-1]:
        ax.set_xlabel("s [m]")
    fig.suptitle(f"{ds.attrs['scene']}: lowest modes (n = {ds.attrs['n']}, {ds.attrs['zero_modes']} rigid motions "
                 "not shown); shapes scaled to 1, share of kinetic energy per field", fontsize=9)
    fig.tight_layout()
    return fig


def plot_modes(ds, path, count=6):
    """Write :func:`modes_figure` to ``path``."""
    save_figure(modes_figure(ds, count), path, dpi=110)
