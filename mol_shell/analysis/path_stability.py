"""Stability along an equilibrium path: the spectrum of the tangent stiffness with the rigid motions projected out,
the sign of its determinant, and the family of a mode."""

from __future__ import annotations

import numpy as np

#: eigenvalues computed nearest zero at each step
EIGENVALUES = 6
#: critical points are located to this width of the bracket: this fraction of ``|stop - start|`` in the load for a
#: bifurcation, this much of the scaled arclength for a limit point
LOCATE_RTOL = 1e-7
#: secant iterations per critical point
LOCATE_ITER = 30
#: Newton iterations allowed to the corrector of a trial point there, and its tolerance: the bordered matrix is
#: singular at a bifurcation, and near one Newton converges slowly to a residual that stalls above the path's
#: tolerance (the eigenvalues at the trial point move by the residual's order only)
LOCATE_NEWTON = 20
LOCATE_TOL = 1e-9
#: a trial of a bifurcation whose crossing eigenvalue is within this share of its values at the bracket's ends
#: leaves the round-off along its mode out of the next trial's Newton steps (:func:`deflation`)
DEFLATE = 1e-2


def stability(eq, q, lam, count=EIGENVALUES):
    """``(w2, phi, negative, det_sign)``: the ``count`` eigenvalues ``omega^2`` of ``K phi = omega^2 M phi``
    nearest zero (ascending) on the free coordinates with the rigid motions projected out, their vectors, how many
    eigenvalues are negative, and the sign of ``det K`` with the gauge's coordinates held (``K = -F_q``).

    Shift-invert about a small negative shift with the operator projected M-orthogonally to the rigid motions,
    which then have no eigenvalue at all (they are exact null vectors of ``K`` at an equilibrium).
    """
    import scipy.sparse.linalg

    _, Fq, _ = eq.evaluate(q, lam)
    K = (-(Fq + Fq.T) / 2).tocsc()
    M = eq.mass(q)
    reduced = K.tocsr()[eq.keep][:, eq.keep].tocsc()
    lu = scipy.sparse.linalg.splu(reduced)
    sign = int(np.prod(np.sign(lu.U.diagonal()))) * _parity(lu.perm_r) * _parity(lu.perm_c)
    shift = -1e-9 * float(np.abs(K.diagonal()).max() / np.abs(M.diagonal()).max())
    shifted = scipy.sparse.linalg.splu((K - shift * M).tocsc())
    R = eq.rigid_vectors
    MR = M @ R
    gram = R.T @ MR

    def project(x):
        return x - R @ np.linalg.solve(gram, MR.T @ x) if R.shape[1] else x

    size = eq.size - R.shape[1]
    op = scipy.sparse.linalg.LinearOperator(K.shape, matvec=lambda b: project(shifted.solve(np.ravel(b))),
                                            dtype=float)
    v0 = project(np.random.default_rng(0).standard_normal(eq.size))
    k = min(count, size - 2)
    while True:
        w2, phi = scipy.sparse.linalg.eigsh(K, k=k, M=M, sigma=shift, which="LM", OPinv=op, v0=v0)
        order = np.argsort(w2)
        w2, phi = w2[order], phi[:, order]
        negative = int(np.sum(w2 < 0))
        if negative < k or k >= size - 2:
            return w2[:count], phi[:, :count], negative, sign
        k = min(2 * k, size - 2)


def deflation(eq, q, phi):
    """``(v, w)`` on the unknowns Newton solves for (``eq.keep``): a step ``d`` less ``v (w . d) / (w . v)`` has no
    component along the critical mode ``phi`` at state ``q``, in its mass metric (``w = (M phi)`` there).

    ``v`` is ``phi`` plus the rigid motions that zero its gauge-held coordinates (so a step keeps them put), ``w`` is
    M-orthogonal to the rigid motions: a step of a symmetric state, whose mode ``phi`` breaks the symmetry, is left as
    it is (a rigid part included), and only the round-off along ``phi`` is taken out, which the solve with the nearly
    singular stiffness amplifies near a bifurcation (:meth:`~mol_shell.analysis.path._Path.at_load`)."""
    w = eq.mass(q) @ phi
    v = phi.copy()
    held = np.setdiff1d(np.arange(eq.size), eq.keep)
    R = eq.rigid_vectors
    if held.size:
        v = v - R @ np.linalg.lstsq(R[held], phi[held], rcond=None)[0]
    return v[eq.keep], w[eq.keep]


def _parity(perm):
    """``+1`` or ``-1``: the sign of a permutation (from its cycles)."""
    perm = np.asarray(perm)
    seen = np.zeros(len(perm), dtype=bool)
    sign = 1
    for i in range(len(perm)):
        if not seen[i]:
            j, length = i, 0
            while not seen[j]:
                seen[j] = True
                j = perm[j]
                length += 1
            if length % 2 == 0:
                sign = -sign
    return sign


def family(eq, q, phi):
    """``axisymmetric`` or ``torsional``: which motion carries most of mode ``phi``'s kinetic energy."""
    M = eq.mass(q)
    Mphi = M @ phi
    local = (eq.q_idx % eq.ny)
    chi = np.array(eq.system.active)[local] == 2
    share = float(np.sum(phi[chi] * Mphi[chi]) / np.dot(phi, Mphi))
    return ("torsional" if share > 0.5 else "axisymmetric"), share
