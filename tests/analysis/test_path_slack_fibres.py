"""A path from the natural state of tension-only fibres: the tangent there is not the path's, a secant starts it.

Tension-only fibres store ``(E_f / 2) max(a.E a, 0)^2``: the force is continuous, the stiffness jumps at zero fibre
strain, where every fibre of the natural state sits. The tangent stiffness there is neither one-sided one, and the
first step's corrector converged away from its predictor at every step size: 0 steps, "the corrector left the
predictor's neighbourhood", in either load direction (:mod:`mol_shell.analysis.path_secant`).

Expected states from a second route: the static equilibrium a run computes under the same constant pressure
(``runs.statics.static_equilibrium``: Newton on the dynamics' exact Jacobian from the natural state, with
continuation in the load), at the path's last load (``stop``, which the last step lands on exactly) and at an
intermediate step's. The static solve holds the mean ``z`` where the path gauges one node's ``z``: ``z`` is
compared less its mean.
"""

from __future__ import annotations

import numpy as np
import pytest

from mol_shell import Sphere, build, path
from mol_shell.runs.statics import static_equilibrium

N = 8
FIBRES = {"material": "svk-plane-stress", "nu": 0.3, "fibre_E": 1e6, "fibre_compression": False}


def static_fields(pressure):
    scene = Sphere(**FIBRES, pressure=pressure)
    system, _ = build(scene, N)
    y, _ = static_equilibrium(scene, N, system.initial_state(scene))
    return system.unpack(y)


@pytest.fixture(scope="module")
def inflated():
    return path(Sphere(**FIBRES), "pressure", 0.0, 100.0, n=N, max_steps=40)


def test_the_path_leaves_the_natural_state_and_reaches_stop(inflated):
    assert inflated.attrs["status"] == "complete" and float(inflated.parameter[-1]) == 100.0
    assert np.all(np.diff(inflated.parameter.values) > 0)


@pytest.mark.parametrize("which", [-1, 3])
def test_the_path_states_are_the_static_equilibria_under_the_same_pressure(inflated, which):
    pressure = float(inflated.parameter[which])
    expected = static_fields(pressure)
    got = np.stack([inflated[f].values[which] for f in ("z", "r", "chi", "theta", "psi")])
    growth = np.abs(got[1] - inflated.r.values[0]).max()
    assert growth > 1e-4  # the sphere did inflate
    assert np.allclose(got[1], expected[1], rtol=0, atol=1e-6 * growth)
    assert np.allclose(got[3], expected[3], rtol=0, atol=1e-6)
    assert np.allclose(got[0] - got[0].mean(), expected[0] - expected[0].mean(), rtol=0, atol=1e-6 * growth)


def test_under_deflation_too():
    ds = path(Sphere(**FIBRES), "pressure", 0.0, -50.0, n=N, max_steps=40)
    assert ds.attrs["status"] == "complete"
    expected = static_fields(-50.0)
    assert np.allclose(ds.r.values[-1], expected[1], rtol=0, atol=1e-9)
