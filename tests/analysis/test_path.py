"""Equilibrium paths (:func:`mol_shell.path`) against closed forms: a closed sphere under external pressure.

Expected values come from thin-shell theory, not from runs:

* classical buckling pressure of a sphere of radius ``a`` and wall thickness ``t = 2h`` (Zoelly):
  ``p_cl = 2 E t^2 / (a^2 sqrt(3 (1 - nu^2)))``, reached by the axisymmetric Legendre mode ``P_l`` whose
  ``l(l+1)`` is nearest ``lam* = (a/t) sqrt(12 (1 - nu^2))`` (the thin-shell critical pressure of mode ``l`` is
  ``p_cl (lam_l/lam* + lam*/lam_l) / 2``). The thicknesses below are chosen so that ``lam*`` equals ``l(l+1)``
  for an odd ``l``: that mode is antisymmetric about the equator, which the discrete sphere keeps exactly (its
  nodes are symmetric), so the first critical point is a genuine (pitchfork) bifurcation, not one that the
  discretisation turns into a smooth path or a fold, as it does for even ``l``;
* the membrane state before buckling: uniform strain ``eps = p a (1 - nu) / (2 E t)`` and stored energy
  ``pi a^4 p^2 (1 - nu) / (E t)`` (half the pressure's work ``p dV`` in the linear range).

The model differs from the classical value through the finite strain before buckling (the radius shrinks by
``eps``, the SVK tangent modulus falls by about ``3 eps`` in compression, the follower pressure acts on the
deformed wall): corrections of a few ``eps``, with ``eps`` about 1 % at ``a/t = 40``. They vanish linearly with
``t/a``, so the critical pressure extrapolated linearly to ``t/a -> 0`` from two thicknesses must give ``p_cl``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from mol_shell import Sphere, path
from mol_shell.analysis.equilibria import EquilibriumEquations
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem

E, NU, A = 1.0e6, 0.3, 1.0
ROOT = math.sqrt(12 * (1 - NU**2))


def classical(h):
    t = 2 * h
    return 2 * E * t**2 / (A**2 * math.sqrt(3 * (1 - NU**2)))


def half_thickness_for_degree(l):
    """``h`` for which Legendre degree ``l`` minimises the thin-shell critical pressure exactly."""
    return A / (2 * l * (l + 1) / ROOT)


def critical_degree(h):
    """The degree ``l`` of the lowest thin-shell critical pressure."""
    lam_star = A / (2 * h) * ROOT
    return min(range(2, 200), key=lambda l: l * (l + 1) / lam_star + lam_star / (l * (l + 1)))


def prebuckling_strain(h, p):
    return abs(p) * A * (1 - NU) / (2 * E * 2 * h)


def sphere(h):
    return Sphere(a=A, h=h, E=E, nu=NU, material="svk-plane-stress")


def sign_changes_of_normal_mode(ds, point=0):
    """Zeros of the critical mode's normal displacement along the meridian (``P_l`` has ``l``)."""
    phi = ds.s.values / A  # polar angle from the pole at s = 0 (z = -a)
    w = ds.point_mode_r.values[point] * np.sin(phi) - ds.point_mode_z.values[point] * np.cos(phi)
    inner = w[2:-2]  # the pole nodes carry the gauge and the ties
    return int(np.sum(np.diff(np.sign(inner)) != 0))


H11 = half_thickness_for_degree(11)  # a/t = 39.9
H15 = half_thickness_for_degree(15)  # a/t = 72.6


@pytest.fixture(scope="module")
def thick():
    return path(sphere(H11), "pressure", 0.0, -1.02 * classical(H11), n=80, steps=10)


@pytest.fixture(scope="module")
def thin():
    return path(sphere(H15), "pressure", 0.0, -1.0 * classical(H15), n=110, steps=10)


def test_the_degrees_are_the_ones_chosen():
    assert critical_degree(H11) == 11 and critical_degree(H15) == 15


