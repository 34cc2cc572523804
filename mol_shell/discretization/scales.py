"""The energy scale of a discretised wall that tolerances and checks are measured against."""

from __future__ import annotations

import numpy as np


def unit_strain_energy(system):
    """The energy of a unit strain of the whole wall, J: ``A 2h (lambda + 2 mu)``, with ``A`` the reference base
    surface's area by the grid's quadrature (``2 pi sum w_i r_i``), ``2h`` the wall's (nominal) thickness and
    ``lambda + 2 mu`` the scene's small-strain modulus.

    The one scale of the energy monitor's round-off allowance (:class:`mol_shell.integrators.base.Monitor`), the
    accumulators' least absolute tolerance (:meth:`mol_shell.integrators.tolerances.Tolerances.accumulator_atol`) and
    the energy balance's least exchange (:func:`mol_shell.runs.building.energy_balance_error`). A graded wall counts
    its nominal ``h`` (not ``h(s)``) and a layered one the scene's own modulus: it is a scale, not the wall's energy.
    """
    area = 2 * np.pi * float(np.sum(system.weights * system.reference[1]))
    return area * 2 * system.thickness.h * (system.lam + 2 * system.mu)
