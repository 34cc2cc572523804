"""A vessel drawn down from its top pole runs backwards: the helix and the twist it runs are the ones drawn.

Its segments run from their last point (``mol_shell.scenes.segments.backwards``), so the run's tangent ``b0_1`` is
the drawing's reversed while the hoop direction ``b0_3 = +phi`` is not. A fibre ``cos(a) b0_1 + sin(a) b0_3`` along
the drawing is ``-(cos(a) b0_1' - sin(a) b0_3)``, the fibre at ``-a`` of the run (a fibre is a line: its sign does
not matter), and a twist ``chi = gamma (s - L/2)`` of the drawing's ``s`` is ``-gamma (s' - L/2)`` of the run's
``s' = L - s``. Run with the values as given, a one-family vessel drawn down was the mirror image of the one drawn:
``chi`` of the opposite sign (an energy the same, a mirror image has it). Now it runs ``-fibre_angle`` and
``-gamma``, and reaches the state of the same vessel drawn up with the same helix and twist (``-a``, ``-gamma`` along
its upward tangent): node for node from the bottom pole, ``r`` and ``chi`` the same and ``z`` moved down by the
height ``H`` (the drawing down starts at ``z = 0`` on top), the same stored energy. The attrs hold each value as run
and as given (``NAME_requested``); a path's scene is the one given.
"""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell.analysis.path_start import path_scene
from mol_shell.scenes import Vessel

#: the asymmetric vessel of test_segments.py: hemispherical bottom, 1 m cylinder, torispherical top (crown 2, knuckle
#: 0.2), drawn up from its bottom pole and down from its top pole
PHI1 = math.asin(0.8 / 1.8)
CROWN, KNUCKLE = repr(math.degrees(PHI1)), repr(90.0 - math.degrees(PHI1))
UP = f"arc 1 -90, line 1, arc 0.2 -{KNUCKLE}, arc 2 -{CROWN}"
DOWN = f"arc 2 {CROWN}, arc 0.2 {KNUCKLE}, line 1, arc 1 90"
HEIGHT = 2.0 + 2.0 * (1 - math.cos(PHI1)) + 0.2 * math.cos(PHI1)
WALL = {"h": 0.02, "material": "svk-plane-stress", "nu": 0.3, "fibre_E": 5e6, "fibre_families": 1, "pressure": 2e3}
N = 17


def _start(segments, angle, gamma):
    return mol_shell.simulate(Vessel(segments=segments, fibre_angle=angle, gamma=gamma, **WALL), "leapfrog", n=N,
                              times=[0.0, 1e-6], stresses=False, progress=False)


@pytest.mark.parametrize("angle, gamma", [(0.5, 0.0), (0.5, 0.2)])
def test_a_vessel_drawn_down_runs_the_helix_and_twist_drawn(angle, gamma):
    """Under pressure one fibre family twists the vessel (its ``chi`` solved for at the static start: 0.09 rad end to
    end), or the twist is held as given (``chi = gamma (s - L/2)`` of the drawing's ``s``, 0.65 rad)."""
    down, up = _start(DOWN, angle, gamma), _start(UP, -angle, -gamma)
    d, u = down.isel(time=0), up.isel(time=0)
    np.testing.assert_allclose(d.r, u.r, rtol=0, atol=1e-12)
    np.testing.assert_allclose(d.z, u.z - HEIGHT, rtol=0, atol=1e-12)
    chi = d.chi.values - u.chi.values
    assert np.ptp(chi) < 1e-12 and np.ptp(d.chi.values) > 1e-2  # a rigid rotation apart, and a twist to tell
    assert float(d.stored_energy) == pytest.approx(float(u.stored_energy), rel=1e-12)
    if gamma:
        s_drawn = d.s.values[-1] - d.s.values  # the drawing's s, from its top pole
        inner = slice(1, -1)  # the poles' chi is tied to their neighbours'
        np.testing.assert_allclose(d.chi.values[inner], gamma * (s_drawn - s_drawn[0] / 2)[inner], rtol=0, atol=1e-12)
    asked = {"fibre_angle": angle, "gamma": gamma}
    ran = {k: v for k, v in asked.items() if v}
    for name, value in asked.items():
        assert down.attrs[name] == -value and (f"{name}_requested" in down.attrs) == bool(value)
        if value:
            assert down.attrs[f"{name}_requested"] == value
        assert f"{name}_requested" not in up.attrs
    assert down.attrs["reversed_parameters"] == ", ".join(k for k in ("gamma", "fibre_angle") if k in ran)
    assert "initial_data_note" not in down.attrs  # no start given as fields
    note = " ".join(Vessel(segments=DOWN, fibre_angle=angle, gamma=gamma, **WALL).stand_ins())
    assert "a twist gamma and one fibre family's fibre_angle, given along the segments, run with the opposite sign" \
        in note


def test_a_pair_of_families_and_a_layer_s_family():
    """A pair ``+-a`` is itself reversed: it runs as given. A layer of one family runs its angle reversed, written
    into ``layers`` (the stresses and the views read it there); its own angle or the scene's."""
    pair = Vessel(segments=DOWN, fibre_angle=0.5, **{**WALL, "fibre_families": 2})
    assert pair.ran_values() == {}
    layered = Vessel(segments=DOWN, fibre_angle=0.3, **{**WALL, "fibre_E": 0.0, "h": 0.03},
                     layers="0.02 svk-plane-stress fibre_E=5e6; 0.02 svk-plane-stress fibre_E=5e6 fibre_angle=0.7; "
                            "0.02 svk-plane-stress")
    assert layered.ran_values() == {"layers": "0.02 svk-plane-stress fibre_E=5000000.0 fibre_angle=-0.3; 0.02 "
                                              "svk-plane-stress fibre_E=5000000.0 fibre_angle=-0.7; 0.02 "
                                              "svk-plane-stress"}
    assert Vessel(segments=UP, fibre_angle=0.5, gamma=0.2, **WALL).ran_values() == {}


def test_a_path_s_scene_is_the_one_given():
    scene = Vessel(segments=DOWN, fibre_angle=0.5, **WALL)
    ds = mol_shell.path(scene, "pressure", 2e3, 2.2e3, n=9, steps=1, progress=False)
    assert ds.attrs["fibre_angle"] == -0.5 and ds.attrs["fibre_angle_requested"] == 0.5
    assert path_scene(ds, 2e3) == scene
