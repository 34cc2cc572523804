"""One helical family of fibres on the axisymmetric scene is refused: the family couples stretch to twist
(``2 cos sin C_13``, ``C_13 = r^2 chi_s ...``) and the scene holds ``chi = 0``, so a "free" end carried a torque no one
gave: a tube pulled by 100 N stretched as lamination theory's tube with its twist held (3.68e-4), not as the free tube
(8.80e-4, the cone scene's). Two balanced families (or a family along the meridian or the hoop) have no coupling and
still run."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mol_shell
from mol_shell import Axisymmetric, ParameterError
from mol_shell.cli.main import main

WALL = {"end1": "magnet", "end2": "free", "h": 0.005, "material": "svk-plane-stress", "nu": 0.3, "fibre_E": 1e7,
        "fibre_angle": 0.5, "R": 1.0}
SETS = [word for k, v in WALL.items() for word in ("--set", f"{k}={v}")]


def test_one_helical_family_is_refused_naming_fibre_families():
    with pytest.raises(ParameterError) as caught:
        Axisymmetric(**WALL)
    assert caught.value.name == "fibre_families"
    text = str(caught.value)
    assert "\n" not in text and "couples stretch to twist" in text and "2 (families at +-fibre_angle" in text
    assert "scene cone with r1 = r2" in text


@pytest.mark.parametrize("keys", [{"fibre_families": 2}, {"fibre_angle": 0.0}, {"fibre_angle": math.pi / 2},
                                  {"fibre_angle": -1.5708}, {"fibre_E": 0.0}])
def test_fibres_without_the_coupling_are_taken(keys):
    assert Axisymmetric(**{**WALL, **keys}).fibre_angle == keys.get("fibre_angle", 0.5)


@pytest.mark.parametrize("command", [["run", "axisymmetric", "--t-end", "1e-3"], ["modes", "axisymmetric"],
                                     ["path", "axisymmetric", "--param", "end2_force=0:100"],
                                     ["study", "axisymmetric", "--vary", "L=3,4", "--path", "end2_force=0:100"]])
def test_every_command_refuses_it_in_one_line(command, tmp_path, capsys, no_build):
    code = main([*command, *SETS, "--n", "11", "-o", str(tmp_path / "out.nc")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert err.startswith("mol-shell: error: fibre_families = 1 is outside 2 (families at +-fibre_angle")


def test_two_balanced_families_still_run_and_stretch_as_lamination_theory():
    """Membrane stiffness per unit length of the wall 2h: the plane-stress matrix E/(1 - nu^2) and each family's
    E_f (c^2, s^2, +-c s) outer itself (a.E a = c^2 e_x + s^2 e_phi +- c s gamma); two families: the shear couplings
    cancel. Axial force F over the circumference 2 pi a, hoop force 0: e_x = 2.6467e-4."""
    scene = Axisymmetric(**{**WALL, "fibre_families": 2})
    ds = mol_shell.path(scene, "end2_force", 0.0, 100.0, n=21, progress=False)
    assert ds.attrs["status"] == "complete" and float(ds.parameter[-1]) == 100.0
    E, nu, t, Ef, c, s = scene.E, 0.3, 2 * 0.005, 1e7, math.cos(0.5), math.sin(0.5)
    stiffness = E * t / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    for sign in (1, -1):
        v = np.array([c * c, s * s, sign * c * s])
        stiffness += Ef * t * np.outer(v, v)
    expected = np.linalg.solve(stiffness, [100.0 / (2 * math.pi), 0.0, 0.0])
    assert abs(expected[2]) < 1e-18  # no stretch-twist coupling left
    z, ss = ds.z.isel(step=-1).values, ds.s.values
    k = len(ss) // 2
    strain = (z[k + 1] - z[k - 1]) / (ss[k + 1] - ss[k - 1]) - 1
    assert strain == pytest.approx(expected[0], rel=2e-3)
    assert float(np.abs(ds.chi).max()) == 0.0  # the scene has no chi: none needed


ANGLE_PLY = "0.005 svk-plane-stress fibre_angle=0.5; 0.005 svk-plane-stress fibre_angle=-0.5"


def test_an_angle_ply_wall_balances_and_stretches_as_lamination_theory():
    """Layers of one family each, +a and -a of one thickness and fibre_E (the standard angle-ply laminate), were
    refused layer by layer, naming a fibre_families nobody set in them; their membrane couplings cancel (A16 = A26 =
    0), so the wall is judged whole and runs: the same membrane stiffness as two families in one wall, e_x = 2.6467e-4
    (the test above's closed form; the layers' bending-stretching coupling leaves the membrane strain at 1e-3)."""
    scene = Axisymmetric(**{**WALL, "layers": ANGLE_PLY})
    ds = mol_shell.path(scene, "end2_force", 0.0, 100.0, n=21, progress=False)
    E, nu, t, Ef, c, s = scene.E, 0.3, 2 * 0.005, 1e7, math.cos(0.5), math.sin(0.5)
    stiffness = E * t / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    for sign in (1, -1):
        v = np.array([c * c, s * s, sign * c * s])
        stiffness += Ef * (t / 2) * np.outer(v, v)  # each family in its layer, half the wall
    expected = np.linalg.solve(stiffness, [100.0 / (2 * math.pi), 0.0, 0.0])
    z, ss = ds.z.isel(step=-1).values, ds.s.values
    k = len(ss) // 2
    assert (z[k + 1] - z[k - 1]) / (ss[k + 1] - ss[k - 1]) - 1 == pytest.approx(expected[0], rel=3e-3)


@pytest.mark.parametrize("layers", ["0.005 svk-plane-stress fibre_angle=0.5; 0.005 svk-plane-stress fibre_angle=0.5",
                                    ANGLE_PLY.replace("-0.5", "-0.5 fibre_E=2e7")])
def test_layers_whose_helices_do_not_balance_are_refused_naming_layers(layers):
    with pytest.raises(ParameterError) as caught:
        Axisymmetric(**{**WALL, "layers": layers})
    assert caught.value.name == "layers" and "helical fibres balance" in str(caught.value)
