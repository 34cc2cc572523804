"""The sphere's first critical point, located on the path from start whatever the steps that bracket it.

A closed sphere under external pressure (``a/t = 40``, the ``l = 11`` sphere of test_path.py) at ``n = 50``: its
symmetric (fundamental) branch loses stability once before its fold, where the lowest eigenvalue of the stiffness
crosses zero (the count of negative eigenvalues goes 0 -> 1; the mode breaks the symmetry about the equator). With
``steps = 10`` the path put that point at 0.97352 ``p_cl``, located, and with ``steps = 20`` at 0.97615 (at
``n = 60``: 0.97143 and 0.97204, and 0.97019 traced back from -1.02 ``p_cl``). The steps of ``steps = 10`` bracket it
between 0.88 ``p_cl`` and the stop, which the last step reaches past the fold (0.9831 ``p_cl``), on another branch:
the secant's trial states started from the chord between the two states, whose residual was below the locating tolerance
already, and were taken as they were (at ``n = 60``: a residual of 2e-10 of a unit strain's force, 4e-4 rad off the
branch where the shell is soft, the lowest eigenvalue 1 s-2 off of 540 unloaded), so the secant closed on a zero of
the chord's, 2.6e-3 ``p_cl`` before the branch's. A trial takes a Newton step now, whatever its residual.

Expected value, derived independently of the path's continuation and locating: the fundamental branch by Newton at
fixed pressure from the unloaded sphere (in increments of ``p_cl / 20`` to 0.95 ``p_cl``, then ``1e-3 p_cl``), each
state by full Newton steps to round-off (the iterate of least residual); the lowest eigenvalue of the pencil
``(K, M)`` with the gauge's coordinate held, by a dense solver; its zero bracketed by that scan and bisected to
``1e-9 p_cl``. Holding one coordinate removes the rigid translation (an exact null vector of ``K``) instead of
projecting it out: by Cauchy's interlacing the held pencil has as many negative eigenvalues as ``K`` has, so its
lowest crosses zero where the path's does. Each path locates to ``LOCATE_RTOL`` of its range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

from mol_shell import Sphere, path
from mol_shell.analysis.equilibria import EquilibriumEquations
from mol_shell.analysis.path_stability import LOCATE_RTOL

E, NU, N = 1.0e6, 0.3, 50
H = math.sqrt(12 * (1 - NU**2)) / (2 * 11 * 12)  # l = 11: l (l + 1) = (a/t) sqrt(12 (1 - nu^2)), a = 1, t = 2h
P_CL = 2 * E * (2 * H) ** 2 / math.sqrt(3 * (1 - NU**2))  # 758.62 Pa
SCENE = Sphere(h=H, E=E, nu=NU, material="svk-plane-stress")


def _fundamental_zero():
    """The zero of the lowest eigenvalue on the fundamental branch, in units of ``p_cl``."""
    eq = EquilibriumEquations(SCENE, "pressure", N)
    keep = eq.keep

    def newton(q, p):  # full steps, to round-off: the state of least residual, once a step did not lower it
        best = (math.inf, q)
        for _ in range(8):
            F, Fq, _ = eq.reduced(q, p)
            if float(np.abs(F).max()) >= best[0]:
                break
            best = (float(np.abs(F).max()), q)
            step = np.zeros(eq.size)
            step[keep] = scipy.sparse.linalg.splu(Fq).solve(-F)
            q = q + step
        return best[1]

    def advance(q, f0, f1):  # from the state at f0 p_cl to f1 p_cl, predicted along dq/dp
        _, Fq, g = eq.reduced(q, -f0 * P_CL)
        slope = np.zeros(eq.size)
        slope[keep] = scipy.sparse.linalg.splu(Fq).solve(-g)
        return newton(q + slope * (f0 - f1) * P_CL, -f1 * P_CL)

    def lowest(q, f):
        _, Fq, _ = eq.evaluate(q, -f * P_CL)
        K, M = (-(Fq + Fq.T) / 2).toarray()[np.ix_(keep, keep)], eq.mass(q).toarray()[np.ix_(keep, keep)]
        return scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[0, 0])[0]

    q, f = newton(eq.unknowns(eq.y_ref), 0.0), 0.0
    for f1 in np.linspace(0.05, 0.95, 19):
        q, f = advance(q, f, f1), f1
    assert lowest(q, f) > 0
    while True:  # the scan
        q1 = advance(q, f, f + 1e-3)
        if lowest(q1, f + 1e-3) < 0:
            break
        q, f = q1, f + 1e-3
        assert f < 1.0, "no crossing below p_cl"
    a, b = f, f + 1e-3
    while b - a > 1e-9:  # bisection, each state from the stable end
        m = (a + b) / 2
        qm = advance(q, a, m)
        if lowest(qm, m) > 0:
            q, a = qm, m
        else:
            b = m
    return (a + b) / 2


@pytest.fixture(scope="module")
def crossing():
    return _fundamental_zero()


def test_the_sphere_is_the_l_11_sphere():
    assert H == pytest.approx(0.01251721, abs=5e-9) and P_CL == pytest.approx(758.62, abs=0.005)


@pytest.mark.parametrize("start, stop", [(0.0, 1.02), (0.977, 0.9)], ids=["forward", "backward"])
@pytest.mark.parametrize("steps", [10, 20])
def test_the_first_critical_point_is_the_fundamental_branch_s_whatever_the_steps(crossing, start, stop, steps):
    ds = path(SCENE, "pressure", -start * P_CL, -stop * P_CL, n=N, steps=steps, max_steps=15, progress=False)
    assert ds.sizes["point"] >= 1
    if start:  # traced back from a state on the fundamental branch past the point: one unstable direction
        assert int(ds.negative_eigenvalues[0]) == 1 and 0.976 < crossing < start
    assert ds.point_kind.values[0] == "bifurcation" and ds.point_located.values[0] == 1
    width = LOCATE_RTOL * abs(stop - start)
    assert abs(float(ds.point_parameter[0]) / -P_CL - crossing) <= 2 * width + 1e-9, (ds.point_parameter.values, crossing)
    # on the branch, symmetric about the equator, and its mode antisymmetric: no round-off of the nearly singular
    # solves along the mode in the state (it was 9e-8 of the radius; now 3e-12, the mode's 1e-8)
    r, mode = ds.point_r.values[0], ds.point_mode_r.values[0]
    assert np.abs(r - r[::-1]).max() <= 1e-9 * np.abs(r).max()
    assert np.abs(mode + mode[::-1]).max() <= 1e-6 * np.abs(mode).max()
