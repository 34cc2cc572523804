"""Errors that name what went wrong in terms a user can act on."""

from __future__ import annotations

import ctypes
import re
import reprlib
from collections.abc import Mapping

import numpy as np

_REPR = reprlib.Repr()
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = 6
_REPR.maxother = 80
_REPR.maxstring = 300  # file paths in full (a temporary directory alone can be 100 characters)


def show(value):
    """A value as an error message shows it: ``repr``, NumPy scalars as Python numbers, long arrays cut short.

    A string is shown whole (a path or a word cut in its middle cannot be acted on); long lists and arrays
    are cut at an element.
    """
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, np.ndarray):
        if value.size > 6:
            return f"<array of {value.size} values, {_REPR.repr(value.ravel()[:3].tolist())[:-1]}, ...]>"
        value = value.tolist()
    text = _REPR.repr(value)
    if "\n" in text:  # a Dataset, a DataFrame: its kind (and sizes) on the one line of a message
        sizes = getattr(value, "sizes", None)
        size = f" ({', '.join(f'{k}: {v}' for k, v in dict(sizes).items())})" if isinstance(sizes, Mapping) else ""
        text = f"<{kind_of(value)}{size}>"
    return text


def kind_of(value):
    """The type of ``value`` as a message names it: ``xarray.Dataset``, ``int`` (builtins without their module)."""
    module = type(value).__module__.split(".")[0]
    return f"{'' if module == 'builtins' else module + '.'}{type(value).__name__}"


