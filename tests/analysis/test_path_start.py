"""Modes and runs from an equilibrium path (:mod:`mol_shell.analysis.path_start`): the prestressed frequencies of a
shallow clamped cap fall to zero at its snap-through limit point as the fold's normal form says.

Derivation of the expected exponent. Near a simple limit point (a fold) of ``F(q, lambda) = 0``, parametrise the
path by its arclength ``s`` from the fold: ``lambda - lambda_c = -c s^2 + O(s^3)`` (``lambda`` turns back), and the
eigenvalue of the tangent stiffness that vanishes there does so linearly, ``mu = mu' s + O(s^2)`` with ``mu' != 0``
(the fold is simple: ``K`` has a simple zero eigenvalue and ``phi . F_lambda != 0``). So
``mu ~ |lambda - lambda_c|^(1/2)``. The lowest prestressed natural frequency is ``omega = sqrt(mu)`` (``K phi =
omega^2 M phi``, ``M`` regular): ``omega^2 ~ |lambda - lambda_c|^(1/2)`` and ``omega ~ |lambda - lambda_c|^(1/4)``.
(At a bifurcation, where ``lambda`` keeps going, ``mu ~ |lambda - lambda_c|`` and ``omega ~ |lambda -
lambda_c|^(1/2)``.) The fit below takes the steps within 5 % of ``p_cl`` of the limit; the next term of the
expansion, ``O(s^2) = O(|lambda - lambda_c|)``, bends the log-log slope by up to a few hundredths there.
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_cap import cap_params, p_classical

import mol_shell
from mol_shell import Sphere, path
from mol_shell.analysis.modes import modes
from mol_shell.analysis.path_start import FLAGS, path_scene, path_start, read_path
from mol_shell.results.dataset import write_netcdf

N = 21
LAMBDA = 5.0


@pytest.fixture(scope="module")
def cap_path():
    """The cap's path from rest through its snap-through limit point (it stops at max_steps past it)."""
    return path(Sphere(**cap_params(LAMBDA)), "pressure", 0.0, -0.7 * p_classical(), n=N, steps=20, max_steps=17)


def test_the_path_stops_at_max_steps_past_the_limit_point(cap_path):
    assert cap_path.attrs["status"] == "max_steps"
    assert "max_steps = 17" in cap_path.attrs["message"] and cap_path.sizes["step"] == 18  # the start and 17 steps
    assert list(cap_path.point_kind.values) == ["limit"] and cap_path.point_located.values[0] == 1


def test_a_step_gives_back_the_scene_and_the_state(cap_path, tmp_path):
    out = tmp_path / "cap.nc"
    write_netcdf(cap_path, out)
    ds = read_path(out)
    scene, n, fields, info = path_start(ds, step=5)
    assert n == N and scene == Sphere(**cap_params(LAMBDA), pressure=float(ds.parameter[5]))
    assert np.array_equal(fields[1], ds.r.values[5]) and "step 5" in info
    scene, _, fields, info = path_start(ds, point=0, perturb=1e-3)
    assert scene.pressure == float(ds.point_parameter[0])
    assert np.allclose(fields[0] - ds.point_z.values[0], 1e-3 * ds.point_mode_z.values[0])
    assert "perturbed by 0.001" in info


@pytest.mark.parametrize("kwargs, name, words, flags", [
    ({"step": 18}, "step", "step = 18 is outside integers 0..17 (the path's steps)",
     "--step = 18 is outside integers 0..17 (the path's steps)"),
    ({"point": 1}, "point", "point = 1 is outside integers 0..0 (the path's critical points)",
     "--point = 1 is outside integers 0..0 (the path's critical points)"),
    ({}, "step", "give one of step=K (a step) or point=K (a critical point)",
     "give one of --step K (a step) or --point K (a critical point) with --from"),
    ({"step": 1, "perturb": 1e-3}, "perturb", ("perturb = 0.001 is outside 0 with step (the critical mode is a "
                                               "point's: use point)"),
     "--perturb = 0.001 is outside 0 with --step (the critical mode is a point's: use --point)"),
])
def test_a_state_out_of_range_is_refused_naming_the_keyword_or_the_commands_flag(cap_path, kwargs, name, words,
                                                                                 flags):
    """From Python the refusals named the command line's flags: ``--step = 999 is outside ...``, ``give one of
    --step K ... with --from``."""
    from mol_shell._core.errors import ParameterError

    with pytest.raises(ParameterError) as exc:
        path_start(cap_path, **kwargs)
    assert exc.value.name == name and str(exc.value) == words
    with pytest.raises(ParameterError) as exc:  # the command line's (mol-shell run/modes --from)
        path_start(cap_path, **kwargs, names=FLAGS)
    assert exc.value.name == "--" + name and str(exc.value) == flags


