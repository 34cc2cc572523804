"""rhoI != 0 (base surface off the centroidal placement) is supported and conserves what it must.

Its dynamics in closed form: the torsional modes stay exact for every base surface (the ``rhoI``
kinetic term supplies the missing moments) and the shear and breathing frequencies follow the
general mass matrix, in ``test_linear_modes.py``; the kinetic energy with ``rhoI`` in ``test_output.py``.
"""

import numpy as np
import pytest

import mol_shell
from mol_shell.runs.simulate import build


def test_rho_i_terms_enter_the_graph_only_when_needed():
    centroidal, _ = build(mol_shell.TwistedCylinder(), 20)
    shifted, _ = build(mol_shell.TwistedCylinder(zeta1=-2 * mol_shell.TwistedCylinder().h), 20)
    assert centroidal.rho_i == 0
    # base surface on the outer face: rhoI = rho int_{-2h}^0 zeta (1 + zeta) dzeta
    h, rho = mol_shell.TwistedCylinder().h, 1000.0
    assert shifted.rho_i == pytest.approx(rho * (-((2 * h) ** 2) / 2 + (2 * h) ** 3 / 3), rel=1e-12)
    assert shifted.kernel_instructions["node"] > centroidal.kernel_instructions["node"]


def test_rho_i_run_conserves_energy_and_angular_momentum():
    h = mol_shell.TwistedCylinder().h
    scene = mol_shell.TwistedCylinder(zeta1=-2 * h, omega=4.0, psi0=0.05)
    runs = [mol_shell.simulate(scene, n=20, times=np.linspace(0, 0.02, 5), dt=dt, progress=False) for dt in (4e-6, 2e-6)]
    errors = [float(abs(ds.energy - ds.energy[0]).max() / ds.energy[0]) for ds in runs]
    assert errors[1] < errors[0] / 3  # second order: the error falls ~4x when dt halves
    assert errors[0] < 1e-6
    L = runs[1].angular_momentum.values
    assert abs(L[0]) > 1 and np.abs(L - L[0]).max() < 1e-12 * abs(L[0])
