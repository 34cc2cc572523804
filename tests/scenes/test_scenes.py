"""Scenes: registry, parameter checks, and scenes that build only the fields they need."""

import dataclasses

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.scenes import get_scene, with_params
from mol_shell.runs.simulate import build


def test_registry_and_string_parameters():
    assert {"twisted-cylinder", "spinning-ring", "axisymmetric", "unshearable", "sphere", "cone", "torus",
            "meridian", "vessel"} == set(mol_shell.SCENES)
    scene = get_scene("twisted-cylinder", gamma="0.2", n_quad="6", R="auto", material="svk-plane-stress")
    assert scene.gamma == 0.2 and scene.n_quad == 6 and scene.R is None and scene.material == "svk-plane-stress"
    with pytest.raises(ParameterError, match="gamma"):
        with_params(mol_shell.Axisymmetric(), {"gamma": "0.1"})  # no twist in an axisymmetric scene


@pytest.mark.parametrize(
    "name,value",
    [("nu", 0.5), ("nu", -1.0), ("h", 0.5), ("E", 0.0), ("rho", -1.0), ("psi0", 1.6), ("n_quad", 0),
     ("eta_mu", -1.0), ("material", "rubber"), ("zeta1", 0.1), ("L", float("nan"))],
)
def test_out_of_range_values_are_named(name, value):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        dataclasses.replace(mol_shell.TwistedCylinder(), **{name: value})


def test_axisymmetric_scene_builds_only_z_r_theta():
    full, _ = build(mol_shell.TwistedCylinder(), 40)
    axi, _ = build(mol_shell.Axisymmetric(), 40)
    assert axi.size == 6 * 40 and full.size == 10 * 40
    assert axi.rhs.n_instructions() < 0.5 * full.rhs.n_instructions()
    # without psi the two samples of a cell coincide: one delta per cell, then r per node (no psi limit)
    # delta per cell sample, r per node, (psi per node), SVK's compressive turning point per cell sample
    assert axi.limits.size1_out(0) == 39 + 40 + 39 and full.limits.size1_out(0) == 2 * 39 + 40 + 40 + 2 * 39


def test_axisymmetric_equals_full_model_without_twist_spin_shear():
    times = [0, 0.005, 0.01]
    axi = mol_shell.simulate(mol_shell.Axisymmetric(R=1.01), times=times, progress=False)
    full = mol_shell.simulate(mol_shell.TwistedCylinder(R=1.01, gamma=0.0), times=times, progress=False)
    for name in ("z", "r", "theta", "chi", "psi", "energy"):
        np.testing.assert_allclose(axi[name], full[name], rtol=0, atol=1e-13 * max(1.0, float(abs(full[name]).max())))
    assert float(abs(axi.r - 1.01).max()) > 1e-3  # it does move


def test_n_quad_needs_two_points():
    """One Gauss point makes the director inertia rhoJ = rhoI^2/rhoA: a singular mass matrix (LinAlgError)."""
    with pytest.raises(ParameterError, match=r"^n_quad = 1 is outside integers 2\.\.32"):
        mol_shell.TwistedCylinder(n_quad=1)
    with pytest.raises(ParameterError, match=r"^n_quad = 33 is outside integers 2\.\.32"):
        mol_shell.TwistedCylinder(n_quad=33)
    with pytest.raises(ParameterError, match=r"^n_quad = 2\.5 is not an integer; allowed: integers 2\.\.32"):
        get_scene("twisted-cylinder", n_quad="2.5")
    assert mol_shell.TwistedCylinder(n_quad=2).n_quad == 2
    assert type(mol_shell.TwistedCylinder(n_quad=np.int64(6)).n_quad) is int
    assert get_scene("twisted-cylinder", n_quad="8.0").n_quad == 8


def test_initial_radius_keeps_the_inner_face_at_a_positive_radius():
    from mol_shell.model.material import centroidal_offset

    scene = mol_shell.TwistedCylinder()
    low = -centroidal_offset(scene.h)  # zeta1 when left to the code (rhoI = 0), about -h
    assert low == pytest.approx(scene.h, rel=1e-2)  # h + h^2/3 + ...
    for R in (0.005, low, -1.0):
        with pytest.raises(ParameterError, match=rf"^R = .* is outside \({low:.4g}, inf\) m: the inner face"):
            dataclasses.replace(scene, R=R)
    assert dataclasses.replace(scene, R=1.001 * low).R == 1.001 * low
    # a given zeta1 moves the bound: the whole thickness above the base surface allows any R > 0
    assert mol_shell.TwistedCylinder(zeta1=0.0, R=0.001).R == 0.001
    with pytest.raises(ParameterError, match=r"^R = 0.01 is outside \(0.01257, inf\) m"):
        mol_shell.TwistedCylinder(zeta1=-2 * scene.h, R=0.01)
    # the unshearable bulge: its thinnest section, R - |dR|
    with pytest.raises(ParameterError, match=r"^R = 0.01 is outside .*R - \|dR\|"):
        mol_shell.Unshearable(R=0.01, dR=0.005)


