"""A first step of a path that does not lean on the tangent at its start: a secant.

Each step's predictor follows the tangent ``-F_q^-1 F_lambda``. Where ``F`` is once but not twice differentiable
at the start, that tangent is not the path's: tension-only fibres (energy ``(E_f / 2) max(a.E a, 0)^2``) have a
second derivative that jumps from 0 to ``E_f`` at zero fibre strain, and in the natural state every fibre sits
there. ``F_q`` is then neither one-sided stiffness (the derivative of ``max`` at a tie is a convention, and the
round-off of the zero strains picks the side point by point), and the first step's corrector converges far from
its predictor at every step size.

:func:`secant_start` steps off instead by Newton at a fixed load, ``start + (stop - start) / steps`` (halved down to
``2^-halvings`` of it): the damped Newton of the path's first state, which needs only the stiffness at its iterates,
off the kink after its first one. Then the displacement weights are balanced on the chord (half load, half
displacement, as :meth:`_Path.weigh <mol_shell.analysis.path._Path.weigh>` does on the tangent) and the tangent is
taken at the new state, oriented along the chord.
"""

from __future__ import annotations

import numpy as np


def secant_start(tracer, q0, lam0, steps, halvings, failure):
    """``(q, lam, t, chord, iterations)``: the first state off the start by Newton at a fixed load, its tangent and
    the unit chord from the start (the tangent of the interval for locating a critical point in it).

    ``failure`` is the exception class of the tracer's Newton; the last one is raised when no load converges.
    """
    span = tracer.stop - tracer.start
    error = None
    for k in range(halvings + 1):
        lam = lam0 + span / steps * 2.0 ** -k
        try:
            q, iterations = tracer.equilibrium(q0.copy(), lam)
        except failure as exc:
            error = exc
            continue
        keep = tracer.eq.keep
        dq, dl = (q - q0)[keep] / tracer.q_scale, (lam - lam0) / tracer.l_scale
        tracer.q_scale = tracer.q_scale * max(np.linalg.norm(dq) / abs(dl), 1e-12)
        chord = np.concatenate([(q - q0)[keep] / tracer.q_scale, [dl]])
        chord = chord / np.linalg.norm(chord)
        chord = (chord[:-1], float(chord[-1]))
        return q, lam, tracer.tangent(q, lam, previous=chord), chord, iterations
    raise error
