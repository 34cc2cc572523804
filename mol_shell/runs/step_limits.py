"""What held an adaptive run's steps, when it was not the tolerance: notes before and after a SUNDIALS run.

* ``cvode-adams`` with its default fixed-point iteration converges only while ``h beta_0 L < 1`` (``L`` the
  Jacobian's largest decay rate: the scene's viscous damping rate). On a stiff viscous wall that, not the error test,
  sets its steps (measured: mean step 0.78-0.80 / damping at ``eta_mu`` = 1e3, 1e4 and 1e6 on the twisted cylinder),
  and about a third of its step attempts fail to converge. Its convergence test then accepts iterates whose
  remaining error is larger than it estimates (the rate estimate is near 1), and over tens of thousands of steps
  these add up: at ``eta_mu`` = 1e4, n = 11, ``rtol`` = 1e-6 the error is 10.6 rtol (1e-3 of SUNDIALS' nonlinear
  coefficient brings it to 0.007 rtol: the corrector's residual, not the error test, makes it). So: a warning
  before the run when ``t_end`` needs more than ``max_steps`` such steps, and after it when 10 % or more of its
  steps failed to converge (:data:`CONVERGENCE_FAIL_SHARE`), naming ``iteration="newton"``, ``cvode-bdf`` and
  ``ida``.
* BDF of orders 3-5 is not A-stable: on the imaginary axis ``z = i h omega`` its largest root exceeds 1 for
  ``0 < |h omega| < 1.94`` (order 3), ``< 4.71`` (order 4) and ``0.71 < |h omega| < 9.39`` (order 5); orders 1 and 2 are
  A-stable. An undamped oscillation far faster than the motion (the director's rotation of a thin wall) then holds
  the steps near ``0.5 / omega_max``, whatever the tolerance (``h = 1e-6``, n = 11: 634,031 steps, 0.52 / omega_max;
  ``max_order = 2``: 6,170). A note after the run when ``cvode-bdf`` or ``ida`` (any order above 2) took at least
  :data:`MIN_STEPS` steps of mean ``h`` with ``h omega_max`` in :data:`BDF_HELD`, that mode undamped
  (``damping < 0.1 omega_max``) and far above the shell's own motion (:data:`SCALE_GAP`), naming
  ``max_order = 2``. The paper's scene steps at 0.18 / omega_max at its rtol 1e-6, up to 0.55 at rtol 1e-2; its
  fastest mode is its motion's (its fields move at 0.012-0.028 omega_max), and it takes 7x more steps at order 2.
"""

from __future__ import annotations

import warnings

import numpy as np

from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import MolShellWarning
from mol_shell.integrators import sundials, sundials_c
from mol_shell.runs.building import observe
from mol_shell.runs.resources import LongRunWarning

#: share of steps whose fixed-point iteration failed to converge above which the steps are stiffness-limited
CONVERGENCE_FAIL_SHARE = 0.1
#: fewest steps for a note: a short run costs nothing whatever held its steps
MIN_STEPS = 1000
#: mean step of a fixed-point Adams run held by convergence, times the damping rate (measured, see above)
ADAMS_STEP_DAMPING = 0.8
#: ``h omega_max`` of steps held by BDF3-5's stability on an undamped oscillation: from above the accuracy-limited
#: paper scene's 0.18 to BDF3's edge on the imaginary axis
BDF_HELD = (0.3, 1.94)
#: the shell's own motion (its fields but the director's angle) at most this fraction of ``omega_max``: the fastest mode
#: is then a director's oscillation far above it (``h = 1e-6``: 9e-4; the paper's scene: 0.012-0.028)
SCALE_GAP = 0.005
STIFF_ROUTES = 'iteration="newton" (--option iteration=newton), cvode-bdf or ida (implicit, for stiff walls)'


def fixed_point_adams(method):
    """Whether ``method`` is CVODE's Adams method with a fixed-point iteration (the compiled route's default)."""
    return isinstance(method, sundials_c.CVODEAdams) and method.fixed_point()


def max_steps_note(method, t_end, damping):
    """One sentence when a fixed-point ``cvode-adams`` would need more than ``max_steps`` steps of
    :data:`ADAMS_STEP_DAMPING` ``/ damping`` to reach ``t_end``; else None."""
    if not fixed_point_adams(method) or damping <= 0:
        return None
    steps = float(t_end) * damping / ADAMS_STEP_DAMPING
    if steps <= method.max_steps:
        return None
    return (f"{method.name}'s fixed-point iteration converges only for steps below about 1/damping = "
            f"{1.0 / damping:.3g} s (the scene's viscous damping rate {damping:.3g} 1/s): about {steps:.3g} steps to "
            f"t = {float(t_end):g} s, more than max_steps = {method.max_steps}; use {STIFF_ROUTES}")


def before_run(method, t_end, damping):
    """:func:`max_steps_note`, warned (and returned); else None."""
    note = max_steps_note(method, t_end, damping)
    if note:
        warnings.warn(note, LongRunWarning, stacklevel=3)  # said by the command line, as a run's projected time is
    return note


def high_order_bdf(method):
    """Whether ``method`` is ``cvode-bdf`` or ``ida`` (either route) with orders above 2 allowed."""
    return (isinstance(method, (sundials.CVODEBDF, sundials.IDA)) and getattr(method, "method", "BDF") == "BDF"
            and (method.max_order or 5) > 2)


