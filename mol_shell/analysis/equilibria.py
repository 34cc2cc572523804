"""The equations at rest of a discretised shell as functions of one load parameter, for path following.

At rest (``p = 0``) Hamilton's equations reduce to ``0 = F(q, lambda) = -dV/dq + f(q) + lambda g(q)`` on the free
coordinates: ``f`` the scene's other loads, ``g`` the generalised force of the continued load at unit magnitude.
Every load of :mod:`mol_shell.discretization.loading` is linear in its magnitude at fixed ``q`` (pressure
``p dVol/dq``, gravity, end forces and torques), so this is exact, not a linearisation: ``F`` is the momentum
rate of the scene's graph with the continued load switched off plus ``lambda`` times the unit load's forces, built
from the same :func:`~mol_shell.discretization.loading.load_terms` as the dynamics. ``dF/dq`` and
``dF/dlambda = g(q)`` are CasADi's exact derivatives of that one graph (SX, or MX above
:attr:`ShellSystem.FLAT_MAX_NODES <mol_shell.discretization.system.ShellSystem.FLAT_MAX_NODES>` nodes), returned
as sparse matrices; nothing here is dense.

Rigid motions: axial translation when no edge imposes ``z``, spin about the axis when no edge imposes ``chi``
(a pole's tied ``chi`` does not). They make ``dF/dq`` singular at every ``q``. A gauge removes each: the ``z``
(or ``chi``) of one node is held and its equation dropped; the dropped equation is the sum of the others when
the loads are self-equilibrated in that direction (a pressure on a closed shell is), which is checked: a load
that pushes a shell no edge holds has no equilibrium and is refused.

The work of the continued load along a path is ``int lambda dPhi`` with ``Phi`` its conjugate displacement
(``dPhi/dq = g``): the enclosed volume for pressure (closed by lids in the edges' planes on an open shell),
``-sum (mA z + mI d.k)`` for gravity, the edge's ``z`` for an end force, its ``chi`` for an end torque.
"""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ParameterError
from mol_shell.discretization.loading import check_end_loads, load_terms, volume_sign
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.loads import cell_volume, gravity_potential
from mol_shell.runs.checks import check_system, resolve
from mol_shell.runs.statics import UNBALANCED, rigid_motions, sparse_evaluator
from mol_shell.scenes import DISPLACEMENTS, DRIVES, LOADS, UNITS

#: the loads a path can be continued in (drag is not a load at rest)
PATH_LOADS = tuple(load for load in LOADS if load != "drag")
#: what a path can be continued in: a load, or a static edge displacement (displacement control)
PATH_PARAMETERS = PATH_LOADS + DISPLACEMENTS
#: units of each load's conjugate displacement ``Phi``; of an edge displacement's conjugate reaction
CONJUGATE_UNITS = {"pressure": "m3", "gravity": "kg m", "end1_force": "m", "end2_force": "m", "end1_torque": "rad",
                   "end2_torque": "rad", "end1_dz": "N", "end2_dz": "N", "end1_dchi": "N m", "end2_dchi": "N m"}
#: the edge reactions recorded along a path: (name, edge node 0 or -1, field)
REACTIONS = (("end1_reaction_force", 0, 0), ("end2_reaction_force", -1, 0), ("end1_reaction_torque", 0, 2),
             ("end2_reaction_torque", -1, 2))
#: a load is self-equilibrated in a rigid direction when its net force there is below this share of its total
SELF_EQUILIBRATED = 1e-9


def allowed_parameters(system):
    """:func:`allowed_loads` and the edge displacements of :data:`DISPLACEMENTS` whose field the edge imposes."""
    out = list(allowed_loads(system))
    for name in DISPLACEMENTS:
        node = 0 if name.startswith("end1") else system.n - 1
        field = 0 if name.endswith("dz") else 2
        if field in system.active and system.imposed[node, field] and system.edges[0 if node == 0 else 1] != "pole":
            out.append(name)
    return tuple(out)