@pytest.mark.parametrize("which, h, l", [("thick", H11, 11), ("thin", H15, 15)])
def test_first_critical_point_is_the_classical_axisymmetric_bifurcation(request, which, h, l):
    ds = request.getfixturevalue(which)
    assert ds.attrs["status"] == "complete"
    p_cl = classical(h)
    first = int(np.argmax(ds.point_parameter.values))  # the least external pressure
    assert ds.point_kind.values[first] == "bifurcation" and ds.point_located.values[first] == 1
    assert ds.point_family.values[first] == "axisymmetric"
    assert sign_changes_of_normal_mode(ds, first) == l
    # no instability before it
    before = ds.parameter.values > ds.point_parameter.values[first]
    assert np.all(ds.negative_eigenvalues.values[before] == 0)
    # within the finite-strain corrections (a few eps) of the classical value
    eps = prebuckling_strain(h, p_cl)
    assert abs(ds.point_parameter.values[first] / -p_cl - 1) < 5 * eps


def test_critical_pressure_extrapolates_to_the_classical_value(thick, thin):
    """The corrections are O(eps) = O(t/a): linear extrapolation in t/a to zero leaves O((t/a)^2) and the
    discretisation's share (the grids resolve each half-wave of P_l by ~7 nodes: a fraction of a percent)."""
    x = np.array([2 * H11 / A, 2 * H15 / A])
    ratio = np.array([ds.point_parameter.values.max() / -classical(h) for ds, h in ((thick, H11), (thin, H15))])
    slope = (ratio[1] - ratio[0]) / (x[1] - x[0])
    intercept = ratio[0] - slope * x[0]
    assert abs(intercept - 1) < 0.01


def test_stored_energy_equals_the_work_of_the_pressure(thick):
    """Conservative load: U(step) = int p dV along the path, up to the trapezoidal rule over the steps (exact for
    a work linear in the load; the path's curvature is O(eps))."""
    stored, work = thick.stored_energy.values, thick.load_work.values
    assert work[-1] > 0
    assert np.all(np.abs(stored - work) <= 1e-3 * work[-1])
    # and the linear membrane state at the first step: U = pi a^4 p^2 (1 - nu) / (E t), to O(eps) and O(t/a)
    p = float(thick.parameter[1])
    expected = math.pi * A**4 * p**2 * (1 - NU) / (E * 2 * H11)
    assert stored[1] == pytest.approx(expected, rel=0.05)
    # the volume it encloses shrinks by the membrane strain: dV / V = 3 eps
    volume = thick.volume.values
    assert 1 - volume[1] / volume[0] == pytest.approx(3 * prebuckling_strain(H11, p), rel=0.05)


def test_traced_in_either_direction_the_path_has_the_same_critical_point(thick):
    back = path(sphere(H11), "pressure", -1.02 * classical(H11), 0.0, n=80, steps=10)
    assert back.attrs["status"] == "complete"
    # each is located to 1e-7 of the range, on trial states whose residual (1e-9 of a unit strain's force) leaves
    # an error along the nearly critical mode: together a few 1e-6 of the load
    assert back.point_parameter.values.max() == pytest.approx(thick.point_parameter.values.max(), rel=2e-5)
    # the same equilibrium at the far end (past three critical points, where a residual at Newton's tolerance
    # moves the state by residual / (a small eigenvalue))
    assert float(back.volume[0]) == pytest.approx(float(thick.volume[-1]), rel=1e-7)
    assert np.all(back.negative_eigenvalues.values[back.parameter.values > back.point_parameter.values.max()] == 0)


