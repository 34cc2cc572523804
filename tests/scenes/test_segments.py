"""Meridians from segments (mol_shell.scenes.segments): a capsule and a torispherical head."""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.model.geometry import self_intersects
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
                             "between its ends and does not cross itself (it reaches the axis at s = 3.142 m)")),
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
    its poles, so ``d0 . (x0 - centre) > 0`` all along the meridian. With positive
    angles the meridian went down from its first pole, the director into the vessel (the product negative) and the
    faces' "inner" and "outer" swapped; it is now the same vessel (run mirrored in z, said in a note)."""
    vessel = Vessel(segments=segments)
    mer = vessel.meridian()
    s = np.linspace(0.0, mer.length, 2001)[1:-1]
    r0, z0, th0, _ = mer.at(s)
    assert mer.poles == (True, True) and mer.at(0.0)[1] == 0.0
    centre = mer.at(mer.length)[1] / 2
    outward = -np.sin(th0) * (z0 - centre) + np.cos(th0) * r0
    assert np.all(outward > 0), s[outward <= 0]
    assert ("mirrored in z" in " ".join(vessel.stand_ins())) == (segments != CAPSULE_UP)
    if segments == CAPSULE_DOWN:  # the same meridian as the upward capsule
        np.testing.assert_array_equal(mer.at(s), Vessel(segments=CAPSULE_UP).meridian().at(s))


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
    closed form puts it: ``(1 + R, R)`` for the rim of radius ``R = 0.5`` turning up (the one turning down runs
    mirrored in z, up)."""
    vessel = Vessel(segments=segments)
    assert vessel.meridian().length == pytest.approx(sum(
        float(w[1]) * (math.radians(abs(float(w[2]))) if w[0] == "arc" else 1.0)
        for w in (part.split() for part in segments.split(","))), rel=1e-14)
    if segments.startswith("line 1, arc 0.5"):
        r, z = vessel.meridian().at(np.array([vessel.meridian().length]))[:2]
        assert (float(r[0]), float(z[0])) == pytest.approx((1.5, 0.5), abs=1e-14)


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
