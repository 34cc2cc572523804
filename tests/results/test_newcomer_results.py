"""What a new user hit on 0.5.0, in the library: run files store the values used (not "none"/"auto"), a free
edge carries no reaction torque, simulate's documentation matches what it takes, every scene class is at
the top level, and the paper's law at nu = 0.49 says how much too stiff it is for rubber."""

import dataclasses
import importlib
import inspect
import math
import re
import warnings

import numpy as np
import pytest
import scipy.optimize

import mol_shell
from reference_ring import lame


def run(scene, n=9, t_end=2e-6, **options):
    return mol_shell.simulate(scene, "leapfrog", n=n, times=[0.0, t_end], dt=1e-6, progress=False, stresses=False,
                              **options)


def centroidal_zeta1(a, h):
    """The lower face ``zeta1`` that puts a sphere's base surface at its centroid: the first moment of the wall's
    volume element ``(a + zeta)^2`` about the base surface vanishes over ``[zeta1, zeta1 + 2h]``."""
    antiderivative = lambda z: a * a * z**2 / 2 + 2 * a * z**3 / 3 + z**4 / 4  # of zeta (a + zeta)^2
    moment = lambda z1: antiderivative(z1 + 2 * h) - antiderivative(z1)
    return scipy.optimize.brentq(moment, -2 * h, 0.0, xtol=1e-18, rtol=4 * np.finfo(float).eps)


# -- item 2: the values used, with what was asked beside them ----------------------------------------------
def test_a_sphere_run_stores_the_radius_edges_and_thickness_it_used():
    """A closed sphere with everything auto: its edges are poles (polar angles 0 and pi), its base surface sits
    at the centroid of the wall, and without loads it starts from the natural sphere, so R = a."""
    ds = run(mol_shell.Sphere())
    assert ds.attrs["R"] == 1.0 and ds.attrs["R_requested"] == "auto"
    assert (ds.attrs["end1"], ds.attrs["end2"]) == ("pole", "pole")
    assert ds.attrs["end1_requested"] == ds.attrs["end2_requested"] == "auto"
    h = 2 * math.pi * 1e-3
    assert ds.attrs["zeta1"] == pytest.approx(centroidal_zeta1(1.0, h), rel=1e-9) and ds.attrs["zeta1_requested"] == "auto"
    for name in ("R", "zeta1", "end1", "end2", "a", "h", "nu"):
        assert ds.attrs[name] != "none" and f"units_{name}" in ds.attrs
    assert ds.attrs["units_R"] == "m" and ds.attrs["units_zeta1"] == "m"


def test_what_was_given_is_stored_as_given_and_nothing_is_marked_requested():
    scene = mol_shell.Sphere(R=1.01, zeta1=-0.005)
    ds = run(dataclasses.replace(scene, alpha1=0.5, end1="clamped"))
    assert ds.attrs["R"] == 1.01 and ds.attrs["zeta1"] == -0.005 and ds.attrs["end1"] == "clamped"
    assert ds.attrs["end2"] == "pole" and ds.attrs["end2_requested"] == "auto"  # the top is on the axis
    assert not {"R_requested", "zeta1_requested", "end1_requested"} & set(ds.attrs)


def test_the_radius_of_a_pressurised_sphere_s_equilibrium_is_its_membrane_radius():
    """R = auto under a constant pressure: the starting state is the discrete shell's equilibrium, a sphere to
    the grid's accuracy; the stored R lies within the distances of its nodes from the centre, and it is the
    membrane value a (1 + p a / (8 h (lambda + mu))) within 5 % of the strain (the grid's error at n = 21;
    docs/loads.md)."""
    scene = mol_shell.Sphere(pressure=1e3)
    ds = run(scene, n=21)
    radius = np.hypot(ds.r.isel(time=0), ds.z.isel(time=0)).values
    assert ds.attrs["R_requested"] == "auto"
    assert radius.min() <= ds.attrs["R"] <= radius.max()
    lam, mu = lame(scene.E, scene.nu)
    strain = scene.pressure * scene.a / (8 * scene.h * (lam + mu))
    assert abs((ds.attrs["R"] - 1) / strain - 1) < 0.05


