"""Small tensor helpers of the stresses (nested 3x3 tuples of floats or CasADi scalars, or NumPy arrays)."""

from __future__ import annotations

import numpy as np


def matmul(A, B):
    """Product of nested 3x3 tuples."""
    return tuple(tuple(sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def transpose(A):
    return tuple(tuple(A[j][i] for j in range(3)) for i in range(3))


def det3(A):
    return (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0])
            + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]))


def cauchy_stress(F, S):
    """``sigma = F S F^T / det F`` (components in the deformed ``b`` basis; ``F`` from ``b0`` to ``b``)."""
    J = det3(F)
    P = matmul(matmul(F, S), transpose(F))
    return tuple(tuple(P[i][j] / J for j in range(3)) for i in range(3))


def thickness_stretched(F, stretch):
    """``F`` with its director column (index 1) multiplied by ``stretch`` (a law's thickness stretch)."""
    return tuple(tuple(F[i][j] * stretch if j == 1 else F[i][j] for j in range(3)) for i in range(3))


def von_mises(sigma):
    """``sqrt(((s11 - s22)^2 + (s22 - s33)^2 + (s33 - s11)^2)/2 + 3 (s12^2 + s23^2 + s13^2))``.

    ``sigma`` as nested 3x3 tuples, or an array ``(..., 3, 3)``.
    """
    if isinstance(sigma, np.ndarray):
        sigma = [[sigma[..., i, j] for j in range(3)] for i in range(3)]
    s = sigma
    value = (((s[0][0] - s[1][1]) ** 2 + (s[1][1] - s[2][2]) ** 2 + (s[2][2] - s[0][0]) ** 2) / 2
             + 3 * (s[0][1] ** 2 + s[1][2] ** 2 + s[0][2] ** 2))
    return np.sqrt(value) if isinstance(value, np.ndarray) else value**0.5


def principal_stresses(sigma):
    """Principal values of symmetric ``sigma`` of shape ``(..., 3, 3)``, in decreasing order along the last axis."""
    return np.linalg.eigvalsh(np.asarray(sigma))[..., ::-1]