def allowed_loads(system, held=True):
    """The loads of :data:`PATH_LOADS` the edges of ``system`` let act (a force needs the edge's ``z`` free, a torque
    its ``chi``) and, with ``held``, hold: gravity and end forces push a shell no edge holds axially, end torques
    spin one no edge holds in ``chi``, so neither has an equilibrium there."""
    out = []
    unbalanced = {load for field in rigid_motions(system).values() for load in UNBALANCED[field]} if held else set()
    for load in PATH_LOADS:
        if load.startswith("end"):
            node = 0 if load.startswith("end1") else system.n - 1
            field = 0 if load.endswith("force") else 2
            if field not in system.active or system.fixed[node, field]:
                continue
        if load not in unbalanced:
            out.append(load)
    return tuple(out)


class EquilibriumEquations:
    """``F(q, lambda)``, its exact derivatives, the mass matrix and the observables of a scene at rest.

    Parameters
    ----------
    scene : ShellScene
        The scene; its value of ``parameter`` is replaced by the continued ``lambda``, its other loads stay.
    parameter : str
        One of :data:`PATH_LOADS`.
    n : int
        Nodes in ``s``.

    Attributes
    ----------
    system : ShellSystem
        The discretised scene without the continued load.
    q_idx : ndarray
        Positions in the state ``y`` of the free coordinates (``keep`` selects the unknowns: all but the gauge).
    gauge : list of str
        The rigid motions removed, each with the coordinate held.
    """

    def __init__(self, scene, parameter, n):
        if parameter not in PATH_PARAMETERS:
            raise ParameterError("parameter", parameter, "{" + ", ".join(PATH_PARAMETERS) + "}",
                                 hint="the loads and edge displacements a path can be continued in")
        for drive in DRIVES:
            if getattr(scene, drive, 0.0):
                raise ParameterError(drive, getattr(scene, drive), "0", hint="a path is a sequence of states at rest")
        self.parameter = parameter
        self.units = UNITS[parameter]
        base = resolve(dataclasses.replace(scene, **{parameter: 0.0}))
        if parameter in DISPLACEMENTS:
            unit = None
        else:
            # the unit load alone: the scene's other loads off, and its own value of the continued one replaced
            others = {load: 0.0 for load in LOADS if getattr(scene, load) != 0 and load != parameter}
            unit = dataclasses.replace(scene, **others, **{parameter: 1.0, parameter + "_history": "constant"})
        self.scene = base
        self.system = system = ShellSystem(base, n)
        check_system(base, system)
        allowed = allowed_parameters(system)
        if parameter not in allowed:
            hint = (f"the loads and edge displacements scene {scene.name} can take with edges {system.edges[0]} and "
                    f"{system.edges[1]}")
            if parameter in allowed_loads(system, held=False):
                what = next(what for what, field in rigid_motions(system).items() if parameter in UNBALANCED[field])
                hint += f"; under {parameter} it has no equilibrium: no edge stops the shell's {what}"
            raise ParameterError("parameter", parameter, "{" + ", ".join(allowed) + "}", hint=hint)
        self.n, self.nf, self.ny = system.n, system.nf, system.ny
        #: the state index the continued edge displacement moves (None for a load)
        self.moved = None
        if unit is None:
            node = 0 if parameter.startswith("end1") else system.n - 1
            self.moved = self.ny * node + system.active.index(0 if parameter.endswith("dz") else 2)
        else:
            check_end_loads(system, unit)
        self._layout()
        self._graphs(unit)
        self.y_ref = self._rest(system.initial_state(base))
        self._check_self_equilibrated()

    # -- unknowns ----------------------------------------------------------------------------
    def _layout(self):
        system, nf, ny = self.system, self.nf, self.ny
        active = list(system.active)
        fixed = system.fixed[:, active]
        free = [(i, k) for i in range(system.n) for k in range(nf) if not fixed[i, k]]
        self.rigid = {}
        for what, field in rigid_motions(system).items():
            node = next(i for i in range(system.n) if not system.fixed[i, field])
            self.rigid[what] = (node, active.index(field))
        held = set(self.rigid.values())
        self.q_idx = np.array([ny * i + k for i, k in free])
        self.p_idx = self.q_idx + nf
        #: positions in ``q_idx`` of the unknowns Newton solves for (the gauge's held coordinates left out)
        self.keep = np.array([m for m, ik in enumerate(free) if ik not in held])
        #: the rigid motions on the free coordinates (columns), for the spectrum to leave out
        self.rigid_vectors = np.zeros((len(free), len(self.rigid)))
        for c, (_, k) in enumerate(self.rigid.values()):
            self.rigid_vectors[[m for m, (_, kk) in enumerate(free) if kk == k], c] = 1.0
        self.gauge = [f"{what} (gauge: the states' mean {f} is the reference's; {f} held at s = {system.s[i]:.6g} m "
                      "while iterating)" for what, (i, _) in self.rigid.items()
                      for f in [("z", "chi")[what.startswith("spin")]]]
        self.size = len(self.q_idx)

    def _rest(self, y):
        """``y`` at rest: momenta and accumulators zero."""
        y = np.array(y, dtype=float)
        y[: self.ny * self.n].reshape(self.n, self.ny)[:, self.nf:] = 0.0
        y[self.ny * self.n:] = 0.0
        return y

    def state(self, q, lam=0.0):
        """The state vector with unknowns ``q`` (the other entries from the reference, at rest; a continued edge
        displacement ``lam`` added to its imposed field)."""
        y = self.y_ref.copy()
        y[self.q_idx] = q
        if self.moved is not None:
            y[self.moved] += lam
        return y

    def fields(self, q, lam=0.0):
        """The fields ``(5, n)`` of :meth:`state`, each rigid motion's gauge traded for the reference's mean: the
        free ``z`` (``chi``) shifted so that their mean is the reference's, as the static solve of ``R = auto``
        leaves it (:func:`mol_shell.runs.statics.newton`). The same equilibrium, moved rigidly; the path iterates
        with one node held."""
        out = self.system.unpack(self.state(q, lam))
        reference = self.system.unpack(self.y_ref)
        for field in rigid_motions(self.system).values():
            free = ~self.system.fixed[:, field]
            out[field] += float(np.mean(reference[field, free] - out[field, free]))
        return self.system.tie(out)  # a pole's chi is its neighbour's (it is no free coordinate, so was not shifted)

    def unknowns(self, y):
        return np.asarray(y)[self.q_idx].copy()

    # -- graphs ------------------------------------------------------------------------------
    def _graphs(self, unit):
        system, n, nf, ny = self.system, self.n, self.nf, self.ny
        y = ca.MX.sym("y", system.size)
        lam = ca.MX.sym("lam")
        Y = ca.reshape(y[: ny * n], ny, n)
        rows = [Y[system.active.index(k), :] if k in system.active else ca.MX.zeros(1, n) for k in range(NF)]
        Q = ca.vertcat(*rows)
        if unit is None:  # an edge displacement: the imposed field's value is y's entry plus lambda
            moved = np.zeros(system.size)
            moved[self.moved] = 1.0
            F = system.rhs_newton(0, y + lam * ca.DM(moved))[list(self.p_idx)]
            g = ca.jacobian(F, lam)
            unit_forces = ca.MX.zeros(NF, n)
        else:
            unit_forces = load_terms(system, unit, 0, Q, ca.MX.zeros(NF, n))[0]
            forces = unit_forces * ca.DM((~system.fixed.T).astype(float))
            g_all = ca.vec(forces[list(system.active), :])  # node-major: nf per node
            node, local = np.divmod(self.p_idx, ny)
            g = g_all[list(nf * node + local - nf)]
            F = system.rhs_newton(0, y)[list(self.p_idx)] + lam * g
        # the unknowns as a symbol of their own, so the Jacobian is taken with respect to them only
        q = ca.MX.sym("q", self.size)
        rest = ca.MX.sym("rest", system.size)
        pick = np.zeros(system.size)
        pick[self.q_idx] = 1.0
        y_of_q = rest * ca.DM(1.0 - pick) + ca.DM.zeros(system.size)
        scatter = ca.DM(ca.Sparsity.triplet(system.size, self.size, list(self.q_idx), list(range(self.size))),
                        1.0)
        y_of_q = y_of_q + ca.mtimes(scatter, q)
        residual = ca.Function("F", [y, lam], [F, g])
        Fq, gq = residual(y_of_q, lam)
        outs = [Fq, ca.jacobian(Fq, q), gq]
        f = ca.Function("equations", [q, rest, lam], outs, ["q", "rest", "lam"], ["F", "F_q", "F_lam"])
        r = ca.Function("residual", [q, rest, lam], [Fq], ["q", "rest", "lam"], ["F"])
        self._equations = f.expand() if not system.mapped else f
        self._residual = r.expand() if not system.mapped else r
        self._evaluate = sparse_evaluator(self._equations)
        self._motion = sparse_evaluator(system.rhs_newton)  # the mass matrix's columns (mass())
        # the conjugate displacement Phi of the continued load (dPhi/dq = g)
        Qt = system.tie(Q)
        # the edge reactions: what the support supplies on an imposed z or chi, dU/dq less the loads' force there
        stored = system.observables(y, 0)[2]
        dU = ca.reshape(ca.gradient(stored, y)[: ny * n], ny, n)
        others = load_terms(system, self.scene, 0, Q, ca.MX.zeros(NF, n))[0] if system.n_extra else ca.MX.zeros(NF, n)
        reactions = []
        for _, node, field in REACTIONS:
            node = node % n
            if field in system.active and system.imposed[node, field] and system.edges[min(node, 1)] != "pole":
                reactions.append(dU[system.active.index(field), node] - others[field, node]
                                 - lam * unit_forces[field, node])
            else:
                reactions.append(ca.MX(np.nan))
        self._reactions = ca.Function("reactions", [y, lam], [ca.vertcat(*reactions)])
        if unit is None:
            phi = ca.MX.zeros(1)  # the conjugate of a displacement is its reaction (conjugate())
        elif self.parameter == "pressure":
            phi = volume_sign(system) * ca.sum2(cell_volume(Qt[0, :-1], Qt[0, 1:], Qt[1, :-1], Qt[1, 1:]))
        elif self.parameter == "gravity":
            m_i = system.inertia[1] if system.has_rho_i else np.zeros(n)
            phi = -sum(gravity_potential(ca.vertsplit(Qt[:, i]), float(system.inertia[0, i]), float(m_i[i]), 1.0)
                       for i in range(n))
        else:
            node = 0 if self.parameter.startswith("end1") else n - 1
            phi = Qt[0 if self.parameter.endswith("force") else 2, node]
        volume = volume_sign(system) * ca.sum2(cell_volume(Qt[0, :-1], Qt[0, 1:], Qt[1, :-1], Qt[1, 1:]))
        self._phi = ca.Function("phi", [y], [phi, volume])
        self._unit_forces = ca.Function("unit_forces", [y], [unit_forces * ca.DM((~system.fixed.T).astype(float))])

    def evaluate(self, q, lam):
        """``(F, F_q, F_lambda)`` at unknowns ``q`` and load ``lam``: a vector, a sparse CSC matrix and a vector."""
        return tuple(self._evaluate(q, self.y_ref, lam))

    def reduced(self, q, lam):
        """:meth:`evaluate` on the unknowns Newton solves for (the gauge's rows and columns left out)."""
        F, Fq, g = self.evaluate(q, lam)
        k = self.keep
        return F[k], Fq.tocsr()[k][:, k].tocsc(), g[k]

    def residual(self, q, lam):
        """``F`` alone on the unknowns Newton solves for."""
        return np.array(self._residual(q, self.y_ref, lam)).ravel()[self.keep]

    def conjugate(self, q, lam=0.0):
        """``(Phi, volume)`` at unknowns ``q``: the continued load's conjugate displacement (an edge displacement's:
        its reaction), the enclosed volume."""
        y = self.state(q, lam)
        phi, vol = self._phi(y)
        if self.moved is not None:
            names = [name for name, _, _ in REACTIONS]
            kind = "force" if self.parameter.endswith("dz") else "torque"
            phi = self.reactions(q, lam)[names.index(f"{self.parameter[:4]}_reaction_{kind}")]
        return float(phi), float(vol)

    def reactions(self, q, lam=0.0):
        """The edge reactions of :data:`REACTIONS` (N, N m; NaN where the edge leaves the field free)."""
        return np.array(self._reactions(self.state(q, lam), lam)).ravel()

    def stored_energy(self, q, lam=0.0):
        return float(self.system.observables(self.state(q, lam), 0)[2])

    def limits_ok(self, q, lam=0.0):
        """``None`` if the state is inside the model's limits, else ``(what, where)`` of the first one reached."""
        g = np.array(self.system.limits(self.state(q, lam))).ravel()
        bad = np.flatnonzero(~(g > 0))
        return None if bad.size == 0 else self.system.limit_names()[int(bad[0])]

    def mass(self, q):
        """The mass matrix on the free coordinates (sparse CSC, block diagonal: one block per node).

        The inverse of the block ``dq_t/dp`` of the dynamics, inverted node by node. The velocities are affine in
        the momenta (``q_t = M(q)^-1 (p - b)``, ``b`` from an edge driven at a constant rate, such as a cylinder's
        ``end_omega``), so column ``j`` of every node's block is ``q_t`` with the ``j``-th free momentum of every
        node 1 and the others 0, less ``q_t`` at ``p = 0``: ``nf + 1`` evaluations of the right-hand side, where the
        dynamics' whole exact Jacobian took 3 to 4 times as long (n = 641).
        """
        import scipy.sparse

        y = self.state(q)
        node = self.q_idx // self.ny
        first = np.searchsorted(node, node)  # each node's free coordinates are contiguous (node-major)
        local = np.arange(self.size) - first
        blocks = np.tile(np.eye(self.nf), (self.n, 1, 1))
        offset = self._motion(0.0, y)[0][self.q_idx]
        for j in range(int(local.max()) + 1):
            unit = y.copy()
            unit[self.p_idx[local == j]] = 1.0
            column = self._motion(0.0, unit)[0][self.q_idx] - offset
            rows = np.flatnonzero(np.isin(node, node[local == j]))
            blocks[node[rows], local[rows], j] = column[rows]
        inverse = np.linalg.inv(blocks)
        rows, cols = self._block_pattern(node)
        M = scipy.sparse.csc_matrix((inverse[node[rows], local[rows], local[cols]], (rows, cols)),
                                    shape=(self.size, self.size))
        return ((M + M.T) / 2).tocsc()

    @staticmethod
    def _block_pattern(node):
        """``(rows, cols)`` of every pair of coordinates of one node."""
        starts = np.flatnonzero(np.r_[True, node[1:] != node[:-1]])
        ends = np.r_[starts[1:], len(node)]
        rows = np.concatenate([np.repeat(np.arange(a, b), b - a) for a, b in zip(starts, ends)])
        cols = np.concatenate([np.tile(np.arange(a, b), b - a) for a, b in zip(starts, ends)])
        return rows, cols

    def _check_self_equilibrated(self):
        """Refuse a continued load with a net force along a rigid motion (the shell would accelerate away)."""
        forces = np.array(self._unit_forces(self.y_ref))
        for what in self.rigid:
            row = forces[0 if what == "axial translation" else 2]
            if abs(float(row.sum())) > SELF_EQUILIBRATED * max(float(np.abs(forces).sum()), 1e-300):
                raise ParameterError("parameter", self.parameter, "a load the edges hold",
                                     hint=f"no edge stops the shell's {what} ({self.system.edges[0]} and "
                                     f"{self.system.edges[1]} edges): under {self.parameter} it has no equilibrium")
