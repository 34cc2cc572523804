"""Method-of-lines discretisation: the semi-discrete Hamiltonian system as CasADi graphs.

The continuum Lagrangian ``2 pi r0 int (T - What) ds`` (section 7) is discretised
on ``n`` equally spaced nodes of ``[0, L]`` with a staggered (cell-centred) energy:

* nodal unknowns ``q_i = (z, r, chi, theta, psi)(s_i)`` and their momenta ``p_i``;
* stored energy ``V = 2 pi r0 sum_cells ds/2 [What(q_s, r_mid, theta_mid, psi_i) + What(q_s, r_mid,
  theta_mid, psi_{i+1})]``: the strains of cell ``[s_i, s_{i+1}]`` are the differences
  ``(q_{i+1} - q_i)/ds``, ``r`` and ``theta`` their midpoint averages (one-point rule: second order,
  and free of shear locking in ``theta``), and ``psi`` is sampled at the two nodes (trapezoidal
  rule, also second order). A midpoint ``psi`` would leave the node-to-node pattern
  ``psi_i = (-1)^i eps`` without its zero-order (transverse-shear) stiffness: a spurious mode of
  frequency ``(2/ds) sqrt(mu/rho)`` (357 rad/s at n = 40), degenerate with the shortest torsional
  waves and strongly excited by them. Sampled at the nodes it sits above the physical shear
  frequency (5,063 against 5,050 rad/s). ``psi -> 0`` is a pointwise constraint in the thin limit,
  so the nodal rule adds no locking;
* kinetic energy lumped at nodes with trapezoidal weights ``ds`` (``ds/2`` at the ends).

Hamilton's equations ``q_t = M(q)^{-1} p``, ``p_t = dT/dq|_v - dV/dq`` are an
equivalent first-order form of the paper's (6.5)-(6.7): energy ``T + V`` is
conserved by the semi-discrete system and the axial angular momentum ``sum p_chi``
is conserved exactly (``V`` depends on ``chi`` only through differences).
Boundary conditions: ``z = s`` and ``theta = 0`` at both ends are imposed (those
rates and momenta stay zero); ``n.a2 = n.a3 = m.c1 = 0`` are the natural ones.

State layout is node-major: with the scene's ``nf`` active fields (all five, or e.g.
``z, r, theta`` for axisymmetric motions), ``y[2 nf i + k]`` is active field ``k`` of node
``i`` for ``k < nf`` and its momentum for ``k >= nf``; this keeps the Jacobian banded.
Inactive fields are identically zero and are not in the graph.
"""

from __future__ import annotations

import math
from functools import cached_property

import casadi as ca
import numpy as np

from .model.kinematics import FIELDS as FIELD_NAMES
from .model.kinematics import delta, kinetic_energy_density
from .model.material import (
    Thickness, centroidal_offset, condensed, effective_lame, inertias, shell_dissipation, shell_energy,
)

NF = 5  # fields of the model (z, r, chi, theta, psi)
FIXED_AT_ENDS = (0, 3)  # z and theta are prescribed at s = 0 and s = L


