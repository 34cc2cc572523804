"""A wall whose thickness varies along the meridian (h_profile; mol_shell.model.thickness_profile)."""

import dataclasses
import math
import time

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.thickness_profile import TABLE_ENDS, thickness_function
from mol_shell.runs import checks
from mol_shell.runs.building import build
from mol_shell.runs.checks import initial_state
from mol_shell.runs.statics import newton
from mol_shell.scenes import Cone, Sphere

PROFILE = "0.005 * (1 + 0.25 * s)"


def h_of(s):
    return 0.005 * (1 + 0.25 * s)


def _inflated(**kw):
    """A closed-end tube (a = 1, L = 2, plane-stress SVK, nu = 0.3) at equilibrium under p = 1 Pa: r - 1 per node."""
    scene = Cone(r1=1.0, r2=1.0, H=2.0, material="svk-plane-stress", E=1e6, nu=0.3, end1="magnet", end2="free",
                 pressure=1.0, dilation=1.0, **kw)
    system, _ = build(scene, 17)
    y, _, res = newton(system, initial_state(scene, system))
    assert res < 1e-10
    return system.s, y[: system.ny * system.n].reshape(system.n, system.ny)[:, 1] - 1


def test_slowly_varying_thickness_agrees_locally_with_the_uniform_wall():
    """h grows by 50 % along the tube. At interior nodes the hoop strain equals that of a uniform wall of the local
    thickness (three such walls computed here; measured 1.3e-4 .. 2.9e-4) and membrane theory's
    ``p a (1 - nu/2) / (E 2h(s))`` (measured below 3.5e-4 from the fifth node on; 1.2e-3 at the fourth, near the end held by its magnet); allowed 1e-3, the order of
    ``(dh/ds)^2``-type corrections of the slowly varying wall and the ends' influence."""
    s, graded = _inflated(h=0.005, h_profile=PROFILE)
    membrane = 1.0 * (1 - 0.3 / 2) / (1e6 * 2 * h_of(s))
    np.testing.assert_allclose(graded[4:-3], membrane[4:-3], rtol=1e-3)
    for i in (4, 8, 12):
        _, uniform = _inflated(h=float(h_of(s[i])), zeta1=-float(h_of(s[i])))
        assert graded[i] == pytest.approx(uniform[i], rel=1e-3)
    assert graded[3] / graded[-4] > 1.25  # the grading is seen (h ratio 1.29 between these nodes)


def test_a_graded_run_keeps_its_energy_and_a_table_works():
    """Leap-frog on a graded sphere released from 1.05 a keeps its energy to O(dt^2); the table form gives the same
    run as the equivalent expression (linear in s: the table interpolates it exactly)."""
    L = np.pi
    table = f"table 0:0.008 {L}:0.012"
    expr = f"0.008 + 0.004 * s / {L!r}"
    runs = [mol_shell.simulate(mol_shell.Sphere(h=0.01, h_profile=p, R=1.05, material="svk-plane-stress", nu=0.3),
                               "leapfrog", n=9, times=np.linspace(0, 0.01, 3), progress=False) for p in (table, expr)]
    e = runs[0].energy.values
    assert np.max(np.abs(e / e[0] - 1)) < 1e-7
    np.testing.assert_allclose(runs[0].r.values, runs[1].r.values, rtol=1e-12, atol=1e-14)
    assert runs[0].attrs["stresses"].startswith("included")