def test_a_cylinder_stores_its_equilibrium_radius_and_that_it_was_computed():
    ds = run(mol_shell.TwistedCylinder(), n=8)
    assert isinstance(ds.attrs["R"], float) and 0.99 < ds.attrs["R"] < 1.0 and ds.attrs["R_requested"] == "auto"
    assert (ds.attrs["end1"], ds.attrs["end2"]) == ("magnet", "magnet")  # open edges: magnets by default
    given = run(mol_shell.TwistedCylinder(R=1.0, gamma=0.0), n=8)
    assert given.attrs["R"] == 1.0 and "R_requested" not in given.attrs


def test_a_dilation_left_to_the_code_is_stored_as_the_scale_used():
    ds = run(mol_shell.Cone())
    assert ds.attrs["dilation"] == 1.0 and ds.attrs["dilation_requested"] == "auto"  # unloaded: the natural cone
    assert run(mol_shell.Cone(dilation=1.01)).attrs["dilation"] == 1.01


def test_the_stored_values_survive_a_file_and_make_the_same_scene(tmp_path):
    """A file's parameters (without the *_requested notes) rebuild a scene that runs to the same first state."""
    ds = run(mol_shell.Sphere())
    path = tmp_path / "s.nc"
    mol_shell.write_netcdf(ds, path)
    back = mol_shell.read_netcdf(path)
    fields = {f.name for f in dataclasses.fields(mol_shell.Sphere)}
    params = {k: v.item() if hasattr(v, "item") else v for k, v in back.attrs.items() if k in fields}
    again = run(mol_shell.Sphere(**params))
    np.testing.assert_array_equal(again.r.isel(time=0), ds.r.isel(time=0))


def test_modes_store_the_values_used_too():
    ds = mol_shell.modes(mol_shell.Sphere(), n=9, count=2)
    assert ds.attrs["R"] == 1.0 and ds.attrs["R_requested"] == "auto" and ds.attrs["end1"] == "pole"


def test_a_vessel_stores_the_head_radii_it_used():
    """The vessel's crown and knuckle left to the code are its documented defaults 2a and 0.2a; the stored values
    rebuild the same meridian."""
    scene = mol_shell.Vessel(a=0.5)
    ds = run(scene, n=12)
    assert ds.attrs["crown"] == 1.0 and ds.attrs["crown_requested"] == "auto"
    assert ds.attrs["knuckle"] == 0.1 and ds.attrs["knuckle_requested"] == "auto"
    again = mol_shell.Vessel(a=0.5, crown=ds.attrs["crown"], knuckle=ds.attrs["knuckle"])
    assert again.meridian().describe() == scene.meridian().describe()
    drawn = run(mol_shell.Vessel(segments="arc 0.5 90, line 1, arc 0.5 90"), n=12)
    assert drawn.attrs["crown"] == "none" and "crown_requested" not in drawn.attrs  # segments replace the heads


def test_a_path_stores_the_values_used_and_no_placeholder():
    """A path's edges, lower face and vessel heads are the values used, as in a run file; a run's initial data
    (R, dilation) left to the code reads auto, since no path state is a run's start."""
    for scene in (mol_shell.Sphere(), mol_shell.Vessel()):
        ds = mol_shell.path(scene, "pressure", 0.0, 50.0, n=10, max_steps=2, progress=False)
        assert (ds.attrs["end1"], ds.attrs["end2"]) == ("pole", "pole") and ds.attrs["end1_requested"] == "auto"
        assert ds.attrs["zeta1"] == ds.attrs["zeta1_used"] < 0 and ds.attrs["units_zeta1"] == "m"
        assert "none" not in ds.attrs.values(), [k for k, v in ds.attrs.items() if v == "none"]
    assert ds.attrs["crown"] == 2.0 and ds.attrs["knuckle"] == 0.2 and ds.attrs["dilation"] == "auto"
    assert "pressure" not in ds.attrs and "units_pressure" not in ds.attrs  # the path's values, not the scene's


# -- item 11: reactions at edges that are not driven -------------------------------------------------------
def test_a_free_edge_carries_no_reaction_and_a_held_one_is_computed():
    """A cone spun at its first edge (a magnet: ``z`` held, ``chi`` driven): the torque and force at the free
    second edge are 0 (nothing holds it), the magnet's axial force is computed; with the second edge clamped, its
    support's torque and force are computed too (their balance laws: tests/model/test_held_reactions.py)."""
    free = run(mol_shell.Cone(end1="magnet", end2="free", end1_spin=10.0), t_end=1e-5)
    torque, force = free.reaction_torque.values, free.reaction_force.values
    assert np.all(torque[:, 1] == 0) and np.all(force[:, 1] == 0)
    assert np.all(np.isfinite(torque[:, 0])) and np.all(np.isfinite(force[:, 0]))
    held = run(mol_shell.Cone(end1="magnet", end2="clamped", end1_spin=10.0), t_end=1e-5)
    assert np.all(np.isfinite(held.reaction_torque.values)) and np.all(np.isfinite(held.reaction_force.values))


