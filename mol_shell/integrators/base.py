"""What every integrator returns, and the checks every integrator shares."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mol_shell._core.errors import ModelLimitError, NumericalInstabilityError
from mol_shell.discretization.scales import unit_strain_energy


@dataclass
class Trajectory:
    """States at the saved times that were reached.

    Attributes
    ----------
    t : ndarray
        Saved times reached, shape ``(k,)``.
    y : ndarray
        States, shape ``(k, size)``.
    status : str
        ``"complete"``, ``"limit"`` (a model limit was reached), ``"unstable"`` (the energy
        grew: numerical instability) or ``"interrupted"`` (Ctrl-C).
    message : str
        Human-readable account of how the run ended.
    stats : dict
        Integrator statistics (``n_steps``, ``n_rhs``, ...).
    failure_time : float
        Time of the failure (NaN when complete).
    """

    t: np.ndarray
    y: np.ndarray
    status: str = "complete"
    message: str = "completed"
    stats: dict = field(default_factory=dict)
    failure_time: float = float("nan")


class Monitor:
    """Checks a state against the model's limits: finite values, ``|psi| < pi/2``, ``r > 0``, ``delta > 0``.

    Parameters
    ----------
    system : ShellSystem
        Supplies the ``delta`` of each cell and the node positions.
    """

    #: relative growth of the energy balance ``E - W + D`` that counts as a numerical instability
    ENERGY_GROWTH = 1e-2

    def __init__(self, system, y0=None):
        self.system = system
        self._observe = system.observables
        self._cells = (system.s[:-1] + system.s[1:]) / 2
        scale = unit_strain_energy(system)
        self.energy_limit = self.energy_start = None
        if y0 is not None:
            out = self._observe(y0, 0.0)
            e0 = self.energy_start = self._balance(out)
            self.energy_limit = e0 + self.ENERGY_GROWTH * abs(e0) + 1e-9 * scale

    @staticmethod
    def _balance(out):
        """``E - work + dissipated``: constant for the exact motion (``E`` alone without loads)."""
        return float(out[1]) + float(out[2]) - float(out[6]) + float(out[7])

    def _check_law_domain(self, y, t):
        """Raise :class:`ModelLimitError` naming the law and the first cell where its stored energy is not finite
        (:meth:`~mol_shell.discretization.limits.ModelLimits.energy_not_finite`): a start outside the law's domain
        (a law of one's own with ``log(I1 - 2.9)`` on a compressed start, or compressed there by the motion), which the
        energy's growth called a numerical instability, with no place."""
        found = getattr(self.system, "energy_not_finite", lambda y: None)(y)
        if found is not None:
            law, where, detail = found
            raise ModelLimitError(f"the energy of {law} is not finite at t = {t:.9g} s, {where}: {detail}, outside "
                                  "the law's domain", t, where)

    def check(self, y, t):
        """Raise :class:`ModelLimitError` naming time and place if ``y`` breaks a limit.

        The energy comes first: an unloaded shell cannot gain energy, so a state whose energy grew
        is a numerical instability (:class:`NumericalInstabilityError`, status ``"unstable"``) even
        when the blow-up has also carried it past a limit of the model. A finite state whose stored energy is not
        finite is outside the law's domain (at the start, or reached during the run), not unstable:
        :meth:`_check_law_domain` names the law and the cell.
        """
        out = self.check_balance(y, t)
        self._check_limits(y, out, t)

    def check_balance(self, y, t):
        """:meth:`check`'s checks of a finite state, a finite stored energy and the energy balance ``E - W + D``
        (without the model's limits); returns the observables at ``y``. The routes that locate a limit's crossing
        inside a step (``dop853-c``, ``rk45-c``) make them at the step's end."""
        if not np.all(np.isfinite(y)):
            bad = np.flatnonzero(~np.isfinite(y))[0]
            # the motion is node-major (ny values a node); after it come the work and dissipation totals
            place = f"s = {self.system.s[bad // self.system.ny]:.6g} m" if bad < self.system.ny * self.system.n else "whole shell"
            raise ModelLimitError(f"non-finite state at t = {t:.9g} s, {place}", t, place)
        out = self._observe(y, t)
        if not math.isfinite(float(out[2])):  # a finite state where the law's energy is not finite somewhere
            self._check_law_domain(y, t)
        energy = self._balance(out)
        # the balance is a difference of the energies in play: its error grows with them (with the loads' work
        # from a state at rest, whose balance starts at 0), so the growth allowed is relative to them too
        in_play = max(abs(float(out[1])) + abs(float(out[2])), abs(float(out[6])), abs(float(out[7])))
        share = self.ENERGY_GROWTH * in_play
        if self.energy_limit is not None and not energy <= self.energy_limit + share:
            # the limit named is the start's (a user can check it against E(0)); the share of the energies in play
            # is said apart: after a blow-up it is 1% of the blown-up energies and would hide the start's scale
            raise NumericalInstabilityError(
                f"numerical instability: the energy balance E - W + D (the energy less the loads' work W plus the "
                f"energy dissipated D) grew to {energy:.6g} J at t = {t:.9g} s, from "
                f"{self.energy_start:.6g} J at the start (limit {self.energy_limit:.6g} J: the start's energy + "
                f"{self.ENERGY_GROWTH:.0%}, plus {self.ENERGY_GROWTH:.0%} of the energies in play now, {share:.6g} J, "
                "for round-off; constant for the exact motion, it cannot grow: a loaded shell's energy grows by W only)",
                t,
                "whole shell",
            )
        return out

    def _check_limits(self, y, out, t):
        fields = self.system.unpack(y)
        psi = np.abs(fields[4])
        if psi.max() >= np.pi / 2:
            i = int(np.argmax(psi))
            where = f"s = {self.system.s[i]:.6g} m"
            raise ModelLimitError(f"|psi| = {psi[i]:.4g} reached pi/2 at t = {t:.9g} s, {where}", t, where)
        r = fields[1][self.system.radial_nodes]
        if r.min() <= 0:
            i = int(self.system.radial_nodes[np.argmin(r)])
            where = f"s = {self.system.s[i]:.6g} m"
            raise ModelLimitError(f"r = {r.min():.3g} <= 0 at t = {t:.9g} s, {where}", t, where)
        delta = np.asarray(out[4]).ravel()  # samples_per_cell values per cell, cell by cell
        if delta.min() <= 0:
            i = int(np.argmin(delta))
            where = f"s = {self._cells[i // self.system.samples_per_cell]:.6g} m"
            raise ModelLimitError(f"delta = {delta[i]:.3g} <= 0 at t = {t:.9g} s, {where}", t, where)
        # the law's own limit (SVK's compressive turning point), and ellipticity when the scene stops there
        if getattr(self.system, "turning_limit", False) or getattr(self.system, "ellipticity_limit", False):
            g = np.asarray(self.system.limits(y)).ravel()
            bad = np.flatnonzero(g <= 0)
            if bad.size:
                what, where = self.system.limit_names()[int(bad[0])]
                raise ModelLimitError(f"{what} at t = {t:.9g} s, {where}", t, where)


class StepBudget:
    """Stops an adaptive run that cannot reach its end in ``max_steps`` steps, before it spends them.

    Every :attr:`EVERY` steps the steps still needed are projected from the mean step size of the
    last :attr:`EVERY` steps; a projection above :attr:`MARGIN` x ``max_steps`` (or a step size that
    no longer advances ``t``) ends the run as ``"failed"`` with a message naming the projection, as
    reaching ``max_steps`` does. Motions far too fast for the horizon (a stiffness or density at the
    edge of double precision, or a collapsing step near a singularity) thus end in seconds instead
    of minutes of steps that could not reach ``t_end``.
    """

    EVERY = 1000
    #: the step size may still grow this much before the projection is trusted
    MARGIN = 10.0

    def __init__(self, name, t_end, max_steps, tolerance=""):
        #: ``tolerance``: the run's tolerances as a failure names them (``rtol = 1e-14, atol = 1e-20``), or ""
        self.name, self.t_end, self.max_steps, self.tolerance = name, float(t_end), int(max_steps), tolerance
        self.steps, self.t_mark = 0, 0.0
        self.steps_mark = 0  # the steps at the last projection of :meth:`project`

    def _fail(self, message, t):
        err = ModelLimitError(message, t, "whole shell")
        err.status = "failed"
        return err

    def _projection(self, needed, count, h, t):
        return self._fail(f"{self.name} would need about {needed:.3g} steps to reach t = {self.t_end:.6g} s at the "
                          f"mean step of its last {count} steps ({h:.3g} s), more than max_steps = "
                          f"{self.max_steps}: the motion is too fast for this horizon"
                          + (f" at {self.tolerance} (a looser tolerance or a larger max_steps goes on; stopped at "
                             if self.tolerance else " (stopped at ") + f"t = {t:.9g} s)", t)

    def step(self, t):
        """Count a step that ended at ``t``; raise :class:`ModelLimitError` (status ``"failed"``) when over budget."""
        self.steps += 1
        if self.steps >= self.max_steps:
            raise self._fail(f"{self.name} took max_steps = {self.max_steps} steps by t = {t:.9g} s", t)
        if self.steps % self.EVERY:
            return
        h = (t - self.t_mark) / self.EVERY
        self.t_mark = t
        needed = self.steps + (self.t_end - t) / h if h > 0 else float("inf")
        if needed > self.MARGIN * self.max_steps:
            raise self._projection(needed, self.EVERY, h, t)

    def project(self, steps, t):
        """The same projection for a loop that counts its own steps and stops between chunks of them (the compiled
        routes): ``steps`` taken in all by ``t``. Once :attr:`EVERY` or more were taken since the last projection,
        the steps still needed are projected from their mean step. A mean over the whole run cannot see steps that
        collapse after a quick start: on a wall 1e-12 m thick IDA reached 1 ms in 900 steps, then stepped 4e-15 s
        at a time, and its projection from the whole run's mean never passed 10 x ``max_steps`` before
        ``max_steps`` (a million steps, 18 s). The first projection is the whole run's mean, as it was."""
        count = steps - self.steps_mark
        if count < self.EVERY:
            return
        h = (t - self.t_mark) / count
        self.steps_mark, self.t_mark = steps, t
        needed = steps + (self.t_end - t) / h if h > 0 else float("inf")
        if needed > self.MARGIN * self.max_steps:
            raise self._projection(needed, count, h, t)