def test_python_values_of_the_wrong_kind_are_parameter_errors():
    with pytest.raises(ParameterError, match=r"^L = 'abc' is not a number; allowed: \(0, inf\) m$"):
        mol_shell.TwistedCylinder(L="abc")
    with pytest.raises(ParameterError, match=r"^gamma = '' is not a number"):
        get_scene("twisted-cylinder", gamma="")
    with pytest.raises(ParameterError, match=r"^nu = True is not a number"):
        mol_shell.TwistedCylinder(nu=True)
    assert mol_shell.TwistedCylinder(R="auto").R is None  # as --set R=auto: computed
    assert dataclasses.replace(mol_shell.TwistedCylinder(R=1.0), R="auto").R is None
    assert mol_shell.TwistedCylinder(E=np.float32(2e6)).E == 2e6


def test_numpy_scalars_become_python_numbers_so_a_float32_radius_builds_in_double_precision():
    """``Sphere(a=np.float32(1.1))``: the field stayed a float32, the meridian was computed in single precision (the
    pole's ``r0`` came out -1.4e-7, not 0; the step bound 7.8e-9 s, not 2e-4 s; CVODE failed at t = 0), and since
    the float32 hashes equal to the float64 ``1.100000023841858``, the in-process caches handed that scene the
    broken build too. Stored as the Python float of the same value, both scenes are one, built in double."""
    single = mol_shell.Sphere(a=np.float32(1.1), R=1.1, h=np.float32(0.01), n_quad=np.int32(4))
    assert [type(v) for v in (single.a, single.h, single.n_quad)] == [float, float, int]
    assert single == mol_shell.Sphere(a=1.100000023841858, R=1.1, h=float(np.float32(0.01)), n_quad=4)
    from mol_shell.runs.building import build

    system, _ = build(single, 11)
    r0 = system.reference[1]
    assert r0[0] == 0.0 and r0[-1] == 0.0 and r0.dtype == np.float64


def test_simulate_refuses_bad_arguments_before_computing():
    scene = mol_shell.TwistedCylinder()
    cases = [
        (dict(scene=scene, t_end="0.01"), r"^t_end = '0.01' is not a number; allowed: \(0, inf\) s$"),
        (dict(scene=None, t_end=0.01), r"^scene = None is not a scene; allowed: .*twisted-cylinder"),
        (dict(scene=scene), r"^t_end is missing: give t_end in \(0, inf\) s, or times$"),
        (dict(scene=scene, times="0,0.01"), r"^times = '0,0.01' is not a list of numbers"),
        (dict(scene=scene, t_end=0.01, dt="1e-6"), r"^dt = '1e-6' is not a number"),
        (dict(scene=scene, integrator="cvode-bdf", t_end=0.01, dt=1e-6), r"^dt is not an option of cvode-bdf \(its options: "),
        (dict(scene=scene, t_end=0.01, rtol=1e-6), r"^rtol is not an option of leapfrog \(its options: chunk, dt, restart\)$"),
        (dict(scene=scene, integrator="cvode-bdf", t_end=0.01, rtol=1.0), r"^rtol = 1.0 is outside \[1e-14, 1\)$"),
        (dict(scene=scene, integrator="cvode-bdf", t_end=0.01, rtol=1e-20), r"^rtol = 1e-20 is outside \[1e-14, 1\)$"),
        (dict(scene="unshearable", integrator="ida", t_end=0.01, dt=1e-6), r"^dt is not an option of ida"),
        (dict(scene="unshearable", integrator="ida", t_end=0.01, atol={"r": 1e-9}), r"^atol = \{'r': 1e-09\} is not a number"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ParameterError, match=message):
            mol_shell.simulate(**kwargs, progress=False)
    # an atol array is not printed in full
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(scene, "cvode-bdf", t_end=0.01, atol=np.full(400, 1e-9), progress=False)
    assert str(info.value).startswith("atol = <array of 400 values") and len(str(info.value)) < 200


def test_a_system_built_from_an_unresolved_scene_refuses_its_initial_state():
    """``R = auto`` is computed by resolve (simulate calls it); a system built directly from the scene got NaN radii
    in its initial state. It now names R; resolved, the state is finite."""
    from mol_shell.discretization.system import ShellSystem
    from mol_shell.runs.checks import resolve

    scene = mol_shell.TwistedCylinder()
    system = ShellSystem(scene, 9)
    with pytest.raises(ParameterError, match=r"^R = None .*resolve"):
        system.initial_state(scene)
    assert np.isfinite(system.initial_state(resolve(scene))).all()


@pytest.mark.parametrize("scene, changes, why", [
    ("twisted-cylinder", {"end2": "free", "end2_dz": 0.01}, "end2 = 'free' leaves z free"),
    ("twisted-cylinder", {"end2": "free", "end2_dchi": 0.01}, "end2 = 'free' leaves chi free"),
    ("twisted-cylinder", {"end1_dchi": 0.01}, "end1 = 'magnet' leaves chi free"),
    ("cone", {"end2": "free", "end2_dz": 0.01}, "end2 = 'free' leaves z free"),
    ("sphere", {"end1_dchi": 0.01}, "end1 = 'pole' ties chi"),
    ("axisymmetric", {"end2": "clamped", "end2_dchi": 0.01}, "the scene has no chi field"),
])
def test_an_edge_displacement_of_a_field_the_edge_does_not_hold_is_refused_by_the_scene(scene, changes, why):
    """Was refused only once the system was built, as momenta that overflow, with a false range (-inf, 1e-300]."""
    name = next(k for k in changes if k.endswith(("_dz", "_dchi")))
    with pytest.raises(ParameterError, match=f"^{name} = 0.01 cannot be imposed: {why}.*allowed: 0, or a displacement"):
        with_params(get_scene(scene), changes)
    held = {"end2": "clamped"} if scene != "sphere" else {}
    if scene not in ("sphere", "axisymmetric"):
        with_params(get_scene(scene), {**changes, **held, "end1": "clamped"})  # held: accepted


def test_a_points_file_is_kept_by_its_absolute_path(tmp_path, monkeypatch):
    """A run's or a path's file stored ``points`` as given, relative to where the command ran: ``run --from`` from
    another folder refused it as unreadable."""
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "pts.txt").write_text("1.0 0.0\n0.92388 0.382683\n0.707107 0.707107\n0.382683 0.92388\n"
                                             "0.0 1.0\n")  # a quarter circle: a dome whose top is a pole
    monkeypatch.chdir(tmp_path)
    scene = mol_shell.scenes.SCENES["meridian"](points="sub/pts.txt")
    assert scene.points == str(tmp_path / "sub" / "pts.txt")
    monkeypatch.chdir(tmp_path / "sub")
    assert mol_shell.scenes.SCENES["meridian"](points=scene.points).meridian().length == scene.meridian().length


