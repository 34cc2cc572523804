"""Meridians from segments (mol_shell.scenes.segments): a capsule and a torispherical head."""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.polyline import self_intersects
from mol_shell.runs.statics import static_equilibrium
from mol_shell.scenes import Vessel
from mol_shell.scenes.segments import SegmentedMeridian


def test_capsule_and_torispherical_geometry():
    """Capsule: length pi a + Lc, poles at both ends, ``r0 = a`` on the cylinder, tangent continuous (``theta0`` from
    pi/2 to -pi/2). Torispherical head: the knuckle ends on the cylinder, ``r0 <= a``, the crown's curvature
    ``-1/Rc`` at the pole; height of a head ``Rc (1 - cos(phi1)) + rk cos(phi1)`` (from the closure condition)."""
    cap = Vessel(a=1.0, Lc=2.0, crown=1.0).meridian()
    assert cap.length == pytest.approx(math.pi + 2.0, rel=1e-14) and cap.poles == (True, True)
    s = np.linspace(0, cap.length, 4001)
    r0, z0, th0, k = cap.at(s)
    assert np.max(np.abs(np.diff(th0))) < 2 * np.diff(s)[0]  # continuous tangent
    assert np.allclose(r0[(z0 > 1.0) & (z0 < 3.0)], 1.0) and z0[-1] == pytest.approx(4.0)
    dr, dz = np.gradient(r0, s), np.gradient(z0, s)
    # dz0/ds = cos theta0, dr0/ds = sin theta0 (central differences: O(ds) = 1e-3 where the curvature jumps)
    assert np.allclose(dz[1:-1], np.cos(th0[1:-1]), atol=1e-3) and np.allclose(dr[1:-1], np.sin(th0[1:-1]), atol=1e-3)
    a, Rc, rk = 1.0, 2.0, 0.2
    tori = Vessel(a=a, Lc=1.0, crown=Rc, knuckle=rk).meridian()
    r0, z0, th0, k = tori.at(np.linspace(0, tori.length, 4001))
    phi1 = math.asin((a - rk) / (Rc - rk))
    height = Rc * (1 - math.cos(phi1)) + rk * math.cos(phi1)
    assert r0.max() == pytest.approx(a, rel=1e-12) and k[0] == -1 / Rc
    assert z0[-1] == pytest.approx(2 * height + 1.0, rel=1e-12)
    same = SegmentedMeridian((("arc", 1.0, -math.pi / 2), ("line", 2.0), ("arc", 1.0, -math.pi / 2)))
    assert np.allclose(same.at(s)[0], Vessel(segments="arc 1 -90, line 2, arc 1 -90").meridian().at(s)[0])


def test_capsule_cylinder_carries_the_membrane_stresses():
    """A closed capsule (``a = 1``, ``Lc = 3``, ``h = 5 mm``, plane-stress SVK) at equilibrium under ``p = 10 Pa``: in the
    middle of its cylinder, far from the caps (1.5 m against a bending length ``sqrt(a t)`` = 0.1 m), the hoop and
    meridional stresses are ``p a / t`` and ``p a / (2 t)``, ``t = 2h``: to 2e-3, the strain (the resultants are per
    unit reference length). Exactly, on the deformed middle (radius ``r``, meridional stretch ``l``): ``N_hoop = p r l``
    per unit reference ``s`` and ``N_s = (p r / 2)(r / a)`` per unit reference circumference, to 1e-4."""
    p, a, h = 10.0, 1.0, 0.005
    scene = Vessel(a=a, Lc=3.0, crown=a, h=h, material="svk-plane-stress", nu=0.3, pressure=p)
    ds = mol_shell.simulate(scene, "leapfrog", n=41, times=[0.0, 1e-6], progress=False)
    assert "static equilibrium" in ds.attrs["initial_state"]
    k = ds.sizes["s_cell"] // 2
    t = 2 * h
    hoop, merid = (ds[v].values[0, k - 1:k + 1] / t for v in ("membrane_force_hoop", "membrane_force_meridional"))
    np.testing.assert_allclose(hoop, p * a / t, rtol=2e-3)
    np.testing.assert_allclose(merid, p * a / (2 * t), rtol=2e-3)
    r = ds.r.values[0, k - 1:k + 2]
    stretch = np.diff(ds.z.values[0, k - 1:k + 2]) / np.diff(ds.s.values[k - 1:k + 2])
    rm = (r[1:] + r[:-1]) / 2
    np.testing.assert_allclose(hoop * t, p * rm * stretch, rtol=1e-4)
    np.testing.assert_allclose(merid * t, p * rm / 2 * rm / a, rtol=1e-4)


