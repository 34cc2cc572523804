"""The static equilibrium a run with ``R`` = auto or ``dilation`` = auto starts from (:mod:`mol_shell.runs.statics`):
sparse Newton, linear memory, the same state as the dense minimum-norm Newton it replaced.

The reference here is that dense Newton, written out in the test (NumPy ``lstsq`` of the dense Jacobian, whose
minimum-norm steps leave a free shell's rigid axial translation where it was): at small ``n`` the sparse Newton,
which holds one ``z`` while it iterates and shifts the result back to the starting mean ``z``, must give the same
state to round-off. At ``n = 4001`` a dense Jacobian of the free coordinates would take ``(5 n)^2 x 8`` bytes =
3.2 GB; the sparse Newton's Python-side peak must stay far below that.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from mol_shell import Cone, Sphere
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.statics import newton


def dense_minimum_norm_newton(system, y0, tol=1e-11):
    """Newton with dense minimum-norm least-squares steps (chi held), halved until the residual falls."""
    y = np.array(y0, dtype=float)
    fixed = system.fixed[:, list(system.active)]
    q = np.array([system.ny * i + j for i in range(system.n) for j, k in enumerate(system.active)
                  if not fixed[i, j] and k != 2])
    p = q + system.nf
    scale = None
    for _ in range(40):
        f = np.array(system.rhs_newton(0, y)).ravel()[p]
        J = np.array(system.jac(0, y))[np.ix_(p, q)]
        scale = scale or float(np.abs(np.diag(J)).max())
        if np.abs(f).max() <= tol * scale:
            return y
        step = np.linalg.lstsq(J, -f, rcond=None)[0]
        for _ in range(20):
            trial = y.copy()
            trial[q] += step
            if np.abs(np.array(system.rhs_newton(0, trial)).ravel()[p]).max() < np.abs(f).max():
                break
            step /= 2
        y = trial
    raise AssertionError("the dense reference did not converge")


@pytest.mark.parametrize("scene", [
    Sphere(h=0.02, nu=0.3, material="svk-plane-stress", pressure=2000.0),  # free to translate axially
    Cone(end1="clamped", end2="free", gravity=9.81, nu=0.3),  # held by its clamped edge
], ids=["closed-sphere-pressure", "clamped-cone-gravity"])
def test_sparse_newton_gives_the_dense_minimum_norm_state(scene):
    system = ShellSystem(scene, 12)
    y0 = system.initial_state(scene)
    y, iterations, residual = newton(system, y0)
    reference = dense_minimum_norm_newton(system, y0)
    fields, expected = system.unpack(y), system.unpack(reference)
    assert residual <= 1e-11 and iterations > 0
    assert np.abs(fields - expected).max() <= 1e-9 * np.abs(expected[:2]).max()


def test_static_equilibrium_at_n_4001_in_linear_memory():
    scene = Sphere(h=0.02, nu=0.3, material="svk-plane-stress", pressure=2000.0)
    system = ShellSystem(scene, 4001)
    y0 = system.initial_state(scene)
    tracemalloc.start()
    try:
        y, _, residual = newton(system, y0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert residual <= 1e-11
    assert peak < 0.05 * (5 * system.n) ** 2 * 8  # measured 45 MB; a dense Jacobian alone: 3.2 GB
    z, r = system.unpack(y)[:2]
    z0 = system.unpack(y0)[0]
    assert np.mean(z) == pytest.approx(np.mean(z0), abs=1e-12)  # the rigid translation left where it was
    radius = np.hypot(r, z - np.mean(z))
    # a sphere, inflated: uniform to the discretisation near the poles, O(ds^2 / a^2) = 6e-7
    assert radius.std() <= 1e-7 * radius.mean() and radius.mean() > 1.0
