"""A path continued in a load the scene already sets: the path's values replace the scene's.

``path(scene, "pressure", ...)`` on a scene with its own ``pressure`` (the shipped example
``examples/pressurised_sphere.toml`` has 1 kPa on a ramp) varies the pressure over the path's range; the scene's
value and history take no part. So the path equals the one of the same scene without that load, and a run or a
modes analysis started from one of its steps (``path_start``) is at rest under the step's load, constant in time.

Independent check of the states: a closed sphere of radius ``a``, wall ``t = 2h``, plane-stress SVK, inflated by
``p`` is in the membrane state ``N = p a / 2`` both ways; its strain ``N (1 - nu) / (E t)`` stretches every
radius ``r0`` (the reference) by ``1 + p a (1 - nu) / (4 h E)`` to first order in the strain (2.8e-3 here; the next order and the wall's
thickness terms are below 1e-2 of the change), and the enclosed volume by its cube. At n = 41 the nodes' stretches
lie within 0.3 % of it, the volume's within 0.04 % (n = 8: 10 % and 3 %, the grid's error).
"""

from __future__ import annotations

import numpy as np
import pytest

from mol_shell import Cone, Sphere, path, simulate
from mol_shell.analysis.modes import modes
from mol_shell.analysis.path_start import path_start
from mol_shell.analysis.path_study import path_study

N = 8
WALL = {"material": "svk-plane-stress", "nu": 0.3}


def test_the_path_replaces_the_scenes_own_value_of_the_load():
    own = path(Sphere(**WALL, pressure=500.0, pressure_history="ramp 0.05"), "pressure", 0.0, 100.0, n=41, steps=2)
    bare = path(Sphere(**WALL), "pressure", 0.0, 100.0, n=41, steps=2)
    assert own.attrs["status"] == "complete"
    assert np.array_equal(own.parameter.values, bare.parameter.values)
    assert np.allclose(own.r.values, bare.r.values, rtol=0, atol=1e-14)
    assert own.attrs["parameter"] == "pressure" and own.attrs["parameter_scene_value"] == 500.0
    assert "pressure = 500 Pa" in own.attrs["parameter_replaced"] and own.attrs["pressure_history"] == "constant"
    scene = Sphere(**WALL)
    strain = 100.0 * scene.a * (1 - scene.nu) / (4 * scene.h * scene.E)
    stretch = own.r.values[-1, 1:-1] / own.r0.values[1:-1]  # every node off the poles, on the grid's sphere
    assert np.allclose(stretch - 1, strain, rtol=1e-2, atol=0)
    volume = own.volume.values
    assert (volume[-1] / volume[0]) ** (1 / 3) - 1 == pytest.approx(strain, rel=2e-3)


def test_an_end_force_the_scene_sets_is_replaced_too():
    edges = {"end1": "clamped", "end2": "free"}
    own = path(Cone(**edges, end2_force=5.0), "end2_force", 0.0, 10.0, n=N)
    bare = path(Cone(**edges), "end2_force", 0.0, 10.0, n=N)
    assert own.attrs["status"] == "complete" and own.attrs["parameter_scene_value"] == 5.0
    assert np.allclose(own.z.values, bare.z.values, rtol=0, atol=1e-14)


def test_modes_from_a_step_of_a_path_whose_scene_ramps_the_load_are_those_at_the_steps_load():
    """The shipped example's load: 1 kPa on a ramp. A step's state is at rest under the step's pressure, so the
    prestressed ``omega^2`` from ``modes`` is the path's own smallest eigenvalue there (a ramp would start at 0 and
    the state would be no equilibrium)."""
    ds = path(Sphere(pressure=1000.0, pressure_history="ramp 0.05"), "pressure", 0.0, 100.0, n=N, max_steps=4)
    scene, n, fields, _ = path_start(ds, step=4)
    assert scene.pressure == float(ds.parameter[4]) and scene.pressure_history == "constant"
    omega = float(modes(scene, n=n, count=1, initial=fields).frequency[0])
    assert omega**2 == pytest.approx(float(ds.smallest_eigenvalues.values[4, 0]), rel=1e-6)


def test_a_study_of_paths_in_a_load_the_scene_sets():
    ds = path_study(Sphere(pressure=50.0), {"h": [0.01, 0.02]}, "pressure", 0.0, -100.0, n=N, scheduler="serial")
    assert list(ds.status.values) == ["complete", "complete"]