def test_a_graded_walls_stresses_are_its_local_membrane_stresses():
    """A closed-end tube (a = 1 m) whose wall thickens by 50 % along it, at rest under p = 1 Pa (the run starts from
    the equilibrium): membrane theory gives, whatever the thickness, n^phi = p a and n^s = p a / 2 (the lid's
    force over the circumference), and a hoop Cauchy stress p a / (2 h(s)) through the local wall. Measured from
    the fourth cell to the fourth from the end: at most 3.5e-4 (the ends' bending decays over sqrt(a h)); allowed
    1e-3. Each cell's faces are its
    own, +-h(s) about the mid-surface."""
    times = np.linspace(0.0, 1e-4, 2)
    scene = Cone(r1=1.0, r2=1.0, H=2.0, material="svk-plane-stress", E=1e6, nu=0.3, end1="magnet", end2="free",
                 pressure=1.0, h=0.005, h_profile=PROFILE)
    ds = mol_shell.simulate(scene, "cvode-bdf", n=17, times=times, progress=False)
    assert float(np.abs(ds.r_t).max()) < 1e-12  # at rest: the equilibrium
    h, inner = h_of(ds.s_cell.values), slice(3, -3)
    np.testing.assert_allclose(ds.zeta_face.values, np.stack([-h, h], axis=-1), rtol=1e-14)
    np.testing.assert_allclose(ds.membrane_force_hoop.values[-1][inner], 1.0, rtol=1e-3)
    np.testing.assert_allclose(ds.membrane_force_meridional.values[-1][inner], 0.5, rtol=1e-3)
    hoop = ds.principal_stress_max.values[-1].mean(axis=-1)  # the two faces' hoop stress, bending's part cancels
    np.testing.assert_allclose((hoop * 2 * h)[inner], 1.0, rtol=1e-3)
    assert hoop[3] / hoop[-4] > 1.25  # the local thickness is seen (h ratio 1.29 between these cells)


def test_a_layered_graded_wall_keeps_each_layers_share():
    """Layers on a graded wall keep their shares of it (thickness times h(s)/h). Two layers of one law give the
    single graded wall (radii to 1e-13, face stresses to 1e-9: round-off); an inner 1 MPa layer of 40 % of the wall
    under an outer 3 MPa one gives at each cell the face stresses of the uniform layered wall of the local
    thickness (cell 8; with cell 4, measured 6.8e-5 .. 2.2e-4; allowed 1e-3, as the unlayered wall above)."""
    times = np.linspace(0.0, 1e-4, 2)
    kw = dict(r1=1.0, r2=1.0, H=2.0, material="svk-plane-stress", E=1e6, nu=0.3, end1="magnet", end2="free",
              pressure=1.0)

    def run(**more):
        return mol_shell.simulate(Cone(**kw, **more), "cvode-bdf", n=17, times=times, progress=False)

    single = run(h=0.005, h_profile=PROFILE)
    equal = run(h=0.005, h_profile=PROFILE, layers="0.004 svk-plane-stress; 0.006 svk-plane-stress")
    np.testing.assert_allclose(equal.r.values, single.r.values, rtol=1e-13)
    for name in ("principal_stress_max", "membrane_force_hoop", "bending_moment_hoop"):
        scale = float(np.abs(single[name]).max())
        np.testing.assert_allclose(equal[name].values, single[name].values, rtol=0, atol=1e-9 * scale, err_msg=name)
    layered = run(h=0.005, h_profile=PROFILE, layers="0.004 svk-plane-stress; 0.006 svk-plane-stress E=3e6")
    for i in (8,):  # one cell (a second, 4, cost a kernel of its own: the suite's time)
        h = float(h_of(layered.s_cell.values[i]))
        local = run(h=h, zeta1=-h, layers=f"{0.8 * h!r} svk-plane-stress; {1.2 * h!r} svk-plane-stress E=3e6")
        np.testing.assert_allclose(layered.principal_stress_max.values[-1, i],
                                   local.principal_stress_max.values[-1, i], rtol=1e-3)
    faces = layered.principal_stress_max.values[-1, 8]
    assert 2.5 < faces[1] / faces[0] < 3.5  # the stiffer outer layer carries about 3x the stress: the layers are seen


