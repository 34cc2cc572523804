"""What a driver or support supplies to an edge's ``z`` or ``chi``: the reactions at driven and held edges.

A driven field's reaction is ``d p_d/dt`` less the generalised forces on it, ``p_d = dT/dv_d`` the momentum
conjugate to it (not a state). A held field (imposed, not driven) is a driven one at rate 0: its reaction is
``d p_held/dt`` less the generalised forces on it, where
``p_held = dT/dv_held`` (at the held rate 0 and the driven rates of the same node) is not zero when the node's free
rates couple to it in the kinetic energy: ``chi`` with ``psi`` at a pinned edge (the director's azimuthal
velocity). ``p_held`` of ``chi`` belongs to the axial angular momentum, so the supports' and drivers' torques
balance its rate exactly in the semi-discrete system. The forces on an edge node come from its one cell (the
kernels of the maps applied to that cell), not from the whole grid: the observables that read them stay cheap
at any ``n``. A pole holds neither field (its ``chi`` is tied to its neighbour's, its ``z`` is free).
"""

from __future__ import annotations

import casadi as ca

from mol_shell._core.constants import NF
from mol_shell.model.edges import driven_node_kernel

#: the fields whose edge reactions a run records: ``z`` (the axial force) and ``chi`` (the axial torque)
REACTION_FIELDS = (0, 2)


def held_fields(system, e):
    """The fields of :data:`REACTION_FIELDS` that edge node ``e`` holds without driving them."""
    kind = system.edges[0 if e == 0 else 1]
    if kind == "pole" or any(nb == e for _, nb in system.ties):  # (a pole's neighbour is never an edge at n >= 3:
        return []  # a guard, so that a tied chi's gathered force is never read from one cell)
    return [k for k in REACTION_FIELDS if system.imposed[e, k] and k not in system.driven_fields(e)]


def edge_forces(system, e, Q, V, trig, node_force, loads):
    """The generalised forces on edge node ``e`` (5-vector, MX), the column ``e`` of the assembled forces before
    masking: ``node_force`` (the node kernel's ``dT/dq``) less the elastic and viscous forces of its cell, plus
    ``loads[:, e]`` (``None``: no loads)."""
    c, side = (0, 0) if e == 0 else (system.n - 2, 1)
    Qt, Vt = system.tie(Q), system.tie(V)
    cells = (Qt[:, c], Qt[:, c + 1])
    if trig is None:
        data = (ca.DM(system.cell_data[:, c]),)
        elastic = system.kernel("cell_forces_kernel")(*cells, *data)
        viscous = system.kernel("viscous_forces_kernel") if system.viscous else None
        inputs = (*cells, Vt[:, c], Vt[:, c + 1], *data)
    else:
        shared = system.shared_cell_data
        data = (ca.DM(shared[:, min(c, shared.shape[1] - 1)]),)
        elastic = system.kernel("cell_forces_shared_kernel", True)(*cells, trig[:, c], trig[:, c + 1], *data)[-2:]
        viscous = system.kernel("viscous_forces_shared_kernel") if system.viscous else None
        inputs = (*cells, Vt[:, c], Vt[:, c + 1], trig[:, c], trig[:, c + 1], *data)
    out = node_force - elastic[side]
    if viscous is not None:
        out = out - viscous(*inputs)[side]
    return out if loads is None else out + loads[:, e]


def edge_reactions(system, t, Q, P, V, trig, node_forces, loads):
    """``[(edge node, field, reaction, momentum)]`` (MX) for the driven and held ``z`` and ``chi`` of both edges,
    each edge's fields in order; ``momentum`` is ``dT/dv`` of the field (not a state).

    ``node_forces``: the two edge nodes' ``dT/dq`` from the RHS's node kernels; ``loads``: the loads' forces
    (``5 x n``) or ``None``. ``d p/dt = dp/dq v + dp/dp p_t + dp/dv_d v_d,t``, with ``p_t`` the node's free rows
    of its forces. The RHS reads the drivers' ones for their power in the ``work`` accumulator.
    """
    out = []
    first, _, last = system.free_sets()
    for e, free, node_force in ((0, first, node_forces[0]), (system.n - 1, last, node_forces[1])):
        driven, held = system.driven_fields(e), held_fields(system, e)
        fields = sorted(driven + held)  # drives are of z and chi only
        if not fields:
            continue
        vd, vd_rate = system.driven_rates(e, t) if driven else (ca.DM.zeros(NF), ca.DM.zeros(NF))
        forces = edge_forces(system, e, Q, V, trig, node_force, loads)
        p_rate = forces * ca.DM((~system.fixed[e]).astype(float))  # p_t of the free fields
        p, dq, dp, dvd = driven_node_kernel(system, free, fields)(Q[:, e], P[:, e], system.inertia[:, e], vd)[3:]
        rate = ca.mtimes(dq, V[:, e]) + ca.mtimes(dp, p_rate) + ca.mtimes(dvd, vd_rate)
        out += [(e, k, rate[j] - forces[k], p[j]) for j, k in enumerate(fields)]
    return out
