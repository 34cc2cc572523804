"""The matrices of :func:`~mol_shell.analysis.modes.modes`: the mass matrix from its inverse block by block, and the
unshearable scene's constraint applied to the eigenproblem.

The unshearable scene (section 4; :mod:`mol_shell.runs.unshearable`) imposes ``chi_s = 0`` and ``psi = 0``, linear
constraints ``G q = 0`` on the free coordinates. Its modes are those of the constrained Lagrangian: with ``q = Z u``,
``Z`` a basis of the null space of ``G``, stationarity of ``L = u_t' Z'MZ u_t / 2 - u' Z'KZ u / 2`` gives
``Z'KZ u = omega^2 Z'MZ u`` (the multipliers do no work on ``q = Z u``; at a state at rest they vanish, so ``K`` is the
free shell's). ``chi_s = 0`` leaves one ``chi`` for the whole shell, the same at every node: the rigid spin when no edge
holds ``chi``, none (``chi = 0``) when one does; ``psi = 0`` leaves no ``psi``; ``z``, ``r`` and ``theta`` keep every
free coordinate. The free shell's torsional modes (``omega = k pi c / L``, ``c = sqrt(mu / rho)``) and its shear modes in
``psi`` are not among the constrained ones; the rest keep their frequencies where they do not couple with ``chi`` or
``psi`` (every axisymmetric state at rest without a twist: its breathing, bending and axial modes).
"""

from __future__ import annotations

import numpy as np

from mol_shell.runs.statics import rigid_motions

#: the largest block :func:`block_inverse` inverts densely
BLOCK_MAX = 64

#: ``attrs["constraint"]`` of the unshearable scene's modes, and the words its title ends with
CONSTRAINED = ("chi_s = 0 and psi = 0 imposed (the unshearable shell, the DAE its ida runs): the modes of the "
               "constrained shell, without the free shell's torsional and shear modes")
TITLE_NOTE = " (constrained: chi_s = 0, psi = 0)"


def block_inverse(A):
    """The inverse of the sparse matrix ``A`` (CSC) block by block: its blocks are the connected components of its
    pattern (a node's own coordinates for the inverse mass matrix, which couples no two nodes), each inverted
    densely. ``scipy.sparse.linalg.inv`` solved for every column of the identity: 15 s at n = 3,000 and quadratic
    in n beyond (minutes at n = 30,000, silent); this is linear."""
    import scipy.sparse  # optional heavy dependency: 0.17 s of every process's start at module level
    import scipy.sparse.csgraph
    import scipy.sparse.linalg

    _, label = scipy.sparse.csgraph.connected_components(A, directed=False)
    sizes = np.bincount(label)
    if sizes.max() > BLOCK_MAX:  # coupled beyond a node's few coordinates (no scene's mass matrix is): column by column
        return scipy.sparse.csc_matrix(scipy.sparse.linalg.inv(A.tocsc()))
    order = np.argsort(label, kind="stable")
    starts = np.concatenate([[0], np.cumsum(sizes)])
    csr, rows, cols, values = A.tocsr(), [], [], []
    for m in np.unique(sizes):  # the blocks of one size at once (a node's free coordinates: a few sizes)
        first = starts[:-1][sizes == m]
        idx = order[first[:, None] + np.arange(m)]  # (blocks, m)
        r, c = np.broadcast_arrays(idx[:, :, None], idx[:, None, :])
        block = np.asarray(csr[r.ravel(), c.ravel()]).reshape(len(idx), m, m)
        rows.append(r.ravel())
        cols.append(c.ravel())
        values.append(np.linalg.inv(block).ravel())
    return scipy.sparse.csc_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                                   shape=A.shape)


def constraint_basis(scene, system, q_idx):
    """``Z`` (sparse, ``(len(q_idx), m)``): a basis of the free coordinates ``q_idx`` that keeps the constraints of
    ``scene`` (the unshearable scene's ``chi_s = 0``, ``psi = 0``), or ``None`` for a scene without constraints. Its
    columns have 0/1 entries on disjoint coordinates: one per free ``z``, ``r``, ``theta``; one on every free ``chi``
    where the spin is a rigid motion (:func:`~mol_shell.runs.statics.rigid_motions`), none where an edge holds ``chi``
    (all of them then stay 0); none for ``psi``."""
    import scipy.sparse  # optional heavy dependency: 0.17 s of every process's start at module level

    if not getattr(scene, "own_formulation", False):
        return None
    fields = np.array(system.active)[np.asarray(q_idx) % system.ny]
    single = np.flatnonzero(np.isin(fields, (0, 1, 3)))
    rows, cols = list(single), list(range(len(single)))
    if 2 in rigid_motions(system).values():
        chi = np.flatnonzero(fields == 2)
        rows += list(chi)
        cols += [len(single)] * len(chi)
    return scipy.sparse.csc_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(q_idx), max(cols, default=-1) + 1))


def constrained_pairs(solve, K, M, basis, rigid=None):
    """``(w2, phi)`` of ``solve(K, M)`` (or ``solve(K, M, rigid)``), on the null space ``basis`` of the constraints
    when one is given (:func:`constraint_basis`): ``solve(Z'KZ, Z'MZ[, rigid in Z's coordinates])``, its shapes
    ``Z u`` on the free coordinates (``M``-orthonormal where ``u`` is ``Z'MZ``-orthonormal)."""
    extra = () if rigid is None else (rigid,)
    if basis is None:
        return solve(K, M, *extra)
    Z = basis.toarray() if isinstance(K, np.ndarray) else basis
    Kr, Mr = Z.T @ K @ Z, Z.T @ M @ Z
    if rigid is not None:  # Z's columns are 0/1 on disjoint coordinates: the rigid motions' coordinates in it
        extra = ((basis.T @ rigid) / np.asarray(basis.sum(axis=0)).ravel()[:, None],)
    w2, u = solve(Kr if isinstance(K, np.ndarray) else Kr.tocsc(), Mr if isinstance(M, np.ndarray) else Mr.tocsc(),
                  *extra)
    return w2, np.asarray(basis @ u)


def constrained_size(size, basis):
    """The number of coordinates the modes are solved for: ``size`` free ones, or the constraints' null space's."""
    return size if basis is None else basis.shape[1]


def labelled(ds, basis):
    """``ds`` (modes) saying, in its title and ``attrs["constraint"]``, that the constraints were imposed."""
    if basis is not None:
        ds.attrs["title"] += TITLE_NOTE
        ds.attrs["constraint"] = CONSTRAINED
    return ds


__all__ = ["BLOCK_MAX", "CONSTRAINED", "TITLE_NOTE", "block_inverse", "constrained_pairs", "constrained_size",
           "constraint_basis", "labelled"]
