"""Where a path starts (:func:`~mol_shell.analysis.path.path`): its first equilibrium, the arclength's weights and the
first tangent.

The first equilibrium is Newton's from the scene's initial state at ``start`` (by continuation in the load from 0
where that fails), or from fields given (``initial``: an earlier path's step, which Newton only polishes). The
displacements are weighed so that the first tangent is half load, half displacement, or as an earlier path's
scales say (its metric, for a continuation). The first tangent heads for ``stop``, or (``heading``, the state before
``initial`` on its path) the way the displacements went from that state: the load is left out of that direction,
since a chord across a fold has it going the wrong way.
"""

from __future__ import annotations

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.analysis.modes import EQUILIBRIUM_TOL
from mol_shell.model.kinematics import FIELDS
from mol_shell.runs.simulate import given_state


def first_state(tracer, start, initial, heading, scales, failed):
    """``(q, iterations, t)``: the first equilibrium, Newton's iterations to it and the first tangent, with
    ``tracer``'s weights set (``failed``: the path's exception class for a corrector that fails)."""
    eq, at = tracer.eq, float(start)
    if initial is not None:  # an equilibrium at start (an earlier path's step): Newton polishes it, nothing more
        said = "the scene's initial state"
        q = eq.unknowns(_state(eq, initial))
        _check_equilibrium(tracer, q, at)
        try:
            q, iterations = tracer.equilibrium(q, at)
        except failed as exc:
            raise ParameterError("initial", None, f"fields of an equilibrium at start = {at:g} {eq.units}",
                                 message=f"initial (the fields given) is no equilibrium at start = {at:g} "
                                 f"{eq.units}: {str(exc).replace(said, 'the fields')}") from None
    else:
        try:
            q, iterations = tracer.start_equilibrium(eq.unknowns(eq.y_ref), at)
        except failed as exc:
            raise ParameterError("start", start, "loads at which the shell has an equilibrium that Newton finds "
                                 "from the scene's initial state or by continuation from 0", hint=str(exc)) from None
    tracer.weigh(q, at, scales)
    moved = None if heading is None else (q - eq.unknowns(_state(eq, heading, "heading")))[eq.keep]
    if moved is not None and np.any(moved):
        return q, iterations, tracer.tangent(q, at, previous=(moved / tracer.q_scale, 0.0))
    return q, iterations, tracer.tangent(q, at)


def _check_equilibrium(tracer, q, at):
    """Refuse (``initial``, with its ``residual`` said) a state ``q`` that is no equilibrium at load ``at``, by the
    test modes makes of its start (:func:`~mol_shell.analysis.modes.check_equilibrium`: forces above
    :data:`~mol_shell.analysis.modes.EQUILIBRIUM_TOL` of a unit strain's): Newton polished a state of another scene
    (a path file whose scene attributes were edited) into another equilibrium, 21 % away. A state that round-off
    moved (a path's step, converged to 1e-10 of that) passes, and Newton polishes it."""
    eq = tracer.eq
    F, Fq, _ = eq.reduced(q, at)
    scale = float(np.abs(Fq.diagonal()).max()) * tracer.length
    forces = np.abs(F)
    if np.all(np.isfinite(forces)) and forces.max(initial=0.0) <= EQUILIBRIUM_TOL * scale:
        return
    m = int(np.argmax(np.where(np.isfinite(forces), forces, np.inf)))
    index = int(eq.q_idx[eq.keep[m]])
    node, field = index // eq.system.ny, FIELDS[eq.system.active[index % eq.system.ny]]
    where = (f"residual force {forces[m]:.3g} on {field} at s = {eq.system.s[node]:.4g} m "
             f"({forces[m] / scale:.2g} of a unit strain's)")
    error = ParameterError("initial", None, f"fields of an equilibrium at start = {at:g} {eq.units}",
                           message=f"initial (the fields given) is no equilibrium at start = {at:g} {eq.units}: "
                           f"{where}")
    error.residual = where  # for a caller that names where the fields came from (path --from)
    raise error


def _state(eq, fields, name="initial"):
    """The state vector of ``fields`` (``(5, n)``, refused by ``name`` unless they fit) at rest."""
    try:
        return given_state(eq.system, fields, eq.system.unpack(eq.y_ref))
    except ParameterError as exc:
        if name == "initial":
            raise
        raise ParameterError(name, exc.value, exc.allowed, message=str(exc).replace("initial", name, 1)) from None