def test_the_command_says_the_scenes_load_was_replaced(tmp_path, capsys):
    """The shipped example under --param pressure: the replacement is said on stderr, not only in the file."""
    from pathlib import Path

    from mol_shell.cli.main import main

    example = Path(__file__).parents[2] / "examples" / "pressurised_sphere.toml"
    out = tmp_path / "p.nc"
    assert main(["path", str(example), "--param", "pressure=0:100", "--n", str(N), "--max-steps", "2",
                 "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "mol-shell: note: the scene's pressure = 1000 Pa (pressure_history 'ramp 0.05') is replaced" in err


def test_another_load_on_a_history_acts_at_its_value_at_t0_and_the_path_says_so(tmp_path, capsys):
    """A path's states are at rest, under the scene's other loads at ``t = 0``: a pressure on a ramp is 0 there
    (the path equals the one without it), on a table starting at half its magnitude it is half (the path equals
    the one with that pressure held constant). This was silent before: the file and the command now say it."""
    from mol_shell.cli.main import main

    edges = {"end1": "clamped", "end2": "free"}
    ramped = path(Cone(**edges, pressure=400.0, pressure_history="ramp 0.01"), "end2_force", 0.0, 10.0, n=N)
    bare = path(Cone(**edges), "end2_force", 0.0, 10.0, n=N)
    assert np.allclose(ramped.z.values, bare.z.values, rtol=0, atol=1e-14)
    assert "pressure = 400 Pa (pressure_history 'ramp 0.01') acts at its value at t = 0 in every state, 0 Pa" \
        in ramped.attrs["loads_at_rest"]
    halved = path(Cone(**edges, pressure=400.0, pressure_history="table 0:0.5 1:1"), "end2_force", 0.0, 10.0, n=N)
    held = path(Cone(**edges, pressure=200.0), "end2_force", 0.0, 10.0, n=N)
    assert np.allclose(halved.z.values, held.z.values, rtol=0, atol=1e-14)
    assert "in every state, 200 Pa" in halved.attrs["loads_at_rest"] and "loads_at_rest" not in held.attrs
    out = tmp_path / "p.nc"
    assert main(["path", "cone", "--set", "end1=clamped", "--set", "end2=free", "--set", "pressure=400",
                 "--set", "pressure_history=sine 50", "--param", "end2_force=0:10", "--n", str(N),
                 "--max-steps", "2", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "mol-shell: note: the scene's pressure = 400 Pa (pressure_history 'sine 50') acts at its value at t = 0 " \
        "in every state, 0 Pa" in err


def test_a_spin_is_left_out_of_a_paths_states_and_the_file_says_so():
    """A drum spun at omega = 20 rad/s: the path's states are at rest, as without the spin; it was silent."""
    spun = path(Cone(end1="clamped", end2="free", omega=20.0), "end2_force", 0.0, 10.0, n=N)
    still = path(Cone(end1="clamped", end2="free"), "end2_force", 0.0, 10.0, n=N)
    assert np.array_equal(spun.z.values, still.z.values)
    assert "omega = 20 rad s-1 is left out: a path's states are at rest" in spun.attrs["loads_at_rest"]


def test_a_twist_asked_for_is_said_to_be_initial_data():
    """The twisted cylinder's gamma = 0.1 rad/m: with its ends free to turn, the path's states at rest are untwisted
    (chi uniform), as they should be; it was silent where a spin was noted."""
    from mol_shell import TwistedCylinder

    ds = path(TwistedCylinder(), "pressure", 0.0, 100.0, n=N, max_steps=3)
    assert np.ptp(ds.chi.values[-1]) < 1e-9  # untwisted: the twist unwound at rest
    assert "gamma = 0.1 rad m-1 is initial data: a path's states are equilibria at rest" in ds.attrs["loads_at_rest"]


@pytest.mark.parametrize("extra", [{}, {"fibre_E": 1e7, "fibre_angle": 0.5, "fibre_families": 1}])
def test_a_paths_state_is_the_run_starts_equilibrium_to_round_off(extra):
    """A closed sphere translates freely along its axis: the path held one node's ``z`` and the run's static solve
    (``R = auto``) keeps the reference's mean ``z``, so the same equilibrium came out shifted by 3.5e-4 m. The path
    reports its states with the static solve's gauge (the rigid motion's mean kept): the two independent solves
    (continuation against Newton from the natural sphere) then give one state. One helical fibre family twists
    the sphere as it inflates: the spin's gauge too, with the poles' chi tied to their neighbours' (the shift left
    them 1.4e-3 rad apart)."""
    scene = Sphere(**WALL, **extra)
    ds = path(scene, "pressure", 0.0, 2000.0, n=41, steps=2)
    start = simulate(Sphere(**WALL, **extra, pressure=float(ds.parameter[-1])), n=41, times=[0.0, 1e-5],
                     stresses=False)
    for name in ("z", "r", "chi", "theta"):
        assert np.allclose(ds[name].values[-1], start[name].values[0], rtol=0, atol=1e-12), name
    assert abs(float(ds.z.values[-1].mean() - ds.z.values[0].mean())) < 1e-12  # the mean z stays the reference's


@pytest.mark.parametrize("layered", [False, True])
def test_a_path_file_of_a_version_whose_neo_hookean_was_the_log_law_continues_with_that_law(layered):
    """Until 0.6.0.dev1 ``neo-hookean`` was the ``(ln J)^2`` law (now ``neo-hookean-log``): ``--from`` a path of
    those versions started under the new law, off equilibrium (a run from a step moved, 0.66 J of kinetic energy)
    without a word. The scene is rebuilt with the law the path was traced with, a layer's too, and a run from a
    step stays at rest; a file of this version keeps ``neo-hookean``."""
    import mol_shell

    wall = ({"layers": "0.01 neo-hookean-log nu=0.3; 0.01 svk-plane-stress nu=0.3", "h": 0.01} if layered else
            {"material": "neo-hookean-log", "nu": 0.3, "h": 0.01})
    ds = path(Sphere(**wall), "pressure", 0.0, 3000.0, n=N, steps=2)
    old = ds.assign_attrs(mol_shell_version="0.6.0.dev0", **(
        {"layers": ds.attrs["layers"].replace("neo-hookean-log", "neo-hookean")} if layered else
        {"material": "neo-hookean"}))
    scene, n, fields, _ = path_start(old, step=2)
    assert (scene.layers.split()[1] if layered else scene.material) == "neo-hookean-log"
    run = simulate(scene, "leapfrog", n=n, t_end=2e-3, initial=fields, progress=False)  # from the path's state
    moved = np.abs(run.r.values - run.r.values[0]).max() / np.abs(run.r.values[0]).max()
    assert moved <= 1e-9, moved
    now, _, _, _ = path_start(old.assign_attrs(mol_shell_version=mol_shell.__version__), step=2)
    assert (now.layers.split()[1] if layered else now.material) == "neo-hookean"