class ShellSystem:
    """Discretised shell for one scene and grid; owns every CasADi object.

    Parameters
    ----------
    scene : TwistedCylinder
        Physical parameters (``R`` is not used here; it only enters initial data).
    n : int
        Number of nodes (``n >= 3``).

    Attributes
    ----------
    rhs : casadi.Function
        ``(t, y) -> y_t``, SX.
    """

    #: largest grid assembled as one flat SX graph; larger grids keep mapped kernels
    FLAT_MAX_NODES = 400

    def __init__(self, scene, n=40):
        if not isinstance(n, (int, np.integer)) or n < 3:
            from .errors import ParameterError

            raise ParameterError("n", n, "integers >= 3")
        self.scene, self.n = scene, int(n)
        self.active = tuple(getattr(scene, "fields", range(NF)))
        self.nf = len(self.active)
        self.ny = 2 * self.nf
        self.ds = scene.L / (self.n - 1)
        self.s = np.linspace(0.0, scene.L, self.n)
        self.r0 = 1.0
        self.lam, self.mu = effective_lame(scene.E, scene.nu, scene.material)
        self.eta_lambda, self.eta_mu = condensed(scene.eta_lambda, scene.eta_mu, scene.material)
        self.viscous = scene.eta_lambda > 0 or scene.eta_mu > 0
        zeta1 = centroidal_offset(scene.h, self.r0) if scene.zeta1 is None else scene.zeta1
        self.thickness = Thickness(zeta1, scene.h, scene.n_quad)
        self.rho_a, self.rho_i, self.rho_j = inertias(scene.rho, self.thickness, self.r0)
        if abs(self.rho_i) < 1e-14 * self.rho_a:
            self.rho_i = 0  # exact zero: the rhoI terms are left out of the graph
        self.weights = np.full(self.n, self.ds)
        self.weights[[0, -1]] = self.ds / 2
        self.fixed = np.zeros((self.n, NF), dtype=bool)
        for k in FIXED_AT_ENDS:
            self.fixed[[0, -1], k] = True
        self._build()

    # -- kernels -------------------------------------------------------------------------
    #: CasADi differentiates a mapped kernel through the kernel's own Jacobian instead of one
    #: forward sweep per colour of the whole Jacobian (15-18 at n = 40): the generated C of the
    #: exact Jacobian is 2.5x smaller and gcc needs 3.2 s instead of 10.8 s for the cell part
    KERNEL_OPTIONS = {"enable_forward": False}

    def cell_energy(self, ql, qr):
        """Stored energy of the cell ``[s_i, s_{i+1}]``: ``2 pi r0 ds`` times the mean of ``What`` at its samples."""
        samples = self.cell_samples(ql, qr)
        area = 2 * math.pi * self.r0 * self.ds / self.samples_per_cell
        return sum(area * shell_energy(e, self.lam, self.mu, self.thickness, self.r0) for e in samples)

    @property
    def samples_per_cell(self):
        """Where ``What`` is sampled in a cell: 2 (``psi`` at each node), 1 when ``psi`` is not a field."""
        return 2 if 4 in self.active else 1

    def cell_samples(self, ql, qr):
        """Strains ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)`` at the samples of a cell (two; one without psi).

        Differences for the derivatives, midpoint averages for ``r`` and ``theta``, and ``psi``
        at the left and at the right node (see the module's docstring). Linear in ``(ql, qr)``,
        so the same map turns nodal rates into the samples' strain rates.
        """
        grad = (qr - ql) / self.ds
        mid = (qr + ql) / 2
        if 4 not in self.active:  # psi = 0 identically (axisymmetric scenes): the two samples coincide
            return ((grad[0], grad[1], grad[2], grad[3], grad[4], mid[1], mid[3], mid[4]),)
        return tuple((grad[0], grad[1], grad[2], grad[3], grad[4], mid[1], mid[3], node[4]) for node in (ql, qr))

    def cell_forces_kernel(self):
        """``(q_left, q_right) -> (dV/dq_left, dV/dq_right)``: the cell's elastic forces on its nodes."""
        ql, qr = ca.SX.sym("ql", NF), ca.SX.sym("qr", NF)
        energy = self.cell_energy(ql, qr)
        return ca.Function("cell", [ql, qr], [ca.gradient(energy, ql), ca.gradient(energy, qr)], self.KERNEL_OPTIONS)

    def _cell_observables(self):
        """``(q_left, q_right) -> (V_cell, delta at the cell's samples)``."""
        ql, qr = ca.SX.sym("ql", NF), ca.SX.sym("qr", NF)
        deltas = [delta(z_s, r_s, r, theta, psi) for z_s, r_s, _, _, _, r, theta, psi in self.cell_samples(ql, qr)]
        return ca.Function("cell_observables", [ql, qr], [self.cell_energy(ql, qr), ca.vertcat(*deltas)])

    def cell_delta(self):
        """``(q_left, q_right) -> delta = r beta1 cos(psi)`` at the cell's samples (the model needs it > 0)."""
        ql, qr = ca.SX.sym("ql", NF), ca.SX.sym("qr", NF)
        return ca.Function("cell_delta", [ql, qr], [self._cell_observables()(ql, qr)[1]])

    def cell_dissipation(self, ql, qr, vl, vr):
        """Rayleigh function of the cell (Kelvin-Voigt), sampled like :meth:`cell_energy`; ``2 D`` is its power."""
        pairs = zip(self.cell_samples(ql, qr), self.cell_samples(vl, vr))
        area = 2 * math.pi * self.r0 * self.ds / self.samples_per_cell
        return sum(area * shell_dissipation(e, e_t, self.eta_lambda, self.eta_mu, self.thickness, self.r0)
                   for e, e_t in pairs)

    def viscous_forces_kernel(self):
        """``(q_left, q_right, v_left, v_right) -> (dD/dv_left, dD/dv_right)``: the cell's viscous forces."""
        ql, qr, vl, vr = (ca.SX.sym(name, NF) for name in ("ql", "qr", "vl", "vr"))
        D = self.cell_dissipation(ql, qr, vl, vr)
        return ca.Function("viscous", [ql, qr, vl, vr], [ca.gradient(D, vl), ca.gradient(D, vr)], self.KERNEL_OPTIONS)

    def _viscous_power(self):
        ql, qr, vl, vr = (ca.SX.sym(name, NF) for name in ("ql", "qr", "vl", "vr"))
        return ca.Function("viscous_power", [ql, qr, vl, vr], [2 * self.cell_dissipation(ql, qr, vl, vr)])

    def _node_kernel(self, free):
        """``(q, p, w) -> (v, dT/dq at fixed v, T)`` for a node whose free rates are ``free``."""
        q, p, w = ca.SX.sym("q", NF), ca.SX.sym("p", NF), ca.SX.sym("w")
        vf = ca.SX.sym("v", len(free))
        v = [vf[free.index(k)] if k in free else 0 for k in range(NF)]
        dens = kinetic_energy_density(ca.vertsplit(q), v, self.rho_a, self.rho_i, self.rho_j)
        T = 2 * math.pi * self.r0 * w * dens
        M = ca.hessian(T, vf)[0]
        lin = ca.substitute(ca.gradient(T, vf), vf, ca.DM.zeros(len(free)))  # zero: T is quadratic
        v_of_p = ca.solve(M, p[free] - lin)
        dTdq = ca.substitute(ca.gradient(T, q), vf, v_of_p)
        T_p = ca.substitute(T, vf, v_of_p)
        v_full = ca.SX.zeros(NF)
        v_full[free] = v_of_p
        return ca.Function("node", [q, p, w], [v_full, dTdq, T_p], self.KERNEL_OPTIONS)

    # -- assembly ------------------------------------------------------------------------
    def _build(self):
        """Assemble the RHS from per-cell and per-node kernels mapped over the grid (MX).

        Up to :attr:`FLAT_MAX_NODES` nodes :attr:`rhs` is expanded into one flat SX graph
        (fast in CasADi's virtual machine, exact sparse Jacobian in SX); above, it stays a
        map of small kernels. :attr:`rhs_mapped` is always the mapped form: generated C for
        it compiles in well under a second whatever ``n``, and runs as fast as the flat
        graph's (measured: 9.7 vs 9.3 us per evaluation at n = 40).
        """
        n, nf, active = self.n, self.nf, list(self.active)
        y = ca.MX.sym("y", self.ny * n)
        Y = ca.reshape(y, self.ny, n)
        zero_row = ca.MX.zeros(1, n)
        Q = ca.vertcat(*[Y[active.index(k), :] if k in active else zero_row for k in range(NF)])
        P = ca.vertcat(*[Y[nf + active.index(k), :] if k in active else zero_row for k in range(NF)])
        cell = self.cell_forces_kernel()
        gl, gr = cell.map(n - 1)(Q[:, :-1], Q[:, 1:])
        pad = ca.MX.zeros(NF, 1)
        dVdq = ca.horzcat(gl, pad) + ca.horzcat(pad, gr)
        interior = self._node_kernel(active)
        end = self._node_kernel([k for k in active if k not in FIXED_AT_ENDS])
        vi, fi, ti = interior.map(n - 2)(Q[:, 1:-1], P[:, 1:-1], self.weights[None, 1:-1])
        v0, f0, t0 = end(Q[:, 0], P[:, 0], self.weights[0])
        vn, fn, tn = end(Q[:, -1], P[:, -1], self.weights[-1])
        V = ca.horzcat(v0, vi, vn)
        forces = ca.horzcat(f0, fi, fn) - dVdq
        dissipation = 0
        if self.viscous:
            fl, fr = self.viscous_forces_kernel().map(n - 1)(Q[:, :-1], Q[:, 1:], V[:, :-1], V[:, 1:])
            forces = forces - ca.horzcat(fl, pad) - ca.horzcat(pad, fr)
            dissipation = ca.sum2(self._viscous_power().map(n - 1)(Q[:, :-1], Q[:, 1:], V[:, :-1], V[:, 1:]))
        forces = forces * ca.DM((~self.fixed.T).astype(float))
        ydot = ca.vec(ca.vertcat(V[active, :], forces[active, :]))
        kinetic = ca.sum2(ti) + t0 + tn
        energies, deltas = self._cell_observables().map(n - 1)(Q[:, :-1], Q[:, 1:])
        stored = ca.sum2(energies)
        t = ca.MX.sym("t")
        rhs = ca.Function("rhs", [t, y], [ydot], ["t", "y"], ["ydot"])
        observables = ca.Function(
            "observables",
            [y],
            [V, kinetic, stored, ca.sum2(P[2, :]), ca.vec(deltas), dissipation],
            ["y"],
            ["v", "kinetic", "stored", "angular_momentum", "delta", "dissipation"],
        )
        self.rhs_mapped = rhs
        self.kernel_instructions = {
            "cell": cell.n_instructions(),
            "node": interior.n_instructions(),
        }
        self.mapped = n > self.FLAT_MAX_NODES
        if self.mapped:
            self.rhs, self.observables = rhs, observables
        else:
            self.rhs, self.observables = rhs.expand(), observables.expand()

    @cached_property
    def limits(self):
        """``y -> g``: the model's limits as functions that must stay positive (:meth:`limit_names` says which).

        ``g = [delta at the samples of each cell; r per node; (pi/2)^2 - psi^2 per node]``
        (the last only when ``psi`` is a field). Leap-frog checks them after every step (in C),
        CVODE and IDA find their roots. Depends on the field entries only, which sit at the same
        places in ``y = (q, p)`` and in IDA's ``x = (q, v)``.
        """
        n, active = self.n, list(self.active)
        y = ca.MX.sym("y", self.size)
        Y = ca.reshape(y, self.ny, n)
        Q = ca.vertcat(*[Y[active.index(k), :] if k in active else ca.MX.zeros(1, n) for k in range(NF)])
        g = [ca.vec(self.cell_delta().map(n - 1)(Q[:, :-1], Q[:, 1:])), Q[1, :].T]
        if 4 in active:
            g.append((math.pi / 2) ** 2 - Q[4, :].T ** 2)
        f = ca.Function("limits", [y], [ca.vertcat(*g)], ["y"], ["g"])
        return f.expand() if n <= self.FLAT_MAX_NODES else f

    def limit_names(self):
        """``(what, where)`` for each entry of :attr:`limits`."""
        cells = (self.s[:-1] + self.s[1:]) / 2
        names = [("delta = r beta1 cos(psi) reached 0", f"s = {s:.6g} m (cell centre)") for s in np.repeat(cells, self.samples_per_cell)]
        names += [("r reached 0", f"s = {s:.6g} m") for s in self.s]
        if 4 in self.active:
            names += [("|psi| reached pi/2", f"s = {s:.6g} m") for s in self.s]
        return names

    @cached_property
    def jac(self):
        """``(t, y) -> d y_t / d y``: exact sparse Jacobian (SX when the RHS is flat, else MX)."""
        t, y = (self.rhs.mx_in if self.mapped else self.rhs.sx_in)()
        J = ca.jacobian(self.rhs(t, y), y)
        return ca.Function("jacobian", [t, y], [J], ["t", "y"], ["J"])

    @property
    def size(self):
        return self.ny * self.n

    def graph_stats(self):
        """Size of the graphs: instructions of the RHS and its kernels, Jacobian non-zeros and bandwidths."""
        sp = self.jac.sparsity_out(0)
        return {
            "cell_kernel_instructions": int(self.kernel_instructions["cell"]),
            "node_kernel_instructions": int(self.kernel_instructions["node"]),
            "rhs_instructions": int(self.rhs.n_instructions()),
            "assembly": "mapped" if self.mapped else "flat",
            "jacobian_nnz": int(sp.nnz()),
            "jacobian_bw_lower": int(sp.bw_lower()),
            "jacobian_bw_upper": int(sp.bw_upper()),
        }

    # -- data ----------------------------------------------------------------------------
    def initial_state(self, sc):
        """Initial data (6.9) of scene ``sc`` (``R`` resolved), with spin ``omega`` and shear ``psi0``.

        Returns the node-major state vector.
        """
        if hasattr(sc, "initial_fields"):  # a scene with its own initial data
            Q, V = sc.initial_fields(self.s)
        else:
            Q = np.zeros((NF, self.n))
            Q[0] = self.s
            Q[1] = sc.R
            Q[2] = getattr(sc, "gamma", 0.0) * (self.s - sc.L / 2)
            Q[4] = getattr(sc, "psi0", 0.0)
            V = np.zeros((NF, self.n))
            V[2] = getattr(sc, "omega", 0.0)
        V[:, [0, -1]] *= ~self.fixed[[0, -1]].T
        return self.pack(Q, self.momenta(Q, V))

    def pack(self, Q, P):
        """Node-major state vector from full fields ``Q`` and momenta ``P`` (each ``5 x n``)."""
        Q, P = np.asarray(Q), np.asarray(P)
        inactive = [k for k in range(NF) if k not in self.active]
        if np.any(Q[inactive]) or np.any(P[inactive]):
            raise ValueError(f"fields {[FIELD_NAMES[k] for k in inactive]} must vanish for this scene")
        return np.concatenate([Q[list(self.active)], P[list(self.active)]]).T.reshape(-1)

    def momenta(self, Q, V):
        """Nodal momenta ``p = M(q) v`` for fields ``Q`` and rates ``V`` (each ``5 x n``)."""
        q, v, w = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("w")
        dens = kinetic_energy_density(ca.vertsplit(q), ca.vertsplit(v), self.rho_a, self.rho_i, self.rho_j)
        f = ca.Function("p", [q, v, w], [ca.gradient(2 * math.pi * self.r0 * w * dens, v)])
        P = np.array(f.map(self.n)(Q, V, self.weights[None, :]))
        P[self.fixed.T] = 0.0
        return P

    def unpack(self, y):
        """Fields ``(5, n)`` from one state vector (or ``(..., 5, n)`` from a stack); inactive ones are 0."""
        y = np.asarray(y)
        out = np.zeros((*y.shape[:-1], NF, self.n))
        out[..., list(self.active), :] = np.swapaxes(y.reshape(*y.shape[:-1], self.n, self.ny)[..., : self.nf], -1, -2)
        return out