def test_auto_is_taken_wherever_auto_is_the_default():
    """``zeta1 = "auto"`` (the documented default) was refused from Python ("'auto' is not a number"), while R and
    scene files took it."""
    assert mol_shell.Sphere(zeta1="auto").zeta1 is None and mol_shell.Sphere(zeta1=" Auto ").zeta1 is None
    assert mol_shell.Cone(dilation="auto").dilation is None and mol_shell.TwistedCylinder(R="none").R is None
    with pytest.raises(ParameterError, match="^h = 'auto' is not a number"):
        mol_shell.Sphere(h="auto")  # not where a number is the default


@pytest.mark.parametrize("cls", [mol_shell.Sphere, mol_shell.TwistedCylinder, mol_shell.Vessel, mol_shell.Unshearable])
def test_an_unknown_keyword_names_the_scenes_parameters(cls):
    """``Sphere(presure=100)`` was Python's "unexpected keyword argument 'presure'": now the one line every other
    refusal gives (the parameters listed, the scene named), still a TypeError for code that caught that."""
    with pytest.raises(TypeError) as caught:
        cls(presure=100.0)
    assert isinstance(caught.value, ParameterError)
    message = str(caught.value)
    assert message.startswith("parameter = 'presure' is outside {h, E, nu,") and " pressure" in message, message
    assert message.endswith(f"(for scene {cls.name})")
    assert cls(E=2e6).E == 2e6 and dataclasses.replace(cls(), E=3e6).E == 3e6  # known keywords as before


def test_a_subclass_with_init_arguments_of_its_own_is_not_refused():
    """The check reads the keywords of the class's own ``__init__``: a subclass's ``InitVar`` or an ``__init__`` of its
    own that takes ``**kwargs`` passes, as Python would let it."""

    @dataclasses.dataclass(frozen=True)
    class Tagged(mol_shell.Sphere):
        tag: dataclasses.InitVar[str] = ""

        def __post_init__(self, tag):
            object.__setattr__(self, "label", tag)
            super().__post_init__()

    class Loose(mol_shell.Sphere):
        def __init__(self, tag=None, **kwargs):
            super().__init__(**kwargs)
            object.__setattr__(self, "tag", tag)

    assert Tagged(tag="a", E=2e6).label == "a" and Loose(tag="b", E=3e6).tag == "b"
    with pytest.raises(ParameterError, match="parameter = 'presure' is outside .* tag"):
        Tagged(presure=1.0)
