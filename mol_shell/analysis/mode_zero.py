"""What counts as a zero ``omega^2`` among natural modes, beyond each mode's own round-off.

:func:`mol_shell.analysis.modes.roundoff_level` bounds the round-off of a mode's Rayleigh quotient from its own
stiffness terms. Two more bounds make an ``omega^2`` zero:

* the eigensolver's: a backward-stable solve of ``K phi = omega^2 M phi`` (Cholesky of ``M``) returns each
  eigenvalue to within a few machine epsilons of the largest ``omega^2``, whatever the mode. On a thin wall the
  stiffness's range (membrane ~h, bending ~h^3, transverse shear ~h over a rotary inertia ~h^3: the largest
  ``omega^2`` grows like 1/h^2) outruns double precision: the natural sphere at ``h = 1e-8`` m, whose stiffness
  ``B^T C B`` is positive semi-definite (every strain is zero), came out with ``omega^2 = -2847.62`` s-2, 1.3 epsilons
  of the largest (1.0e19 s-2), and was declared unstable. A negative ``omega^2`` within :data:`SOLVER_ROUNDOFF`
  epsilons of the largest is zero to round-off (:func:`solver_floor`), said as such (:func:`floor_note`); a positive
  one keeps its frequency (a decoupled mode, the clamped pipe's slow twist at 3.3e-4 s-2, is resolved far below it).
* a located critical point's (:func:`located_band`): a path locates a bifurcation to a bracket of ``LOCATE_RTOL
  |stop - start|`` in the load (a limit point to ``LOCATE_RTOL`` of the scaled arclength), so its critical
  ``omega^2`` is zero to that bracket times the slope of the path's eigenvalues there (-6.5e-6 and -1.2e-4 s-2 at two
  located points of a compressed cylinder were listed as unstable).
"""

from __future__ import annotations

import math

import numpy as np

from mol_shell._core.errors import ParameterError, is_number
from mol_shell.analysis.path_stability import LOCATE_RTOL

#: a negative omega^2 within this many machine epsilons of the largest omega^2 is zero to the eigensolver's round-off
#: (measured: 1.1, 1.3 and 2.0 epsilons on the natural sphere at n = 21, h = 1e-7, 1e-8, 1e-14 m)
SOLVER_ROUNDOFF = 10.0
#: the band of a located critical point: this many times its bracket times the slope of the path's eigenvalues
LOCATED_SAFETY = 10.0
#: the widest ``zero_band`` modes take, as a share of the largest omega^2 (a located point's is about 1e-11 of it)
BAND_SHARE = 1e-6


def checked_band(band, largest=None):
    """``band`` (s-2) if a finite number in ``[0, BAND_SHARE x largest]`` (``largest`` None: before the solve, in
    ``[0, inf)``); else refused naming ``zero_band`` (an infinite band listed every mode at 0 rad/s)."""
    if not is_number(band) or not 0.0 <= float(band) < math.inf:
        raise ParameterError("zero_band", band, "[0, inf) s-2, finite")
    high = BAND_SHARE * abs(float(largest)) if largest is not None else math.inf
    if float(band) > high:
        raise ParameterError("zero_band", band, f"[0, {high:.4g}] s-2 (at most {BAND_SHARE:g} of the largest "
                             f"omega^2, {abs(float(largest)):.4g} s-2: a wider band would swallow frequencies)")
    return float(band)


def solver_floor(largest):
    """The eigensolver's round-off of an ``omega^2`` (s-2): :data:`SOLVER_ROUNDOFF` epsilons of ``largest``."""
    return SOLVER_ROUNDOFF * np.finfo(float).eps * abs(float(largest))


def zero_mask(w2, own, floor, band=0.0):
    """The modes whose ``omega^2`` (``w2``) is zero: within their own round-off ``own`` (per mode), negative within the
    eigensolver's ``floor``, or within a located critical point's ``band``."""
    w2 = np.asarray(w2)
    return (np.abs(w2) <= own) | ((w2 < 0) & (-w2 <= floor)) | (np.abs(w2) <= band)


def floor_note(w2, own, floor, largest):
    """A sentence when any of the listed modes (``w2``, their own round-off ``own``) is negative within the
    eigensolver's ``floor`` only, else ``""``."""
    w2 = np.asarray(w2)
    hit = np.flatnonzero((w2 < 0) & (-w2 <= floor) & (np.abs(w2) > own))
    if not hit.size:
        return ""
    numbers = ", ".join(str(int(m) + 1) for m in hit)
    return (f"mode{'s' * (hit.size != 1)} {numbers} (omega^2 down to {w2[hit].min():.6g} s-2) "
            f"{'are' if hit.size != 1 else 'is'} zero to the eigensolver's round-off, not unstable: |omega^2| <= "
            f"{floor:.3g} s-2, {SOLVER_ROUNDOFF:g} machine epsilons of the largest omega^2 ({largest:.3g} s-2); "
            "listed at 0 rad/s. Modes below that are not resolved in double precision: the wall's stiffness range "
            "(membrane ~h, bending ~h^3, shear ~h over a rotary inertia ~h^3) outruns it; a thicker wall (h) "
            "resolves them")


def located_band(path, point):
    """The band (s-2) within which ``omega^2`` is zero about critical point ``point`` of ``path`` (a path Dataset),
    0 when the path did not locate it: :data:`LOCATED_SAFETY` times the bracket the path closes
    (:data:`~mol_shell.analysis.path_stability.LOCATE_RTOL` of ``|stop - start|`` in the load for a bifurcation, of
    the scaled arclength for a limit point) times the largest slope of the path's eigenvalues nearest zero between
    the steps around it."""
    if "point_located" in path and not int(path["point_located"].values[point]):
        return 0.0
    if "smallest_eigenvalues" not in path or path.sizes.get("step", 0) < 2:
        return 0.0
    i = min(int(path["point_step"].values[point]), path.sizes["step"] - 2)
    spectra = path["smallest_eigenvalues"].values[[i, i + 1]]
    if str(path["point_kind"].values[point]) == "limit":
        along, bracket = path["arclength"].values[[i, i + 1]], LOCATE_RTOL
    else:
        along = path["parameter"].values[[i, i + 1]]
        bracket = LOCATE_RTOL * abs(float(path.attrs["stop"]) - float(path.attrs["start"]))
    change = np.abs(spectra[1] - spectra[0])
    width = abs(float(along[1] - along[0]))
    if not width or not np.isfinite(change).any():
        return 0.0
    return float(LOCATED_SAFETY * bracket * np.nanmax(change) / width)
