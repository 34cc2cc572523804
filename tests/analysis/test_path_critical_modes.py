"""A path's critical modes: the grid's flagged (``point_grid_mode_share`` and a warning), and a near-miss of an
imperfect bifurcation recorded as a near-critical point (dim ``near``).

Derivation. A thin cylinder (radius ``a``, wall ``t = 2h``) under axial compression from a membrane state buckles
axisymmetrically at the ring stress ``sigma_cl = E t / (a sqrt(3 (1 - nu^2)))``, the uniform axial strain
``eps_cl = sigma_cl / E``, into ``cos(m pi s / L)`` waves of the classical half-wavelength
``l_cl = pi sqrt(a t) / (12 (1 - nu^2))^(1/4)`` (Timoshenko & Gere sec. 11.4; tests/analysis/test_path_cylinder.py
derives it). A mode's grid-mode share (:func:`mol_shell.analysis.grid_modes.grid_mode_share`) is
``(1 - cos k ds) / 2`` for a wave of ``k``: 0.5 at a half-wavelength of two cells, ``(1 - cos(pi / 5)) / 2 = 0.0955``
at five.

* ``L = 4``, ``t = 0.01``: ``l_cl = 0.1728`` m, under one cell of 0.2 m at n = 21: no critical mode the grid finds
  can be the shell's, and its share must be at least 0.5 (the grid's half-wavelength under two cells).
* ``L = 0.35``: ``L / l_cl = 2.03``, the critical mode is ``m = 2`` (``N_m`` within 3e-4 of the classical), half a
  wavelength ``L / 2`` = five cells at n = 11. With edges ``z, theta`` at both ends and the end displaced
  (``end2_dz``) the perfect cylinder bifurcates at ``dz = -eps_cl L``. A wall 0.1 % thicker at mid-length (a bump
  that projects on ``cos(2 pi s / L)``) makes the bifurcation imperfect: under displacement control the lowest
  eigenvalue dips near ``eps_cl L`` and rises again, with no crossing, and the path must say so.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from mol_shell import TwistedCylinder, path
from mol_shell.analysis.equilibria import EquilibriumEquations
from mol_shell.analysis.path import _Path
from mol_shell.analysis.path_stability import stability
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf

E, NU, A, H = 1.0e6, 0.3, 1.0, 0.005
T = 2 * H
EPS_CL = T / (A * math.sqrt(3 * (1 - NU**2)))
L_CL = math.pi * math.sqrt(A * T) / (12 * (1 - NU**2)) ** 0.25


def test_a_critical_mode_the_grid_cannot_hold_is_flagged(tmp_path, capsys):
    cells = 20
    assert L_CL < 4.0 / cells  # the classical half-wavelength is under one cell
    out = tmp_path / "p.nc"
    sets = [x for kv in ("gamma=0", "L=4", f"h={H}", f"nu={NU}", "material=svk-plane-stress", "end1=z,theta",
                         "end2=theta") for x in ("--set", kv)]
    assert main(["path", "twisted-cylinder", "--param", "end2_force=0:-400", "--n", str(cells + 1), *sets,
                 "-o", str(out)]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if "of the grid" in line]
    assert len(err) == 1 and err[0].startswith("mol-shell: warning: critical mode") and "refine n" in err[0]
    ds = read_netcdf(out)
    # the first bifurcation, near the classical load 2 pi a t sigma_cl
    assert ds.point_parameter.values[0] == pytest.approx(-2 * math.pi * A * T * E * EPS_CL, rel=0.03)
    assert ds.point_grid_mode_share.values[0] >= 0.5
    assert "grid_mode_warning" in ds.attrs


def _imperfect_cylinder():
    L = 0.35
    bump = f"table 0:{H} {L / 4}:{H} {L / 2}:{H * 1.001} {3 * L / 4}:{H} {L}:{H}"
    return L, TwistedCylinder(gamma=0.0, L=L, a=A, h=H, E=E, nu=NU, material="svk-plane-stress", end1="z,theta",
                              end2="z,theta", h_profile=bump)


@pytest.fixture(scope="module")
def imperfect():
    L, scene = _imperfect_cylinder()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        ds = path(scene, "end2_dz", 0.0, -1.01 * EPS_CL * L, n=11, progress=False)
    return L, scene, ds, said


def test_an_imperfect_bifurcation_is_a_near_critical_point(imperfect):
    L, _, ds, said = imperfect
    m = round(L / L_CL)
    assert m == 2
    assert ds.attrs["status"] == "complete" and ds.sizes["point"] == 0  # no crossing
    assert ds.sizes["near"] == 1
    assert ds.near_parameter.values[0] == pytest.approx(-EPS_CL * L, rel=0.01)
    assert 0 < ds.near_eigenvalue_share.values[0] < 0.01
    # five cells a half-wavelength: a resolved mode
    assert ds.near_grid_mode_share.values[0] == pytest.approx((1 - math.cos(math.pi / 5)) / 2, abs=0.01)
    assert "grid_mode_warning" not in ds.attrs
    near = [str(w.message) for w in said if "near-critical" in str(w.message)]
    assert len(near) == 1 and "imperfect bifurcation" in near[0] and ds.attrs["near_critical_warning"] == near[0]


def test_a_near_critical_point_is_the_minimum_between_the_steps(imperfect):
    """The near-critical load is where the lowest eigenvalue on the path is least, not the step nearest it.

    The minimum is found here on its own: golden-section search in ``end2_dz`` over ``[0.99, 1.0] eps_cl L`` (the
    perfect cylinder's bifurcation, about 0.996 of it at n = 11, lies inside), each state by Newton at that fixed
    displacement from the scene's reference, its lowest eigenvalue by the path's stability solve. The path's steps
    around the minimum are 1e-4 of it apart: its load must agree with the search's to far better than that."""
    L, scene, ds, _ = imperfect
    eq = EquilibriumEquations(scene, "end2_dz", 11)
    tracer = _Path(eq, 0.0, -1.01 * EPS_CL * L)
    q = tracer.start_equilibrium(eq.unknowns(eq.y_ref), -0.99 * EPS_CL * L)[0]

    def lowest(dz):
        return stability(eq, tracer.equilibrium(q.copy(), dz)[0], dz)[0][0]

    gold = (math.sqrt(5) - 1) / 2
    a, b = -0.99 * EPS_CL * L, -1.0 * EPS_CL * L
    x1, x2 = b - gold * (b - a), a + gold * (b - a)
    f1, f2 = lowest(x1), lowest(x2)
    while abs(b - a) > 1e-7 * EPS_CL * L:
        if f1 < f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - gold * (b - a)
            f1 = lowest(x1)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + gold * (b - a)
            f2 = lowest(x2)
    least = (a + b) / 2
    step = int(ds.near_step.values[0])
    assert abs(float(ds.parameter[step]) - least) > 1e-5 * EPS_CL * L  # the step itself is not the minimum
    assert ds.near_located.values[0] == 1
    assert ds.near_parameter.values[0] == pytest.approx(least, rel=2e-6)
    assert ds.near_eigenvalue.values[0] == pytest.approx(min(f1, f2), rel=1e-6)
    assert ds.near_eigenvalue.values[0] < ds.smallest_eigenvalues.values[step, 0]


def test_the_search_between_steps_keeps_a_minimum_its_last_allowed_trial_closes_on(monkeypatch):
    """A V-shaped eigenvalue (no parabola helps: golden sections only) on steps 0.3, 0.5, 0.7 closes its bracket to
    LOCATE_RTOL on the 18th trial: with 18 trials allowed that minimum is located, not thrown away for the step's."""
    from types import SimpleNamespace

    from mol_shell.analysis import path_modes

    def eigen(load):
        return 1.0 + abs(load - 0.5123)

    trials = []

    def stability(eq, q, load):
        trials.append(load)
        return np.array([eigen(load), 1e9]), np.eye(2), 0, 1

    class Failed(Exception):
        pass

    loads = [0.3, 0.5, 0.7]
    record = SimpleNamespace(eq=None, lams=loads, qs=[np.array([x]) for x in loads], tls=[1.0] * 3,
                             eigen=[np.array([eigen(x)]) for x in loads], det_sign=[1] * 3,
                             tracer=SimpleNamespace(l_scale=1.0), failed=Failed,
                             state_at=lambda x, *_: np.array([x]))
    monkeypatch.setattr(path_modes, "stability", stability)
    found = {}
    for allowed in (17, 18):
        monkeypatch.setattr(path_modes, "LOCATE_ITER", allowed)
        trials.clear()
        load, _, _, _, located = path_modes.least_eigenvalue(record, 1, 0)
        found[allowed] = (load, located, len(trials) - 1)  # the first call: the step's own spectrum
    assert found[17][:2] == (0.5, False) and found[17][2] == 17
    assert found[18][1] and abs(found[18][0] - 0.5123) < 2 * path_modes.LOCATE_RTOL and found[18][2] == 18
