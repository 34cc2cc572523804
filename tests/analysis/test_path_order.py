"""The critical points of a path are numbered in the order the path meets them.

A cylinder under axial compression (edges ``end1=z,theta``, ``end2=theta``: the uniform membrane state) unloaded
from beyond its first bifurcations back to 0: its count of negative eigenvalues falls at each, and a path that goes
from a compressive force towards 0 meets them in increasing force (less compression). One step of the path holds two
of them; they were listed by the crossing eigenvalue, ascending, which on the way down is the reverse of the order
met (-1526.1, -1547.5, -1485.8 N at n = 41).
"""

from __future__ import annotations

import warnings

import numpy as np

from mol_shell import path
from mol_shell.scenes import Axisymmetric


def test_an_unloaded_cylinder_lists_its_bifurcations_in_the_order_met():
    cylinder = Axisymmetric(L=1.955, a=1.0, R=1.0, h=0.01, E=1e6, nu=0.3, material="svk-plane-stress",
                            end1="z,theta", end2="theta")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = path(cylinder, "end2_force", -2000.0, 0.0, n=11, steps=10, max_steps=20)
    steps, loads = ds.point_step.values, ds.point_parameter.values
    assert ds.attrs["status"] == "complete" and len(loads) >= 2
    assert len(set(steps)) < len(steps)  # two points in one step: the case the order was wrong in
    assert set(ds.point_kind.values) == {"bifurcation"}
    # met along the path: by step, and within a step in the direction the force moves (towards 0: increasing)
    assert np.all(np.diff(steps) >= 0)
    assert np.all(np.diff(loads) > 0), loads
    # each between the states of its step
    for k, load in zip(steps, loads):
        lo, hi = sorted(ds.parameter.values[k:k + 2])
        assert lo <= load <= hi