def is_number(value):
    """A real number (``int``, ``float`` or a NumPy scalar), not a ``bool``.

    Other ``numbers.Real`` types (``fractions.Fraction``) are not: CasADi cannot compute with them.
    """
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def flag(name, value):
    """``value`` of a true/false parameter of the Python API as a ``bool`` (a NumPy bool too); anything else, a
    string or a number, is a ParameterError naming ``name`` (``constrained="no"`` was taken as True)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError.not_a(name, value, "a bool", "True or False")
    return bool(value)


def scalar(value):
    """``value`` with a NumPy 0-d array taken as the number it holds (``np.array(12)`` as ``12``): NumPy hands them
    out (``x.sum()`` of an array, ``np.array(t)``), and a check that reads them as arrays refused ``n = 12`` as
    outside ``integers >= 3``. Anything else is returned as it is."""
    return value.item() if isinstance(value, np.ndarray) and value.ndim == 0 else value


class ParameterError(ValueError):
    """A parameter is outside its allowed range (or of the wrong kind, or missing).

    The message always names the parameter and the allowed range, and the value when there is
    one, e.g. ``nu = 0.7 is outside (-1, 0.5)``. ``allowed`` is the range's text, or a declared range
    (:mod:`mol_shell._core.ranges`), which is then kept as ``range``. The alternative phrasings, for values that are
    not even of the right kind, are the class methods :meth:`not_a`, :meth:`missing` and
    :meth:`not_an_option`.
    """

    def __init__(self, name, value, allowed, hint="", *, message=None):
        #: the declared range (an :class:`~mol_shell._core.ranges.Interval` or ``Choice``) when the check gave one
        self.range = allowed if hasattr(allowed, "text") else None
        if self.range is not None:
            allowed = allowed.text()
        self.name, self.value, self.allowed, self.hint = name, value, allowed, hint
        if message is None:
            message = f"{name} = {show(value)} is outside {allowed}"
        super().__init__(message + (f" ({hint})" if hint else ""))

    @classmethod
    def invalid(cls, name, value, problem, allowed, hint=""):
        """``-o = 'out' is a directory; allowed: a file path``: a value that is wrong in a way a range cannot say."""
        return cls(name, value, allowed, hint, message=f"{name} = {show(value)} {problem}; allowed: {allowed}")

    @classmethod
    def not_a(cls, name, value, kind, allowed, hint=""):
        """``L = 'abc' is not a number; allowed: (0, inf) m``."""
        return cls.invalid(name, value, f"is not {kind}", allowed, hint)

    @classmethod
    def missing(cls, name, allowed, hint=""):
        """``t_end is missing: give t_end in (0, inf) s, or times``."""
        return cls(name, None, allowed, hint, message=f"{name} is missing: {allowed}")

    @classmethod
    def not_an_option(cls, name, integrator, options, more=()):
        """``rtol is not an option of leapfrog (its options: dt)``; ``more``, options given elsewhere (a scene file's
        ``[run]`` table, Python), listed after ``options`` (the command line's)."""
        listed = ", ".join(sorted(options))
        rest = ", ".join(sorted(set(more) - set(options)))
        also = f"; also {rest} in a scene file's [run] table or in Python" if rest else ""
        return cls(name, name, listed, message=f"{name} is not an option of {integrator} (its options: {listed}{also})")


class UnknownParameterError(ParameterError, TypeError):
    """A keyword that names no parameter of a scene: a :class:`ParameterError` (one line, exit 2 on the command
    line) and, like Python's own refusal of an unexpected keyword argument, a ``TypeError``."""


def by_interrupt(exc):
    """Whether ``exc`` is a Ctrl-C: a ``KeyboardInterrupt``, or an error raised because one arrived inside a call into
    C, which reports it in its own way: CasADi's wrappers return with the interrupt set (Python raises a
    ``SystemError`` caused by it), ctypes raises an ``ArgumentError`` naming it in its text (``argument 1:
    KeyboardInterrupt: ``: it arrived while ctypes converted an argument, with no cause recorded), CasADi a
    ``RuntimeError`` whose last line names it (raised inside a CasADi call, by its own check for signals or a Python
    function it called). Causes and contexts are followed."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt) or _names_interrupt(exc):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _names_interrupt(exc):
    """An error of a C extension that wraps a ``KeyboardInterrupt`` in its text only (:func:`by_interrupt`)."""
    if isinstance(exc, ctypes.ArgumentError):
        return re.match(r"argument \d+: KeyboardInterrupt:", str(exc)) is not None
    if isinstance(exc, RuntimeError):
        lines = str(exc).strip().splitlines()
        return bool(lines) and re.fullmatch(r"KeyboardInterrupt(?::.*)?", lines[-1].strip()) is not None
    return False


class MolShellWarning(UserWarning):
    """A warning of mol_shell about a run, its scene or its result (a start that is unstable, grid modes, a stored case
    run again, stresses not computed, ...): a run goes on. Python's warnings, filtered as usual; the command line says
    each in one line, ``mol-shell: warning: ...``, whatever ``python -W`` asks (``-W error`` would end the command
    and lose its result). The categories below derive from it."""


class RunWarning(MolShellWarning, RuntimeWarning):
    """A :class:`MolShellWarning` about the course of a run or a study (its worker processes that stopped before their
    first case); a ``RuntimeWarning`` too, as it was before."""


class MaterialWarning(MolShellWarning):
    """A material law used outside the range where it describes the wall it is meant for (a run goes on).

    The message is one line naming the parameters and the law to choose instead; the command line prints
    it as ``mol-shell: warning: ...``, and a run records it in its Dataset's attrs.
    """


class SceneWarning(MolShellWarning):
    """A scene parameter that has no effect as the scene is set (a load's history without the load): one line
    naming it and what would use it; the command line prints it as ``mol-shell: warning: ...``, and a run records it
    in its Dataset's attrs (``scene_warning``)."""


class ModelLimitError(RuntimeError):
    """A run reached a limit of the model (``delta <= 0``, ``r <= 0``) or produced NaN/Inf.

    Attributes
    ----------
    time : float
        First time at which the limit was detected.
    where : str
        Which quantity, and the arc length ``s`` where it failed.
    """

    status = "limit"

    def __init__(self, message, time, where):
        self.time, self.where = time, where
        super().__init__(message)


class NumericalInstabilityError(ModelLimitError):
    """The energy of an unloaded shell grew: the time step or the method is unstable."""

    status = "unstable"

