"""Grid modes among natural modes: the share of each mode in the node-to-node ``(-1)^i`` pattern.

On thin walls the lowest modes of the discretisation can be the grid's, far below the physical spectrum: ``theta``
alternates in sign from node to node under a slow envelope, with the kinetic energy in ``r`` and ``z`` (the thin
sphere, ``h = 3e-4``, plane stress, ``nu = 0.3``: 14.65 rad/s at n = 41, where no mode of the membrane sphere lies
below 23.236 rad/s; at n = 161 the lowest is 23.234 rad/s). Refining ``n`` moves them up. :func:`mark_grid_modes`
measures each mode's share in that pattern (:func:`mol_shell.results.study_store.grid_mode`, its local form), stores
it as ``grid_mode_share`` and warns where one of the listed modes is mostly the pattern.
"""

from __future__ import annotations

import warnings

import numpy as np

from mol_shell._core.errors import MolShellWarning
from mol_shell.model.kinematics import FIELDS
from mol_shell.results.study_store import grid_mode

#: a mode whose share (:func:`grid_mode_share`) is at least this is a grid mode
GRID_MODE_SHARE = 0.5


def grid_mode_share(ds):
    """Each mode's share of its amplitude in the ``(-1)^i`` node pattern, ``(mode,)``, between 0 and 1.

    Per field, the pattern's squared amplitude (:func:`~mol_shell.results.study_store.grid_mode` with ``local``:
    ``(1/4, 1/2, 1/4)`` means of ``u (-1)^i``, the envelope free to change sign) over the field's own, on the
    interior nodes; these are weighted by the field's share of the mode's kinetic energy (``energy_fraction``,
    negative shares taken as 0), and the share is the square root of the sum: 1 for a ``(-1)^i`` pattern in every
    field that moves, ``(1 - cos k ds) / 2`` for a wave of ``k``, 0.5 at four nodes a wavelength, ``O(k ds)^2`` for
    a resolved wave."""
    weights = ds["energy_fraction"].clip(min=0.0)
    weights = weights / weights.sum("field").where(weights.sum("field") > 0)
    parts = []
    for name in FIELDS:
        amplitude, _ = grid_mode(ds[name], "s", local=True)
        inner = ds[name].isel(s=slice(1, -1))
        total = (inner**2).sum("s")
        ratio = ((amplitude.isel(s=slice(1, -1)) ** 2).sum("s") / total.where(total > 0)).fillna(0.0)
        parts.append(weights.sel(field=name) * ratio)
    return np.sqrt(sum(parts).clip(0.0, 1.0)).drop_vars("field", errors="ignore")


def mark_grid_modes(ds, stacklevel=3):
    """``ds`` (the Dataset of :func:`mol_shell.analysis.modes.modes`) with ``grid_mode_share(mode)``, and where any
    mode reaches :data:`GRID_MODE_SHARE`, ``attrs["grid_mode_warning"]``, said as a :class:`~mol_shell.MolShellWarning`."""
    share = grid_mode_share(ds)
    ds["grid_mode_share"] = share.assign_attrs(units="1", long_name=(
        "share of the mode's amplitude (fields weighted by their kinetic energy) in the node-to-node (-1)^i pattern "
        f"under a slow envelope; from {GRID_MODE_SHARE:g}: a grid mode, not physical"))
    flagged = np.flatnonzero(share.values >= GRID_MODE_SHARE)
    if flagged.size:
        numbers = ", ".join(str(int(m) + 1) for m in flagged)
        ds.attrs["grid_mode_warning"] = (
            f"mode{'s' * (flagged.size != 1)} {numbers}{_span(ds['frequency'].values[flagged])} "
            f"{'are grid modes' if flagged.size != 1 else 'is a grid mode'}: {share.values[flagged].min():.2f} or "
            f"more of the amplitude in the node-to-node (-1)^i pattern (grid_mode_share); not physical, the "
            f"discretisation's on a thin wall: refining n moves them up")
        warnings.warn(ds.attrs["grid_mode_warning"], MolShellWarning, stacklevel=stacklevel)
    return ds


def _span(freq):
    """`` (14.6 .. 15.2 rad/s)``: the frequencies of the flagged modes, for the warning; a zero one (``omega^2`` zero to
    round-off, listed at 0: :mod:`mol_shell.analysis.mode_zero`) said apart, not as the range's end (``0 .. 0
    rad/s``), and an unstable one's (NaN) left out."""
    freq = freq[np.isfinite(freq)]
    zero, positive = freq[freq == 0], freq[freq > 0]
    parts = []
    if positive.size:
        low, high = positive.min(), positive.max()
        parts.append(f"{low:.6g} rad/s" if f"{low:.6g}" == f"{high:.6g}" else f"{low:.6g} .. {high:.6g} rad/s")
    if zero.size:  # at 0 rad/s: all of them, or so many besides the range
        parts.append(f"{f'{zero.size} ' if positive.size else ''}at 0 rad/s: omega^2 zero to round-off")
    return f" ({'; '.join(parts)})" if parts else ""
