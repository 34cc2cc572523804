"""Whether saved states kept the shell's equations elliptic in ``s`` (the Legendre-Hadamard condition of the 1-D
shell, :meth:`~mol_shell.discretization.limits.ModelLimits.ellipticity_margins`): a Dataset variable, and a warning
with the time (or path step) and place where they did not.

Past that point a compressive membrane force exceeds what a shear (transverse, or in the wall: the twist) carries, waves
short enough grow at rates set by the grid, and a finer grid stops sooner or shows more wrinkles: what follows depends
on ``n``. The check runs on the saved states after the integration (it costs the loop nothing), on every k-th saved
state where all of them would take more than :data:`MAX_INSTRUCTIONS` of CasADi's virtual machine (measured: 0.04-0.10 s
at n = 40 with 200 saved states, 0.15-0.32 s at n = 2,560 with 50). The unshearable scene's DAE is not checked (its
principal symbol is another one); ``ellipticity_limit = true`` (a scene parameter) stops a run there instead
(:meth:`~mol_shell.discretization.limits.ModelLimits.cell_minors`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from mol_shell._core.errors import MaterialWarning
from mol_shell.results.cf import variables

#: Instructions of the principal symbol's kernel evaluated at most per run (cells x states x the kernel's size, 10-30 ns
#: each with the calls): 600 instructions per cell for SVK, 3,000-9,000 for the laws integrated point by point
MAX_INSTRUCTIONS = 6_000_000

FIELDS = ("z", "r", "chi", "theta", "psi")

LONG_NAME = ("smallest eigenvalue over the cells of the shell's principal symbol d2W/d(q_s)2 relative to the natural "
             "state's (the equations are elliptic in s while it is positive)")

CONSEQUENCE = ("compression beyond what a shear (transverse or in the wall) carries; from there short waves grow at "
               "rates set by the grid, so what follows depends on n (docs/materials.md)")


def state_minimum(margins):
    """The smallest margin over the cells of each state (rows of ``margins``), NaN where no cell could be checked."""
    margins = np.atleast_2d(margins)
    low = np.where(np.isnan(margins), np.inf, margins).min(axis=1)
    return np.where(np.isinf(low), np.nan, low)


def unchecked_note(system):
    """A note where some cells cannot be checked (their natural state's principal symbol is singular), else None."""
    bad = int(np.sum(~system._natural_root[1]))
    return None if bad == 0 else (f"ellipticity not checked in {bad} of {system.n - 1} cells: their natural state's "
                                  "principal symbol is not positive definite in double precision (a law without "
                                  "shear stiffness, stiffnesses that, scaled to their diagonal, lie more than "
                                  "1e15 apart, or whose second derivatives under- or overflow)")


def sampled_margins(system, Qs):
    """``(per_state, every, lost)`` for the stack of fields ``Qs`` ``(count, 5, n)``: the smallest margin of each state
    (checked: every ``every``-th state from the first, and the last; NaN at the others and where no cell could be
    checked), and ``(state, s)`` of the first state whose margin is not positive (None if none)."""
    count = len(Qs)
    per_state = np.full(count, np.nan)
    if count == 0:
        return per_state, 1, None
    every = max(1, math.ceil(count * (system.n - 1) * system.principal_symbol.n_instructions() / MAX_INSTRUCTIONS))
    picked = list(range(0, count, every))
    if picked[-1] != count - 1:
        picked.append(count - 1)
    margins = system.ellipticity_margins(np.asarray(Qs)[picked])
    per_state[picked] = state_minimum(margins)
    bad = np.flatnonzero(per_state[picked] <= 0)
    if not bad.size:
        return per_state, every, None
    cell = int(np.nanargmin(margins[bad[0]]))
    return per_state, every, (picked[bad[0]], float((system.s[cell] + system.s[cell + 1]) / 2))


def check_ellipticity(system, ds, warn=True):
    """``ds`` (a run's) with ``ellipticity_margin`` (per saved time; NaN where not checked) and, where it reached 0,
    the attrs ``ellipticity_lost_time`` and ``ellipticity_lost_position`` and a :class:`~mol_shell.MaterialWarning`."""
    Qs = np.stack([ds[name].values for name in FIELDS], axis=1)
    per_state, every, lost = sampled_margins(system, Qs)
    ds = ds.assign(variables({"ellipticity_margin": (("time",), per_state, {"units": "1", "long_name": LONG_NAME})}))
    ds.attrs["ellipticity_checked_every"] = every
    note = unchecked_note(system)
    if note:
        ds.attrs["ellipticity_note"] = note
        if warn and np.all(np.isnan(per_state)):  # said on stderr when no state could be checked at all
            warnings.warn(note, MaterialWarning, stacklevel=3)
    if lost is not None:
        t, s = float(ds.time[lost[0]]), lost[1]
        ds.attrs.update({"ellipticity_lost_time": t, "units_ellipticity_lost_time": "s",
                         "ellipticity_lost_position": s, "units_ellipticity_lost_position": "m"})
        note = (f"the shell's equations lost ellipticity by t = {t:.6g} s at s = {s:.6g} m (cell centre; the first "
                f"{'saved' if every == 1 else 'checked'} state where d2W/d(q_s)2 is not positive definite: "
                f"{CONSEQUENCE})")
        ds.attrs["ellipticity_warning"] = note
        if warn:
            warnings.warn(note, MaterialWarning, stacklevel=3)
    return ds


__all__ = ["CONSEQUENCE", "LONG_NAME", "MAX_INSTRUCTIONS", "check_ellipticity", "sampled_margins", "state_minimum",
           "unchecked_note"]
