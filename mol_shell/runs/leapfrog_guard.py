"""Leap-frog's refusal of a viscous case its parasitic root would blow up, for every scene it runs: the shells of
:func:`~mol_shell.runs.simulate.simulate` and the unshearable scene's free shell (:mod:`mol_shell.runs.unshearable`,
which went on and stopped as "numerical instability" where the twisted cylinder was refused up front)."""

from __future__ import annotations

import math

import numpy as np

from mol_shell._core.constants import stated_down
from mol_shell._core.errors import ParameterError
from mol_shell.integrators.leapfrog import carried_log_growth, parasitic_growth_rate, restart_advice

#: leap-frog is refused when damped modes could grow by more than exp(this) (1e6) over the run
LEAPFROG_MAX_LOG_GROWTH = float(np.log(1e6))


#: what else runs a shell that leap-frog cannot
IMPLICIT = "another integrator (cvode-bdf or ida: implicit, for stiff viscous shells)"


def check_step(dt, omega_max, default_note=""):
    """Refuse a leap-frog step ``dt`` (s) at or past its stability bound ``1/omega_max``, the bound stated to 4 digits
    on the side applied (``(0, 0.0001889)`` ran 0.0001889 and refused 0.00018895); ``default_note``: what to say when
    ``dt`` is the default, not one given."""
    bound = stated_down(1.0 / omega_max)
    if dt * omega_max >= 1.0 or dt >= bound:
        raise ParameterError("dt", dt, f"(0, {bound:.4g}) s", hint="leap-frog stability bound 1/max|eig J(y0)|"
                             + default_note)


def check_parasitic(integrator, method, damping, omega_max, t_end, alternative=IMPLICIT):
    """Refuse ``method`` (a :class:`~mol_shell.integrators.leapfrog.Leapfrog`) where its parasitic root grows damped
    modes (the largest damping rate ``damping``, 1/s, the spectral radius ``omega_max``, rad/s) by more than
    ``exp(LEAPFROG_MAX_LOG_GROWTH)`` between two restarts or carried through them up to ``t_end``, s; the message
    says how fast, and what would run it (``alternative``: an implicit integrator; restarts, a smaller step)."""
    dt = method.dt
    growth = parasitic_growth_rate(damping, omega_max, dt)
    total, every = round(t_end / dt), method.restart_steps()  # the restarts the run takes (100 steps or more)
    span = min(t_end, every * dt if every else math.inf)  # the parasitic root starts again at each restart
    carried = carried_log_growth(damping, omega_max, dt, every, total)  # ... from what it had grown to
    if max(growth * span, carried) > LEAPFROG_MAX_LOG_GROWTH:
        allowed = (alternative + restart_advice(damping, omega_max, dt, t_end, LEAPFROG_MAX_LOG_GROWTH))
        raise ParameterError(
            "integrator", integrator, allowed,
            message=f"integrator = {integrator!r} cannot run this case: its parasitic root grows damped modes like "
            f"exp({growth:.4g}/s * t) at dt = {dt:g} s, and up to t = {span:g} s (the run's end or its next "
            f"restart) that is exp({growth * span:.3g})" + (f", carried through the restarts exp({carried:.3g}) "
            "over the run" if carried else "") + f" (viscosity makes the system stiff); allowed: {allowed}")


__all__ = ["IMPLICIT", "LEAPFROG_MAX_LOG_GROWTH", "check_parasitic", "check_step"]
