"""The ``meridian`` scene's table of points: ends on the axis by the poles' rule are poles, and sizes the model
cannot compute are refused naming ``points``.

* A unit sphere sampled as ``(sin a, -cos a)`` has ``sin(pi) = 1.22e-16``, not 0, at its top: an end that the
  poles' rule (``|r| <= 1e-12`` of the size) calls a pole must be one, i.e. the same meridian as the table with
  ``0`` written there: the tangent perpendicular to the axis (``theta0 = -pi/2``, ``dr0/ds = sin(theta0) = -1``,
  ``dz0/ds = 0``) and the shell mirror-symmetric about ``z = 0`` (``r0(L - s) = r0(s)``, ``z0(L - s) = -z0(s)``,
  ``theta0(L - s) = -theta0(s)``), as the sampled curve is.
* The spin inertia of a node, ``mA r^2``, is a part of the shell's moment of inertia about the axis; for a cylinder
  of radius ``S`` and length ``S`` (wall ``2h``) that is ``4 pi rho h S^4``, and it must stay finite.
"""

import math
import sys

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.modes import modes
from mol_shell.cli.args import scene_and_run
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.geometry import PointsMeridian
from mol_shell.runs import checks
from mol_shell.scenes import MeridianShell


def sphere_rows(exact_poles):
    a = np.linspace(0.0, math.pi, 23)
    table = np.column_stack([np.sin(a), -np.cos(a)])
    if exact_poles:
        table[[0, -1], 0] = 0.0
    return table


@pytest.fixture(scope="module")
def sphere_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("poles")
    out = {}
    for name, exact in (("sin", False), ("zero", True)):
        np.savetxt(folder / f"{name}.txt", sphere_rows(exact))
        out[name] = str(folder / f"{name}.txt")
    return out


