"""Meridians from segments (mol_shell.scenes.segments): a capsule and a torispherical head."""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
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
