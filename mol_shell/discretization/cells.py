"""The cell kernels of the discretised shell: strains at a cell's samples, its stored energy and dissipation.

A mixin of :class:`~mol_shell.discretization.system.ShellSystem` (which holds the material, the thickness rule,
the active fields and the per-cell geometry data ``cell_data``). Each cell ``[s_i, s_{i+1}]`` is sampled
twice (``psi`` at each node, ``r`` and ``theta`` at the midpoint, derivatives as differences: ``ds = 1``
in the kernel), the thickness integral either by the readable per-point reference form or by the
per-cell moments of the same Gauss rule (``reference=False``, the default, equal to round-off). See the
module docstring of :mod:`mol_shell.discretization` for the scheme.
"""

from __future__ import annotations

import math
from functools import cached_property

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ParameterError
from mol_shell.model.fibres import fibre_thickness_energy
from mol_shell.model.hyperelastic import (
    incompressible_dissipation,
    law_thickness_energy,
    law_thickness_values,
    shell_cauchy_green,
)
from mol_shell.model.kinematics import column_polynomials, delta
from mol_shell.model.laws import SVK_LAW
from mol_shell.model.material import (
    svk_turning_limit,
    thickness_dissipation,
    thickness_dissipation_moments,
    thickness_energy,
    thickness_energy_moments,
    thickness_moments,
)

#: |beta2_0| below this (relative to beta1_0) is an exact zero: straight generators leave it out of the kernel
BETA2_ZERO = 1e-13


def solve_stages(values):
    """The ``exp``, ``log`` and division operations of per-point iterative solves, rank by rank across the points.

    ``values``: SX scalars, the solves' results. A node's rank is the number of these slow operations on the
    longest path from the inputs to it, itself included; returns ``[[the rank-1 nodes], [the rank-2 nodes], ...]``.
    A kernel listing these as outputs before its own is compiled in that order (CasADi sorts depth first from
    the outputs): the points' chains of dependent operations side by side, which the processor overlaps,
    rather than one point's whole chain after another's.
    """
    slow = (ca.OP_EXP, ca.OP_LOG, ca.OP_DIV)  # long latencies (divisions: the steps', C_22's)
    rank, by_rank = {}, {}
    stack = list(values)
    while stack:  # iterative depth-first ranking (the chains are long)
        x = stack[-1]
        key = x.element_hash()
        if key in rank:
            stack.pop()
            continue
        deps = [x.dep(i) for i in range(x.n_dep())] if not (x.is_symbolic() or x.is_constant()) else []
        todo = [d for d in deps if d.element_hash() not in rank]
        if todo:
            stack.extend(todo)
            continue
        stack.pop()
        r = max((rank[d.element_hash()] for d in deps), default=0)
        if any(x.is_op(op) for op in slow):
            r += 1
            by_rank.setdefault(r, []).append(x)
        rank[key] = r
    return [by_rank[r] for r in sorted(by_rank)]


def trig_chain(t, g):
    """``dV/dq`` contributed through a node's trigonometric values ``t`` (:meth:`CellKernels.node_trig_kernel`).

    ``g = dV/dt``; ``t = (cos psi, sin psi, cos theta/2, sin theta/2)``, so only ``theta`` and ``psi`` receive.
    """
    return ca.vertcat(0, 0, 0, 0.5 * (t[2] * g[3] - t[3] * g[2]), t[0] * g[1] - t[1] * g[0])



def sample_trigs(tl, tr):
    """The two samples' ``(cos theta, sin theta, cos psi, sin psi)`` from their nodes' :meth:`~CellKernels.node_trig_kernel`
    values: ``theta`` at the midpoint (its cosine and sine as products of the half angles'), ``psi`` at each node."""
    cos_mid, sin_mid = tl[2] * tr[2] - tl[3] * tr[3], tl[3] * tr[2] + tl[2] * tr[3]
    return [(cos_mid, sin_mid, t[0], t[1]) for t in (tl, tr)]


def cell_samples(ql, qr, both=True):
    """Strains ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)`` at the samples of a cell, in difference form.

    ``ql, qr`` index the five fields first (CasADi vectors, or NumPy arrays of shape ``(5, ...)``).
    Differences ``q_{i+1} - q_i`` for the derivatives (``ds`` times them: the kernel works with
    ``ds = 1``), midpoint averages for ``r`` and ``theta``, and ``psi`` at the left and at the
    right node (see the module's docstring); ``both=False``: the one sample of a scene without ``psi``
    (the two coincide). Linear in ``(ql, qr)``, so the same map turns nodal rates into the samples'
    strain rates.
    """
    grad = qr - ql
    mid = (qr + ql) / 2
    if not both:
        return ((grad[0], grad[1], grad[2], grad[3], grad[4], mid[1], mid[3], mid[4]),)
    return tuple((grad[0], grad[1], grad[2], grad[3], grad[4], mid[1], mid[3], node[4]) for node in (ql, qr))