@pytest.mark.parametrize("profile, words", [
    ("table 0:0.01 1:0.01", "h_profile = 'table 0:0.01 1:0.01' is outside a table covering the meridian [0, 2] m"),
    ("0.01 * unknown(s)", "h_profile = '0.01 * unknown(s)' is outside"),
    ("0.01 - s", "a positive, finite h(s) on the meridian"),
    # numbers alone, evaluated as Python's: internal errors (ZeroDivisionError, OverflowError, a complex TypeError)
    # and hangs (big integers); as doubles they give inf or NaN, refused as any h that is not positive and finite
    ("0.01+1/0", "(h = inf m at s = 0 m)"),
    ("0.01+0*10.0**400", "(h = nan m at s = 0 m)"),
    ("(-0.01)**0.5", "(h = nan m at s = 0 m)"),
    ("9**9**9", "(h = inf m at s = 0 m)"),
    ("0.01+0*(10**10**8)", "(h = nan m at s = 0 m)"),
])
def test_a_bad_profile_is_one_line_exit_2(capsys, tmp_path, profile, words):
    start = time.perf_counter()
    args = ["run", "cone", "--set", "r2=1", "--set", "H=2", "--set", f"h_profile={profile}", "--n", "9",
            "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert time.perf_counter() - start < 10  # no hang
    with pytest.raises(ParameterError, match="zeta1"):
        Cone(r2=1.0, H=2.0, h_profile="0.01", zeta1=-0.01)


@pytest.mark.parametrize("profile", ["1.5", "s**s", "1e300"])
def test_a_profile_past_the_centre_of_curvature_is_refused_by_name(capsys, tmp_path, profile):
    """The unit sphere's centre of curvature lies 1 m inside the mid-surface at every s: a wall whose h(s) reaches
    1 m there is refused naming h_profile and that distance (both factors of det G0 change sign past the centre,
    so their product alone does not see it), one line, exit 2."""
    args = ["run", "sphere", "--set", "h=0.01", "--set", f"h_profile={profile}", "--set", "R=1.05", "--n", "8",
            "--t-end", "0.001", "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"mol-shell: error: h_profile = '{profile}' is outside "), err
    assert "below 1 m" in err[0], err
    Sphere(h=0.01, h_profile="0.9")  # inside the centre: accepted


@pytest.mark.parametrize("h", [0.9, 1.5])
def test_a_uniform_wall_past_the_centre_of_curvature_is_refused_by_the_scene(h):
    """The uniform wall's twin of the check above: its scene checked the product of the two factors, which a sphere's
    wall past its centre (on the axis: both factors flip) passed; the build caught it later. The centroidal interval
    ``[zeta1, zeta1 + 2h]`` of the unit sphere reaches past its centre, 1 m inside, once ``-zeta1 >= 1``."""
    with pytest.raises(ParameterError, match=f"h = {h} is outside values whose thickness interval stays off the axis"):
        Sphere(h=h)
    inner = -Sphere(h=0.4).zeta1_used()
    assert 0 < inner < 1  # accepted, its inner face inside the centre


def test_the_cells_own_check_of_a_graded_wall_names_h_profile():
    """Should a profile pass the scene's sampling and still reach a centre of curvature in a cell, the cells' check
    names h_profile and the cell (a profile set past the scene's check here: 1.5 m on the unit sphere)."""
    scene = Sphere(h=0.01, h_profile="0.5")
    object.__setattr__(scene, "h_profile", "1.5")
    with pytest.raises(ParameterError) as info:
        ShellSystem(scene, 8)
    assert info.value.name == "h_profile" and "h = 1.5 m in the cell at s = " in str(info.value), str(info.value)


def test_a_table_reaching_zero_between_the_sampled_points_is_refused():
    """Linear between its points, a table's least value on the meridian is at one of them: h = 0 at s = 1.5 m (not
    a point of a uniform sampling of [0, pi]) is refused, and the message says where."""
    with pytest.raises(ParameterError) as info:
        Sphere(h=0.01, h_profile="table 0:0.01 1.5:0 3.2:0.01")
    assert info.value.name == "h_profile" and "h = 0 m at s = 1.5 m" in str(info.value), str(info.value)


def test_a_table_short_of_the_meridian_says_by_how_much_and_its_ends_may_be_typed_to_a_few_digits():
    """The unit half-circle is pi m long. A table ending at 3.14 falls pi - 3.14 m short: refused, both ranges
    printed with the digits that tell them apart. One ending at 3.14159 (2.7e-6 m short, within TABLE_ENDS of the
    length) was refused too, so a user had to type pi to twelve digits: it is taken, its last h held to the end."""
    with pytest.raises(ParameterError) as info:
        Sphere(h=0.01, h_profile="table 0:0.01 3.14:0.01")
    text = str(info.value)
    assert f"[0, {math.pi:.12g}] m" in text and "[0, 3.14] m" in text, text
    assert f"{math.pi - 3.14:.3g} m short" in text, text
    assert (math.pi - 3.14159) / math.pi < TABLE_ENDS
    h = thickness_function("table 0:0.01 3.14159:0.02", math.pi)
    assert h(np.array([math.pi]))[0] == 0.02


def test_a_profile_too_thin_for_double_precision_is_blamed_on_h_profile(capsys, tmp_path):
    """h = 0.01 with h_profile = 1e-300: the nominal wall is fine, the profile is not. The refusal names h_profile
    with the least h(s) the numbers allow; that edge is checked here on both sides by the finiteness test itself
    (a constant profile 3x above it is finite, 10x below it is not)."""
    args = ["run", "sphere", "--set", "h=0.01", "--set", "h_profile=1e-300", "--set", "R=1.05", "--n", "8",
            "--t-end", "0.001", "-o", str(tmp_path / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mol-shell: error: h_profile = '1e-300' is outside "), err
    scene = Sphere(h=0.01, h_profile="1e-300", R=1.05)
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(scene, n=5, times=[0, 1e-6])
    assert info.value.name == "h_profile" and "least h(s)" in str(info.value), str(info.value)
    edge = info.value.range.low
    assert 0 < edge < 0.01
    assert checks._is_bad(dataclasses.replace(scene, h_profile=repr(edge * 3)), 5) is False
    assert checks._is_bad(dataclasses.replace(scene, h_profile=repr(edge / 10)), 5) is True


def test_a_profile_of_subnormal_values_is_blamed_on_h_profile_with_the_same_edge(capsys, tmp_path):
    """h_profile = 1e-320 was refused naming R = 1.0, which nobody set: the factor towards the nominal h, h/1e-320,
    overflowed. The edge is that of h_profile = 1e-300 (the same finiteness test, to its half-decade)."""
    assert main(["run", "twisted-cylinder", "--n", "6", "--t-end", "1e-5", "--set", "h_profile=1e-320",
                 "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mol-shell: error: h_profile = '1e-320' is outside profiles whose "
                                               "least h(s) is within about ["), err
    edges = []
    for profile in ("1e-320", "1e-300"):
        with pytest.raises(ParameterError) as info:
            mol_shell.simulate(mol_shell.TwistedCylinder(h_profile=profile), n=5, times=[0, 1e-6])
        assert info.value.name == "h_profile"
        edges.append(info.value.range.low)
    assert edges[1] / 10 < edges[0] < edges[1] * 10, edges


@pytest.mark.parametrize(("profile", "refused"), [("0.5", True), ("2", True), ("0.3 + 0.1 * s", True),
                                                  ("table 0:0.01 2.001:0.01 2.0025:0.6 2.004:0.01 4:0.01", True),  # a peak
                                                  # between the samples
                                                  ("0.49", False), ("0.005 * (1 + 0.5 * s)", False)])
def test_a_cylinder_s_graded_wall_has_the_bound_of_its_uniform_wall(profile, refused):
    """``h = 0.5`` on a cylinder of a = 1 m is refused (the wall 2h must stay below a), but ``h_profile = "0.5"``, a
    wall 1 m thick, ran, and ``"2"`` was refused with another bound (h < a, the faces off the axis). The profile
    now has h's bound: max h(s) below a/2 (``0.3 + 0.1 s`` reaches 0.7 m at s = 4 m)."""
    scene = mol_shell.TwistedCylinder(material="svk-plane-stress")
    if refused:
        with pytest.raises(mol_shell.ParameterError, match=r"^h_profile = .* is outside values with h\(s\) below "
                           r"a/2 = 0.5 m, as h's"):
            dataclasses.replace(scene, h_profile=profile)
    else:
        assert dataclasses.replace(scene, h_profile=profile).h_profile == profile