def may_note(method):
    """Whether a run of ``method`` can get a note here (:func:`fixed_point_adams`, :func:`high_order_bdf`): the scene's
    spectrum is needed for those alone."""
    return fixed_point_adams(method) or high_order_bdf(method)


def convergence_note(method, stats):
    """One sentence when a fixed-point ``cvode-adams`` failed to converge in :data:`CONVERGENCE_FAIL_SHARE` of its
    steps or more (``stats``: the driver's counters), else None."""
    steps, fails = stats.get("sundials_steps", stats.get("n_steps", 0)), stats.get("n_convergence_fails", 0)
    if not fixed_point_adams(method) or steps < MIN_STEPS or fails < CONVERGENCE_FAIL_SHARE * steps:
        return None
    return (f"{method.name}'s fixed-point iteration failed to converge {fails:,} times in {steps:,} steps: the wall is "
            f"stiff (viscous), its steps are set by that iteration, not by the tolerance, and its error may exceed "
            f"rtol many times; use {STIFF_ROUTES}")


def shell_rate(ds):
    """The rate of the shell's own motion in ``ds`` (1/s): the largest ``max|x_t| / max|x - x(0)|`` of its fields
    other than the director's angle ``psi`` (0 for a shell at rest)."""
    names = [v for v in ds.data_vars if v != "psi" and f"{v}_t" in ds.data_vars]
    return motion_rate([ds[name].values for name in names], [ds[f"{name}_t"].values for name in names])


def states_rate(system, states, times):
    """:func:`shell_rate` of saved ``states`` at ``times`` (a trajectory's, before it is a Dataset)."""
    velocities, _ = observe(system, states, times)
    fields = system.unpack(np.asarray(states))
    kept = [k for k, name in enumerate(FIELDS) if name != "psi"]
    return motion_rate([fields[:, k] for k in kept], [velocities[:, k] for k in kept])


def motion_rate(values, rates):
    """The largest ``max|x_t| / max|x - x(0)|`` over the pairs of arrays ``(x, x_t)`` (time first); 0 for none."""
    out = [0.0]
    for x, rate in zip(values, rates):
        x, rate = np.asarray(x, dtype=float), np.abs(np.asarray(rate, dtype=float))
        moved = np.abs(x - x[:1]).max() if x.size else 0.0
        if moved > 0 and np.isfinite(moved) and np.isfinite(rate).all():
            out.append(float(rate.max() / moved))
    return max(out)


def bdf_note(method, stats, t_end, omega_max, damping, slow_rate):
    """One sentence when a BDF run's steps were held by orders 3-5's stability on an undamped oscillation far faster
    than the shell's motion (``slow_rate`` below :data:`SCALE_GAP` ``omega_max``), else None. ``slow_rate``: a number,
    or a function giving it, called only where the rest holds (:func:`states_rate` costs the rates of the states)."""
    steps = stats.get("n_steps", 0)
    if not high_order_bdf(method) or steps < MIN_STEPS or omega_max <= 0 or damping >= 0.1 * omega_max:
        return None
    held = float(t_end) / steps * omega_max
    if not BDF_HELD[0] <= held <= BDF_HELD[1]:
        return None
    if (slow_rate() if callable(slow_rate) else slow_rate) >= SCALE_GAP * omega_max:  # measured last: it may cost
        return None
    return (f"{method.name} took {steps:,} steps of mean {float(t_end) / steps:.3g} s = {held:.2g} / omega_max "
            f"(omega_max = {omega_max:.3g} rad/s, undamped): held by the stability of BDF orders 3-5 on an undamped "
            "oscillation (they are unstable on part of the imaginary axis), not by the tolerance; max_order = 2 "
            "(--option max_order=2: A-stable BDF2) may take far fewer steps")


def run_notes(method, stats, message, t_end, omega_max, damping, slow_rate):
    """The notes (sentences) on what held the steps of a run of ``method`` to ``t_end`` (``stats``, ``message``: the
    run's counters and message), ``[]`` where nothing but the tolerance did: :func:`convergence_note` (unless the
    stop at ``max_steps`` said it) and :func:`bdf_note` (``slow_rate`` as there). What :func:`after_run` says of a
    run, and ``mol-shell compare`` of each integrator's runs."""
    said = "failed to converge" in str(message)  # by the stop at max_steps
    return [note for note in (None if said else convergence_note(method, stats),
                              bdf_note(method, stats, t_end, omega_max, damping, slow_rate) if t_end > 0 else None)
            if note]


def after_run(method, ds, omega_max, damping):
    """``ds`` (a run's Dataset) with the notes on what held its steps in ``attrs["step_warning"]``, each warned."""
    t_end = float(ds["time"].values[-1]) if ds.sizes.get("time", 0) else 0.0
    notes = run_notes(method, ds.attrs, ds.attrs.get("message", ""), t_end, omega_max, damping, lambda: shell_rate(ds))
    for note in notes:  # a package warning, as the start's stability note: the command line says it
        warnings.warn(note, MolShellWarning, stacklevel=3)
    if notes:
        ds.attrs["step_warning"] = " ".join(notes)
    return ds
