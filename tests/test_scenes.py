"""Scenes: registry, parameter checks, and scenes that build only the fields they need."""

import dataclasses

import numpy as np
import pytest

import mol_shell
from mol_shell.errors import ParameterError
from mol_shell.scenes import get_scene, with_params
from mol_shell.simulate import build


def test_registry_and_string_parameters():
    assert set(mol_shell.SCENES) == {"twisted-cylinder", "spinning-ring", "axisymmetric", "unshearable"}
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


def test_axisymmetric_equals_full_model_without_twist_spin_shear():
    times = [0, 0.005, 0.01]
    axi = mol_shell.simulate(mol_shell.Axisymmetric(R=1.01), times=times, progress=False)
    full = mol_shell.simulate(mol_shell.TwistedCylinder(R=1.01, gamma=0.0), times=times, progress=False)
    for name in ("z", "r", "theta", "chi", "psi", "energy"):
        np.testing.assert_allclose(axi[name], full[name], rtol=0, atol=1e-13 * max(1.0, float(abs(full[name]).max())))
    assert float(abs(axi.r - 1.01).max()) > 1e-3  # it does move
