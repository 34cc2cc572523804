"""Modes about the natural state of tension-only fibres: warned, and bracketed by the slack and the taut wall's.

Tension-only fibres store ``(E_f / 2) max(a.E a, 0)^2``. In the natural state every fibre strain is zero, where the
energy's second derivative jumps from 0 to ``E_f``: no linear mode exists there, and the stiffness the modes use
takes one side or the other point by point, as the round-off of the zero strains falls. What holds whichever side
each point takes: at zero strain the fibres' stiffness is ``E_f g g^T`` (``g`` the gradient of the fibre strain,
the stress term vanishing) on the points that take the stretched side, a positive semi-definite addition to the
wall's; the mass does not change. So (Weyl's monotonicity, for ``K_slack <= K_mixed <= K_taut`` with one mass) every
frequency lies between the slack wall's (``fibre_E = 0``) and the taut wall's (``fibre_compression = true``), mode by
mode. The command and the file say which state this is; an inflated state, where every fibre is stretched, is not
warned about.
"""

from __future__ import annotations

import numpy as np
import pytest

from mol_shell import MaterialWarning, Sphere, modes

N = 8
COUNT = 6
WALL = {"material": "svk-plane-stress", "nu": 0.3, "fibre_angle": 0.3}


@pytest.fixture(scope="module")
def natural():
    with pytest.warns(MaterialWarning, match="tension-only fibres") as caught:
        ds = modes(Sphere(**WALL, fibre_E=1e12, fibre_compression=False), n=N, count=COUNT)
    return ds, caught


def test_the_natural_state_of_tension_only_fibres_is_warned_about_in_the_run_and_the_file(natural):
    ds, caught = natural
    assert "no linear mode exists there" in ds.attrs["fibre_warning"]
    assert any("fibre_compression = true gives the taut wall's modes" in str(w.message) for w in caught)


def test_each_frequency_lies_between_the_slack_and_the_taut_walls(natural):
    ds, _ = natural
    slack = modes(Sphere(**WALL, fibre_E=0.0), n=N, count=COUNT).frequency.values
    taut = modes(Sphere(**WALL, fibre_E=1e12, fibre_compression=True), n=N, count=COUNT).frequency.values
    mixed = ds.frequency.values
    assert np.all(taut > slack * (1 + 1e-3))  # the fibres are stiff enough to tell the walls apart
    assert np.all(mixed >= slack * (1 - 1e-9)) and np.all(mixed <= taut * (1 + 1e-9))


def test_taut_fibres_and_an_inflated_state_are_not_warned_about(recwarn):
    taut = modes(Sphere(**WALL, fibre_E=1e12, fibre_compression=True), n=N, count=2)
    inflated = modes(Sphere(**WALL, fibre_E=1e8, fibre_compression=False, pressure=1e3), n=N, count=2)
    assert "fibre_warning" not in taut.attrs and "fibre_warning" not in inflated.attrs
    assert not [w for w in recwarn if "tension-only" in str(w.message)]
