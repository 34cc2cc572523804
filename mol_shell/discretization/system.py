"""Method-of-lines discretisation: the semi-discrete Hamiltonian system as CasADi graphs.

The continuum Lagrangian ``2 pi int r0 (T - What) ds`` (section 7) of a shell of revolution with
reference meridian ``(r0, z0, theta0)(s)`` (:mod:`mol_shell.model.geometry`) is discretised on ``n``
equally spaced nodes of ``[0, L]`` with a staggered (cell-centred) energy:

* nodal unknowns ``q_i = (z, r, chi, theta, psi)(s_i)`` and their momenta ``p_i``;
* stored energy ``V = sum_cells 2 pi int W_SVK(F) det G0 dzeta ds``, sampled twice per cell: the strains
  of cell ``[s_i, s_{i+1}]`` are the differences ``(q_{i+1} - q_i)/ds``, ``r`` and ``theta`` their
  midpoint averages (one-point rule: second order, and free of shear locking in ``theta``), and
  ``psi`` is sampled at the two nodes (trapezoidal rule, also second order). A midpoint ``psi``
  would leave the node-to-node pattern ``psi_i = (-1)^i eps`` without its zero-order
  (transverse-shear) stiffness: a spurious mode of frequency ``(2/ds) sqrt(mu/rho)`` (357 rad/s at
  n = 40 on the paper's cylinder). ``psi -> 0`` is a pointwise constraint in the thin limit, so the
  nodal rule adds no locking;
* the reference configuration is the discrete one: ``F = G G0^-1`` (:func:`~mol_shell.model.kinematics.
  deformation_gradient`) with ``G0`` from the same difference and midpoint formulas applied to the
  nodal reference coordinates ``(z0, r0, theta0)_i``, so the natural state has ``F = I`` exactly at
  every sample and is an exact equilibrium on every meridian (exact midpoint values of the meridian
  would leave an ``O(ds^2)`` residual stress);
* the geometry enters the cell kernel as per-cell data (the factors ``j1, j3, vol`` of
  :func:`~mol_shell.model.material.quadrature_factors` at each thickness point, and ``beta2_0`` when the
  meridian is curved), so one kernel serves every meridian and grid of a material. The kernel works
  with differences, not derivatives (``ds = 1``): ``F`` is unchanged and ``det G0`` carries ``ds``;
* kinetic energy lumped at nodes: the exact inertia of each node's dual cell
  (:func:`~mol_shell.model.geometry.node_inertias`; the trapezoidal weights on a cylinder, and a
  positive mass at a pole).

Hamilton's equations ``q_t = M(q)^{-1} p``, ``p_t = dT/dq|_v - dV/dq`` are an equivalent first-order
form of the paper's (6.5)-(6.7): energy ``T + V`` is conserved by the semi-discrete system and the
axial angular momentum ``sum p_chi`` is conserved exactly when both edges leave ``chi`` free (``V``
depends on ``chi`` only through differences). Edge conditions (:mod:`mol_shell.model.edges`): imposed fields
keep their initial values (those rates and momenta stay zero); the others get the natural conditions
of the variational form. At a pole ``r = 0``, ``theta = theta0``, ``psi = 0`` are imposed and the
massless ``chi`` of the pole node is tied to its neighbour's (its force is added there).

State layout is node-major: with the scene's ``nf`` active fields (all five, or e.g.
``z, r, theta`` for axisymmetric motions), ``y[2 nf i + k]`` is active field ``k`` of node
``i`` for ``k < nf`` and its momentum for ``k >= nf``; this keeps the Jacobian banded.
Inactive fields are identically zero and are not in the graph.
"""

from __future__ import annotations

