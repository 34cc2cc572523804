"""The model's limits on the discrete state (delta > 0, r > 0 off the axis, |psi| < pi/2, SVK's turning point) as one
CasADi function that must stay positive, with what and where each entry is: a part of
:class:`~mol_shell.discretization.system.ShellSystem`, which the leap-frog checks after every step and CVODE and IDA
hand to SUNDIALS' root finding. And the equations' ellipticity in ``s`` (:meth:`ModelLimits.ellipticity_margins`),
checked on saved states."""

from __future__ import annotations

import math
from functools import cached_property

import casadi as ca
import numpy as np

from mol_shell._core.errors import ParameterError

#: what each of the model's limits is, as a run that reaches it says (:meth:`ModelLimits.limit_names`; the ring ODE's,
#: :mod:`mol_shell.runs.ring`)
DELTA_REACHED = "delta = r beta1 cos(psi) reached 0"
R_REACHED = "r reached 0"
PSI_REACHED = "|psi| reached pi/2"
TURNING_REACHED = ("an in-plane stretch reached 1/sqrt(3) in compression, where the St Venant-Kirchhoff stress turns "
                   "back (a limit of the law)")


def symbol_inputs(Q):
    """``(g, m)`` of every cell of the fields ``Q`` ``(5, n)`` (NumPy or CasADi): the differences of the five fields
    and the midpoint ``(r, theta, psi)``, the inputs of :attr:`ModelLimits.principal_symbol` (difference form)."""
    return Q[:, 1:] - Q[:, :-1], (Q[[1, 3, 4], 1:] + Q[[1, 3, 4], :-1]) / 2


