"""The torque the constraint of an unshearable run carries, which its law does not.

The constrained run of the unshearable scene (:mod:`mol_shell.runs.unshearable`) adds to the discrete Lagrangian

    - 2 pi r0 sum_cells lambda_chi (chi_{i+1} - chi_i) = - sum_cells ds (2 pi r0 lambda_chi) chi_s,

so the constraint's energy per unit reference length of the generator is ``2 pi r0 lambda_chi chi_s``. The axial
torque through a section is the derivative of the energy per unit length with respect to ``chi_s``
(:mod:`mol_shell.results.stresses`: ``d(2 pi r0 What)/dchi_s``, the flux of axial angular momentum), so the
constraint adds ``2 pi r0 lambda_chi`` to the law's torque: with ``chi_s = 0`` and ``psi = 0`` the law's is zero to
round-off, and the whole torque is the constraint's (the sections of a spinning shell that breathes exchange their
angular momentum through it). Its chi equation at node ``i``, ``d/dt p_i = T_i - T_{i-1}`` with ``T`` the total
torque of cell ``i``, makes the torque through a section the rate of change of the angular momentum on its smaller
``s`` side.

``lambda_psi``, the multiplier of ``psi = 0``, is conjugate to ``psi`` itself, not to a derivative along ``s``: a
couple per unit area, like a distributed load, which enters no resultant through a section. The torque of
``lambda_chi`` is a total: how it is shared between ``r n^s.a3`` (``membrane_shear_force``) and ``m^s.k``
(``twisting_moment``), and through the thickness (the face stresses), the constraint does not determine, so those
stay the law's.
"""

from __future__ import annotations

import math

import numpy as np

#: ``attrs["comment"]`` of ``axial_torque`` where the constraint's torque is in it
CONSTRAINT_COMMENT = (
    "a constrained (unshearable) run: the law's torque plus the torque of the constraint chi_s = 0, 2 pi r0 "
    "lambda_chi (with chi_s = 0 and psi = 0 the law's is zero); how the constraint's torque is shared between "
    "membrane_shear_force and twisting_moment, and through the thickness, it does not determine: those and the face "
    "stresses are the law's alone")


def constraint_torque(ds):
    """``2 pi r0 lambda_chi`` on ``(time, s_cell)`` (N m) of a constrained unshearable run ``ds`` (its ``lambda_chi``
    on the cells, ``r0`` the reference radius at the cell centres), or ``None`` for a run without the constraint."""
    if "lambda_chi" not in ds or ds["lambda_chi"].dims != ("time", "s_cell"):
        return None
    r0 = np.asarray(ds["r0"].values, dtype=float) if "r0" in ds else np.ones(ds.sizes["s"])
    return 2 * math.pi * (r0[1:] + r0[:-1]) / 2 * np.asarray(ds["lambda_chi"].values, dtype=float)


__all__ = ["CONSTRAINT_COMMENT", "constraint_torque"]
