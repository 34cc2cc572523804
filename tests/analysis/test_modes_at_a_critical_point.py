"""Modes about a critical point of a closed sphere's path: the rigid motions are taken out exactly.

There the critical mode's ``omega^2`` is zero to round-off, as are the two rigid motions' (axial translation and
spin about the axis: no edge holds a closed sphere), and the eigensolver returns any mix of the three: the spin
was listed as mode 1 at 0 rad/s and the critical mode lost. Independent reference: the path's own critical mode
(``point_mode_*``, from a shift-invert solve projected M-orthogonally to the rigid motions,
:mod:`mol_shell.analysis.path_stability`), against the modes' dense generalised eigenproblem with the rigid
motions deflated; and the critical mode (axisymmetric) carries no twist.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell import Sphere, path
from mol_shell.analysis.modes import modes
from mol_shell.analysis.path_start import path_start


def test_the_first_mode_at_a_bifurcation_is_the_paths_critical_mode_not_a_rigid_motion(tmp_path):
    scene = Sphere(h=0.012517, nu=0.3, material="svk-plane-stress")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = path(scene, "pressure", 0.0, -775.0, n=40)
        ds.to_netcdf(tmp_path / "path.nc")
        start, n, initial, _ = path_start(str(tmp_path / "path.nc"), point=0)
        found = modes(start, n=n, initial=initial)
    assert found.attrs["zero_modes"] == 2
    first = found.isel(mode=0)
    assert abs(float(first.omega_squared)) < 1e-6 * float(found.omega_squared[1])  # critical: zero to round-off
    # the critical mode is axisymmetric: no twist (the spin listed in its place was chi = -1 at every node)
    assert np.abs(first.chi.values).max() < 1e-8 * np.abs(np.concatenate([first.r.values, first.z.values])).max()
    shape = np.concatenate([first.r.values, first.z.values])
    reference = np.concatenate([ds.point_mode_r.values[0], ds.point_mode_z.values[0]])
    cosine = abs(shape @ reference) / (np.linalg.norm(shape) * np.linalg.norm(reference))
    assert cosine > 0.999, cosine


def test_modes_that_are_not_finite_in_double_precision_stop_with_a_reason():
    """rho = 1e-300 (inside rho's range: normal doubles) puts the inertias in the subnormals: `mol-shell modes` wrote
    omega^2 = nan as an "unstable" mode, miscounted the rigid motions and exited 0. It stops now (ModelLimitError, exit
    3 from the command line) saying why; rho = 1e-280 still gives finite modes."""
    from mol_shell._core.errors import ModelLimitError

    with pytest.raises(ModelLimitError, match=r"the modes of n = 11 nodes are not finite in double precision "
                                              r"\(omega\^2 = nan\): the mass matrix \(rho = 1e-300 kg m-3\)"):
        mol_shell.modes(mol_shell.Sphere(rho=1e-300), n=11, count=3)
    ds = mol_shell.modes(mol_shell.Sphere(rho=1e-280), n=11, count=3)
    assert np.isfinite(ds.frequency.values).all() and ds.attrs["zero_modes"] == 2
