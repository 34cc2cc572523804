"""A vessel drawn down from its top pole runs backwards: its graded wall is the one drawn.

Its segments run from their last point (``mol_shell.scenes.segments.backwards``), so the run's ``s'`` is ``L - s`` of
the drawing's ``s``. A graded wall (``h_profile``) is given along the segments as drawn: ``h(s)`` of the drawing is
``h(L - s')`` of the run. Taken in the run's ``s'`` as given, the thick part of the wall stood at the other end of the
vessel. The asymmetric vessel of test_segments.py drawn up from its bottom pole with ``h_up(s)`` and drawn down from
its top pole with ``h_down(s) = h_up(L - s)`` (the same wall: thick at the head) is one shell: both run from the
bottom pole, node for node the same material point, the drawing down starting at ``z = 0`` on top (``z`` moved down
by the height ``H``). The attrs hold the profile as run and as given (``h_profile_requested``).
"""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.path_start import scene_params
from mol_shell.analysis.run_scene import run_scene
from mol_shell.discretization.system import ShellSystem
from mol_shell.model import thickness_profile
from mol_shell.model.thickness_profile import thickness_function
from mol_shell.scenes import Vessel
from mol_shell.views.fields import face_depths

#: the asymmetric vessel of test_segments.py: hemispherical bottom (radius 1), 1 m cylinder, torispherical top
#: (crown 2, knuckle 0.2, ``sin(phi1) = 0.8 / 1.8``), drawn up from its bottom pole and down from its top pole
PHI1 = math.asin(0.8 / 1.8)
CROWN, KNUCKLE = repr(math.degrees(PHI1)), repr(90.0 - math.degrees(PHI1))
UP = f"arc 1 -90, line 1, arc 0.2 -{KNUCKLE}, arc 2 -{CROWN}"
DOWN = f"arc 2 {CROWN}, arc 0.2 {KNUCKLE}, line 1, arc 1 90"
HEIGHT = 2.0 + 2.0 * (1 - math.cos(PHI1)) + 0.2 * math.cos(PHI1)
LENGTH = math.pi / 2 + 1.0 + 0.2 * (math.pi / 2 - PHI1) + 2.0 * PHI1  # the arcs' R |angle| and the line


def h_up(s):
    """The wall drawn up: 5 mm at the bottom pole, three times that at the top pole (``s`` from the bottom)."""
    return 0.005 * (1 + 2 * (s / LENGTH) ** 2)


#: the same wall as the two drawings give it: along each one's own s
PROFILE_UP = f"0.005 * (1 + 2 * (s / {LENGTH!r}) ** 2)"
PROFILE_DOWN = f"0.005 * (1 + 2 * (({LENGTH!r} - s) / {LENGTH!r}) ** 2)"
WALL = {"h": 0.01, "material": "svk-plane-stress", "nu": 0.3, "pressure": 2e3, "gravity": 9.81}
N = 17


def _static(segments, profile):
    """The vessel at its static start under pressure and gravity, carried at its bottom pole (``end1``, both
    drawings) by an axial force equal to its weight ``g sum mA`` (the lumped masses gravity acts on)."""
    weight = WALL["gravity"] * float(np.sum(ShellSystem(Vessel(segments=segments, h_profile=profile, **WALL),
                                                        N).inertia[0]))
    scene = Vessel(segments=segments, h_profile=profile, end1_force=weight, **WALL)
    return scene, mol_shell.simulate(scene, "leapfrog", n=N, times=[0.0, 1e-6], progress=False)


