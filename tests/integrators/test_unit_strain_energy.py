"""The energy of a unit strain of the wall, the one scale of the energy monitor, the accumulators' tolerance and the
energy balance's floor (it was computed in each of the three, from ``scene.h`` in two and ``thickness.h`` in one)."""

import math

import numpy as np
import pytest

from mol_shell.discretization.scales import unit_strain_energy
from mol_shell.discretization.system import ShellSystem
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.base import Monitor
from mol_shell.runs.building import energy_balance_error
from mol_shell.runs.checks import initial_state
from mol_shell.scenes import Cone

E, NU, H = 1e6, 0.3, 0.005

WALLS = {
    "uniform": {},
    "graded": {"h_profile": "0.005 * (1 + 0.25 * s)"},  # h(s) from h to 1.5 h; the scale keeps the nominal h
    "layered": {"layers": "0.004 svk-plane-stress; 0.006 svk-plane-stress E=3e6"},
    "graded and layered": {"h_profile": "0.005 * (1 + 0.25 * s)",
                           "layers": "0.004 svk-plane-stress; 0.006 svk-plane-stress E=3e6"},
}


def _tube(**wall):
    """A tube of radius 1 m and length 2 m (a cone with r1 = r2), plane-stress SVK: lambda + 2 mu = E / (1 - nu^2)."""
    scene = Cone(r1=1.0, r2=1.0, H=2.0, material="svk-plane-stress", E=E, nu=NU, h=H, end1="clamped", end2="free",
                 end2_force=10.0, dilation=1.0, **wall)
    return scene, ShellSystem(scene, 7)


@pytest.mark.parametrize("wall", WALLS)
def test_the_scale_is_the_walls_unit_strain_energy_and_the_same_in_all_three_places(wall):
    scene, system = _tube(**WALLS[wall])
    unit = unit_strain_energy(system)
    # the closed form: area 2 pi a L, thickness 2 h (nominal), modulus E / (1 - nu^2); the grid's trapezoidal area of
    # a cylinder is exact
    assert unit == pytest.approx(2 * math.pi * 1.0 * 2.0 * 2 * H * E / (1 - NU**2), rel=1e-13)
    # scene.h and the thickness rule's h are one number whatever the wall (a graded or layered wall keeps the
    # nominal h in its rule), so the three former formulas agreed to the last bit
    assert system.thickness.h == scene.h
    area = 2 * np.pi * float(np.sum(system.weights * system.reference[1]))
    assert unit == area * 2 * scene.h * (system.lam + 2 * system.mu)
    assert unit == area * 2 * system.thickness.h * (system.lam + 2 * system.mu)

    y0 = initial_state(scene, system)
    monitor = Monitor(system, y0)
    e0 = monitor.energy_start
    assert monitor.energy_limit == e0 + Monitor.ENERGY_GROWTH * abs(e0) + 1e-9 * unit
    method = INTEGRATORS["cvode-bdf"](rtol=1e-6)
    out = system.observables(y0, 0.0)
    start = abs(float(out[1])) + abs(float(out[2]))
    assert method.accumulator_atol(system, y0) == 1e-6 * max(start, 1e-9 * unit)
    tiny = 0.1 * 1e-12 * unit  # a defect below the floor of the exchange: relative to the floor
    zeros = np.zeros(2)
    totals = {"kinetic": np.array([0.0, tiny]), "stored": zeros, "work": zeros, "dissipated": zeros}
    assert energy_balance_error(system, totals) == tiny / (1e-12 * unit)