@pytest.mark.parametrize("setting, words", [
    ("segments=arc 1", "segments = 'arc 1' is outside"),
    ("crown=0.5", "crown = 0.5 is outside [a, inf) = [1, inf) m"),
    ("knuckle=2", "knuckle = 2"),
    # were refused naming h (the thickness interval off the axis)
    ("segments=arc 1 -720", ("segments = 'arc 1 -720' is outside 'arc RADIUS ANGLE_DEG' and 'line LENGTH' separated "
                             "by commas (radius, length > 0, m; 0 < |ANGLE_DEG| < 360) (the arc 'arc 1 -720' turns by "
                             "-720 degrees")),
    ("segments=arc 1 -300", ("segments = 'arc 1 -300' is outside segments whose meridian stays off the axis "
                             "between its ends and does not cross itself (segment 1 ('arc 1 -300') reaches the axis "
                             "at s = 3.142 m along the segments as drawn, from the start of the first)")),
    # were refused as internal tuples, or with the full circle's reason
    ("segments=line -1", "(the line 'line -1' has a length that is not positive and finite)"),
    ("segments=arc 0 90", "(the arc 'arc 0 90' has a radius that is not positive and finite)"),
    ("segments=arc 0.5 0", "(the arc 'arc 0.5 0' turns by 0 degrees: an arc must turn)"),
])
def test_bad_segments_one_line_exit_2(capsys, tmp_path, setting, words):
    args = ["run", "vessel", "--set", setting, "--n", "9", "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    with pytest.raises(ParameterError):
        SegmentedMeridian((("arc", -1.0, 1.0),))


@pytest.mark.parametrize("law", [{}, {"material": "svk-plane-stress"}, {"nu": 0.3, "E": 2e9}])
def test_an_overflowing_meridian_is_blamed_on_its_segments_not_on_the_law(law):
    """An arc of radius 1e300 m: the centroid's equation for h overflows. With a law set beside it, the refusal
    named ``material`` (the first changed field), a parameter that plays no part in whether the wall fits."""
    with pytest.raises(ParameterError) as caught:
        Vessel(segments="arc 1e300 -90, line 2, arc 1 -90", **law)
    assert caught.value.name == "segments" and str(caught.value).startswith("segments = 'arc 1e300 -90"), caught.value


# -- the director out of the vessel whatever the angles' sign -----------------------------------------------------
CAPSULE_UP, CAPSULE_DOWN = "arc 1 -90, line 2, arc 1 -90", "arc 1 90, line 2, arc 1 90"


@pytest.mark.parametrize("segments", [CAPSULE_UP, CAPSULE_DOWN, "arc 1 180"])
def test_a_vessel_s_director_points_out_of_the_volume_it_encloses(segments):
    """The director ``d0`` (the tangent turned +90 degrees in the ``(z, r)`` plane: ``(-sin theta0, cos theta0)``)
    points away from the enclosed volume: a capsule or a sphere (convex) holds its centre on the axis halfway between
    its poles, so ``d0 . (x0 - centre) > 0`` all along the meridian. With positive angles the meridian goes down from
    its first pole (at ``z = 0``), the director into the vessel; it is run backwards from its last point, the bottom
    pole (said in a note), where the segments put it: the downward capsule is the upward one moved down by its
    height ``4 = 2 + 2 x 1`` (``r0``, ``theta0``, ``theta0_s`` the same, bit for bit; ``z0`` to round-off), the half
    turn ``arc 1 180`` the unit sphere below ``z = 0`` (it was run mirrored, above it)."""
    vessel = Vessel(segments=segments)
    mer = vessel.meridian()
    s = np.linspace(0.0, mer.length, 2001)[1:-1]
    r0, z0, th0, _ = mer.at(s)
    ends = mer.at(np.array([0.0, mer.length]))[1]
    assert mer.poles == (True, True)
    centre = ends.mean()
    outward = -np.sin(th0) * (z0 - centre) + np.cos(th0) * r0
    assert np.all(outward > 0), s[outward <= 0]
    note = " ".join(vessel.stand_ins())
    assert ("traversed backwards" in note) == (segments != CAPSULE_UP)
    height = {CAPSULE_UP: 4.0, CAPSULE_DOWN: 4.0, "arc 1 180": 2.0}[segments]
    top = 0.0 if segments != CAPSULE_UP else height  # the first pole stays where the segments start it
    np.testing.assert_allclose(ends, [top - height, top], rtol=0, atol=1e-15 * height)
    if segments == CAPSULE_DOWN:  # the upward capsule moved down by its height
        up = Vessel(segments=CAPSULE_UP).meridian().at(s)
        for i in (0, 2, 3):
            np.testing.assert_array_equal(mer.at(s)[i], up[i])
        np.testing.assert_allclose(z0, up[1] - height, rtol=0, atol=1e-15 * height)
        assert "the bottom pole at (r, z) = (0, -4) m, end2 at their first pole (z = 0)" in note


#: an asymmetric closed vessel: a hemispherical bottom (radius 1), a 1 m cylinder and a torispherical top (crown 2,
#: knuckle 0.2, crown angle ``phi1 = asin(0.8 / 1.8)``: the knuckle ends on the cylinder), drawn up from its bottom
#: pole and down from its top pole (the same segments in reverse order, every angle's sign reversed)
PHI1 = math.asin(0.8 / 1.8)
CROWN, KNUCKLE = repr(math.degrees(PHI1)), repr(90.0 - math.degrees(PHI1))
ASYMMETRIC_UP = f"arc 1 -90, line 1, arc 0.2 -{KNUCKLE}, arc 2 -{CROWN}"
ASYMMETRIC_DOWN = f"arc 2 {CROWN}, arc 0.2 {KNUCKLE}, line 1, arc 1 90"


def test_an_asymmetric_vessel_drawn_down_stands_under_gravity_as_the_same_vessel_drawn_up():
    """The asymmetric vessel (``h = 5 cm``, ``zeta1 = -h``) under gravity ``g = 0.1 m/s2`` (along ``-k``), carried by
    an axial force at its bottom pole (``end1``) equal to its weight ``g sum mA`` (the lumped masses the gravity load
    acts on; the closed form ``2 pi rho (2h int r0 ds - 2h^3/3 sum kappa dz)`` agrees to 1e-5, their quadrature
    across the junctions): drawn down from its top pole, it is run backwards from its bottom pole, the upward
    drawing's segments and start ``(0, -H, pi/2)`` with ``H = 2 + Rc (1 - cos phi1) + rk cos phi1`` (the closure of
    the torispherical head). The equations are invariant under a translation along the axis (gravity's force does
    not depend on ``z``; no edge imposes ``z``; the static solve keeps the mean ``z`` of its start), so its static
    equilibrium is the upward drawing's moved down by ``H``, node for node (both from the bottom pole): to
    round-off, 1e-14 m (Newton is polished to a residual of 1e-17). The vessel stands on its hemisphere, the head
    on top, pushed in at the support by the 3 mm the equilibrium moves it. Its outer face is outside: ``d0`` is the
    outward normal (``-k`` at the bottom pole, ``+j2`` on the cylinder) and ``zeta1 + 2h`` the larger radius there.
    Mirrored in ``z``, as before, it stood above ``z = 0``, the head on the support and the hemisphere on top: node
    for node from the bottom pole, ``r`` off the upward drawing's by 0.10 m and ``z`` by 0.20 m."""
    n, g, h = 21, 0.1, 0.05
    height = 2.0 + 2.0 * (1 - math.cos(PHI1)) + 0.2 * math.cos(PHI1)
    states = {}
    for order, segments in (("up", ASYMMETRIC_UP), ("down", ASYMMETRIC_DOWN)):
        weight = g * float(np.sum(ShellSystem(Vessel(segments=segments, h=h, zeta1=-h, gravity=g), n).inertia[0]))
        scene = Vessel(segments=segments, h=h, zeta1=-h, gravity=g, end1_force=weight)
        system = mol_shell.build(scene, n)[0]
        y, info = static_equilibrium(scene, n, system.initial_state(scene))
        assert "static equilibrium" in info
        states[order] = (system.unpack(y), np.array(system.reference))
    (up, up0), (down, down0) = states["up"], states["down"]
    moved = down.copy()
    moved[0] += height
    np.testing.assert_allclose(moved, up, rtol=0, atol=1e-14)
    np.testing.assert_allclose(down0[0], up0[0] - height, rtol=0, atol=1e-14)  # the shape where it is drawn
    assert down0[0, -1] == pytest.approx(0.0, abs=1e-14) and up[0, 0] - up0[0, 0] > 2e-3  # pushed in at the support
    mer = Vessel(segments=ASYMMETRIC_DOWN).meridian()
    s = np.linspace(0.0, mer.length, 401)[1:-1]
    r0, z0, th0, _ = mer.at(s)
    centre = -height + 1.5  # the middle of the cylinder: inside the convex vessel
    assert np.all(-np.sin(th0) * (z0 - centre) + np.cos(th0) * r0 > 0)
    assert mer.at(0.0)[2] == math.pi / 2 and np.all(np.cos(th0[(z0 > 1.05 - height) & (z0 < 1.95 - height)]) == 1.0)


def test_a_dome_drawn_from_its_pole_runs_from_its_rim_and_says_which_end_is_which():
    """``arc 1 90`` from a pole at ``z = 0`` is a dome (a half sphere above its rim at ``(1, -1)``), not the bowl
    it ran as (mirrored: rim at ``z = +1``): run from its rim (``end1``, ``s = 0``, heading up: ``theta0 = 0``) to
    its pole (``end2``), the director outward. ``end2 = clamped`` meant for the rim (the segments' end) is refused
    naming ``end2`` and saying which end is which; ``end1 = clamped`` clamps the rim."""
    mer = Vessel(segments="arc 1 90", end1="clamped").meridian()
    assert mer.poles == (False, True)
    start, end = (np.array(x).ravel() for x in zip(*mer.at(np.array([0.0, mer.length]))))
    np.testing.assert_allclose(start, [1.0, -1.0, 0.0, -1.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(end, [0.0, 0.0, -math.pi / 2, -1.0], rtol=0, atol=1e-15)
    with pytest.raises(ParameterError) as caught:
        Vessel(segments="arc 1 90", end2="clamped")
    assert caught.value.name == "end2" and "end1 at the segments' last point, the open edge at (r, z) = (1, -1) m" \
        in str(caught.value)


@pytest.mark.parametrize("segments", [CAPSULE_UP, CAPSULE_DOWN])
def test_a_vessel_s_inner_face_carries_the_higher_hoop_stress(segments):
    """A pressurised capsule (``a = 1``, ``h = 20 mm``, plane-stress SVK, ``nu = 0.3``) at equilibrium: in the middle
    of its cylinder the true inner face carries the higher hoop stress. The shell's faces move radially by the same
    ``w`` (the director stays normal), so the hoop strain is ``w / rho`` at a face of radius ``rho``, and the
    meridional strain ``eps_s`` is the same at both; closed ends give ``N_s = N_hoop / 2``, so
    ``nu eps_s / w = nu (1/2 - nu) / ((1 - nu/2) a)`` and, in plane stress,
    ``sigma_inner / sigma_outer = (1/rho_in + c) / (1/rho_out + c)``, ``c = nu eps_s / w``, ``rho_in = a + zeta1``,
    ``rho_out = rho_in + 2h`` (1.0381; Lame's thick cylinder, ``(1 + (rho_out/rho_in)^2) / 2``: 1.0417); the 21
    nodes give it to 8% of its excess over 1 (81 nodes: 0.3%). With positive angles the faces were swapped: the
    face named inner carried the lower stress (ratio 1/1.04)."""
    a, h, nu = 1.0, 0.02, 0.3
    scene = Vessel(segments=segments, h=h, material="svk-plane-stress", nu=nu, pressure=100.0)
    ds = mol_shell.simulate(scene, "leapfrog", n=21, times=[0.0, 1e-6], progress=False)
    k = ds.sizes["s_cell"] // 2
    assert abs(ds.s_cell.values[k] - (math.pi / 2 + 1.0)) < 0.2  # the middle of the cylinder
    inner, outer = ds.principal_stress_max.values[0, k]  # the hoop stress: the larger principal one
    rho_in = a + float(ds.attrs["zeta1_used"])
    c = nu * (0.5 - nu) / ((1 - nu / 2) * a)
    expected = (1 / rho_in + c) / (1 / (rho_in + 2 * h) + c)
    assert inner / outer - 1 == pytest.approx(expected - 1, rel=0.1)


# -- what crosses itself ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("segments", ["line 1, arc 0.5 90", "line 1, arc 0.5 -90", "line 2, arc 1 -45, line 1",
                                      "line 1, arc 0.3 -90, line 0.5"])
def test_a_line_and_an_arc_joined_tangentially_do_not_cross(segments):
    """A flat disc of radius 1 m with a quarter-arc rim (down or up) touches itself only at the joint of consecutive
    segments, where the tangent is continuous: no crossing. It was refused as "it crosses itself": the samples of
    the line ``z = cos(pi/2) s`` are collinear to round-off and two chords apart were found to meet (the cross
    product of their directions, 6e-36, divided round-off by round-off). The vessel is built; its end is where the
    closed form puts it: ``(1 + R, R)`` for the rim of radius ``R = 0.5`` turning up; the one turning down runs
    backwards from its rim at ``(1 + R, -R)`` to the pole at the origin."""
    vessel = Vessel(segments=segments)
    assert vessel.meridian().length == pytest.approx(sum(
        float(w[1]) * (math.radians(abs(float(w[2]))) if w[0] == "arc" else 1.0)
        for w in (part.split() for part in segments.split(","))), rel=1e-14)
    if segments.startswith("line 1, arc 0.5"):
        r, z = vessel.meridian().at(np.array([0.0, vessel.meridian().length]))[:2]
        ends = [(0.0, 0.0), (1.5, 0.5)] if segments.endswith("-90") else [(1.5, -0.5), (0.0, 0.0)]
        assert list(zip(r, z)) == [pytest.approx(end, abs=1e-14) for end in ends]


def test_a_meridian_that_loops_back_over_itself_is_still_refused(capsys, tmp_path):
    """``line 1, arc 0.2 -270, line 1``: the arc (centre ``(1, 0.2)``) turns the tangent up, back toward the axis and
    down, ending at ``(0.8, 0.2)`` heading ``-z``; the last line then crosses the first, ``z = 0``, at ``r = 0.8``.
    Refused in one line naming ``segments``; so is a polyline that runs back over itself (collinear chords that
    overlap: exactly parallel ones were skipped) or touches an earlier point, while a straight one does not."""
    args = ["run", "vessel", "--set", "segments=line 1, arc 0.2 -270, line 1", "--n", "9", "--t-end", "1e-5",
            "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].endswith("does not cross itself (it crosses itself)"), err
    direction = np.array([math.sin(1.0), math.cos(1.0)])  # not representable: the points are collinear to round-off
    line = np.linspace(0.0, 3.0, 61)[:, None] * direction
    assert not self_intersects(line)
    assert self_intersects(np.concatenate([line, line[-2:20:-1]]))  # back over itself
    assert self_intersects(np.concatenate([line[:21], line[20:21] + [[0.0, 1.0]], [[0.5, 0.5]], line[10:11]]))
    up = np.column_stack([np.ones(31), np.linspace(0.0, 3.0, 31)])  # exactly parallel chords: were never compared
    assert not self_intersects(up) and self_intersects(np.concatenate([up, up[-2:10:-1]]))


def test_a_vessel_run_backwards_names_where_each_end_load_acts():
    """A dome drawn from its pole (``arc 1 90``) runs from its rim: ``end2`` is the pole. An ``end2_force`` meant for the
    rim then acted at the pole with nothing said but which end is which; the note names each end value given."""
    dome = mol_shell.get_scene("vessel", segments="arc 1 90", end2_force=100.0, end1_dz=0.001)
    note = dome.stand_ins()[0]
    assert note.endswith("; end2_force acts at end2 (their first pole); end1_dz acts at end1 (the segments' last point)")
    assert "acts at" not in mol_shell.get_scene("vessel", segments="arc 1 90").stand_ins()[0]