@pytest.mark.parametrize("param", ["drag=0:1", "pressure=5:5", "pressure=0:abc", "pressure", "gravity=0:1"])
def test_bad_input_exits_2_with_one_line_naming_the_option(tmp_path, capsys, param):
    code = main(["path", "sphere", "--param", param, "--n", "10", "-o", str(tmp_path / "p.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "--param" in err
    assert not (tmp_path / "p.nc").exists()


def test_the_command_writes_a_readable_dataset(tmp_path, capsys):
    out = tmp_path / "sub" / "path.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-100", "--n", "16", "--set", "h=0.01", "--set", "nu=0.3",
                 "--set", "material=svk-plane-stress", "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    with xr.open_dataset(out) as ds:
        assert ds.parameter.attrs["parameter"] == "pressure" and ds.parameter.attrs["units"] == "Pa"
        assert float(ds.parameter[0]) == 0 and float(ds.parameter[-1]) == -100
        assert ds.r.dims == ("step", "s") and ds.r.attrs["units"] == "m"
        assert ds.attrs["Conventions"] == "CF-1.8" and "rotationally symmetric" in ds.attrs["critical_points"]
        assert ds.sizes["point"] == 0 and np.all(ds.negative_eigenvalues.values == 0)
        states = ds.sizes["step"]
    assert f"wrote {out}: {states} states ({states - 1} steps) from pressure = 0" in capsys.readouterr().out


def test_the_summary_counts_the_start_as_a_state_not_a_step(tmp_path, capsys):
    out = tmp_path / "one.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-100", "--n", "10", "--max-steps", "1", "-o", str(out)])
    assert code == 0 and "2 states (1 step) from pressure = 0" in capsys.readouterr().out



@pytest.fixture(scope="module")
def crushed():
    """A thick sphere (a/t = 10) pushed to 16 x its classical pressure: past its buckling the wall folds until
    delta = r beta1 cos(psi), the stretch of a circle of the wall, reaches 0 (a limit of the model)."""
    return path(Sphere(h=0.05, nu=0.3, material="svk-plane-stress", law_limit=False), "pressure", 0.0, -2e5, n=12,
                steps=5)  # law_limit: past SVK's compressive turning point, to the fold


def test_a_path_that_reaches_a_model_limit_keeps_its_steps_and_says_where(crushed):
    assert crushed.attrs["status"] == "limit"
    assert "delta = r beta1 cos(psi) reached 0 at s = " in crushed.attrs["message"]
    assert crushed.sizes["step"] > 2 and -2e5 < float(crushed.parameter[-1]) < 0
    assert crushed.point_kind.values[0] in ("limit", "bifurcation")


def test_the_command_exits_3_on_a_path_that_cannot_continue_and_writes_its_steps(crushed, tmp_path, capsys,
                                                                                monkeypatch):
    monkeypatch.setattr("mol_shell.cli.path.path", lambda *args, **kwargs: crushed)
    out = tmp_path / "crushed.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-2e5", "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 3
    assert err.splitlines()[0].startswith("mol-shell: path stopped: the path cannot continue") and "reached 0" in err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "limit" and ds.sizes["step"] == crushed.sizes["step"]


def test_the_path_equations_are_the_dynamics_at_rest_and_exactly_linear_in_the_load():
    """F(q, lambda) equals the momentum rates of the scene built with the load at lambda (the graph runs use), and
    dF/dlambda is the unit load's force, exact: F(q, l2) - F(q, l1) = (l2 - l1) dF/dlambda to round-off."""
    scene = sphere(0.02)
    eq = EquilibriumEquations(scene, "pressure", 10)
    q = eq.unknowns(eq.y_ref) * (1 + 0.01 * np.random.default_rng(3).standard_normal(eq.size))
    lam = -123.0
    F, Fq, g = eq.evaluate(q, lam)
    loaded = ShellSystem(Sphere(a=A, h=0.02, E=E, nu=NU, material="svk-plane-stress", pressure=lam), 10)
    y = np.zeros(loaded.size)
    y[: eq.y_ref.size] = eq.state(q)[: eq.y_ref.size]
    rates = np.array(loaded.rhs_newton(0, y)).ravel()[eq.p_idx]
    scale = np.abs(rates).max()
    assert np.abs(F - rates).max() <= 1e-12 * scale
    F2 = eq.evaluate(q, lam + 50.0)[0]
    assert np.abs(F2 - F - 50.0 * g).max() <= 1e-12 * scale
    # and dF/dq is the Jacobian of F: a directional difference agrees to second order
    dq = 1e-6 * np.random.default_rng(4).standard_normal(eq.size)
    assert np.abs(eq.evaluate(q + dq, lam)[0] - eq.evaluate(q - dq, lam)[0] - 2 * Fq @ dq).max() <= 1e-6 * np.abs(
        2 * Fq @ dq).max()
