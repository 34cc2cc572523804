"""Eigenvalues crossing zero in one step beyond the six nearest zero a step keeps: an axially crushed cylinder at
n = 12 goes from 5 to 11 negative eigenvalues in one step. Locating the seventh of them read past the stored six and
ended the path with an internal IndexError, the steps traced lost (also `sphere` at -1e5 Pa and a clamped cap);
the spectrum is now computed again at both ends of such a step, with as many eigenvalues as cross."""

import numpy as np

import mol_shell


def test_a_step_where_six_eigenvalues_cross_gives_six_points():
    ds = mol_shell.path(mol_shell.Axisymmetric(), "end2_dz", 0.0, -2.0, n=12, progress=False)
    negative = ds.negative_eigenvalues.values
    jumps = np.flatnonzero((negative[1:] != negative[:-1]) & (np.maximum(negative[1:], negative[:-1]) > 6))
    assert jumps.size, negative  # the case still has such a step
    k = int(jumps[0])
    at = ds.point_step.values == k
    assert at.sum() == abs(int(negative[k + 1]) - int(negative[k]))  # one point per crossing eigenvalue
    loads = ds.point_parameter.values[at]
    low, high = sorted((float(ds.parameter.values[k]), float(ds.parameter.values[k + 1])))
    assert np.all((low <= loads) & (loads <= high))  # each inside its step
    assert ds.attrs["status"] in ("limit", "complete", "failed")  # the path ends as a path, with its steps kept