def test_an_end_within_round_off_of_the_axis_is_a_pole_with_a_horizontal_tangent(sphere_files):
    """``sin(pi) = 1.22e-16`` at the top: a pole put on the axis, the tangent perpendicular to it (was -1.5295 rad,
    a cone tip of 2.4 degrees), the same reference geometry as the table with 0 written, and mirror-symmetric."""
    assert sphere_rows(False)[-1, 0] != 0.0  # the case: a tiny but nonzero radius
    sampled = MeridianShell(points=sphere_files["sin"]).meridian()
    exact = MeridianShell(points=sphere_files["zero"]).meridian()
    assert sampled.poles == exact.poles == (True, True)
    L = sampled.length
    r0, z0, th0, _ = sampled.at(np.array([0.0, L]))
    assert r0 == pytest.approx([0.0, 0.0], abs=1e-15)
    assert th0 == pytest.approx([math.pi / 2, -math.pi / 2], abs=1e-14)
    s = np.linspace(0.0, L, 21)
    for got, want in zip(sampled.at(s), exact.at(s)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    r0, z0, th0, k0 = sampled.at(s)
    r1, z1, th1, k1 = sampled.at(L - s)
    np.testing.assert_allclose(r1, r0, atol=1e-12)
    np.testing.assert_allclose(z1, -z0, atol=1e-12)
    np.testing.assert_allclose(th1, -th0, atol=1e-12)
    np.testing.assert_allclose(k1, k0, atol=1e-9)


def test_the_sampled_sphere_with_sin_pi_vibrates_as_with_an_exact_pole(sphere_files):
    """The same shell, so the same lowest modes (n = 15) as the table with 0 written, to the eigen-solver's round-off
    (were 5e-6 apart at n = 40: the lopsided tip)."""
    sampled = modes(MeridianShell(points=sphere_files["sin"]), n=15, count=4)
    exact = modes(MeridianShell(points=sphere_files["zero"]), n=15, count=4)
    assert sampled.attrs["edge_s0"] == sampled.attrs["edge_sL"] == "pole"
    np.testing.assert_allclose(sampled.frequency.values, exact.frequency.values, rtol=1e-9)


def cylinder_table(path, size):
    np.savetxt(path, np.column_stack([size * np.ones(5), size * np.linspace(0.0, 1.0, 5)]))
    return str(path)


def test_a_table_too_large_for_the_inertia_is_refused_naming_points(tmp_path):
    """1e90 m, inside the points' 1e100 m, was refused as ``scene = 'meridian' has the right-hand side at t = 0 is not
    finite``. Now one line naming the file and the size that fits: the cylinder's axial inertia ``4 pi rho h S^4``
    times 2 for the wall's and curvature's factors (bounded by 2 each way), kept 100 times below the largest
    double, ``S = (0.01 DBL_MAX / (8 pi rho h))^(1/4)`` = 1.03e76 m with the defaults."""
    path = cylinder_table(tmp_path / "big.txt", 1e90)
    with pytest.raises(ParameterError) as info:
        MeridianShell(points=path)
    scene = MeridianShell()
    fits = (0.01 * sys.float_info.max / (8 * math.pi * scene.rho * scene.h)) ** 0.25
    message = str(info.value)
    assert info.value.name == "points" and "\n" not in message
    assert message.startswith(f"points = '{path}' has coordinates up to 1e+90 m")
    assert f"allowed: a table with coordinates up to about {fits:.2g} m" in message
    # inside the stated size the model's numbers are finite
    inside = MeridianShell(points=cylinder_table(tmp_path / "inside.txt", 0.9 * fits))
    system = ShellSystem(inside, 5)
    assert checks.problem(system, system.initial_state(inside)) is None


def test_the_generic_refusal_names_a_text_parameter_and_reads(sphere_files):
    """When no number was changed, the refusal of non-finite numbers names the text parameter that, set back to its
    default, makes them finite (was ``scene = 'meridian' has the right-hand side ... is not finite``)."""
    scene = MeridianShell(points=sphere_files["zero"])
    reason = "the right-hand side at t = 0 is not finite in double precision"
    error = checks._diagnose(scene, reason, bad=lambda sc: sc.points != "")
    assert error.name == "points"
    assert str(error) == (f"points = '{sphere_files['zero']}' leaves the model's numbers outside double precision: "
                          f"{reason}; allowed: values whose discretised numbers are finite in double precision "
                          "(they are with points = '', the default)")


# -- an interior row on the axis to round-off ---------------------------------------------------------------------
@pytest.mark.parametrize("r", [1e-16, 0.0, 5e-13, 1e-300])
def test_an_interior_row_within_round_off_of_the_axis_is_refused_naming_its_line(tmp_path, capsys, r):
    """Only an end may be on the axis (a pole). A row between the ends with ``r = 1e-16`` (round-off of 0, inside the
    poles' rule ``|r| <= 1e-12 max(1 m, largest r)`` = 1e-12 m for this table of radii up to 1 m) was let through to
    the thickness check, which named ``h`` ("a face reaches the axis"); ``r = 0`` alone was refused. Now one line
    naming the file, the line as a user counts it (4: a comment line comes first) and the allowed radii."""
    path = tmp_path / "pinched.txt"
    path.write_text(f"# r z\n1 0\n0.5 0.5\n{r!r} 1\n0.5 1.5\n1 2\n")
    args = ["run", "meridian", "--set", f"points={path}", "--n", "9", "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith(f"mol-shell: error: points = '{path}' touches the axis between its ends, on line 4 "
                             f"(r = {r:.3g} m); allowed: rows between the first and the last with r > 1e-12 m"), err


def test_a_straight_table_is_no_crossing():
    """Four collinear rows of a frustum (``r`` from 1 to 0.3 m while ``z`` rises 1 m) were refused as "a curve that
    crosses itself": the spline's samples along the line are collinear to round-off, and two chords apart were found
    to meet. A line does not cross itself; the table is the cone with ``theta0 = -atan(0.7)`` (the spline of collinear
    points is the line), of length ``hypot(0.7, 1)``."""
    table = np.column_stack([np.linspace(1.0, 0.3, 4), np.linspace(0.0, 1.0, 4)])
    meridian = PointsMeridian(table)
    assert meridian.length == pytest.approx(math.hypot(0.7, 1.0), rel=1e-12)
    assert meridian.at(np.array([0.5]))[2] == pytest.approx(-math.atan(0.7), rel=1e-12)


# -- a table listed from the top down -----------------------------------------------------------------------------
def test_a_table_listed_from_the_top_down_runs_as_given_with_a_note_naming_its_inner_face(sphere_files, tmp_path):
    """The unit sphere listed from the top pole down: run as given (``z0 = 1`` at ``s = 0``, not mirrored), its
    director ``d0 = (-sin theta0) k + (cos theta0) j2`` toward the axis (``cos theta0 = dz0/ds < 0`` between the
    poles), so the face the stresses call "inner" (``zeta1``, ``d0``'s negative side) is the geometric outer one: a note
    says so (there was none). Listed from the bottom up, the director is outward and nothing is said."""
    down = tmp_path / "down.txt"
    np.savetxt(down, sphere_rows(True)[::-1])
    scene = MeridianShell(points=str(down))
    meridian = scene.meridian()
    _, z0, th0, _ = meridian.at(np.linspace(0.0, meridian.length, 21))
    assert z0[0] == pytest.approx(1.0, abs=1e-15) and z0[-1] == pytest.approx(-1.0, abs=1e-15)
    assert np.all(np.cos(th0[1:-1]) < 0)
    (note,) = scene.stand_ins()
    assert note.startswith(f"points = '{down}' are listed from the top down (z decreasing along the rows) and run "
                           "as given, not mirrored in z"), note
    assert "the stresses' \"inner\" face (zeta1) is its geometric outer face and \"outer\" its inner one" in note
    assert MeridianShell(points=sphere_files["zero"]).stand_ins() == []


@pytest.mark.parametrize("order", ["up", "down"])
def test_the_face_that_carries_the_higher_stress_is_named_by_the_note(tmp_path, order):
    """A pressurised sphere (``a = 1``, ``h = 20 mm``, plane-stress SVK) at equilibrium: at the equator the true inner
    face carries the higher stress. Its faces move out by the same ``w`` (the director stays normal), so both strains
    are ``w / rho`` at a face of radius ``rho`` and the (equal biaxial) stresses are in the ratio
    ``rho_out / rho_in = 1 + 2h / (1 + zeta1)`` (1.0408; Lame's thick sphere, ``(2 + (b/a)^3) / 3``: 1.0425); the 21
    nodes give it to 10% of its excess over 1. Listed from the top down, the face named "outer" carries it, as the
    note says, with the same values."""
    path = tmp_path / f"{order}.txt"
    np.savetxt(path, sphere_rows(True)[::-1] if order == "down" else sphere_rows(True))
    h = 0.02
    scene = MeridianShell(points=str(path), h=h, material="svk-plane-stress", nu=0.3, pressure=100.0)
    ds = mol_shell.simulate(scene, "leapfrog", n=21, times=[0.0, 1e-6], progress=False)
    k = ds.sizes["s_cell"] // 2  # the cell above or below the equator: the same by symmetry
    named_inner, named_outer = ds.principal_stress_max.values[0, k]
    true_inner, true_outer = (named_inner, named_outer) if order == "up" else (named_outer, named_inner)
    zeta1 = float(ds.attrs["zeta1_used"])
    rho_in = 1.0 + zeta1 if order == "up" else 1.0 - (zeta1 + 2 * h)  # zeta counts along d0: outward, or inward
    assert true_inner / true_outer - 1 == pytest.approx((rho_in + 2 * h) / rho_in - 1, rel=0.1)


def test_a_dome_listed_from_the_top_down_sags_under_gravity_as_the_same_dome_listed_upward(tmp_path):
    """Why a top-down table is not mirrored in ``z`` (as a vessel's downward segments are): gravity acts along
    ``-k`` on the shell where the table puts it. A dome (half ellipsoid, 1 m by 0.6 m, clamped at its equator) listed
    from the pole down is the same shell as listed upward, so its static equilibrium under gravity is the same, node
    for node with ``s`` reversed (to round-off), the pole sagging (``z`` below its natural 0.6 m); mirrored, it would
    have been a bowl hanging from its rim."""
    t = np.linspace(0.0, np.pi / 2, 9)
    dome = np.column_stack([np.cos(t), 0.6 * np.sin(t)])
    states = {}
    for order, table, clamp in (("up", dome, "end1"), ("down", dome[::-1], "end2")):
        np.savetxt(tmp_path / f"{order}.txt", table)
        scene = MeridianShell(points=str(tmp_path / f"{order}.txt"), gravity=9.81, **{clamp: "clamped"})
        ds = mol_shell.simulate(scene, "leapfrog", n=15, times=[0.0, 1e-6], progress=False)
        assert "static equilibrium" in ds.attrs["initial_state"]
        states[order] = np.array([ds.z.values[0], ds.r.values[0]])
    np.testing.assert_allclose(states["down"][:, ::-1], states["up"], rtol=0, atol=1e-12)
    assert states["up"][0, -1] < 0.6 - 1e-3  # the pole, at s = L of the upward table


def test_points_and_h_are_checked_together_whatever_their_order(tmp_path):
    """A thin tube, ``r = 2 mm`` (a straight table: ``theta0 = 0``, no curvature): the wall fits while its inner face
    is off the axis, ``r + zeta1 > 0``, with the centroidal ``zeta1 = m - h``, ``m`` the root nearest 0 of
    ``int zeta (r + zeta) dzeta = 0`` over ``[m - h, m + h]``: ``m^2 + r m + h^2/3 = 0``, ``m = (-r + sqrt(r^2 -
    4h^2/3)) / 2``, so ``m - h > -r`` exactly for ``h < 3r/4`` = 1.5 mm (real roots need ``h <= sqrt(3) r/2``). The
    default ``h = 6.28 mm`` does not fit, ``h = 1e-9`` does. ``get_scene`` built the scene from its file first, with
    the default ``h``, so ``--set h=1e-9 --set points=FILE`` (or the other order) was refused ("points = ... is
    outside values for which h = 0.006283 m fits"); all values are now applied and checked once."""
    r = 0.002
    path = tmp_path / "tube.txt"
    np.savetxt(path, np.column_stack([np.full(5, r), np.linspace(0.0, 0.01, 5)]))
    assert MeridianShell.h > 0.75 * r
    with pytest.raises(ParameterError, match="h = 0.006283 m fits"):
        mol_shell.get_scene("meridian", points=str(path))
    for params in ({"h": "1e-9", "points": str(path)}, {"points": str(path), "h": "1e-9"}):
        assert mol_shell.get_scene("meridian", **params).h == 1e-9
    for sets in (["h=1e-9", f"points={path}"], [f"points={path}", "h=1e-9"]):  # the command line's --set
        assert scene_and_run("meridian", sets)[0].h == 1e-9
    assert mol_shell.get_scene("meridian", points=str(path), h=0.99 * 0.75 * r).h == 0.99 * 0.75 * r
    with pytest.raises(ParameterError) as caught:
        mol_shell.get_scene("meridian", points=str(path), h=1.01 * 0.75 * r)
    assert caught.value.name == "h"
