"""The rigid motions of the modes are the edges' (not every low mode), the sparse solver's shift is an omega^2, and
the shapes' scaling is signed and comes with its modal mass.

Closed forms: a cylinder of radius ``a`` between clamped ends twists as a string, ``omega_1 = pi c / L`` with
``c = sqrt(G / rho)``, ``chi = sin(pi s / L)``, and the modal mass of that shape is its polar moment
``rho 2 pi a 2h (a^2 + h^2)`` (``h`` the half-thickness) times ``int sin^2 = L / 2`` (the lumped nodes' sum at n = 41 is exactly ``L / 2``);
a closed sphere's slowest torsional mode is Lamb's ``omega = 2 c / a``."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.sparse.linalg

import mol_shell
import mol_shell.analysis.modes as modes_module
from mol_shell import ModelLimitError, Sphere, TwistedCylinder
from mol_shell.cli.main import main


def _modes(scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mol_shell.modes(scene, **kw)


def _shear_speed(scene):
    return math.sqrt(scene.E / (2 * (1 + scene.nu)) / scene.rho)


def test_a_slow_mode_of_a_clamped_pipe_keeps_its_frequency_and_its_modal_mass_is_the_closed_form():
    """L = 1000 m, h = 1 mm: omega_1^2 = 3.3e-4 s-2 was below 1e-9 of the largest eigenvalue and written as 0 rad/s
    beside omega_squared = 3.3e-4 (0 rigid motions: both edges clamp chi and z)."""
    pipe = TwistedCylinder(gamma=0, L=1000, h=1e-3, end1="clamped", end2="clamped")
    ds = _modes(pipe, n=41, count=2)
    assert ds.attrs["zero_modes"] == 0
    exact = math.pi * _shear_speed(pipe) / pipe.L
    first = ds.isel(mode=0)
    assert float(first.frequency) == pytest.approx(exact, rel=1e-3)  # O(ds^2): (pi / 40)^2 / 24 = 2.6e-4
    assert float(first.frequency) == pytest.approx(math.sqrt(float(first.omega_squared)), rel=1e-12)
    assert float(first.chi.max()) == 1.0 and float(first.chi.min()) >= 0.0  # +1 at mid-length, not -1
    a, h = pipe.a, pipe.h
    polar = pipe.rho * 2 * math.pi * a * 2 * h * (a**2 + h**2)  # h: the half-thickness
    assert float(first.modal_mass) == pytest.approx(polar * pipe.L / 2, rel=1e-3)
    assert ds.modal_mass.attrs["units"] == "kg m2"


def test_a_thin_spheres_low_modes_are_listed_at_their_frequency_beside_its_two_rigid_motions():
    """h = 1e-4: modes 1-4 (omega^2 81-101 s-2, 1e-9 of the largest 1.2e11) were written as 0 rad/s."""
    ds = _modes(Sphere(h=1e-4, material="svk-plane-stress", nu=0.3), n=41, count=6)
    assert ds.attrs["zero_modes"] == 2
    w2 = ds.omega_squared.values
    assert (w2 > 0).all()
    np.testing.assert_allclose(ds.frequency.values, np.sqrt(w2), rtol=1e-12)
    for m in range(ds.sizes["mode"]):  # the entry of largest magnitude is +1: the sign is fixed
        shape = np.concatenate([ds[f].values[m] for f in ("z", "r", "chi", "theta", "psi")])
        assert shape.max() == 1.0 and shape.min() >= -1.0


@pytest.fixture
def sparse(monkeypatch):
    """The sparse solver from 100 free coordinates (n = 41: 197)."""
    monkeypatch.setattr(modes_module, "DENSE_MAX", 100)


def test_the_sparse_solvers_modes_of_a_heavy_sphere_are_lambs_not_zero(sparse):
    """rho = 1e7: omega^2 ~ 1e-2 s-2 was below the zero threshold 1e-9 max diag K (N/m): every mode 0 rad/s; and the
    shift -1e-6 max diag K (N/m) left ARPACK without convergence at a = 50 m, n = 700 (an internal error)."""
    heavy = Sphere(rho=1e7)
    ds = _modes(heavy, n=41, count=10)
    assert ds.attrs["method"] == "sparse shift-invert" and ds.attrs["zero_modes"] == 2
    assert (ds.frequency.values > 0).all()
    torsional = ds.frequency.values[ds.energy_fraction.sel(field="chi").values > 0.99]
    assert torsional[0] == pytest.approx(2 * _shear_speed(heavy) / heavy.a, rel=2e-3)


def test_an_arpack_that_does_not_converge_is_said_in_one_line_exit_3(sparse, monkeypatch, capsys, tmp_path):
    def never(*args, **kwargs):
        raise scipy.sparse.linalg.ArpackNoConvergence("ARPACK error -1: No convergence", np.array([0.5]),
                                                      np.zeros((197, 1)))

    monkeypatch.setattr(scipy.sparse.linalg, "eigsh", never)
    with pytest.raises(ModelLimitError, match=r"did not converge: 1 of the 10 lowest modes of 197 free coordinates"):
        _modes(Sphere(), n=41, count=10)
    code = main(["modes", "sphere", "--n", "41", "--count", "3", "-o", str(tmp_path / "m.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3, err
    assert err[-1].startswith("mol-shell: stopped: the sparse eigensolver (ARPACK") and "internal error" not in err[-1]


def test_a_thin_rings_slow_bending_mode_is_not_taken_for_round_off():
    """A flat annulus (a cone with H = 0), free edges, h = 1e-4 m: its first mode (omega^2 = 3.3e-4 s-2) is a bending
    mode, and was listed at 0 rad/s, under a round-off threshold of 1e3 eps times the grid's max K_ii / M_ii (which
    grows like 1/h^2). A bending mode's omega^2 goes as the wall's h^2 (stiffness h^3, mass h): ten times thicker,
    a hundred times omega^2."""
    omega2 = {}
    for h in (1e-4, 1e-3):
        scene = mol_shell.Cone(r1=1.0, r2=0.5, H=0.0, h=h, end1="free", end2="free", dilation=1.0,
                               material="svk-plane-stress")
        ds = mol_shell.modes(scene, n=21, count=1)
        omega2[h] = float(ds.omega_squared[0])
        assert float(ds.frequency[0]) == pytest.approx(omega2[h] ** 0.5, rel=1e-12)
    assert omega2[1e-4] > 0 and omega2[1e-3] / omega2[1e-4] == pytest.approx(100.0, rel=0.02)
