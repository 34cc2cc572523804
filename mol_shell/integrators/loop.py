"""The one run loop every integrator of the shell runs in, and the protocol an integrator follows.

An integrator is a frozen dataclass whose fields are exactly the options it takes (checked by
:func:`check_declared` from each field's declared :class:`Option`), with class attributes ``name`` and
``order``, and a method ``start(system, compiled, y0, times, monitor) -> Stepper``. The loop
(:func:`run`) owns what is common to all of them, as ``scipy.integrate.solve_ivp`` owns it for SciPy's
solvers: the saved times, progress, the checks of the model's limits at saved times
(:class:`~mol_shell.integrators.base.Monitor`), Ctrl-C, and the kinds of failure:

``"limit"``
    a limit of the model was reached (``delta -> 0``, ``r -> 0``, ``|psi| -> pi/2``, a non-finite state);
``"unstable"``
    the energy balance E - W + D grew: a numerical instability;
``"failed"``
    the integrator gave up (its step underflowed, ``max_steps``, a solver error);
``"interrupted"``
    Ctrl-C.

Each ends the run with the saved times reached kept and ``failure_time`` set.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields
from typing import Callable, Protocol

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.constants import RTOL_RANGE
from mol_shell._core.errors import ModelLimitError, ParameterError, by_interrupt, show
from mol_shell.integrators.base import Monitor, Trajectory

#: how a run can end other than ``"complete"``, and what each means
FAILURE_KINDS = {
    "limit": "a limit of the model was reached (delta -> 0, r -> 0, |psi| -> pi/2, a non-finite state)",
    "unstable": "the energy balance E - W + D grew: a numerical instability",
    "failed": "the integrator gave up (step underflow, max_steps, a solver error)",
    "interrupted": "interrupted by the user (Ctrl-C)",
}


@dataclass(frozen=True)
class Option:
    """An integrator option's type and allowed range, declared once beside its field.

    ``check(value) -> bool`` decides; ``allowed`` is the range as the error message states it; ``convert``, if given,
    makes an accepted value the type the option is stored as (a float option given ``10**20`` holds ``1e20``: the
    run's netCDF attributes cannot hold a Python integer beyond 64 bits). ``words``: :data:`NONE_WORDS` are ``None``
    for an option that takes it (:func:`typed_value`); False where ``None`` is only the default left out (leap-frog's
    ``restart``: ``restart=none`` read as the default restarted every 1 s, the opposite of what it says).
    """

    allowed: str
    check: Callable[[object], bool]
    doc: str = ""
    convert: Callable[[object], object] | None = None
    words: bool = True


#: the largest integer option: they are stored as 64-bit integers (the run's netCDF attributes, the drivers' step
#: counters, ``long long`` in C)
INT64_MAX = 2**63 - 1


def _number(value):
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def real(value):
    """A number option's value as a float: an integer beyond the floats' range as +-inf (``float(10**400)`` raises),
    anything but a number NaN, so a range's comparisons refuse it."""
    if not _number(value):
        return math.nan
    try:
        return float(value)
    except OverflowError:
        return math.inf if value > 0 else -math.inf


def positive(unit=""):
    return Option(f"(0, inf){unit}", lambda v: 0 < real(v) < math.inf, convert=real)


def non_negative(unit="", zero=""):
    return Option(f"[0, inf){unit}{zero}", lambda v: 0 <= real(v) < math.inf, convert=real)


def zero_or_at_least(low, unit="", zero=""):
    """``0`` (``zero`` says what it means) or ``[low, inf)``; ``low`` is stated to 4 digits: one that has no more
    (:func:`~mol_shell._core.constants.stated_up`), so that the range stated is the one applied."""
    return Option(f"0{zero} or [{low:.4g}, inf){unit}", lambda v: real(v) == 0 or low <= real(v) < math.inf,
                  convert=real)


def integers(low, high=INT64_MAX):
    """``[low, high]``, Python or NumPy integers (not bools); at most :data:`INT64_MAX`, as they are stored."""
    return Option(f"integers in [{low}, {high}]", lambda v: isinstance(v, (int, np.integer))
                  and not isinstance(v, (bool, np.bool_)) and low <= v <= high, convert=int)


def interval(low, high, unit=""):
    """``[low, high)``: a relative tolerance below ``low`` is under round-off, one at ``high`` controls nothing."""
    return Option(f"[{low:g}, {high:g}){unit}", lambda v: low <= real(v) < high, convert=real)


def choice(*values):
    return Option("{" + ", ".join(map(str, values)) + "}", lambda v: v in values)


BOOL = Option("{True, False}", lambda v: isinstance(v, (bool, np.bool_)))

#: relative tolerances accepted by every adaptive integrator (:data:`~mol_shell._core.constants.RTOL_RANGE`)
RTOL = interval(*RTOL_RANGE)


def option(default, spec):
    """A dataclass field with its declared :class:`Option` in the metadata."""
    return field(default=default, metadata={"option": spec})


def declared(cls):
    """``{name: Option}`` of the integrator class ``cls`` (its dataclass fields)."""
    return {f.name: f.metadata["option"] for f in fields(cls) if "option" in f.metadata}


#: the words a command line (``--option max_order=none``) or a scene file's ``[run]`` table writes for ``None``, in
#: any case: TOML has no null, and scene parameters take the same two words for theirs
NONE_WORDS = ("none", "auto")


def typed_value(spec, value):
    """An option's value as a command line or a scene file gives it: :data:`NONE_WORDS` as ``None`` where the option
    declared by ``spec`` takes ``None`` (``max_order``, ``max_newton``) and not the word itself; else ``value``."""
    if (isinstance(value, str) and value.strip().lower() in NONE_WORDS and not spec.check(value)
            and spec.check(None) and spec.words):
        return None
    return value


def _integer(value):
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def refusal(name, value, spec, typed=None):
    """The :class:`ParameterError` for ``value`` outside the option ``spec`` declares, by ``name``: a value that is not
    even of the option's kind says so (``chunk = 1e12``, a float, "is not an integer", not "outside integers in [1,
    ...]", which it is not). ``typed``: the value as the user wrote it (``1e12``), for the message."""
    shown = typed if typed is not None else show(value)
    if spec.allowed.startswith("integers") and value is not None and not _integer(value):
        whole = isinstance(value, (float, np.floating)) and abs(value) < 2.0**64 and float(value).is_integer()
        hint = f"a float: write it as the integer {int(value)}" if whole else ""
        return ParameterError(name, value, spec.allowed, hint,
                              message=f"{name} = {shown} is not an integer; allowed: {spec.allowed}")
    if not _number(value) and "inf" in spec.allowed:
        word = isinstance(value, str) and value.strip().lower() in NONE_WORDS  # restart=none: not its default
        return ParameterError(name, value, spec.allowed, "leave it out for the default" if word else "",
                              message=f"{name} = {shown} is not a number; allowed: {spec.allowed}")
    return ParameterError(name, value, spec.allowed, message=f"{name} = {shown} is outside {spec.allowed}")


def check_declared(instance):
    """Refuse, by name and with its allowed range, an option value outside its declared range (:func:`refusal`);
    store an accepted one as its declared type (:attr:`Option.convert`)."""
    for name, spec in declared(type(instance)).items():
        value = getattr(instance, name)
        if not spec.check(value):
            raise refusal(name, value, spec)
        if spec.convert is not None and value is not None:  # stored as its type (the run's attributes are written)
            object.__setattr__(instance, name, spec.convert(value))


class _NotStarted:
    """Stands for a stepper whose start failed (a limit at the first step)."""

    t = 0.0

    def stats(self):
        return {"n_steps": 0}


class Stepper(Protocol):
    """One solve in progress, as an integrator's ``start`` returns it."""

    #: time reached (s)
    t: float

    def advance(self, target: float) -> None:
        """Move towards ``target`` (one step or a chunk of steps; never past it unless ``state`` interpolates);
        raise :class:`~mol_shell._core.errors.ModelLimitError` for any failure."""

    def state(self, target: float) -> np.ndarray:
        """The Hamiltonian state ``(q, p)`` at the saved time ``target`` (reached or passed)."""

    def stats(self) -> dict:
        """Counters: ``n_steps``, ``n_rhs``, ... (``wall_time_s`` to replace the loop's own measure)."""


def run(integrator, system, compiled, y0, times, *, progress=None):
    """Run ``integrator`` from ``times[0] = 0`` through ``times``: the one loop, for every integrator.

    Returns a :class:`~mol_shell.integrators.base.Trajectory` of the saved times reached; a failure of any
    kind (:data:`FAILURE_KINDS`) ends the run there with its status, message and time. A Ctrl-C (SIGINT) is noted
    by a handler of the loop's own wherever it lands (:func:`mol_shell._core.interrupts.watched`: inside a
    CasADi or ctypes call, which lose or wrap a ``KeyboardInterrupt``) and ends the run ``"interrupted"`` at the end
    of the chunk it arrived in; an integrator whose chunk is one long CasADi call that stops itself on a signal
    (``interrupt_inside``) has it raised there too.
    """
    times = np.asarray(times, dtype=float)
    if times[0] != 0:
        raise ParameterError("times", float(times[0]), "first saved time must be 0")
    with interrupts.watched(raising=getattr(integrator, "interrupt_inside", False)) as watch:
        traj = _steps(integrator, system, compiled, y0, times, progress, watch)
    if watch.caught and traj.status == "complete":  # after the loop's last look, before its handler was put back
        t = float(traj.t[-1])
        traj.status, traj.message, traj.failure_time = "interrupted", f"interrupted by the user at t = {t:.9g} s", t
    return traj


def _steps(integrator, system, compiled, y0, times, progress, watch):
    """:func:`run`'s loop, with SIGINT noted in ``watch``."""
    monitor = Monitor(system, y0)
    saved, reached = [np.array(y0, dtype=float)], [0.0]
    status, message, failure = "complete", "completed", float("nan")
    stepper = _NotStarted()
    setup = start = time.perf_counter()
    try:
        # the set-up (loading compiled drivers, creating the solver, a first step) is timed apart from the
        # stepping: wall_time_s is the integration's own cost, as work-precision compares it
        # a start outside the model's limits stops here, at t = 0 (a root-finding solver sees only crossings: a
        # run started past the loss of ellipticity with ellipticity_limit on went on, warned only afterwards)
        monitor.check(saved[0], 0.0)
        _stop_if_caught(watch)  # before the solver's set-up (an interrupt in the run's own set-up, or lost before it)
        stepper = integrator.start(system, compiled, y0, times, monitor)
        start = time.perf_counter()
        if hasattr(progress, "reset"):  # its clock from here, as wall_time_s's: a build (gcc) is no simulated time
            progress.reset()
        shown = 0.0  # the simulated time progress has been told of: all a stepper reached, up to the end
        for target in times[1:]:
            while stepper.t < target:
                _stop_if_caught(watch)
                stepper.advance(float(target))
                if progress is not None:  # a step or call past several saved times (casadi-*: all of them) counts
                    progress.update(min(stepper.t, times[-1]) - shown)
                    shown = min(stepper.t, times[-1])
            y = stepper.state(float(target))
            if not getattr(integrator, "checks_every_chunk", False):  # else the stepper checked it already
                monitor.check(y, float(target))
            saved.append(y)
            reached.append(float(target))
        _stop_if_caught(watch)  # a signal in the last chunk: the run was interrupted, whatever it reached
    except BaseException as exc:  # every error that is a Ctrl-C's (by_interrupt), or came after one
        watch.raising = False  # the run ends here: a second Ctrl-C is noted, not raised in the middle of it
        if isinstance(exc, ModelLimitError) and not watch.caught:
            status, message, failure = exc.status, str(exc), exc.time
        elif watch.caught or by_interrupt(exc):  # a solver that failed because of the interrupt was interrupted
            t = float(stepper.t)
            status, message, failure = "interrupted", f"interrupted by the user at t = {t:.9g} s", t
        else:
            raise
    stats = {"wall_time_s": time.perf_counter() - start, "setup_time_s": start - setup, **stepper.stats()}
    return Trajectory(np.array(reached), np.array(saved), status=status, message=message, stats=stats,
                      failure_time=failure)


def _stop_if_caught(watch):
    """End the run (as a ``KeyboardInterrupt`` would) once a SIGINT has been noted."""
    if watch.caught:
        raise KeyboardInterrupt


__all__ = ["FAILURE_KINDS", "NONE_WORDS", "Option", "RTOL", "Stepper", "check_declared", "declared", "option",
           "refusal", "run", "typed_value"]