class ModelLimits:
    """The limits of a :class:`~mol_shell.discretization.system.ShellSystem` (a mixin: it reads the system's fields,
    edges, cell kernels and grid)."""

    @cached_property
    def limits(self):
        """``y -> g``: the model's limits as functions that must stay positive (:meth:`limit_names` says which).

        ``g = [delta at the samples of each cell; r per node; (pi/2)^2 - psi^2 per node; det(C_t - I/3) at the
        samples of each cell; the leading principal minors of each cell's principal symbol]`` (the third only when
        ``psi`` is a field; the fourth for the SVK laws without fibres:
        :func:`~mol_shell.model.material.svk_turning_limit`; the last with the scene's ``ellipticity_limit``:
        :meth:`cell_minors`). Leap-frog checks them after every step (in C),
        CVODE and IDA find their roots. Depends on the field entries only, which sit at the same
        places in ``y = (q, p)`` and in IDA's ``x = (q, v)``.
        """
        f = self.limits_mapped
        return f.expand() if self.n <= self.FLAT_MAX_NODES else f

    @cached_property
    def limits_mapped(self):
        """:attr:`limits` as a map of the cell kernels whatever ``n``: the form to compile (the flat graph of a few
        hundred nodes is tens of thousands of lines of straight C, which gcc -O3 takes a minute over)."""
        n = self.n
        y = ca.MX.sym("y", self.size)
        Q = self.tie(self._fields(ca.reshape(y[: self.ny * n], self.ny, n)))
        g = [ca.vec(self.cell_delta().map(n - 1)(Q[:, :-1], Q[:, 1:], self.cell_data)), Q[1, list(self.radial_nodes)].T]
        if 4 in self.active:
            g.append((math.pi / 2) ** 2 - Q[4, :].T ** 2)
        if self.turning_limit:
            g.append(ca.vec(self.cell_turning().map(n - 1)(Q[:, :-1], Q[:, 1:], self.cell_data)))
        if self.ellipticity_limit:
            g.append(ca.vec(self.cell_minors().map(n - 1)(*symbol_inputs(Q), self.cell_data,
                                                          ca.DM(self._natural_minors().T))))
        return ca.Function("limits", [y], [ca.vertcat(*g)], ["y"], ["g"])

    @property
    def ellipticity_limit(self):
        """Whether runs stop where the shell's equations stop being elliptic in ``s`` (the scene's
        ``ellipticity_limit``; off by default: the runs then check their saved states afterwards)."""
        return bool(getattr(self.scene, "ellipticity_limit", False))

    def cell_minors(self):
        """``(g, m, geo, K0 minors) -> the leading principal minors of the principal symbol K`` (:attr:`principal_symbol`),
        each over the natural state's: all positive exactly while ``K`` is positive definite (Sylvester), each a root
        function (a single determinant would miss two eigenvalues crossing 0 within one step, as the transverse and
        the hoop polarisations of an equibiaxially compressed sphere nearly do)."""
        a = len(self.active)
        g, m, geo, ref = ca.SX.sym("g", 5), ca.SX.sym("m", 3), ca.SX.sym("geo", self.n_cell_data), ca.SX.sym("k0", a)
        K = ca.reshape(self.principal_symbol(g, m, geo), a, a)
        minors = [ca.det(K[:k, :k]) / ref[k - 1] for k in range(1, a + 1)]
        return ca.Function("cell_minors", [g, m, geo, ref], [ca.vertcat(*minors)])

    def _natural_minors(self):
        """``(n - 1, a)``: the leading principal minors of each cell's ``K`` at the natural state."""
        K0 = self._natural_symbols
        minors = np.stack([np.linalg.det(K0[:, :k, :k]) for k in range(1, K0.shape[1] + 1)], axis=1)
        if not np.all(minors > 0):
            raise ParameterError("ellipticity_limit", True, "false for this scene",
                                 hint="its natural state's principal symbol is not positive definite in every cell")
        return minors

    def limit_names(self):
        """``(what, where)`` for each entry of :attr:`limits`."""
        cells = (self.s[:-1] + self.s[1:]) / 2
        names = [(DELTA_REACHED, f"s = {s:.6g} m (cell centre)") for s in np.repeat(cells, self.samples_per_cell)]
        names += [(R_REACHED, f"s = {self.s[i]:.6g} m") for i in self.radial_nodes]
        if 4 in self.active:
            names += [(PSI_REACHED, f"s = {s:.6g} m") for s in self.s]
        if self.turning_limit:
            names += [(TURNING_REACHED, f"s = {s:.6g} m (cell centre)")
                      for s in np.repeat(cells, self.samples_per_cell)]
        if self.ellipticity_limit:
            what = ("the shell's equations stopped being elliptic in s (d2W/d(q_s)2 is no longer positive definite: "
                    "compression beyond what a shear carries; ellipticity_limit)")
            names += [(what, f"s = {s:.6g} m (cell centre)") for s in np.repeat(cells, len(self.active))]
        return names

    def energy_not_finite(self, y):
        """``(law, where, detail)`` for the first cell whose stored energy is not finite at the finite state ``y``, or
        ``None``: the law's energy outside its domain there (a law of one's own with ``log(I1 - 2.9)`` on a compressed
        start). ``law`` names it (``material 'NAME'``, or the wall's ``layers``); ``detail`` gives the cell's energy
        and the mid-surface stretches there, along the meridian and round it. One evaluation of the cell energies,
        made where the total is not finite (a check of the run: its start, a saved time), never in the stepping."""
        Q = self.tie(self.unpack(np.asarray(y, dtype=float)))
        with np.errstate(all="ignore"):
            cells = self._cell_observables().map(self.n - 1)(Q[:, :-1], Q[:, 1:], self.cell_data)[0]
            energies = np.array(cells, dtype=float).ravel()
            bad = np.flatnonzero(~np.isfinite(energies))
            if not bad.size:
                return None
            i = int(bad[0])
            z0, r0 = self.reference[0], self.reference[1]
            meridian = math.hypot(Q[0, i + 1] - Q[0, i], Q[1, i + 1] - Q[1, i]) / math.hypot(z0[i + 1] - z0[i],
                                                                                              r0[i + 1] - r0[i])
            hoop = (Q[1, i] + Q[1, i + 1]) / (r0[i] + r0[i + 1])
        layers = str(getattr(self.scene, "layers", "") or "").strip()
        law = f"the wall's layers ({layers!r})" if layers else f"material {str(self.scene.material)!r}"
        where = f"s = {(self.s[i] + self.s[i + 1]) / 2:.6g} m (cell centre)"
        detail = (f"{energies[i]:g} J in that cell, at the stretches {meridian:.4g} along the meridian and {hoop:.4g} "
                  "round it")
        why = self._thickness_unsolved(Q, i)
        return law, where, detail + (f"; {why}" if why else "")

    def _thickness_unsolved(self, Q, i):
        """Why the law's thickness treatment has no solution in cell ``i`` of the fields ``Q`` (a plane-stress law of
        one's own with no root ``C_22 > 0``, or one its Newton steps do not reach: ``Law.unsolved``), at the first
        thickness point where it has none; ``None`` for the other laws, a layered wall, or where it has one."""
        law = self.law
        if law is None or self.layer_laws is not None or law.unsolved is None:
            return None
        with np.errstate(all="ignore"):
            points = np.array(self.cell_point_tensors()(Q[:, i], Q[:, i + 1], self.cell_data[:, i]), dtype=float)
        for c11, c33, c13, c12, c23 in points.T:
            why = law.unsolved(((c11, c12, c13), (c12, 1.0, c23), (c13, c23, c33)), self.law_params)
            if why:
                return why
        return None

    @cached_property
    def principal_symbol(self):
        """``(g, m, geo) -> vec K`` of one cell (map it over the cells): ``K = d2W/dg2``, the Hessian of one sample's stored energy
        (:meth:`sample_energy`) in the derivatives ``g = (z_s, r_s, chi_s, theta_s, psi_s)`` of the active fields at
        fixed ``m = (r, theta, psi)``: the principal symbol of the shell's equations in ``s``."""
        g, m, geo = ca.SX.sym("g", 5), ca.SX.sym("m", 3), ca.SX.sym("geo", self.n_cell_data)
        active = list(self.active)
        K = ca.hessian(self.sample_energy((*ca.vertsplit(g), *ca.vertsplit(m)), geo), g)[0][active, active]
        return ca.Function("principal_symbol", [g, m, geo], [ca.vec(K)])

    def _symbols(self, Qs):
        """``K`` of every cell of each state of the stack ``Qs`` ``(T, 5, n)``: ``(T, n - 1, a, a)``."""
        T, a, cells = Qs.shape[0], len(self.active), self.n - 1
        G, M = (np.hstack(parts) for parts in zip(*(symbol_inputs(Q) for Q in Qs)))
        K = np.array(self.principal_symbol.map(T * cells)(G, M, np.tile(self.cell_data, (1, T))))
        return K.T.reshape(T, cells, a, a)

    def ellipticity_margins(self, Qs):
        """The smallest eigenvalue of each cell's principal symbol ``K`` (:attr:`principal_symbol`) relative to the
        natural state's ``K_0`` turned with the cell, ``min eig(K_0^-1/2 R^T K R K_0^-1/2)`` (``R`` turns ``(z_s, r_s)``
        by the cell's rotation in the meridian plane, ``theta - theta0`` at its midpoint, so that a rotation alone
        leaves 1), for fields ``Qs`` ``(5, n)`` or a stack ``(T, 5, n)``: ``(n - 1,)`` or ``(T, n - 1)``.

        The shell's equations are hyperbolic (elliptic in ``s``) while it is positive (the Legendre-Hadamard
        condition of the 1-D shell). Where it reaches 0 a compressive membrane force has exceeded what a shear
        carries (for the director-constrained SVK law under equibiaxial compression, the stretch
        ``a^2 = (l + mu) / (l + 2 mu)``, Lame's ``l``: 1 % at ``nu = 0.49``, in the hoop polarisation); beyond it
        waves short enough grow at a rate that rises with their wavenumber (elastic) or at ``|K| / eta`` (viscous):
        results depend on the grid. NaN in cells where ``K_0`` is not positive definite and for states that are not
        finite.
        """
        Qs = np.asarray(Qs, dtype=float)
        single = Qs.ndim == 2
        Qs = Qs[None] if single else Qs
        finite = np.all(np.isfinite(Qs), axis=(1, 2))
        Qs = np.where(finite[:, None, None], Qs, self._natural_fields()[None])
        K = self._symbols(Qs)
        active = list(self.active)
        if 0 in active and 1 in active:  # turn each cell's K back by its rotation in the meridian plane
            i, j = active.index(0), active.index(1)
            turn = (Qs[:, 3, 1:] + Qs[:, 3, :-1] - self.reference[2][1:] - self.reference[2][:-1]) / 2
            R = np.broadcast_to(np.eye(len(active)), K.shape).copy()
            R[..., i, i], R[..., i, j], R[..., j, i], R[..., j, j] = np.cos(turn), -np.sin(turn), np.sin(turn), np.cos(turn)
            K = np.swapaxes(R, -1, -2) @ K @ R
        root, ok = self._natural_root
        scaled = root @ K @ np.swapaxes(root, -1, -2)
        valid = np.all(np.isfinite(scaled), axis=(-2, -1))  # stiffnesses that under- or overflow: not checked
        scaled = np.where(valid[..., None, None], scaled, np.eye(scaled.shape[-1]))
        margins = np.linalg.eigvalsh(scaled).min(axis=-1)
        margins = np.where(ok[None] & finite[:, None] & valid, margins, np.nan)
        return margins[0] if single else margins

    @cached_property
    def _natural_symbols(self):
        """``K_0``: each cell's principal symbol at the natural state, ``(n - 1, a, a)``."""
        return self._symbols(self._natural_fields()[None])[0]

    @cached_property
    def _natural_root(self):
        """``(M per cell, whether K_0 is positive definite there)`` with ``M K_0 M^T = I``: the margins are the
        eigenvalues of ``M K M^T``. ``K_0`` is scaled by its diagonal first (``S = D^-1 K_0 D^-1``, ``M =
        S^-1/2 D^-1``): its entries mix units (membrane ``~E h``, bending ``~E h^3``), and the test that ``S`` is
        positive definite in double precision (each eigenvalue above the rounding of the largest, ``size x eps x``
        it, the backward error of ``eigh``) must not depend on them. Without the scaling a 10 um sphere lost every
        cell; with ``> 0`` as the test a wall with ``h / R = 6e-13`` was checked on one LAPACK build, not another."""
        K0 = self._natural_symbols
        d = np.sqrt(np.abs(np.einsum("cii->ci", K0)))
        d = np.where(d > 0, d, 1.0)
        S = K0 / d[:, :, None] / d[:, None, :]
        finite = np.all(np.isfinite(S), axis=(1, 2))  # a law whose second derivatives under- or overflow (E ~ 1e-160)
        w, V = np.linalg.eigh(np.where(finite[:, None, None], S, np.eye(S.shape[-1])))
        ok = finite & (w.min(axis=1) > w.shape[-1] * np.finfo(float).eps * np.abs(w).max(axis=1))
        root = np.einsum("cij,cj,ckj->cik", V, 1 / np.sqrt(np.where(w > 0, w, 1.0)), V)
        return root / d[:, None, :], ok

    def _natural_fields(self):
        """The reference (natural) state's fields ``(5, n)``."""
        Q = np.zeros((5, self.n))
        Q[0], Q[1], Q[3] = self.reference
        return Q

    @property
    def radial_nodes(self):
        """Nodes where ``r > 0`` is a limit of the model: all but the poles (where ``r = 0`` is imposed)."""
        poles = {0 if self.edges[0] == "pole" else -1, self.n - 1 if self.edges[1] == "pole" else -1}
        return np.array([i for i in range(self.n) if i not in poles], dtype=int)


__all__ = ["DELTA_REACHED", "PSI_REACHED", "R_REACHED", "TURNING_REACHED", "ModelLimits"]
