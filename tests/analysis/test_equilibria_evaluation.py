"""The path's equations evaluated without CasADi matrices: the same numbers as the DM route, by a second route.

``EquilibriumEquations.evaluate`` reads its outputs from a preallocated buffer and builds SciPy CSC on the
Jacobian's pattern read once; ``mass`` takes the mass matrix's blocks from ``nf`` evaluations of the right-hand
side (the velocities are affine in the momenta). The references: CasADi's own call and sparse conversion
(``DM.sparse()``), and the block ``dq_t/dp`` of the dynamics' exact Jacobian inverted node by node.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse

import mol_shell
from mol_shell import Cone, Sphere, Torus, TwistedCylinder
from mol_shell.analysis.equilibria import EquilibriumEquations

CASES = [
    (Sphere(nu=0.3, material="svk-plane-stress"), "pressure"),  # poles: chi tied, a gauge on z
    (Cone(end1="clamped", end2="free", nu=0.3), "end2_torque"),  # a fixed edge: fewer free coordinates there
    (Torus(nu=0.3), "gravity"),  # rhoI != 0: the director's inertia couples a node's fields
    (TwistedCylinder(gamma=0.0, R=1.0, end1="clamped", end2="clamped", fibre_E=1e6, fibre_angle=0.4), "pressure"),
    # ends driven at a constant spin: at a magnet edge q_t = M^-1 (p - b(end_omega)), affine in p, not linear (the
    # mass from unit momenta alone was off by 2.4e-4 relative at end_omega = 5, 0.28 at 5e4)
    (TwistedCylinder(gamma=0.0, R=1.0, end_omega=500.0), "pressure"),
]


def mass_from_the_jacobian(eq, q):
    """The mass matrix as the inverse of the exact Jacobian's block ``dq_t/dp``, node by node."""
    J = eq.system.jac(0, eq.state(q)).sparse().tocsr()
    Minv = J[eq.q_idx][:, eq.p_idx].toarray()
    node = eq.q_idx // eq.ny
    M = np.zeros((eq.size, eq.size))
    for i in np.unique(node):
        mine = np.flatnonzero(node == i)
        M[np.ix_(mine, mine)] = np.linalg.inv(Minv[np.ix_(mine, mine)])
    assert np.abs(Minv[node[:, None] != node[None, :]]).max(initial=0.0) == 0.0  # block diagonal indeed
    return M


@pytest.mark.parametrize(("scene", "parameter"), CASES, ids=[f"{s.name}-{p}" for s, p in CASES])
def test_mass_and_equations_equal_casadis_own_route(scene, parameter):
    eq = EquilibriumEquations(scene, parameter, 12)
    q = eq.unknowns(eq.y_ref) * (1 + 0.01 * np.sin(np.arange(eq.size)))  # away from the reference state
    expected = mass_from_the_jacobian(eq, q)
    M = eq.mass(q)
    assert scipy.sparse.issparse(M)
    assert np.abs(M.toarray() - expected).max() <= 1e-13 * np.abs(expected).max()
    F, Fq, g = eq.evaluate(q, 3.0)
    F_ref, Fq_ref, g_ref = eq._equations(q, eq.y_ref, 3.0)
    np.testing.assert_array_equal(F, np.array(F_ref).ravel())
    np.testing.assert_array_equal(g, np.array(g_ref).ravel())
    assert (Fq != Fq_ref.sparse()).nnz == 0 and Fq.shape == Fq_ref.shape
    F[:] = np.nan  # the outputs are copies: the next evaluation is not changed through them
    assert np.all(np.isfinite(eq.evaluate(q, 3.0)[0]))


def test_a_structurally_dense_jacobian_is_still_a_matrix():
    """Clamped at both ends with 4 nodes, the equations' Jacobian has no structural zero: it came back as a flat
    array of its entries and the path failed on ``.tocsr()``."""
    scene = TwistedCylinder(gamma=0.0, R=1.0, end1="clamped", end2="clamped")
    eq = EquilibriumEquations(scene, "pressure", 4)
    F, Fq, g = eq.evaluate(eq.unknowns(eq.y_ref), 1.0)
    assert scipy.sparse.issparse(Fq) and Fq.shape == (F.size, F.size) and g.shape == F.shape
    ds = mol_shell.path(scene, "pressure", 0.0, 100.0, n=4, max_steps=5)
    assert ds.attrs["status"] in ("complete", "max_steps") and ds.sizes["step"] > 1