class CellKernels:
    """Cell-level kernels of :class:`~mol_shell.discretization.system.ShellSystem` (a mixin).

    ``law``/``law_params`` (:func:`~mol_shell.model.laws.law_parameters`): ``None`` for the SVK materials (their
    Lame pair ``lam, mu`` and thickness moments), else the law integrated point by point in every kernel.
    """

    law = law_params = fibres = graded = layer_laws = None

    def _law_energy(self, e, factors, beta2_0, trig=None):
        """``sum_q vol_q W(C_q)`` of the law, or of a layered wall layer by layer (each its ``n_quad`` points)."""
        if self.layer_laws is None:
            return law_thickness_energy(e, self.law, self.law_params, factors, beta2_0, trig)
        nq, total = self.scene.n_quad, 0.0
        for k, (law, params, fibres) in enumerate(self.layer_laws):
            part = factors[k * nq:(k + 1) * nq]
            total = total + law_thickness_energy(e, law, params, part, beta2_0, trig)
            if fibres is not None:
                total = total + fibre_thickness_energy(e, fibres, part, beta2_0, trig)
        return total

    def _fibre_energy(self, samples, factors, beta2_0, trigs=None):
        """The fibres' stored energy of a cell (:mod:`mol_shell.model.fibres`), 0 without fibres (not in the graph)."""
        if self.fibres is None:
            return 0.0
        trigs = trigs or [None] * len(samples)
        return sum(fibre_thickness_energy(e, self.fibres, factors, beta2_0, trig)
                   for e, trig in zip(samples, trigs)) / len(samples)

    def _cell_data(self):
        """Per-cell kernel data (columns): ``(j1, j3, vol)`` at each thickness point, then ``beta2_0`` if curved.

        From the nodal reference coordinates by the cell's own difference and midpoint formulas, in
        difference form (``ds = 1``); ``vol`` includes the factor ``2 pi``. Refuses a thickness
        interval that reaches the axis or a centre of curvature (``det G0 <= 0``).
        """
        z0, r0, th0 = self.reference
        dz, dr, dth = np.diff(z0), np.diff(r0), np.diff(th0)
        thm, r0m = (th0[1:] + th0[:-1]) / 2, (r0[1:] + r0[:-1]) / 2
        beta1 = dz * np.cos(thm) + dr * np.sin(thm)
        beta2 = -dz * np.sin(thm) + dr * np.cos(thm)
        rows = []
        nodes_weights = self.thickness.nodes_weights
        if self.graded is not None:  # each cell its own interval [-h, h] about the mid-surface (arrays over cells)
            hc = self.graded((self.s[1:] + self.s[:-1]) / 2)
            if self.layer_laws is None:
                x, w = np.polynomial.legendre.leggauss(self.thickness.n_quad)
                nodes_weights = ([hc * xq for xq in x], [hc * wq for wq in w])
            else:  # the layers keep their shares of the wall: the nominal [-h, h] scaled to the cell's
                scale = hc / self.scene.h
                nodes_weights = tuple([scale * v for v in values] for values in nodes_weights)
        for zeta, w in zip(*nodes_weights):
            a, c = beta1 - zeta * dth, r0m + zeta * np.cos(thm)
            if np.any(a <= 0) or np.any(c <= 0):
                if self.graded is not None:  # zeta and the faces are arrays over the cells: name the first cell
                    k = int(np.flatnonzero((a <= 0) | (c <= 0))[0])
                    raise ParameterError("h_profile", self.scene.h_profile, "values whose h(s) keeps every cell's "
                                         "thickness interval off the axis and inside every centre of curvature",
                                         hint=f"h = {hc[k]:.4g} m in the cell at s = {(self.s[k] + self.s[k + 1]) / 2:.4g}"
                                         " m has a non-positive volume element")
                h, z1 = self.scene.h, self.thickness.zeta1
                raise ParameterError("h", h, "values whose thickness interval stays off the axis and inside every "
                                     "centre of curvature", hint=f"zeta1 = {z1:.4g} m: the face at zeta = {zeta:.4g} m "
                                     "has a non-positive volume element")
            rows += [1.0 / a, 1.0 / c, 2 * math.pi * w * a * c]
        self.curved = bool(np.any(np.abs(beta2) > BETA2_ZERO * np.abs(beta1)))
        if self.curved:
            rows.append(beta2)
        nq = self.thickness.n_quad
        zetas = nodes_weights[0]
        rows += thickness_moments([(zetas[q], rows[3 * q], rows[3 * q + 1], rows[3 * q + 2]) for q in range(nq)])
        if self.graded is not None:
            rows += list(zetas)  # the cells' thickness points: data of the kernels (a graded wall only)
        return np.array([np.broadcast_to(row, beta1.shape) for row in rows])

    def _factors(self, data):
        """``quadrature_factors``-like tuples from a symbolic per-cell data column, and ``beta2_0``."""
        return self._factors_and_moments(data)[:2]

    def shared_moments(self, geo):
        """``(beta2_0, thickness moments)`` from a column of :attr:`shared_cell_data` (every row of the cell data
        for a law or fibres; else ``beta2_0`` if curved, then the moments)."""
        if self.law is not None or self.fibres is not None:
            return self._factors_and_moments(geo)[1:]
        start = int(self.curved)
        return (geo[0] if self.curved else 0.0), [geo[k] for k in range(start, start + 22)]

    def _factors_and_moments(self, data):
        """:meth:`_factors` and the thickness moments (:func:`~mol_shell.model.material.thickness_moments`) of a cell."""
        nq = self.thickness.n_quad
        start = 3 * nq + int(self.curved)
        zetas = self.thickness.nodes_weights[0]
        end = start + 22  # the 22 moments (thickness_moments)
        if self.graded is not None:  # the points are the cell's, after its moments
            zetas = [data[end + q] for q in range(nq)]
        factors = [(zetas[q], data[3 * q], data[3 * q + 1], data[3 * q + 2]) for q in range(nq)]
        return factors, (data[3 * nq] if self.curved else 0.0), [data[k] for k in range(start, end)]

    # -- kernels -------------------------------------------------------------------------
    #: CasADi differentiates a mapped kernel through the kernel's own Jacobian instead of one
    #: forward sweep per colour of the whole Jacobian (15-18 at n = 40): the generated C of the
    #: exact Jacobian is 2.5x smaller and gcc needs 3.2 s instead of 10.8 s for the cell part
    KERNEL_OPTIONS = {"enable_forward": False}

    @property
    def n_cell_data(self):
        return self.cell_data.shape[0]

    def cell_energy(self, ql, qr, data, reference=None):
        """Stored energy of the cell ``[s_i, s_{i+1}]``: the mean over its samples of ``2 pi int W det G0 dzeta``.

        ``reference`` (default: the system's choice) selects the readable per-point form. The moments form
        is for the forces: its value sums O(1) terms to an O(strain^2) energy and keeps ~1e-12 relative
        accuracy, its gradient ~1e-14; the observables' stored energy uses the per-point form.
        """
        samples = self.cell_samples(ql, qr)
        return sum(self.sample_energy(e, data, reference) for e in samples) / len(samples)

    def sample_energy(self, e, data, reference=None):
        """``2 pi int W det G0 dzeta`` at one sample's strains ``e = (z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)``
        (difference form) with a cell's data column: the law's, or SVK's per point or by its moments, and the fibres'."""
        factors, beta2_0, moments = self._factors_and_moments(data)
        fibres = self._fibre_energy((e,), factors, beta2_0)
        if self.law is not None:  # any other law: per thickness point in both forms
            return self._law_energy(e, factors, beta2_0) + fibres
        if self.reference_kernel if reference is None else reference:
            return thickness_energy(e, self.lam, self.mu, factors, beta2_0) + fibres
        return thickness_energy_moments(e, self.lam, self.mu, moments, beta2_0) + fibres

    @property
    def samples_per_cell(self):
        """Where ``What`` is sampled in a cell: 2 (``psi`` at each node), 1 when ``psi`` is not a field."""
        return 2 if 4 in self.active else 1

    def cell_samples(self, ql, qr):
        """:func:`cell_samples` of this model: one sample when ``psi`` is not a field."""
        return cell_samples(ql, qr, both=4 in self.active)

    def _cell_symbols(self):
        return ca.SX.sym("ql", NF), ca.SX.sym("qr", NF), ca.SX.sym("geo", self.n_cell_data)

    def cell_forces_kernel(self):
        """``(q_left, q_right, geo) -> (dV/dq_left, dV/dq_right)``: the cell's elastic forces on its nodes."""
        ql, qr, geo = self._cell_symbols()
        energy = self.cell_energy(ql, qr, geo)
        forces = [ca.gradient(energy, ql), ca.gradient(energy, qr)]
        if not self.reference_kernel:
            forces = ca.cse(forces)  # the two samples share their differences, midpoints and trigonometry
        return ca.Function("cell", [ql, qr, geo], forces, self.KERNEL_OPTIONS)

    def node_trig_kernel(self):
        """``q -> (cos psi, sin psi, cos theta/2, sin theta/2)`` of a node, computed once per node and evaluation.

        The lean RHS passes them to the node's kernel and to both of its cells (whose midpoint angle
        ``(theta_l + theta_r)/2`` has its cosine and sine as products of the half angles'): two ``sincos``
        per node instead of two per node kernel and three per cell.
        """
        q = ca.SX.sym("q", NF)
        return ca.Function("node_trig", [q], [ca.vertcat(ca.cos(q[4]), ca.sin(q[4]), ca.cos(q[3] / 2),
                                                         ca.sin(q[3] / 2))])

    @cached_property
    def shared_cell_data(self):
        """The rows of :attr:`cell_data` that :meth:`cell_forces_shared_kernel` reads (``beta2_0`` if curved, the
        thickness moments); one column when every cell has the same (a cylinder), broadcast by the map.

        At n = 10,240 the full table is 2.8 MB, more than the cache: passing only these rows, once for a uniform
        meridian, keeps a leap-frog step's data in cache.
        """
        per_point = self.law is not None or self.fibres is not None
        rows = self.cell_data[0 if per_point else 3 * self.thickness.n_quad:, :]  # a law or fibres: every row
        return rows[:, :1] if np.all(rows == rows[:, :1]) else rows

    def cell_forces_shared_kernel(self, staged=False):
        """:meth:`cell_forces_kernel` taking the nodes' :meth:`node_trig_kernel` values: ``(ql, qr, tl, tr, geo)``.

        The energy is built on the trigonometric values as inputs; the chain rule back to ``theta`` and
        ``psi`` is applied inside, so the outputs are the same forces ``dV/dq`` to round-off. ``staged``: a law
        with a plane-stress solve lists its :func:`solve_stages` as outputs before the forces (the same
        arithmetic, in an order that runs the thickness points' solves side by side; the forces are the last
        two outputs, the stages are for no one and cost nothing in a map that leaves them unused).
        """
        ql, qr, _ = self._cell_symbols()
        tl, tr = ca.SX.sym("tl", 4), ca.SX.sym("tr", 4)
        geo = ca.SX.sym("geo", self.shared_cell_data.shape[0])  # beta2_0 if curved, the moments (a law: every row)
        samples = self.cell_samples(ql, qr)  # psi at the left node, then the right (one sample: psi = 0)
        trigs = sample_trigs(tl, tr)
        envelope, stages = None, []
        if self.law is not None and self.law.thickness != "director" and self.layer_laws is None:  # C_22 held
            factors, beta2_0, _ = self._factors_and_moments(geo)
            solved = [law_thickness_values(e, self.law, self.law_params, factors, beta2_0, trig)
                      for e, trig in zip(samples, trigs)]  # per sample, per point: C_22 (and the law's own values)
            held = [[tuple(ca.SX.sym(f"c22_{k}_{q}_{i}") for i in range(len(values)))
                     for q, values in enumerate(points)] for k, points in enumerate(solved)]
            energy = sum(law_thickness_energy(e, self.law, self.law_params, factors, beta2_0, trig, values)
                         for e, trig, values in zip(samples, trigs, held)) / len(samples)
            envelope = tuple(ca.vertcat(*[x for points in every for values in points for x in values])
                             for every in (held, solved))
            if staged:
                stages = [ca.vertcat(*nodes) for nodes in solve_stages(ca.vertsplit(envelope[1]))]
        elif self.law is not None:
            factors, beta2_0, _ = self._factors_and_moments(geo)
            energy = sum(self._law_energy(e, factors, beta2_0, trig) for e, trig in zip(samples, trigs)) / len(samples)
        elif self.fibres is not None:  # SVK's moments, then the fibres point by point
            factors, beta2_0, moments = self._factors_and_moments(geo)
            energy = sum(thickness_energy_moments(e, self.lam, self.mu, moments, beta2_0, trig)
                         for e, trig in zip(samples, trigs)) / len(samples)
        else:
            beta2_0, moments = self.shared_moments(geo)
            energy = sum(thickness_energy_moments(e, self.lam, self.mu, moments, beta2_0, trig)
                         for e, trig in zip(samples, trigs)) / len(samples)
        if self.fibres is not None:
            energy = energy + self._fibre_energy(samples, factors, beta2_0, trigs)
        forces = [ca.gradient(energy, q) + trig_chain(t, ca.gradient(energy, t)) for q, t in ((ql, tl), (qr, tr))]
        if envelope is not None:  # dW/dC_22 = 0 there: the gradient at the condensed C_22 needs no dC_22/dq (the
            forces = ca.vertsplit(ca.substitute(ca.vertcat(*forces), *envelope), [0, NF, 2 * NF])  # (the Jacobian,
            # differentiating this, still gets dC_22/dq)
        outputs = ca.cse(stages + forces)
        return ca.Function("cell", [ql, qr, tl, tr, geo], outputs, self.KERNEL_OPTIONS)

    def _cell_observables(self):
        """``(q_left, q_right, geo) -> (V_cell, ds x delta at the cell's samples)``."""
        ql, qr, geo = self._cell_symbols()
        deltas = [delta(z_s, r_s, r, theta, psi) for z_s, r_s, _, _, _, r, theta, psi in self.cell_samples(ql, qr)]
        return ca.Function("cell_observables", [ql, qr, geo], [self.cell_energy(ql, qr, geo, reference=True),
                                                               ca.vertcat(*deltas)])

    @property
    def turning_limit(self):
        """Whether the runs watch SVK's compressive turning point (:func:`~mol_shell.model.material.svk_turning_limit`):
        for the SVK laws without fibres (their own kernel), and for a layered wall with a layer of one (the criterion
        is the in-plane stretch of the base surface, which every layer shares, whatever the layers' moduli and the other
        layers' laws: layered walls ran past it before), unless the scene's ``law_limit`` is off (docs/materials.md)."""
        if self.layer_laws is not None:
            svk = any(law is SVK_LAW and fibres is None for law, _, fibres in self.layer_laws)
        else:
            svk = self.law is None and self.fibres is None
        return svk and bool(getattr(self.scene, "law_limit", True))

    def cell_turning(self):
        """``(q_left, q_right, geo) -> det(C_t - I/3)`` at the cell's samples (must stay > 0; SVK only)."""
        ql, qr, geo = self._cell_symbols()
        _, beta2_0, moments = self._factors_and_moments(geo)
        values = [svk_turning_limit(e, moments, beta2_0) for e in self.cell_samples(ql, qr)]
        return ca.Function("cell_turning", [ql, qr, geo], [ca.vertcat(*values)])

    def cell_point_tensors(self):
        """``(q_left, q_right, geo) -> (C_11, C_33, C_13, C_12, C_23)`` at each thickness point of each of the cell's
        samples, a column each (``C_22 = 1``, the director's, for the law's treatment to set): where a run stopped,
        to say why the law's thickness has no solution there
        (:meth:`~mol_shell.discretization.limits.ModelLimits.energy_not_finite`)."""
        ql, qr, geo = self._cell_symbols()
        factors, beta2_0, _ = self._factors_and_moments(geo)
        columns = []
        for e in self.cell_samples(ql, qr):
            a, b, c, d, c2 = column_polynomials(e, beta2_0)
            for zeta, j1, j3, _ in factors:
                C = shell_cauchy_green(a, b, c, d, c2, zeta, j1, j3)
                columns.append(ca.vertcat(C[0][0], C[2][2], C[0][2], C[0][1], C[1][2]))
        return ca.Function("cell_point_tensors", [ql, qr, geo], [ca.horzcat(*columns)])

    def cell_delta(self):
        """``(q_left, q_right, geo) -> ds x delta``, ``delta = r beta1 cos(psi)`` at the cell's samples (must stay > 0)."""
        ql, qr, geo = self._cell_symbols()
        return ca.Function("cell_delta", [ql, qr, geo], [self._cell_observables()(ql, qr, geo)[1]])

    @property
    def incompressible_viscosity(self):
        """Whether the Kelvin-Voigt stress follows ``det C = 1``
        (:func:`~mol_shell.model.hyperelastic.incompressible_dissipation`, ``eta_mu`` alone): a single incompressible
        law. A layered wall keeps the condensed pair of the scene's material for every layer
        (:func:`~mol_shell.model.laws.viscosities`), as before."""
        return self.law is not None and self.law.thickness == "incompressible" and self.layer_laws is None

    def cell_dissipation(self, ql, qr, vl, vr, data, reference=None):
        """Rayleigh function of the cell (Kelvin-Voigt), sampled like :meth:`cell_energy`; ``2 D`` is its power.

        An incompressible law (:attr:`incompressible_viscosity`): ``eta_mu E_t : E_t`` with the thickness rate that
        ``det C = 1`` sets, point by point in both forms
        (:func:`~mol_shell.model.hyperelastic.incompressible_dissipation`). Every other law (and a layered wall)
        takes the pair ``(eta_lambda, eta_mu)`` condensed as the scene's material asks, in the thickness moments'
        form (:func:`~mol_shell.model.material.thickness_dissipation_moments`, the same quadrature to round-off);
        ``reference`` (default: the system's choice) selects the per-point form.
        """
        factors, beta2_0, moments = self._factors_and_moments(data)
        pairs = list(zip(self.cell_samples(ql, qr), self.cell_samples(vl, vr)))
        if self.incompressible_viscosity:
            return sum(incompressible_dissipation(e, e_t, self.eta_mu, factors, beta2_0)
                       for e, e_t in pairs) / len(pairs)
        if self.reference_kernel if reference is None else reference:
            return sum(thickness_dissipation(e, e_t, self.eta_lambda, self.eta_mu, factors, beta2_0)
                       for e, e_t in pairs) / len(pairs)
        return sum(thickness_dissipation_moments(e, e_t, self.eta_lambda, self.eta_mu, moments, beta2_0)
                   for e, e_t in pairs) / len(pairs)

    def viscous_forces_kernel(self):
        """``(q_left, q_right, v_left, v_right, geo) -> (dD/dv_left, dD/dv_right, 2 D)``: the cell's viscous forces
        and the power they dissipate (``D`` is quadratic in the rates: ``2 D = v . dD/dv``)."""
        ql, qr, geo = self._cell_symbols()
        vl, vr = ca.SX.sym("vl", NF), ca.SX.sym("vr", NF)
        D = self.cell_dissipation(ql, qr, vl, vr, geo)
        return self._viscous_outputs("viscous", D, [ql, qr, vl, vr, geo])

    def viscous_forces_shared_kernel(self):
        """:meth:`viscous_forces_kernel` on the nodes' trigonometry (:meth:`node_trig_kernel`) and the shared cell
        data (:attr:`shared_cell_data`): ``(q_left, q_right, v_left, v_right, t_left, t_right, geo)``: the
        thickness moments' form, or an incompressible law's per-point one (:meth:`cell_dissipation`)."""
        ql, qr, _ = self._cell_symbols()
        vl, vr = ca.SX.sym("vl", NF), ca.SX.sym("vr", NF)
        tl, tr = ca.SX.sym("tl", 4), ca.SX.sym("tr", 4)
        geo = ca.SX.sym("geo", self.shared_cell_data.shape[0])
        pairs = list(zip(self.cell_samples(ql, qr), self.cell_samples(vl, vr), sample_trigs(tl, tr)))
        if self.incompressible_viscosity:  # a law's shared data hold every row of the cell data
            factors, beta2_0, _ = self._factors_and_moments(geo)
            D = sum(incompressible_dissipation(e, e_t, self.eta_mu, factors, beta2_0, trig)
                    for e, e_t, trig in pairs) / len(pairs)
        else:
            beta2_0, moments = self.shared_moments(geo)
            D = sum(thickness_dissipation_moments(e, e_t, self.eta_lambda, self.eta_mu, moments, beta2_0, trig)
                    for e, e_t, trig in pairs) / len(pairs)
        return self._viscous_outputs("viscous_shared", D, [ql, qr, vl, vr, tl, tr, geo])

    def _viscous_outputs(self, name, D, inputs):
        """The kernel ``inputs -> (dD/dv_left, dD/dv_right, 2 D)`` (``2 D = v . dD/dv``, ``D`` quadratic in ``v``)."""
        vl, vr = inputs[2], inputs[3]
        fl, fr = ca.gradient(D, vl), ca.gradient(D, vr)
        return ca.Function(name, inputs, ca.cse([fl, fr, ca.dot(vl, fl) + ca.dot(vr, fr)]), self.KERNEL_OPTIONS)