import contextlib
import io
from functools import cached_property

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ParameterError
from mol_shell.discretization.cells import BETA2_ZERO, CellKernels, trig_chain  # noqa: F401  (BETA2_ZERO: where it is defined)
from mol_shell.discretization.limits import ModelLimits
from mol_shell.discretization.loading import check_end_loads, edge_displacements, load_terms
from mol_shell.discretization.reactions import edge_reactions
from mol_shell.model.edges import driven_node_kernel, driven_rates, free_rates, imposed_mask, resolve_edges, tied_chi
from mol_shell.model.fibres import scene_fibres
from mol_shell.model.geometry import node_inertias
from mol_shell.model.kinematics import FIELDS as FIELD_NAMES
from mol_shell.model.kinematics import kinetic_energy_density
from mol_shell.model.laws import law_parameters, layer_laws, small_strain_lame, viscosities
from mol_shell.model.linalg import spd_solve
from mol_shell.model.loads import history
from mol_shell.model.material import Thickness, inertias
from mol_shell.model.thickness_profile import graded_node_inertias, scene_profile, thickness_function


class ShellSystem(ModelLimits, CellKernels):
    """Discretised shell for one scene and grid; owns every CasADi object.

    Parameters
    ----------
    scene : ShellScene
        Physical parameters; ``scene.meridian()`` gives the reference meridian (initial data are
        not used here).
    n : int
        Number of nodes (``n >= 3``).
    reference : bool
        Build the cell kernel from the readable reference energy (:func:`~mol_shell.model.material.thickness_energy`:
        ``F``, ``E`` and ``W`` at each thickness point) instead of the lean one
        (:func:`~mol_shell.model.material.thickness_energy_moments`: per-sample dot products against per-cell
        thickness moments of the same quadrature, equal to round-off); tests check one against the other.
    at_rest : bool
        Driven edges held where they are, at rate 0 (their fields still prescribed, their rates zero): the
        equations of the static equilibrium at ``t = 0`` (:mod:`mol_shell.runs.statics`), which a spin or a drive
        is set on afterwards.

    Attributes
    ----------
    rhs : casadi.Function
        ``(t, y) -> y_t``, SX.
    s : ndarray
        Node arc lengths; ``reference`` the nodal ``(z0, r0, theta0)`` (``3 x n``).
    edges : tuple of str
        Edge kinds at ``s = 0`` and ``s = L`` (:mod:`mol_shell.model.edges`).
    inertia : ndarray
        ``(mA, mI, mJ)`` per node (``3 x n``), kg, kg m, kg m^2.
    fixed : ndarray
        ``(n, 5)``: fields whose momenta stay zero (imposed ones and a pole's tied ``chi``).
    """

    #: largest grid assembled as one flat SX graph; larger grids keep mapped kernels
    FLAT_MAX_NODES = 400

    def __init__(self, scene, n=40, *, reference=False, at_rest=False):
        self.reference_kernel = bool(reference)
        if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 3:
            raise ParameterError("n", n, "integers >= 3")
        self.scene, self.n = scene, int(n)
        self.active = tuple(getattr(scene, "fields", range(NF)))
        self.nf = len(self.active)
        self.ny = 2 * self.nf
        self.meridian = scene.meridian()
        self.L = self.meridian.length
        self.ds = self.L / (self.n - 1)
        self.s = np.linspace(0.0, self.L, self.n)
        r0, z0, th0, _ = self.meridian.at(self.s)
        self.reference = np.array([z0, r0, th0])
        self.edges = resolve_edges(getattr(scene, "end1", None), getattr(scene, "end2", None), self.meridian.poles)
        self.lam, self.mu = small_strain_lame(scene)  # the SVK kernels' pair; scales for the other laws
        self.law, self.law_params = law_parameters(scene)
        self.fibres = scene_fibres(scene)  # None without fibres: nothing of them in the graph
        self.eta_lambda, self.eta_mu = viscosities(scene)
        self.viscous = scene.eta_lambda > 0 or scene.eta_mu > 0
        profile = scene_profile(scene)  # as it runs: a vessel drawn down runs backwards, h(L - s) of the one given
        self.graded = thickness_function(profile, self.L) if profile else None  # h(s) of a graded wall
        zeta1 = -scene.h if self.graded else scene.zeta1_used()
        self.thickness = Thickness(zeta1, scene.h, scene.n_quad)
        if getattr(scene, "layers", ""):  # layer by layer: each its law (the first one routes the kernels)
            self.thickness, self.layer_laws = layer_laws(scene)
            self.law, self.law_params, self.fibres = *self.layer_laws[0][:2], None
        self.inertia = (node_inertias(self.meridian, self.s, scene.rho, self.thickness) if self.graded is None else
                        graded_node_inertias(self.meridian, self.s, scene.rho, self.graded, scene.n_quad))
        self.has_rho_i = bool(np.any(np.abs(self.inertia[1]) > 1e-14 * self.inertia[0] * scene.h))
        if not self.has_rho_i:
            self.inertia[1] = 0.0  # exact zero: the rhoI terms are left out of the graph
        # per unit reference area at mid-length (constant on a cylinder; for the record on other shells)
        mid = self.meridian.at(np.array([self.L / 2]))
        self.r0 = float(mid[0][0])
        self.rho_a, self.rho_i, self.rho_j = inertias(scene.rho, self.thickness, self.r0, float(mid[2][0]), float(mid[3][0]))
        if not self.has_rho_i:
            self.rho_i = 0
        self.weights = np.full(self.n, self.ds)  # lengths of the dual cells
        self.weights[[0, -1]] = self.ds / 2
        self.imposed = imposed_mask(self.n, self.edges, self.active)
        self.ties = tied_chi(self.n, self.edges, self.active)
        self.fixed = self.imposed.copy()
        for pole, _ in self.ties:
            self.fixed[pole, 2] = True
        self.cell_data = self._cell_data()
        self.drives = scene.drives() if hasattr(scene, "drives") else {}
        for (e, k), _ in self.drives.items():
            node, name = (0, "end1") if e == 0 else (self.n - 1, "end2")
            if self.edges[e] == "pole" or k not in self.active:
                what = "spin" if k == 2 else "axial_speed"
                raise ParameterError(f"{name}_{what}", self.drives[(e, k)][0], "0 for this edge",
                                     hint=f"{name} is a pole" if self.edges[e] == "pole" else "this scene has no chi")
            self.fixed[node, k] = True  # driven: the rate is prescribed, the momentum is not a state
        if at_rest:  # held where they are at t = 0: no centrifugal force (nor drag, viscosity) of the driven rate
            self.drives = {key: (0.0, hist) for key, (_, hist) in self.drives.items()}
        self.n_extra = 2 if getattr(scene, "loaded", False) else 0  # work and dissipated, integrated with the motion
        if self.n_extra:
            check_end_loads(self, scene)
        self._build()

    # -- geometry per cell -----------------------------------------------------------------
    def kinetic_energy(self, q, v, m, trig=None):
        """Lumped kinetic energy of a node: ``mA |r_t|^2/2 + mI r_t.d_t + mJ |d_t|^2/2`` (``m`` its inertias)."""
        m_i = m[1] if self.has_rho_i else 0
        return kinetic_energy_density(q, v, m[0], m_i, m[2], trig)

    def _node_kernel(self, free, shared=False):
        """``(q, p, m) -> (v, dT/dq at fixed v, T)`` for a node whose free rates are ``free``.

        ``shared``: a fourth input takes the node's :meth:`node_trig_kernel` values (the lean RHS).
        """
        q, p, m = ca.SX.sym("q", NF), ca.SX.sym("p", NF), ca.SX.sym("m", 3)
        t = ca.SX.sym("t", 4)
        vf = ca.SX.sym("v", len(free))
        v = [vf[free.index(k)] if k in free else 0 for k in range(NF)]
        trig = (t[2] * t[2] - t[3] * t[3], 2 * t[2] * t[3], t[0], t[1]) if shared else None
        T = self.kinetic_energy(ca.vertsplit(q), v, ca.vertsplit(m), trig)
        M = ca.hessian(T, vf)[0]
        lin = ca.substitute(ca.gradient(T, vf), vf, ca.DM.zeros(len(free)))  # zero: T is quadratic
        v_of_p = (ca.solve if self.reference_kernel else spd_solve)(M, p[free] - lin)  # the reference keeps QR
        dTdq = ca.gradient(T, q) + (trig_chain(t, ca.gradient(T, t)) if shared else 0)
        dTdq = ca.substitute(dTdq, vf, v_of_p)
        T_p = ca.substitute(T, vf, v_of_p)
        v_full = ca.SX.zeros(NF)
        v_full[free] = v_of_p
        outs = [v_full, dTdq, T_p]
        if not self.reference_kernel:
            outs = ca.cse(outs)
        return ca.Function("node", [q, p, m] + ([t] if shared else []), outs, self.KERNEL_OPTIONS)

    def _driven_node_kernel(self, free, driven):
        """The edge-node kernel with prescribed rates (:func:`mol_shell.model.edges.driven_node_kernel`), its
        first three outputs (the momenta of the driven fields are the reactions', :mod:`~mol_shell.discretization.reactions`)."""
        return driven_node_kernel(self, free, driven, momenta=False)

    def free_sets(self):
        """Free rates at node 0, at interior nodes and at node ``n - 1`` (imposed, tied and driven fields are not)."""
        ends = [[k for k in free_rates(kind, self.active) if k not in self.driven_fields(e)]
                for kind, e in zip(self.edges, (0, self.n - 1))]
        return ends[0], list(self.active), ends[1]

    def driven_fields(self, node):
        """Fields of edge node ``node`` whose rates are prescribed (driven edges)."""
        end = 0 if node == 0 else 1 if node == self.n - 1 else None
        return sorted(k for (e, k) in self.drives if e == end)

    def driven_rates(self, node, t):
        """``(vd, vd_t)`` of the prescribed rates at edge node ``node`` (:func:`mol_shell.model.edges.driven_rates`)."""
        return driven_rates(self, node, t)

    # -- assembly ------------------------------------------------------------------------
    def _fields(self, Y, offset=0):
        """The ``5 x n`` field rows of a node-major matrix (inactive rows zero)."""
        active, n = list(self.active), self.n
        if active == list(range(NF)):  # one block of rows: no gathers row by row
            return Y[offset:offset + NF, :]
        zero_row = ca.MX.zeros(1, n)
        return ca.vertcat(*[Y[offset + active.index(k), :] if k in active else zero_row for k in range(NF)])

    def tie(self, Q):
        """``Q`` with each pole's ``chi`` replaced by its neighbour's (rows ``5 x n``; MX or NumPy)."""
        if not self.ties:
            return Q
        index = np.arange(self.n)
        for pole, nb in self.ties:
            index[pole] = nb
        if isinstance(Q, np.ndarray):
            Q = Q.copy()
            Q[2] = Q[2][..., index] if Q.ndim == 2 else Q[2]
            return Q
        return ca.vertcat(Q[:2, :], Q[2, list(index)], Q[3:, :])

    def gather_ties(self, F):
        """Forces on the tied ``chi`` added to the neighbours' (the transpose of :meth:`tie`), the poles' set to 0."""
        if not self.ties:
            return F
        row = F[2, :]
        extra = ca.MX.zeros(1, self.n)
        for pole, nb in self.ties:
            extra[0, nb] = row[0, pole]
            extra[0, pole] = -row[0, pole]
        return ca.vertcat(F[:2, :], row + extra, F[3:, :])

    def elastic_forces(self, Q, trig=None):
        """``dV/dq`` (``5 x n``, MX) of the fields ``Q`` (ties applied inside); ``trig``: the nodes' trigonometry
        (:meth:`node_trig_kernel`, ``4 x n``) for the shared cell kernel."""
        n = self.n
        Qt = self.tie(Q)
        if trig is None:
            gl, gr = self._map(self.kernel("cell_forces_kernel"), n - 1)(Qt[:, :-1], Qt[:, 1:], self.cell_data)
        else:  # a pole's tied chi does not enter the trigonometry
            gl, gr = self._map(self.kernel("cell_forces_shared_kernel", True), n - 1)(
                Qt[:, :-1], Qt[:, 1:], trig[:, :-1], trig[:, 1:], self.shared_cell_data)[-2:]
        pad = ca.MX.zeros(NF, 1)
        return self.gather_ties(ca.horzcat(gl, pad) + ca.horzcat(pad, gr))

    def viscous_forces(self, Q, V, trig=None):
        """``(dD/dv, 2 D)`` at fields ``Q`` and rates ``V``: the viscous forces (``5 x n``, MX; ties applied
        inside) and the power they dissipate. ``trig``: as for :meth:`elastic_forces`."""
        n = self.n
        Qt, Vt = self.tie(Q), self.tie(V)
        if trig is None:
            fl, fr, power = self._map(self.kernel("viscous_forces_kernel"), n - 1)(Qt[:, :-1], Qt[:, 1:], Vt[:, :-1], Vt[:, 1:],
                                                                          self.cell_data)
        else:
            fl, fr, power = self._map(self.kernel("viscous_forces_shared_kernel"), n - 1)(
                Qt[:, :-1], Qt[:, 1:], Vt[:, :-1], Vt[:, 1:], trig[:, :-1], trig[:, 1:], self.shared_cell_data)
        pad = ca.MX.zeros(NF, 1)
        return self.gather_ties(ca.horzcat(fl, pad) + ca.horzcat(pad, fr)), ca.sum2(power)

    def kernel(self, method, *args):
        """``getattr(self, method)(*args)``, a cell kernel built once per system (the maps of every assembly and the
        edges' reactions share it)."""
        memo = self.__dict__.setdefault("_kernels", {})
        if (method, args) not in memo:
            memo[method, args] = getattr(self, method)(*args)
        return memo[method, args]

    #: kernels mapped with CasADi's "openmp" map while :attr:`rhs_parallel` is assembled
    _parallel = False

    def _map(self, kernel, count):
        """``kernel.map(count)``; with OpenMP pragmas in generated C while :attr:`rhs_parallel` is assembled."""
        if not self._parallel:
            return kernel.map(count)
        with contextlib.redirect_stderr(io.StringIO()):  # the pip CasADi warns that its own VM runs it serially
            return kernel.map(count, "openmp")

    @cached_property
    def rhs_parallel(self):
        """:attr:`rhs_mapped` with the cell and node kernels in OpenMP maps (``#pragma omp parallel for`` in C).

        The same graph and arithmetic per cell, so its generated C gives the serial results to the last
        bit whatever the thread count (each cell and node is computed by one thread, and sums over
        cells stay in the serial order outside the parallel loops). CasADi's own virtual machine
        evaluates it serially; :class:`~mol_shell.discretization.compiled.CompiledRHS` builds it with ``-fopenmp``.
        """
        self._parallel = True
        try:
            return self._assemble()[0]
        finally:
            self._parallel = False

    def _build(self):
        rhs, newton, observables, interior = self._assemble()
        self.rhs_mapped = rhs
        self.rhs_newton_mapped = newton
        self.kernel_instructions = {
            "cell": (self.cell_forces_kernel() if self.reference_kernel else self.cell_forces_shared_kernel()
                     ).n_instructions(),
            "node": interior.n_instructions(),
        }
        self.mapped = self.n > self.FLAT_MAX_NODES
        if self.mapped:
            self.rhs, self.observables, self.rhs_newton = rhs, observables, newton
        else:
            self.rhs, self.observables, self.rhs_newton = rhs.expand(), observables.expand(), newton.expand()

    def _assemble(self):
        """Assemble the RHS from per-cell and per-node kernels mapped over the grid (MX).

        Up to :attr:`FLAT_MAX_NODES` nodes :attr:`rhs` is expanded into one flat SX graph
        (fast in CasADi's virtual machine, exact sparse Jacobian in SX); above, it stays a
        map of small kernels. :attr:`rhs_mapped` is always the mapped form: generated C for
        it compiles in well under a second whatever ``n``, and runs as fast as the flat
        graph's (measured: 9.7 vs 9.3 us per evaluation at n = 40).
        """
        n, nf, active = self.n, self.nf, list(self.active)
        y = ca.MX.sym("y", self.size)
        Y = ca.reshape(y[: self.ny * n], self.ny, n)
        Q, P = self._fields(Y), self._fields(Y, nf)
        first, inner, last = self.free_sets()
        shared = not self.reference_kernel  # trigonometry once per node (node_trig_kernel)
        trig = self._map(self.node_trig_kernel(), n)(Q) if shared else None

        def node_inputs(nodes):
            inertia = self.inertia[:, nodes]
            if inertia.ndim == 2 and np.all(inertia == inertia[:, :1]):
                inertia = inertia[:, :1]  # the same for every node (a cylinder): broadcast by the map
            return (Q[:, nodes], P[:, nodes], inertia) + ((trig[:, nodes],) if shared else ())

        interior = self._node_kernel(inner, shared)
        t = ca.MX.sym("t")
        vi, fi, ti = self._map(interior, n - 2)(*node_inputs(slice(1, -1)))
        ends = []
        for e, free in ((0, first), (n - 1, last)):
            driven = self.driven_fields(e)
            if driven:
                vd = self.driven_rates(e, t)[0]
                ends.append(self._driven_node_kernel(free, driven)(Q[:, e], P[:, e], self.inertia[:, e], vd))
            else:
                ends.append(self._node_kernel(free, shared)(*node_inputs(e)))
        (v0, f0, t0), (vn, fn, tn) = ends
        V = self.tie(ca.horzcat(v0, vi, vn))
        forces = ca.horzcat(f0, fi, fn) - self.elastic_forces(Q, trig)
        dissipation = 0
        if self.viscous:
            viscous, dissipation = self.viscous_forces(Q, V, trig)
            forces = forces - viscous
        rates = []
        work, dissipated = 0, 0
        load_forces = None
        if self.n_extra:
            load_forces, power, drag_power = load_terms(self, self.scene, t, Q, V)
            forces = forces + load_forces
        # the drivers' and supports' reactions, from the edge nodes' own cells (mol_shell.discretization.reactions)
        edge = edge_reactions(self, t, Q, P, V, trig, [f0, fn], load_forces)
        if self.n_extra:  # the drivers' power: their reactions times the prescribed rates (a support does no work)
            for e, k, reaction, _ in edge:
                if k in self.driven_fields(e):
                    power = power + reaction * V[k, e]
            rates = [power, dissipation + drag_power]
            work, dissipated = y[self.ny * n], y[self.ny * n + 1]
        forces = forces * ca.DM((~self.fixed.T).astype(float))
        motion = ca.vec(ca.vertcat(V[active, :], forces[active, :]))
        ydot = ca.vertcat(motion, *rates)
        kinetic = ca.sum2(ti) + t0 + tn
        reactions = ca.vertcat(*[r for _, _, r, _ in edge]) if edge else ca.MX.zeros(0)
        # sum p_chi, with the momenta of driven and held chi (not states) added
        angular = ca.sum2(P[2, :]) + sum(momentum for _, k, _, momentum in edge if k == 2)
        self.reaction_names = [(e, k) for e, k, _, _ in edge]
        Qt = self.tie(Q)
        energies, deltas = self._cell_observables().map(n - 1)(Qt[:, :-1], Qt[:, 1:], self.cell_data)
        stored = ca.sum2(energies)
        rhs = ca.Function("rhs", [t, y], [ydot], ["t", "y"], ["ydot"])
        # the same without the accumulators' dependence on the motion: what Newton iterations and spectra use
        # (the accumulators do not feed back, and their rows would break the Jacobian's band)
        newton = ca.Function("rhs_newton", [t, y], [ca.vertcat(motion, ca.MX.zeros(self.n_extra))], ["t", "y"],
                             ["ydot"])
        observables = ca.Function(
            "observables",
            [y, t],
            [V, kinetic, stored, angular, ca.vec(deltas) / self.ds, dissipation, work, dissipated, reactions],
            ["y", "t"],
            ["v", "kinetic", "stored", "angular_momentum", "delta", "dissipation", "work", "dissipated", "reactions"],
        )
        return rhs, newton, observables, interior

    @cached_property
    def jac(self):
        """``(t, y) -> d y_t / d y``: exact sparse Jacobian (SX when the RHS is flat, else MX)."""
        t, y = (self.rhs.mx_in if self.mapped else self.rhs.sx_in)()
        J = ca.jacobian(self.rhs_newton(t, y), y)
        return ca.Function("jacobian", [t, y], [J], ["t", "y"], ["J"])

    @cached_property
    def spectrum_jac(self):
        """``(t, y) -> d y_t / d y`` through the mapped kernels' own Jacobians (MX): the values of :attr:`jac` to
        round-off, built in ~0.02 s instead of ~0.13 s at n = 40, for the spectrum and the finiteness checks that
        every run makes once (its structural non-zeros include some of :attr:`jac`'s exact zeros)."""
        if self.mapped:
            return self.jac
        t, y = self.rhs_newton_mapped.mx_in()
        return ca.Function("jacobian", [t, y], [ca.jacobian(self.rhs_newton_mapped(t, y), y)], ["t", "y"], ["J"])

    @property
    def size(self):
        """Length of the state: ``2 nf n``, plus the accumulators ``work, dissipated`` when the scene has loads."""
        return self.ny * self.n + self.n_extra

    def graph_stats(self):
        """Size of the graphs: instructions of the RHS and its kernels, Jacobian non-zeros and bandwidths."""
        sp = self.jac.sparsity_out(0) if self.mapped else self.rhs_newton.sparsity_jac(1, 0)  # :attr:`jac`'s, unbuilt
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
        """The node-major state vector of scene ``sc``'s initial data (``R`` and the like resolved).

        The scene gives the fields at the nodes from the reference coordinates (``sc.initial_fields(s,
        reference)``); a pole's ``chi`` takes its neighbour's value, and the momenta follow from the rates
        (:meth:`initial_rates`) as ``p = M(q) v`` (those of imposed and driven fields are not states: zero).
        """
        Q, _ = sc.initial_fields(self.s, self.reference)
        Q = self.tie(np.array(Q, dtype=float))
        for node, field, value in edge_displacements(self, sc):  # end1_dz, ...: an imposed field moved
            Q[field, node] += value
        return self.pack(Q, self.momenta(Q, self.initial_rates(sc)))

    def initial_rates(self, sc):
        """Scene ``sc``'s rates at ``t = 0`` (``5 x n``): its own (a spin ``omega``), imposed ones zero, driven
        edges at their prescribed rate from ``t = 0`` (their neighbours' momenta see it)."""
        V = np.array(sc.initial_fields(self.s, self.reference)[1], dtype=float) * ~self.fixed.T
        for (e, k), (rate, hist) in self.drives.items():
            V[k, 0 if e == 0 else self.n - 1] = rate * history(hist, 0.0)
        return V

    def moving(self, y, sc):
        """State ``y``'s positions moving at scene ``sc``'s initial rates (a static equilibrium set spinning)."""
        Q = self.unpack(y)
        return self.pack(Q, self.momenta(Q, self.initial_rates(sc)))

    def pack(self, Q, P):
        """Node-major state vector from full fields ``Q`` and momenta ``P`` (each ``5 x n``)."""
        Q, P = np.asarray(Q), np.asarray(P)
        inactive = [k for k in range(NF) if k not in self.active]
        if np.any(Q[inactive]) or np.any(P[inactive]):
            raise ValueError(f"fields {[FIELD_NAMES[k] for k in inactive]} must vanish for this scene")
        motion = np.concatenate([Q[list(self.active)], P[list(self.active)]]).T.reshape(-1)
        return np.concatenate([motion, np.zeros(self.n_extra)])

    def momenta(self, Q, V):
        """Nodal momenta ``p = M(q) v`` for fields ``Q`` and rates ``V`` (each ``5 x n``)."""
        q, v, m = ca.SX.sym("q", NF), ca.SX.sym("v", NF), ca.SX.sym("m", 3)
        f = ca.Function("p", [q, v, m], [ca.gradient(self.kinetic_energy(ca.vertsplit(q), ca.vertsplit(v),
                                                                          ca.vertsplit(m)), v)])
        P = np.array(f.map(self.n)(Q, V, self.inertia))
        P[self.fixed.T] = 0.0
        return P

    def unpack(self, y):
        """Fields ``(5, n)`` from one state vector (or ``(..., 5, n)`` from a stack); inactive ones are 0."""
        y = np.asarray(y)
        out = np.zeros((*y.shape[:-1], NF, self.n))
        motion = y[..., : self.ny * self.n]
        out[..., list(self.active), :] = np.swapaxes(motion.reshape(*y.shape[:-1], self.n, self.ny)[..., : self.nf], -1, -2)
        return out
