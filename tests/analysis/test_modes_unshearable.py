"""The unshearable scene's modes are the constrained shell's (chi_s = 0, psi = 0): no torsional mode but the rigid
spin, the breathing, bending and axial modes of the free shell unchanged."""

import math
import warnings

import numpy as np
import pytest

from mol_shell.analysis import modes as modes_module
from mol_shell.analysis.modes import modes
from mol_shell.scenes import TwistedCylinder, Unshearable


def _modes(scene, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return modes(scene, n=21, count=8, **kwargs)


@pytest.fixture(scope="module")
def pair():
    """The unshearable scene at rest on its natural state, and the same free shell (the twisted cylinder, untwisted,
    the same ends)."""
    unshearable = Unshearable(omega=0.0, dR=0.0)
    free = TwistedCylinder(gamma=0.0, R=1.0, end1=unshearable.end1, end2=unshearable.end2)
    return _modes(unshearable), _modes(free)


def test_no_torsional_mode_but_the_rigid_spin(pair):
    constrained, free = pair
    scene = Unshearable()
    mu = scene.E / (2 * (1 + scene.nu))
    torsion = math.pi * math.sqrt(mu / scene.rho) / scene.L  # the free tube's first torsional mode, k pi c / L
    assert np.min(np.abs(free.frequency.values / torsion - 1)) < 0.01  # the free shell has it
    assert np.min(np.abs(constrained.frequency.values / torsion - 1)) > 0.05  # the constrained one not
    assert float(abs(constrained.energy_fraction.sel(field=["chi", "psi"])).max()) < 1e-12
    assert np.all(constrained.chi.values == 0) and np.all(constrained.psi.values == 0)
    assert constrained.attrs["zero_modes"] == free.attrs["zero_modes"] == 1  # the spin, still a rigid motion
    assert "constrained: chi_s = 0, psi = 0" in constrained.attrs["title"] and "chi_s = 0" in constrained.attrs[
        "constraint"]
    assert "constraint" not in free.attrs


def test_the_modes_without_twist_or_shear_keep_their_frequencies(pair):
    """At an axisymmetric state at rest chi and psi decouple from z, r, theta: the constrained modes are the free
    shell's whose kinetic energy is not in chi or psi."""
    constrained, free = pair
    untwisted = free.energy_fraction.sel(field=["chi", "psi"]).sum("field").values < 1e-9
    kept = free.frequency.values[untwisted]
    np.testing.assert_allclose(constrained.frequency.values[: len(kept)], kept, rtol=1e-9)


def test_the_sparse_route_imposes_them_too(pair, monkeypatch):
    constrained, _ = pair
    monkeypatch.setattr(modes_module, "DENSE_MAX", 10)  # 64 coordinates: shift-invert
    sparse = _modes(Unshearable(omega=0.0, dR=0.0))
    assert sparse.attrs["method"] == "sparse shift-invert"
    np.testing.assert_allclose(sparse.frequency.values, constrained.frequency.values, rtol=1e-8)
