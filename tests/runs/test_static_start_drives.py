"""The static start (``R``/``dilation`` auto) under the loads at ``t = 0`` is the equilibrium at rest; a spin or a
driven edge's rate is set on it afterwards (docs/loads.md). Until December 7 2026 a driven edge's rate entered the
equilibrium equations: its node carried the centrifugal force of its own lumped mass (``m_i r omega^2``, ``m_i``
about ``1/n``), so a spun edge without loads started displaced by an amount that halved with each doubling of ``n``
(a cone's end2_spin = 50 rad/s: 0.134 m at n = 21), and at larger rates the start was refused as if the loads had no
equilibrium."""

from __future__ import annotations

import numpy as np
import pytest

from mol_shell import Cone, TwistedCylinder
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.checks import resolve
from mol_shell.runs.simulate import starting_state
from mol_shell.runs.statics import newton, static_equilibrium

N = 21


@pytest.mark.parametrize("scene", [TwistedCylinder(gamma=0.0, end_omega=50.0),
                                   Cone(material="svk-plane-stress", nu=0.3, end2_spin=50.0)],
                         ids=["cylinder-end_omega", "cone-end2_spin"])
def test_a_driven_spin_without_loads_starts_at_the_natural_state(scene):
    """No loads: the natural state ``r = r0`` (the reference meridian, which carries no force at rest) is the
    start, whatever the spin of the driven edges (as simulate makes it: ``R``/``dilation`` resolved, then the
    start); the driven edges then move at their rate from ``t = 0``."""
    resolved = resolve(scene)
    system = ShellSystem(resolved, N)
    y, how = starting_state(resolved, system, N, asked=scene)
    Q = system.unpack(y)
    assert np.abs(Q[:2] - system.reference[:2]).max() <= 1e-12
    assert "under the loads" not in how  # there are none
    rate = scene.end_omega if isinstance(scene, TwistedCylinder) else scene.end2_spin
    assert system.observables(y, 0.0)[0][2, -1] == pytest.approx(rate, rel=1e-12)


# each driven edge beside the same edge holding the driven field where it is: the same equations at rest
PAIRS = {
    "cone-end2_spin": (Cone(material="svk-plane-stress", nu=0.3, pressure=200.0, end2_spin=50.0),
                       Cone(material="svk-plane-stress", nu=0.3, pressure=200.0, end2="z,chi,theta")),
    "cone-end2_axial_speed": (Cone(material="svk-plane-stress", nu=0.3, pressure=200.0, end2="free",
                                   end2_axial_speed=5.0),
                              Cone(material="svk-plane-stress", nu=0.3, pressure=200.0, end2="z")),
    "cylinder-end_omega": (TwistedCylinder(gamma=0.0, R=1.0, pressure=10.0, end_omega=50.0),
                           TwistedCylinder(gamma=0.0, R=1.0, pressure=10.0, end1="z,chi,theta",
                                           end2="z,chi,theta")),
}


@pytest.mark.parametrize("pair", PAIRS.values(), ids=PAIRS.keys())
def test_a_driven_edge_under_load_starts_at_the_equilibrium_of_the_edge_held_at_rest(pair):
    """Under a pressure, the static start of a scene with a driven edge (spun, or moved axially) is the
    equilibrium of the same scene with that edge holding the driven field where it is at ``t = 0``: the rate is
    not in the equations at rest."""
    driven, held = pair
    system = ShellSystem(driven, N)
    y, how = static_equilibrium(driven, N, system.initial_state(driven))
    assert how.startswith("static equilibrium")
    system_held = ShellSystem(held, N)
    y_held = newton(system_held, system_held.initial_state(held))[0]  # the equations at rest of the held edge
    start, start_held = system.unpack(y), system_held.unpack(y_held)
    assert np.abs(start[1] - system.reference[1]).max() > 1e-6  # the pressure moved the wall
    assert np.abs(start - start_held).max() <= 1e-12
