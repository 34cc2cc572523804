"""A symbolic solve for the small symmetric positive-definite mass matrices of the node kernels.

``casadi.solve`` on an SX matrix builds a sparse QR factorisation (square roots and many divisions): for the
5 x 5 mass matrix of a shell node it made the node kernel cost as much as a cell's elastic forces. The mass
matrix of the Hamiltonian form is symmetric positive definite, so an LDL^T factorisation without pivoting is
exact and needs one reciprocal per row. Rows are eliminated in increasing order of their coupling (a
minimum-degree order on the structural non-zeros), so decoupled rates (``z``, ``r``; ``psi`` and ``theta``,
coupled only through ``chi``) cost one multiplication and fill-in never appears on the shell's matrices.
"""

from __future__ import annotations

import casadi as ca


def spd_solve(M, b):
    """``M^-1 b`` for a symmetric positive-definite ``casadi.SX`` matrix ``M`` (``k x k``) and ``b`` (``k x 1``).

    LDL^T without pivoting in a minimum-degree order, skipping structural zeros: the same solution as
    ``casadi.solve`` up to round-off, with ``k`` reciprocals and no square roots.
    """
    k = M.size1()
    M = ca.SX(M)
    entry = [[M[i, j] for j in range(k)] for i in range(k)]
    nonzero = [[not entry[i][j].is_zero() for j in range(k)] for i in range(k)]
    order = sorted(range(k), key=lambda i: sum(nonzero[i]))
    A = [[entry[i][j] for j in order] for i in order]
    rhs = [b[i] for i in order]
    nz = [[nonzero[i][j] for j in order] for i in order]
    # factor: A = L D L^T, column by column (L unit lower triangular)
    L = [[None] * k for _ in range(k)]
    inv_d = [None] * k
    d = [None] * k
    for j in range(k):
        dj = A[j][j]
        for m in range(j):
            if nz[j][m]:
                dj = dj - L[j][m] * L[j][m] * d[m]
        d[j], inv_d[j] = dj, 1 / dj
        for i in range(j + 1, k):
            lij = A[i][j] if nz[i][j] else 0
            for m in range(j):
                if nz[i][m] and nz[j][m]:
                    lij = lij - L[i][m] * L[j][m] * d[m]
            fill = not (isinstance(lij, (int, float)) or ca.SX(lij).is_zero())
            nz[i][j] = nz[j][i] = fill
            L[i][j] = lij * inv_d[j] if fill else 0
    # solve L y = rhs, D w = y, L^T x = w
    y = list(rhs)
    for i in range(k):
        for m in range(i):
            if nz[i][m]:
                y[i] = y[i] - L[i][m] * y[m]
    x = [y[i] * inv_d[i] for i in range(k)]
    for i in reversed(range(k)):
        for m in range(i + 1, k):
            if nz[m][i]:
                x[i] = x[i] - L[m][i] * x[m]
    out = [None] * k
    for pos, i in enumerate(order):
        out[i] = x[pos]
    return ca.vertcat(*out)
