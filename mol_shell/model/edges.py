"""Edge conditions of the discretised shell: one condition per field at each end (the repaired eq. 6.8).

An imposed field keeps its initial value (its rate and momentum stay zero); a natural one gets the
condition the variational form gives (zero flux: no force or couple conjugate to it). Per edge:

=========  ==========================  ==========================================================
edge       imposed                     natural
=========  ==========================  ==========================================================
magnet     z, theta                    n.a2 = n.a3 = 0, m.c1 = 0 (the paper's lubricated magnets)
clamped    z, r, chi, theta, psi       none
pinned     z, r, chi                   m.a3 = m.c1 = 0 (rotations free)
free       none                        n.k = n.a2 = n.a3 = 0, m.a3 = m.c1 = 0
pole       r = 0, theta = theta0,      ``chi`` is tied to its neighbour's (it has no inertia on the
           psi = 0                     axis, and the cell next to the pole carries no twist); z free
a set      the fields named            the natural conditions of the others (``end2=r,theta``)
=========  ==========================  ==========================================================

An edge on the axis (``r0 = 0``) is a pole whatever is asked; an open edge cannot be one.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Choice
from mol_shell.model.linalg import spd_solve
from mol_shell.model.loads import history, history_rate

#: the fields, in the order of their indices, as an edge given by the set of fields it imposes names them
EDGE_FIELDS = ("z", "r", "chi", "theta", "psi")


class _Imposed(dict):
    """Fields imposed at an edge of each kind; an edge given as a set of fields (``"r,theta"``, canonical: in the
    order of :data:`EDGE_FIELDS`, see :func:`check_edge`) imposes those."""

    def __missing__(self, kind):
        return tuple(EDGE_FIELDS.index(f) for f in str(kind).split(","))


#: fields imposed at an edge of each kind (indices into FIELDS: z, r, chi, theta, psi)
IMPOSED = _Imposed({
    "magnet": (0, 3),
    "clamped": (0, 1, 2, 3, 4),
    "pinned": (0, 1, 2),
    "free": (),
    "pole": (1, 3, 4),
})
EDGES = ("magnet", "clamped", "pinned", "free")
#: what an edge may be, for messages
EDGE_FORMS = (*EDGES, "pole", "auto (a pole on the axis, magnet elsewhere)",
              "a set of the fields it imposes, e.g. r,theta (fields: z, r, chi, theta, psi)")

#: the edge parameters, whose string "none" is refused (:func:`check_edge`), not read as None ("auto") as other
#: parameters' "none" is
EDGE_PARAMETERS = ("end1", "end2")
NONE_HINT = "ambiguous: write free for an edge that imposes no field, or auto for the one chosen from the geometry"


def field_set(value):
    """``"theta, r"`` -> ``"r,theta"`` (canonical), or ``None`` if ``value`` is not a set of distinct field names."""
    parts = [p.strip() for p in value.split(",")]
    if not parts or any(p not in EDGE_FIELDS for p in parts) or len(set(parts)) != len(parts):
        return None
    return ",".join(f for f in EDGE_FIELDS if f in parts)


def check_edge(name, value):
    """``value`` if it is an edge kind, or a set of imposed fields (returned canonical), or ``None`` (chosen from
    the geometry; ``"auto"``); else a ParameterError. The string ``"none"`` is refused: read as the set of imposed
    fields it is ``free``, read as no choice ``auto`` (which it silently was)."""
    if value is None or (isinstance(value, str) and value.strip().lower() == "auto"):
        return None
    if isinstance(value, str) and value.strip().lower() == "none":  # the empty set (free) or no choice (auto)?
        raise ParameterError(name, value, Choice(EDGE_FORMS), hint=NONE_HINT)
    if isinstance(value, str) and value.strip() in EDGES + ("pole",):
        return value.strip()
    canonical = field_set(value) if isinstance(value, str) else None
    if canonical is None:
        raise ParameterError(name, value, Choice(EDGE_FORMS))
    return canonical


def resolve_edges(end1, end2, poles, default="magnet"):
    """The edge kinds at ``s = 0`` and ``s = L`` for the requested ``end1, end2`` and the meridian's ``poles``.

    ``None`` means: a pole on the axis, ``default`` elsewhere. Asking an axis edge to be anything but a
    pole, or an open edge to be a pole, is refused naming the parameter.
    """
    out = []
    for name, asked, pole in (("end1", end1, poles[0]), ("end2", end2, poles[1])):
        asked = check_edge(name, asked)
        if pole:
            if asked not in (None, "pole"):
                raise ParameterError(name, asked, Choice(("pole", "auto")), hint=f"the edge at {'s = 0' if name == 'end1' else 's = L'} "
                                     "is on the axis")
            out.append("pole")
        else:
            if asked == "pole":
                raise ParameterError(name, asked, Choice((*EDGES, "auto")),
                                     hint="this edge is not on the axis (r0 > 0)")
            out.append(asked or default)
    return tuple(out)


#: edges that hold each field a static displacement can move (z, chi), for messages
HOLDERS = {0: "magnet, clamped, pinned, or a set with z", 2: "clamped, pinned, or a set with chi"}


def check_displacements(displacements, edges, active):
    """Refuse a static edge displacement (``{"end2_dz": 0.01, ...}``) at an edge that does not hold its field.

    ``edges`` are the resolved kinds at ``s = 0`` and ``s = L`` (:func:`resolve_edges`), ``active`` the scene's
    fields. Checked by the scene, before anything is built.
    """
    for end, kind in zip(("end1", "end2"), edges):
        for what, field in (("dz", 0), ("dchi", 2)):
            name, letter = f"{end}_{what}", EDGE_FIELDS[field]
            value = displacements.get(name, 0.0)
            if not value or (field in active and field in IMPOSED[kind]):
                continue
            why = (f"the scene has no {letter} field" if field not in active else
                   f"{end} = 'pole' ties chi to its neighbour's (an edge on the axis)" if kind == "pole" and field else
                   f"{end} = {kind!r} leaves {letter} free" + (" (an edge on the axis)" if kind == "pole" else ""))
            raise ParameterError.invalid(name, value, f"cannot be imposed: {why}",
                                         f"0, or a displacement at an edge that holds {letter} ({HOLDERS[field]})")


def imposed_mask(n, edges, active):
    """``(n, 5)`` booleans: which nodal fields are imposed (held at their initial values)."""
    mask = np.zeros((n, 5), dtype=bool)
    for node, kind in zip((0, n - 1), edges):
        for k in IMPOSED[kind]:
            mask[node, k] = True
    inactive = [k for k in range(5) if k not in active]
    mask[:, inactive] = False
    return mask


def tied_chi(n, edges, active):
    """``(pole node, neighbour)`` pairs whose ``chi`` is tied (poles, when ``chi`` is a field)."""
    if 2 not in active:
        return ()
    pairs = []
    if edges[0] == "pole":
        pairs.append((0, 1))
    if edges[1] == "pole":
        pairs.append((n - 1, n - 2))
    return tuple(pairs)


def free_rates(kind, active):
    """Fields whose rates are unknowns at an edge of ``kind`` (imposed ones and a pole's tied ``chi`` are not)."""
    fixed = set(IMPOSED[kind]) | ({2} if kind == "pole" else set())
    return [k for k in active if k not in fixed]


def driven_node_kernel(system, free, driven, momenta=True):
    """``(q, p, m, vd) -> (v, dT/dq, T, p_d, dp_d/dq, dp_d/dp, dp_d/dvd)`` for an edge node with driven rates.

    ``vd`` holds the prescribed rates (entries ``driven``); ``p_d = dT/dv_d`` are the momenta conjugate to
    the driven fields (not states: the reaction is ``d p_d/dt`` less the other generalised forces).
    ``momenta=False``: the first three outputs only (the right-hand side's; the reactions take the rest).
    """
    q, p, m, vd = ca.SX.sym("q", NF), ca.SX.sym("p", NF), ca.SX.sym("m", 3), ca.SX.sym("vd", NF)
    vf = ca.SX.sym("v", len(free))
    v = [vf[free.index(k)] if k in free else (vd[k] if k in driven else 0) for k in range(NF)]
    T = system.kinetic_energy(ca.vertsplit(q), v, ca.vertsplit(m))
    M = ca.hessian(T, vf)[0]
    lin = ca.substitute(ca.gradient(T, vf), vf, ca.DM.zeros(len(free)))  # the driven rates' share of p
    v_of_p = (ca.solve if system.reference_kernel else spd_solve)(M, p[free] - lin)
    dTdq = ca.substitute(ca.gradient(T, q), vf, v_of_p)
    T_p = ca.substitute(T, vf, v_of_p)
    v_full = ca.SX.zeros(NF)
    v_full[free] = v_of_p
    for k in driven:
        v_full[k] = vd[k]
    outs = [v_full, dTdq, T_p]
    if momenta:
        pd = ca.substitute(ca.vertcat(*[ca.jacobian(T, vd)[k] for k in driven]), vf, v_of_p)  # dT/dv_d
        outs += [pd, ca.jacobian(pd, q), ca.jacobian(pd, p), ca.jacobian(pd, vd)]
    return ca.Function("driven_node", [q, p, m, vd], outs, system.KERNEL_OPTIONS)


def driven_rates(system, node, t):
    """``(vd, vd_t)`` (5-vectors, MX) of the prescribed rates at edge node ``node`` and their time derivatives."""
    end = 0 if node == 0 else 1
    vd, vd_t = [0] * NF, [0] * NF
    for (e, k), (rate, hist) in system.drives.items():
        if e == end:
            vd[k], vd_t[k] = rate * history(hist, t), rate * history_rate(hist, t)
    return ca.vertcat(*vd), ca.vertcat(*vd_t)
