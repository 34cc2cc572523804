"""The polishing Newton steps of a path (``_Path._polished``) build no Jacobian they do not use.

Each polishing step is kept only when it lowers the residual; after the last one only that residual is compared,
so the tangent stiffness of the last trial state was built for nothing (one sparse Jacobian per corrected point).
The path must stay the same: the reference below is the polishing as it was, Jacobian and all.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg

from mol_shell import Sphere, path
from mol_shell.analysis import path as path_module
from mol_shell.analysis.equilibria import EquilibriumEquations

SCENE = Sphere(nu=0.3, material="svk-plane-stress")


def _polished_building_every_jacobian(self, q, lam, F, Fq, steps=2, along=None):
    """The polishing before the fix: every trial state's ``(F, F_q)``, the last one's ``F_q`` unused (the steps
    without the critical mode ``along``, as the polishing of a locating trial leaves it out)."""
    for _ in range(steps):
        try:
            trial = q + self._full(self._deflated(scipy.sparse.linalg.splu(Fq).solve(-F), along))
        except RuntimeError:
            break
        F_trial, Fq_trial, _ = self.eq.reduced(trial, lam)
        if not (np.all(np.isfinite(F_trial)) and np.abs(F_trial).max() < np.abs(F).max()):
            break
        q, F, Fq = trial, F_trial, Fq_trial
    return q


def _counted_path(monkeypatch):
    """The path through the sphere's first critical point, the number of Jacobians built on the way and, for each
    polishing, its ``steps`` and the Jacobians it built."""
    calls, polishings = [], []
    reduced, polished = EquilibriumEquations.reduced, path_module._Path._polished

    def counting(self, q, lam):
        calls.append(lam)
        return reduced(self, q, lam)

    def polishing(self, q, lam, F, Fq, steps=2, along=None):
        before = len(calls)
        out = polished(self, q, lam, F, Fq, steps=steps, along=along)
        polishings.append((steps, len(calls) - before))
        return out

    monkeypatch.setattr(EquilibriumEquations, "reduced", counting)
    monkeypatch.setattr(path_module._Path, "_polished", polishing)
    ds = path(SCENE, "pressure", 0.0, -260.0, n=10, progress=False)
    return ds, len(calls), polishings


def test_polishing_builds_no_jacobian_after_its_last_step_and_the_path_is_unchanged(monkeypatch):
    ds, jacobians, polishings = _counted_path(monkeypatch)
    assert {steps for steps, _ in polishings} == {1, 2}  # the start's (two steps) and the correctors' (one)
    assert all(built <= steps - 1 for steps, built in polishings), polishings
    with monkeypatch.context() as old:
        old.setattr(path_module._Path, "_polished", _polished_building_every_jacobian)
        ref, ref_jacobians, _ = _counted_path(old)
    assert jacobians < ref_jacobians
    assert ds.sizes == ref.sizes and ds.sizes["point"] == 1
    scale = float(np.abs(ref.smallest_eigenvalues).max())
    np.testing.assert_allclose(ds.parameter, ref.parameter, rtol=1e-9, atol=1e-9 * 260.0)
    np.testing.assert_allclose(ds.r, ref.r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(ds.z, ref.z, rtol=0, atol=1e-9)
    np.testing.assert_allclose(ds.smallest_eigenvalues, ref.smallest_eigenvalues, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(ds.point_parameter, ref.point_parameter, rtol=1e-9)
    np.testing.assert_allclose(ds.point_eigenvalue, ref.point_eigenvalue, rtol=0, atol=1e-9 * scale)
    assert (ds.negative_eigenvalues.values == ref.negative_eigenvalues.values).all()
