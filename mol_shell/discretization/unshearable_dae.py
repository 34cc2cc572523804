"""The azimuthally unshearable shell (section 4) discretised as a DAE with Lagrange multipliers.

The constraints (4.1), ``chi_s = 0`` and ``psi = 0``, are imposed on the same discrete Lagrangian as
:class:`~mol_shell.discretization.system.ShellSystem` (its cell kernel for the stored energy, the model's kinetic
energy density lumped at nodes); the residual in ``(q, v, lambda_chi, lambda_psi)``, its exact Jacobians and
consistent initial values are here. The physics and the run: :mod:`mol_shell.runs.unshearable`; IDA on it:
:mod:`mol_shell.integrators.constrained`.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF

#: DAE unknowns per node: q (5), v (5), lambda_chi of the cell to the right (a dummy at the last node), lambda_psi
NODE = 12


class UnshearableDAE:
    """Residual, Jacobians and consistent initial values of the constrained system.

    Parameters
    ----------
    shell : ShellSystem
        The unconstrained discretisation of the same scene (all five fields): its cell
        (and viscous) kernels, weights, inertias and end conditions are reused.
    """

    def __init__(self, shell):
        if shell.nf != NF:
            raise ValueError("the unshearable DAE needs a ShellSystem with all five fields")
        self.shell, self.n = shell, shell.n
        self.size = NODE * self.n
        n, c = self.n, 2 * math.pi * shell.r0
        y, yp = ca.SX.sym("y", self.size), ca.SX.sym("yp", self.size)
        Y, YP = ca.reshape(y, NODE, n), ca.reshape(yp, NODE, n)
        Q, V, Lc, Lp = Y[:5, :], Y[5:10, :], Y[10, : n - 1], Y[11, :]
        Qp, Vp = YP[:5, :], YP[5:10, :]
        inertial = self._node_kernel().map(n)(Q, V, Qp, Vp, shell.inertia)
        gl, gr = shell.cell_forces_kernel().map(n - 1)(Q[:, :-1], Q[:, 1:], shell.cell_data)
        pad = ca.SX.zeros(NF, 1)
        generalized = inertial + ca.horzcat(gl, pad) + ca.horzcat(pad, gr)
        if shell.viscous:
            fl, fr, _ = shell.viscous_forces_kernel().map(n - 1)(Q[:, :-1], Q[:, 1:], V[:, :-1], V[:, 1:], shell.cell_data)
            generalized += ca.horzcat(fl, pad) + ca.horzcat(pad, fr)
        zero = ca.SX.zeros(1, 1)
        constraint = ca.SX.zeros(NF, n)
        constraint[2, :] = c * (ca.horzcat(zero, Lc) - ca.horzcat(Lc, zero))
        constraint[4, :] = c * shell.weights[None, :] * Lp
        fixed = ca.DM(shell.fixed.T.astype(float))
        balance = (1 - fixed) * (generalized + constraint) + fixed * Vp
        accel = ca.horzcat((Vp[2, 1:] - Vp[2, :-1]) / shell.ds, Y[10, n - 1])
        res = ca.vec(ca.vertcat(Qp - V, balance, accel, Vp[4, :]))
        self.residual = ca.Function("residual", [y, yp], [res], ["y", "yp"], ["res"])
        Jy, Jyp = ca.jacobian(res, y), ca.jacobian(res, yp)
        self.jacobians = ca.Function("jacobians", [y, yp], [ca.densify(Jy), ca.densify(Jyp)])
        cj = ca.SX.sym("cj")
        iteration = Jy + cj * Jyp  # IDA's iteration matrix dF/dy + cj dF/dyp, sparse
        self.iteration_matrix = ca.Function("iteration_matrix", [y, yp, cj], [iteration])
        pattern = iteration.sparsity()
        self.pattern = (np.array(pattern.row()), np.repeat(np.arange(self.size), np.diff(pattern.colind())))
        self.bandwidth = (int(pattern.bw_lower()), int(pattern.bw_upper()))
        self.algebraic = np.array([NODE * i + k for i in range(n) for k in (10, 11)])

    def _node_kernel(self):
        """``(q, v, q_t, v_t, m) -> d/dt dT/dv - dT/dq`` for the lumped kinetic energy of one node (inertias ``m``)."""
        sh = self.shell
        q, v, qp, vp, m = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("qp", NF), ca.SX.sym("vp", NF), ca.SX.sym("m", 3)
        T = sh.kinetic_energy(ca.vertsplit(q), ca.vertsplit(v), ca.vertsplit(m))
        gv = ca.gradient(T, v)
        rate = ca.jtimes(gv, ca.vertcat(q, v), ca.vertcat(qp, vp))
        return ca.Function("lagrange", [q, v, qp, vp, m], [rate - ca.gradient(T, q)])

    def pack(self, Q, V, Lc=None, Lp=None):
        """DAE vector from fields ``Q``, rates ``V`` (``5 x n``) and multipliers (``n - 1``, ``n``)."""
        n = self.n
        Y = np.zeros((NODE, n))
        Y[:5], Y[5:10] = Q, V
        if Lc is not None:
            Y[10, : n - 1] = Lc
        if Lp is not None:
            Y[11] = Lp
        return Y.T.reshape(-1)

    def unpack(self, y):
        """``(Q, V, lambda_chi, lambda_psi)`` of a stack of DAE vectors ``(..., size)``."""
        Y = np.swapaxes(np.asarray(y).reshape(*np.shape(y)[:-1], self.n, NODE), -1, -2)
        return Y[..., :5, :], Y[..., 5:10, :], Y[..., 10, : self.n - 1], Y[..., 11, :]

    def consistent(self, Q, V):
        """``(y0, yp0)``: accelerations and multipliers solved from the residual (affine in them)."""
        y0, yp0 = self.pack(Q, V), self.pack(V, np.zeros_like(V))
        per_node = np.zeros(NODE, dtype=bool)
        rates, mult = per_node.copy(), per_node.copy()
        rates[5:10], mult[10:] = True, True
        rates, mult = np.tile(rates, self.n), np.tile(mult, self.n)
        rows = rates | mult  # the balance and constraint rows (the q_t - v rows hold already)
        F = np.array(self.residual(y0, yp0)).ravel()
        Jy, Jyp = (np.array(J) for J in self.jacobians(y0, yp0))
        J = np.hstack([Jyp[:, rates], Jy[:, mult]])[rows]
        u = np.linalg.solve(J, -F[rows])
        yp0[rates] = u[: rates.sum()]
        y0[mult] = u[rates.sum():]
        return y0, yp0


__all__ = ["NODE", "UnshearableDAE"]