def test_a_graded_vessel_drawn_down_stands_as_the_same_vessel_drawn_up():
    """Inflated by 2 kPa and hung by its bottom pole under gravity, from its static start. The equations are
    invariant under a translation along the axis, so the drawing down's equilibrium is the drawing up's moved down by
    ``H``: ``r`` the same at equal ``z - z(bottom pole)`` node for node, to round-off. Its wall is the drawn one: the
    half-thickness in the files (``zeta_face``, the faces ``-h, +h`` at the cell centres; the views' face depths at
    the nodes) is ``h_up`` of the arc length from the bottom pole in both. Before, the drawing down ran
    ``h_down`` of its own ``s`` (from the bottom pole), the thick wall at the bottom (14.4 mm at the bottom pole's
    cell for 5.0 mm): ``r`` off by 25 mm, ``z`` by 0.16 m. The file holds the profile as run (the run's ``s``), the one given in ``h_profile_requested``, and its
    scene (``--from``, ``scenes RUN.nc --toml``) is the one given."""
    (_, up), (down_scene, down) = _static(UP, PROFILE_UP), _static(DOWN, PROFILE_DOWN)
    u, d = up.isel(time=0), down.isel(time=0)
    np.testing.assert_allclose(d.z.values + HEIGHT, u.z.values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(d.r.values, u.r.values, rtol=0, atol=1e-12)
    assert np.ptp(u.r.values[1:-1] - u.r0.values[1:-1]) > 1e-3  # an asymmetric state to tell the ends apart
    s_cell = (u.s.values[1:] + u.s.values[:-1]) / 2  # from the bottom pole in both runs
    for ds in (up, down):
        np.testing.assert_allclose(ds.zeta_face.values, np.column_stack([-h_up(s_cell), h_up(s_cell)]),
                                   rtol=1e-12, atol=0)
        np.testing.assert_allclose(face_depths(ds)[1], h_up(u.s.values), rtol=1e-12, atol=0)
    assert down.attrs["h_profile_requested"] == PROFILE_DOWN and down.attrs["reversed_parameters"] == "h_profile"
    np.testing.assert_allclose(thickness_function(down.attrs["h_profile"], LENGTH)(u.s.values), h_up(u.s.values),
                               rtol=1e-14, atol=0)
    assert "h_profile_requested" not in up.attrs and "reversed_parameters" not in up.attrs
    assert scene_params(down)["h_profile"] == PROFILE_DOWN and run_scene(down) == down_scene
    note = " ".join(down_scene.stand_ins())
    assert "a graded wall's h_profile is given in the drawing's s (from their first pole) and runs as h(L - s)" in note


def test_a_table_runs_reversed_and_its_masses_are_where_drawn():
    """A table's points at ``L - s`` in reverse order, its ``h`` as typed (``h`` piecewise linear, so the same at the
    run's nodes to round-off); the lumped masses (``mA``, ``mI``) of the drawing down are the drawing up's node for
    node. An expression's ``s`` becomes ``(L - s)``; an expression without ``s`` or a text that does not read is
    left as given (no ``h_profile`` in ``ran_values``; a refusal quotes what was typed)."""
    table = "table 0:0.006 1:0.012 2.5:0.02 4:0.008"
    turned = thickness_profile.reversed_profile(table, 4.0)
    assert turned == "table 0.0:0.008 1.5:0.02 3.0:0.012 4.0:0.006"
    s = np.linspace(0.0, 4.0, 41)
    np.testing.assert_allclose(thickness_function(turned, 4.0)(s), thickness_function(table, 4.0)(4.0 - s), rtol=1e-15)
    expression = "0.01 * sqrt(1 + s) * exp(-s / 2)"
    np.testing.assert_allclose(thickness_function(thickness_profile.reversed_profile(expression, 4.0), 4.0)(s),
                               0.01 * np.sqrt(5 - s) * np.exp(-(4 - s) / 2), rtol=1e-15, atol=0)
    assert thickness_profile.reversed_profile("0.01 * pi", 4.0) == "0.01 * pi"
    assert thickness_profile.reversed_profile("table 0:x", 4.0) == "table 0:x"
    assert "h_profile" not in Vessel(segments=DOWN, h_profile="0.01").ran_values()
    length = Vessel(segments=UP).meridian().length
    up_table = f"table 0:0.005 1:0.006 3:0.012 {length!r}:0.015"
    down_table = f"table 0:0.015 {length - 3!r}:0.012 {length - 1!r}:0.006 {length!r}:0.005"
    up, down = (ShellSystem(Vessel(segments=seg, h_profile=p, h=0.01), 13) for seg, p in ((UP, up_table),
                                                                                           (DOWN, down_table)))
    np.testing.assert_allclose(down.inertia, up.inertia, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(down.graded(down.s), up.graded(up.s), rtol=1e-12, atol=0)


def test_a_wall_too_thick_for_the_knuckle_is_refused_where_it_is_drawn():
    """The drawing down's knuckle (radius 0.2 m) lies at its ``s`` in ``[2 phi1, 2 phi1 + 0.2 (pi/2 - phi1)]``
    (0.921 to 1.148 m, after the crown of radius 2). A 0.25 m wall there reaches the knuckle's centre of curvature:
    refused naming ``h_profile``, at an ``s`` of the drawing inside the knuckle. The same wall on the bottom
    hemisphere (radius 1) fits; it was refused before, taken from the bottom pole (onto the knuckle)."""
    start, end = 2 * PHI1, 2 * PHI1 + 0.2 * (math.pi / 2 - PHI1)
    thick = f"table 0:0.01 0.9:0.01 0.95:0.25 1.1:0.25 1.15:0.01 {LENGTH!r}:0.01"
    with pytest.raises(ParameterError) as caught:
        Vessel(segments=DOWN, h_profile=thick)
    assert caught.value.name == "h_profile" and caught.value.value == thick
    where = float(str(caught.value).split("(at s = ")[1].split(" m")[0])
    assert start - 0.01 <= where <= end + 0.01, str(caught.value)
    bottom = f"table 0:0.01 {LENGTH - 1.15!r}:0.01 {LENGTH - 1.1!r}:0.25 {LENGTH - 0.95!r}:0.25 " \
             f"{LENGTH - 0.9!r}:0.01 {LENGTH!r}:0.01"
    assert Vessel(segments=DOWN, h_profile=bottom).ran_values()["h_profile"].startswith("table ")