# -- item 10: the documentation of simulate, and the scene classes --------------------------------------------
def documented_parameters(function):
    doc = inspect.getdoc(function)
    section = re.search(r"^Parameters\n-+\n(.*?)(?=^\w[\w ]*\n-+\n|\Z)", doc, flags=re.S | re.M).group(1)
    names = []
    for line in section.splitlines():
        if line and not line.startswith(" "):
            names += [part.strip() for part in line.split(" : ")[0].split(",")]
    return names


@pytest.mark.parametrize("function", [mol_shell.simulate, mol_shell.study, mol_shell.modes, mol_shell.load_scene])
def test_the_documented_parameters_are_the_signature_s(function):
    signature = inspect.signature(function).parameters.values()
    taken = [("**" if p.kind is p.VAR_KEYWORD else "*" if p.kind is p.VAR_POSITIONAL else "") + p.name for p in signature]
    assert documented_parameters(function) == taken


def test_every_name_simulate_s_documentation_refers_to_exists():
    """``:func:``/``:data:``/``:class:`` targets in help(mol_shell.simulate) resolve to objects (0.5.0 still named
    modules that had moved)."""
    doc = inspect.getdoc(mol_shell.simulate)
    targets = re.findall(r":(?:func|data|class|mod):`~?([\w.]+)`", doc)
    assert targets
    module = inspect.getmodule(mol_shell.simulate)
    for target in targets:
        parts = target.split(".")
        if len(parts) == 1:
            assert hasattr(module, target), target
            continue
        for cut in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:cut]))
            except ImportError:
                continue
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
            break
        else:
            pytest.fail(f"{target} does not resolve")


def test_every_scene_class_is_at_the_top_level():
    for name, cls in mol_shell.SCENES.items():
        assert getattr(mol_shell, cls.__name__) is cls and cls.__name__ in mol_shell.__all__, name
    assert mol_shell.Sphere().name == "sphere"


# -- item 12: the director law at nu = 0.49 ------------------------------------------------------------------
def test_the_paper_s_law_near_incompressibility_warns_with_the_stiffness_ratios():
    """Under the inextensible director the in-plane stiffness is lambda + 2 mu (hoop) and 2 (lambda + mu) (equal
    stretch both ways); a thin wall in plane stress has E/(1 - nu^2) and E/(1 - nu): at nu = 0.49, 13.0 and 17.1.
    The warning says both, names the plane-stress law and is kept in the run's attrs."""
    scene = mol_shell.Sphere()
    lam, mu = lame(scene.E, scene.nu)
    hoop = (lam + 2 * mu) / (scene.E / (1 - scene.nu**2))
    both = 2 * (lam + mu) / (scene.E / (1 - scene.nu))
    with pytest.warns(mol_shell.MaterialWarning) as caught:
        ds = run(scene)
    text = str(caught[0].message)
    assert f"{hoop:.3g} times stiffer" in text and f"{both:.3g} times" in text and (round(hoop), round(both)) == (13, 17)
    assert 'choose material = "svk-plane-stress"' in text and "\n" not in text
    assert ds.attrs["material_warning"] == text


@pytest.mark.parametrize("changes", [{"nu": 0.3}, {"nu": 0.449}, {"material": "svk-plane-stress"}])
def test_no_warning_where_the_law_fits(changes):
    with warnings.catch_warnings():
        warnings.simplefilter("error", mol_shell.MaterialWarning)
        ds = run(dataclasses.replace(mol_shell.Sphere(), **changes))
    assert "material_warning" not in ds.attrs


def test_a_study_warns_once_not_once_per_case():
    # three cases that each warn; varied in the spin (initial data): one compiled right-hand side for all three
    with pytest.warns(mol_shell.MaterialWarning) as caught:
        mol_shell.study(mol_shell.Sphere(), {"omega": [0.0, 1.0, 2.0]}, "leapfrog", n=5, times=[0, 1e-6],
                        scheduler="serial", progress=False)
    assert len([w for w in caught if issubclass(w.category, mol_shell.MaterialWarning)]) == 1
