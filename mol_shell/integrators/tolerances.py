"""The tolerances every adaptive integrator takes: ``rtol``, ``atol`` (per field; momenta scaled by their mass)
and ``max_step``, each declared with its range."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mol_shell._core.constants import ATOL_MIN, FIELDS
from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell.discretization.scales import unit_strain_energy
from mol_shell.integrators import loop
from mol_shell.integrators.loop import RTOL, Option, non_negative, option, real

#: the absolute tolerances' range (:data:`~mol_shell._core.constants.ATOL_MIN`: below it the error norms overflow)
ATOL_RANGE = f"[{ATOL_MIN:g}, inf)"
ATOL_ALLOWED = f"{ATOL_RANGE}: one value, {{field: value}} or five values (z, r, chi, theta, psi)"
#: what ``max_step = 0`` means, as every range of ``max_step`` states it (Python, ``--max-step``, a ``[run]`` table)
MAX_STEP_NOTE = " (0: unbounded)"


#: the share of ``max_steps`` a ``max_step`` must leave free beyond the steps of at most ``max_step`` (one more per
#: saved interval than ``interval / max_step``): the first steps, below ``max_step`` as the error control starts
MAX_STEP_MARGIN = 0.01


def smallest_max_step(t_end, intervals, max_steps, longest=None):
    """The smallest ``max_step`` (s) with which ``max_steps`` steps reach ``t_end`` through ``intervals`` saved
    intervals: steps of at most ``max_step`` shortened to land on each saved time take up to ``t_end / max_step +
    intervals``, and :data:`MAX_STEP_MARGIN` of ``max_steps`` is left for the start (``max_step = t_end / max_steps``
    took all 1,000,000 steps by 0.00999992 of t = 0.01 s); inf where ``max_steps`` cannot hold even that.

    With ``longest`` (s), the longest saved interval, for a route whose ``max_steps`` counts the steps of one saved
    interval (casadi-cvodes, casadi-idas: CasADi's ``max_num_steps``): each interval's steps reach its end, ``longest
    / (0.99 max_steps - 1)`` (a run total refused 150 steps per interval at 200 intervals, which ran in 63)."""
    free = max_steps * (1.0 - MAX_STEP_MARGIN) - (1 if longest is not None else intervals)
    span = longest if longest is not None else t_end
    return span / free if free > 0 else np.inf


def least_max_steps(t_end, intervals, max_step, longest=None):
    """The least ``max_steps`` with which steps of at most ``max_step`` reach the saved times: the least for which
    :func:`smallest_max_step` (same arguments) is at most ``max_step``."""
    need, span = (1, longest) if longest is not None else (intervals, t_end)
    least = max(1, math.ceil((span / max_step + need) / (1.0 - MAX_STEP_MARGIN)))
    while least > 1 and smallest_max_step(t_end, intervals, least - 1, longest) <= max_step:  # to the last digit
        least -= 1
    while smallest_max_step(t_end, intervals, least, longest) > max_step:
        least += 1
    return least


def atol_ok(value):
    """Whether one absolute tolerance is a number in :data:`ATOL_RANGE` (a big integer as its float)."""
    return ATOL_MIN <= real(value) < np.inf


def field_atol(a):
    """Absolute tolerance per field ``(z, r, chi, theta, psi)`` from one number, a dict or five numbers."""
    if isinstance(a, dict):
        bad = [key for key in a if key not in FIELDS]
        if bad:
            raise ParameterError.invalid("atol", a, f"names {show(bad[0])}, which is not a field",
                                         "{field: value} with field in {" + ", ".join(FIELDS) + "}")
        values = [a.get(name, 1e-9) for name in FIELDS]
    elif isinstance(a, (int, float, np.integer, np.floating)):
        values = [a] * len(FIELDS)
    else:
        try:
            values = list(a)
        except TypeError:
            raise ParameterError("atol", a, ATOL_ALLOWED) from None
        if len(values) != len(FIELDS):
            raise ParameterError("atol", a, "one value, {field: value}, or five values (z, r, chi, theta, psi)")
    if not all(map(atol_ok, values)):
        raise ParameterError("atol", a, ATOL_RANGE)
    return np.array([real(v) for v in values], dtype=float)


def _atol_ok(value):
    try:
        field_atol(value)
    except ParameterError:
        return False
    return True


@dataclass(frozen=True)
class Tolerances:
    """Tolerances of an adaptive integrator.

    Parameters
    ----------
    rtol : float
        Relative tolerance, in :data:`~mol_shell._core.constants.RTOL_RANGE`.
    atol : float or dict or sequence
        Absolute tolerance of the fields (m or rad): one number, ``{field: value}`` or five values
        (``z, r, chi, theta, psi``). Rates get the same number (per second); momenta that number
        times the lumped mass of their entry, so CVODE and IDA control comparable quantities.
    max_step : float
        Largest step, s (0: unbounded).
    """

    rtol: float = option(1e-6, RTOL)
    atol: object = option(1e-9, Option(ATOL_ALLOWED, _atol_ok, convert=lambda a: real(a) if is_number(a) else a))
    max_step: float = option(0.0, non_negative(" s", MAX_STEP_NOTE))

    def __post_init__(self):
        if isinstance(self.atol, (dict, list, tuple)):  # a field's name or an entry first: the declared range's
            self.field_atol()  # check calls them "not a number"
        loop.check_declared(self)
        self.field_atol()  # names the wrong entry

    def settings(self):
        return self.tolerances()

    def tolerances(self):
        """``rtol``, ``atol`` (a number, or per field as ``"z=1e-09,r=1e-08,..."``) and ``max_step`` as attributes."""
        atol = self.atol if is_number(self.atol) else ",".join(
            f"{name}={float(value)!r}" for name, value in zip(FIELDS, self.field_atol()))  # round-trips
        return {"rtol": self.rtol, "atol": atol, "max_step": self.max_step}

    def tolerance_text(self):
        """``rtol = 1e-14, atol = 1e-20`` (``atol`` per field where it was given so), as failures name it."""
        tolerances = self.tolerances()
        atol = tolerances["atol"]
        return f"rtol = {tolerances['rtol']:g}, atol = " + (f"{atol:g}" if is_number(atol) else "{" + atol + "}")

    def field_atol(self):
        """Absolute tolerance per field ``(z, r, chi, theta, psi)``."""
        return field_atol(self.atol)

    def atol_vector(self, system, y0, momenta):
        """Per-entry absolute tolerances of the node-major state."""
        fa = self.field_atol()[list(system.active)]
        nf = system.nf
        vec = np.tile(np.r_[fa, fa], system.n)
        if momenta:  # p = M v: scale by the lumped diagonal mass of each entry (interior value where fixed)
            Q = system.unpack(y0)
            for j, k in enumerate(system.active):
                V = np.zeros_like(Q)
                V[k] = 1.0
                m = np.array(system.momenta(Q, V))[k]
                m[m <= 0] = m.max()
                vec[nf + j : system.ny * system.n : 2 * nf] *= m
        if system.n_extra:
            vec = np.concatenate([vec, np.full(system.n_extra, self.accumulator_atol(system, y0))])
        return vec

    def accumulator_atol(self, system, y0):
        """Absolute tolerance of the ``work`` and ``dissipated`` accumulators (J): ``rtol`` times the energy in play
        at the start (kinetic + stored of ``y0``), and at least ``rtol`` times 1e-9 of a unit strain's energy of the
        wall (the energy of a strain of 4.5e-5: a start at rest in its natural state has no energy to scale by).

        Their error is then controlled at the run's energies, so ``E - E(0) - work + dissipated`` holds to about
        ``rtol`` of them. ``atol`` (1e-9) times a unit strain's energy, as before, was 1.1e-3 J on a cone, 3 % of its
        driver's work: a kink in a drive's history then left ``work`` 0.0081 J off and CVODE stopped on a false
        numerical instability. Step counts of ordinary runs changed by -6 to +20 % (docs/loads.md)."""
        unit = unit_strain_energy(system)
        out = system.observables(y0, 0.0)
        start = abs(float(out[1])) + abs(float(out[2]))
        if not np.isfinite(start):  # a start outside the law's domain: the run's checks name it
            start = 0.0
        return float(self.rtol) * max(start, 1e-9 * unit)

