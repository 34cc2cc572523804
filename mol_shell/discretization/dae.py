"""The semi-discrete shell in linearly implicit form, for IDA: ``F(t, x, x_t) = 0``.

State ``x`` is node-major like the Hamiltonian state of :class:`~mol_shell.discretization.system.ShellSystem`,
with the momenta replaced by the rates: per node the active fields ``q`` then their rates ``v``.
The residual is the balance of momentum as it stands, without inverting the mass matrix:

* ``q_t - v = 0``;
* ``d/dt p(q, v) - dT/dq + dV/dq (+ dD/dv) = M(q) v_t + (dp/dq) q_t - dT/dq + dV/dq (+ dD/dv) = 0``
  with ``p = dT/dv = M(q) v``: Lagrange's equations of the discrete Lagrangian ``T - V``
  (the first-order form of the paper's (6.5)-(6.7)); ``D`` is the Kelvin-Voigt dissipation
  potential (section 3) when the scene is viscous.

``T`` is the lumped kinetic energy built from :func:`~mol_shell.model.kinematics.kinetic_energy_density`
and ``V`` the stored energy of :class:`ShellSystem`; both come from the same cell and node
kernels as the ODE right-hand side (here mapped over the grid, as in ``ShellSystem._build``, so the
graph and its compiled Jacobian stay small whatever ``n``). Imposed fields at the edges
(:mod:`mol_shell.model.edges`) have the rows ``q_t - v = 0`` and ``m v_t = 0`` (``v`` stays 0); a pole's tied
``chi`` has ``q_t = v`` of its neighbour.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from mol_shell.discretization.loading import load_terms
from mol_shell.discretization.system import NF


class ShellDAE:
    """Residual, its iteration matrix and the state conversions for one :class:`ShellSystem`.

    Attributes
    ----------
    residual : casadi.Function
        ``(t, x, xp) -> F`` (MX of mapped kernels).
    jacobian : casadi.Function
        ``(t, x, xp, cj) -> dF/dx + cj dF/dxp`` (sparse), the matrix IDA's Newton iteration needs.
    to_momenta : casadi.Function
        ``(x, t) -> y``: rates to momenta ``p = M(q) v`` (the Hamiltonian state the rest of the package uses;
        ``t`` sets the prescribed rates of driven edges).
    """

    def __init__(self, system):
        self.system = system
        self.size = system.size
        self._build()

    def _node_residual(self, free, moving=()):
        """``(q, v, q_t, v_t, m) -> M(q) v_t + (dp/dq) q_t - dT/dq`` at a node whose free rates are ``free``.

        ``moving``: further fields whose (prescribed) rates enter the kinetic energy (driven edges); their
        rows, like those of imposed fields, read ``m v_t``.
        """
        sy = self.system
        q, v, qt, vt = (ca.SX.sym(name, NF) for name in ("q", "v", "qt", "vt"))
        m = ca.SX.sym("m", 3)
        vf = [v[k] if k in free or k in moving else 0 for k in range(NF)]
        T = sy.kinetic_energy(ca.vertsplit(q), vf, ca.vertsplit(m))
        p = ca.gradient(T, v)
        inertial = ca.jtimes(p, q, qt) + ca.jtimes(p, v, vt) - ca.gradient(T, q)
        mass = m[0]  # scale of the rows of fixed rates: m v_t = 0
        rows = [inertial[k] if k in free else mass * vt[k] for k in range(NF)]
        return ca.Function("node_residual", [q, v, qt, vt, m], [ca.vertcat(*rows)], self.system.KERNEL_OPTIONS)

    def _build(self):
        sy = self.system
        n, nf, active = sy.n, sy.nf, list(sy.active)
        x, xp = ca.MX.sym("x", self.size), ca.MX.sym("xp", self.size)
        t, cj = ca.MX.sym("t"), ca.MX.sym("cj")
        body = sy.ny * n
        X, XP = ca.reshape(x[:body], sy.ny, n), ca.reshape(xp[:body], sy.ny, n)
        Q, V, QT, VT = sy._fields(X), sy._fields(X, nf), sy._fields(XP), sy._fields(XP, nf)
        free = ca.DM((~sy.fixed.T).astype(float))
        V = V * free  # fixed rates enter nowhere (they stay 0)
        driven = {e: sy.driven_fields(e) for e in (0, n - 1) if sy.driven_fields(e)}
        if driven:  # prescribed rates and their derivatives at driven edges
            mask = np.ones((NF, n))
            for e, fields in driven.items():
                mask[fields, e] = 0.0
            VT_raw = VT
            VT = VT * ca.DM(mask)  # a driven rate's derivative is prescribed (the x entry stays 0, its row m v_t)
            cols = {e: sy.driven_rates(e, t) for e in driven}
            zero = ca.MX.zeros(NF, 1)
            V = V + ca.horzcat(cols[0][0] if 0 in cols else zero, ca.MX.zeros(NF, n - 2),
                               cols[n - 1][0] if n - 1 in cols else zero)
            VT = VT + ca.horzcat(cols[0][1] if 0 in cols else zero, ca.MX.zeros(NF, n - 2),
                                 cols[n - 1][1] if n - 1 in cols else zero)
        forces = sy.elastic_forces(Q)  # dV/dq, the stored energy of ShellSystem
        dissipation = 0
        if sy.viscous:
            viscous, dissipation = sy.viscous_forces(Q, sy.tie(V))  # dD/dv, 2 D
            forces = forces + viscous
        extra_rows, extra_newton = [], []
        if sy.n_extra:
            load_forces, power, drag_power = load_terms(sy, sy.scene, t, Q, sy.tie(V))
            forces = forces - load_forces
            first, _, last = sy.free_sets()
            for e, fields in driven.items():  # reaction = the driven rows' residual: what the driver supplies
                whole = (first if e == 0 else last) + fields
                rows = self._node_residual(whole)(Q[:, e], V[:, e], QT[:, e], VT[:, e], sy.inertia[:, e])
                for k in fields:
                    power = power + (rows[k] + forces[k, e]) * V[k, e]
            extra_rows = [xp[body] - power, xp[body + 1] - dissipation - drag_power]
            extra_newton = [xp[body], xp[body + 1]]  # the accumulators do not feed back: cj on the diagonal only
        first, inner, last = sy.free_sets()
        m = sy.inertia
        ri = self._node_residual(inner).map(n - 2)(Q[:, 1:-1], V[:, 1:-1], QT[:, 1:-1], VT[:, 1:-1], m[:, 1:-1])
        r0 = self._node_residual(first, driven.get(0, ()))(Q[:, 0], V[:, 0], QT[:, 0], VT[:, 0], m[:, 0])
        rn = self._node_residual(last, driven.get(n - 1, ()))(Q[:, -1], V[:, -1], QT[:, -1], VT[:, -1], m[:, -1])
        momentum = ca.horzcat(r0, ri, rn) + forces * free
        if driven:  # the driven fields' own rows: m v_t = 0 on their (unused) x entries
            momentum = momentum + ca.DM(1.0 - mask) * (VT_raw - VT) * ca.repmat(ca.DM(sy.inertia[0][None, :]), NF, 1)
        kinematic = QT - sy.tie(V)  # a pole's chi follows its neighbour's rate
        motion = ca.vec(ca.vertcat(kinematic[active, :], momentum[active, :]))
        F = ca.vertcat(motion, *extra_rows)
        self.residual = ca.Function("dae_residual", [t, x, xp], [F], ["t", "x", "xp"], ["F"])
        Fn = ca.vertcat(motion, *extra_newton)
        J = ca.jacobian(Fn, x) + cj * ca.jacobian(Fn, xp)
        self.jacobian = ca.Function("dae_jacobian", [t, x, xp, cj], [J], ["t", "x", "xp", "cj"], ["J"])
        # conversions between the Hamiltonian state y = (q, p) and x = (q, v), node by node
        y = ca.MX.sym("y", self.size)
        ydot = sy.rhs_mapped(0, y)
        mask_q = np.tile(np.r_[np.ones(nf), np.zeros(nf)], n).astype(bool)
        free_x = np.concatenate([np.ones((n, nf)), (~sy.fixed[:, active]).astype(float)], axis=1).ravel()
        mask_q = np.concatenate([mask_q, np.ones(sy.n_extra, dtype=bool)])  # the accumulators are the same in x and y
        free_x = np.concatenate([free_x, np.zeros(sy.n_extra)])
        x_of_y = y * ca.DM(mask_q.astype(float)) + self._shift_rates(ydot[: sy.ny * n], nf, n, sy.n_extra) * ca.DM(free_x)
        self.from_momenta = ca.Function("from_momenta", [y], [x_of_y], ["y"], ["x"])
        P = ca.vertcat(*[self._momentum(Q, V, k) for k in range(NF)])
        Yq = ca.vertcat(*[Q[k, :] for k in active])
        Yp = ca.vertcat(*[P[k, :] for k in active])
        self.to_momenta = ca.Function("to_momenta", [x, t], [ca.vertcat(ca.vec(ca.vertcat(Yq, Yp)), x[sy.ny * n:])],
                                      ["x", "t"], ["y"])
        self._mask_q = mask_q
        self._free_x = free_x

    @staticmethod
    def _shift_rates(ydot, nf, n, n_extra=0):
        """``x``'s rate entries from ``y_t``: the rate of field ``k`` of node ``i`` is ``y_t[2 nf i + k]``."""
        Yd = ca.reshape(ydot, 2 * nf, n)
        return ca.vertcat(ca.vec(ca.vertcat(ca.MX.zeros(nf, n), Yd[:nf, :])), ca.MX.zeros(n_extra))

    def _momentum(self, Q, V, k):
        """Row ``k`` of the nodal momenta ``p = dT/dv`` (0 for fixed rates, as in the Hamiltonian state)."""
        sy = self.system
        q, v, m = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("m", 3)
        T = sy.kinetic_energy(ca.vertsplit(q), ca.vertsplit(v), ca.vertsplit(m))
        f = ca.Function("p", [q, v, m], [ca.gradient(T, v)])
        P = f.map(sy.n)(Q, V, sy.inertia) * ca.DM((~sy.fixed.T).astype(float))
        return P[k, :]

    def consistent_rates(self, y):
        """``(x, x_t)`` at a Hamiltonian state ``y``: ``x_t = (v, v_t)`` with ``v_t = dv/dy y_t + dv/dt`` (exact,
        no solve).

        ``v(t, q, p)`` is the rate part of the ODE right-hand side; its time derivative along the
        motion is the rate rows of ``J(y) y_t`` plus its explicit one (a driven edge's rate on a history moves
        its neighbours' rates: without it a ramped drive left ``F(0, x, x_t)`` off by the drive's
        acceleration, and IDA failed its error test at ``t = 0`` at tight tolerances), so ``F(t, x, x_t) = 0``
        holds to rounding.
        """
        sy = self.system
        y = np.asarray(y, dtype=float)
        ydot = np.array(sy.rhs(0, y)).ravel()
        t, Y = ca.MX.sym("t"), ca.MX.sym("y", y.size)
        explicit = ca.Function("dv_dt", [t, Y], [ca.jacobian(sy.rhs(t, Y), t)])
        jv = np.array(sy.jac(0, y) @ ca.DM(ydot)).ravel() + np.array(explicit(0.0, y)).ravel()
        x = np.array(self.from_momenta(y)).ravel()
        nf, body = sy.nf, sy.ny * sy.n
        Yd, Jv = ydot[:body].reshape(sy.n, 2 * nf), jv[:body].reshape(sy.n, 2 * nf)
        XP = np.concatenate([Yd[:, :nf], Jv[:, :nf]], axis=1)
        XP[:, nf:] *= self._free_x[:body].reshape(sy.n, 2 * nf)[:, nf:]
        return x, np.concatenate([XP.ravel(), ydot[body:]])
