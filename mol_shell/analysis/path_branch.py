"""Branch switching at a simple bifurcation point of an equilibrium path (``path(..., branch=K)``).

At a simple bifurcation ``(q_c, lambda_c)`` the tangent stiffness has one null vector ``phi`` (the critical mode),
and two branches cross: the path's own, with unit tangent ``t``, and one leaving along ``phi`` (for a symmetric
problem, a pitchfork). The standard switch (Keller 1977; Seydel, *Practical bifurcation and stability analysis*,
sec. 5.6): take the direction ``v = phi - (phi . t) t`` in the scaled coordinates of the continuation, normalised,
and solve ``F(q, lambda) = 0`` with the arclength equation ``v . (u - u_c) = ds``. That hyperplane crosses the
bifurcating branch at distance ``ds`` from the point and the path's own branch (tangent to it) only far away, so
Newton from the predictor ``u_c + ds v`` lands on the new branch. The step is halved on failure (down to
``ds / 2^MIN_HALVINGS``), and the orientation ``+v`` is tried first, then ``-v``.
"""

from __future__ import annotations

import numpy as np


class BranchFailed(Exception):
    """No converged state on the bifurcating branch near the point."""


def no_branch_reason(record, index):
    """Why no branch can be followed from critical point ``index`` (a limit point: the path turns there, no branch
    leaves), naming the bifurcation points found up to it; ``None`` for a bifurcation point."""
    point = record.points[index]
    if point["kind"] == "bifurcation":
        return None
    bifurcations = [m for m, p in enumerate(record.points) if p["kind"] == "bifurcation"]
    found = ("the bifurcation points found up to it: " + ", ".join(map(str, bifurcations)) if bifurcations
             else "no bifurcation point was found up to it")
    return (f"critical point {index} is a limit point at {record.eq.parameter} = {point['parameter']:.6g} "
            f"{record.eq.units}: the path turns there, no branch leaves ({found})")


def switch(tracer, point, t, ds, min_ds, failed):
    """``(q, lam, v, iterations)``: the first state on the branch leaving bifurcation ``point`` (a record of
    ``PathRecord.points``) and the direction ``v`` it was reached along; ``t`` is the path's tangent there, ``failed``
    the exception class of a corrector that does not converge."""
    eq = tracer.eq
    tq, tl = t
    phi = point["mode"][eq.keep] / tracer.q_scale
    v = np.concatenate([phi, [0.0]])
    tt = np.concatenate([tq, [tl]])
    v = v - np.dot(v, tt) * tt
    norm = np.linalg.norm(v)
    if not norm > 0:
        raise BranchFailed("the critical mode is parallel to the path's tangent")
    v = v / norm
    q_c, lam_c = point["q"], point["parameter"]
    for sign in (1.0, -1.0):
        h = ds
        while h >= min_ds:
            direction = (sign * v[:-1], float(sign * v[-1]))
            try:
                q, lam, its = tracer.correct(q_c, lam_c, direction, h)
                if eq.limits_ok(q, lam) is None:
                    return q, lam, direction, its
            except failed:
                pass
            h /= 2
    raise BranchFailed(f"Newton found no state on the branch leaving {eq.parameter} = {lam_c:.6g} {eq.units}")


def closed(tracer, origin, q, lam, arc, record):
    """Whether a branch has come back to the critical point it left (``origin``): within the last step's length
    of it, once it has been farther than three such steps from it. A branch that closes into a loop (the vessel's
    two heads snapping in turn) would otherwise go round it until ``max_steps``."""
    away = tracer.distance(origin[0], origin[1], q, lam)
    record.farthest = max(record.farthest, away)
    return away < arc and record.farthest > 3.0 * arc