def test_prestressed_frequency_falls_to_zero_at_the_limit_point_like_the_fold_normal_form(cap_path):
    ds = cap_path
    lam_c = float(ds.point_parameter[0])
    before = np.arange(int(ds.point_step[0]) + 1)
    distance = np.abs(ds.parameter.values[before] - lam_c)
    near = before[distance <= 0.05 * p_classical()]
    assert len(near) >= 3
    omega = []
    for k in near:
        scene, n, fields, _ = path_start(ds, step=int(k))
        omega.append(float(modes(scene, n=n, count=1, initial=fields).frequency[0]))
    omega = np.array(omega)
    # the modes analysis and the path's own stability agree: omega^2 is the path's smallest eigenvalue
    assert np.allclose(omega**2, ds.smallest_eigenvalues.values[near, 0], rtol=1e-6)
    slope_w2 = np.polyfit(np.log(distance[near - before[0]]), np.log(omega**2), 1)[0]
    slope_w = np.polyfit(np.log(distance[near - before[0]]), np.log(omega), 1)[0]
    assert slope_w2 == pytest.approx(0.5, abs=0.05)
    assert slope_w == pytest.approx(0.25, abs=0.025)


def test_the_path_scene_ignores_attrs_that_are_no_parameter(cap_path):
    scene = path_scene(cap_path, -1.0)
    assert scene.pressure == -1.0 and scene.alpha2 == pytest.approx(cap_params(LAMBDA)["alpha2"])


def test_at_a_bifurcation_the_frequency_falls_like_the_square_root():
    """The other kind of critical point: the compressed cylinder of tests/analysis/test_path_cylinder.py, whose path
    before its bifurcation is the uniform membrane state, linear in the load to O(eps). There the eigenvalue that
    crosses zero does so linearly in the load, ``omega^2 = c (lambda_c - lambda) + O((lambda_c - lambda)^2)``: the
    frequency goes like ``|lambda - lambda_c|^(1/2)``. Fitted on steps between 0.9 and 0.995 of the critical force
    (the O((lambda_c - lambda)^2) term bends the slope by a few hundredths over 0.8 .. 0.97);
    ``omega^2`` from the path's eigenvalues, checked against ``modes`` at the step nearest the point."""
    import math

    from mol_shell import Axisymmetric

    E, NU, h = 1.0e6, 0.3, 0.01
    t = 2 * h
    D = E * t**3 / (12 * (1 - NU**2))
    L = 8 * math.pi / (E * t / D) ** 0.25
    scene = Axisymmetric(L=L, a=1.0, R=1.0, h=h, E=E, nu=NU, material="svk-plane-stress", end1="z,theta",
                         end2="theta")
    onset = path(scene, "end2_force", 0.0, -2e3, n=61, steps=10, max_steps=20)
    f_c = float(onset.point_parameter.values.max())  # the least compressive critical force
    ds = path(scene, "end2_force", 0.9 * f_c, 0.995 * f_c, n=61, steps=12)
    assert ds.sizes["point"] == 0 and ds.attrs["status"] == "complete"
    distance = np.abs(ds.parameter.values - f_c)
    w2 = ds.smallest_eigenvalues.values[:, 0]
    slope = np.polyfit(np.log(distance), np.log(np.sqrt(w2)), 1)[0]
    assert slope == pytest.approx(0.5, abs=0.02)
    scene_k, n, fields, _ = path_start(ds, step=ds.sizes["step"] - 1)
    assert float(modes(scene_k, n=n, count=1, initial=fields).frequency[0]) ** 2 == pytest.approx(w2[-1], rel=1e-6)


def test_path_start_takes_the_path_file_too(tmp_path):
    """``path_start("m.nc", step=2)`` was an AttributeError ('str' object has no attribute 'attrs')."""
    import mol_shell
    from mol_shell.analysis.path_start import path_start

    ds = mol_shell.path(mol_shell.Sphere(nu=0.3, material="svk-plane-stress"), "pressure", 0.0, 100.0, n=8,
                        max_steps=3)
    mol_shell.write_netcdf(ds, tmp_path / "m.nc")
    _, n, fields, info = path_start(tmp_path / "m.nc", step=2)
    np.testing.assert_array_equal(fields[1], ds.r.values[2])
    assert n == 8 and info.startswith("equilibrium path step 2")
    with pytest.raises(mol_shell.ParameterError, match="does not exist"):
        path_start(tmp_path / "none.nc", step=2)


@pytest.mark.parametrize("given", ["run", 3, None])
def test_path_start_of_something_else_than_a_path_is_refused_naming_ds(given):
    """``path_start`` of a run's Dataset (simulate's docstring points to it) ended in ``KeyError: 'parameter'``; an
    in-memory Dataset is now checked as a file is."""
    from mol_shell.analysis.path_start import path_start

    if given == "run":
        given = mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=False, stresses=False)
    with pytest.raises(mol_shell.ParameterError, match=r"^ds = '<[\w.]+>' is not an equilibrium path; allowed: the "
                       r"Dataset of mol_shell.path, or its netCDF file"):
        path_start(given, step=0)
