"""Errors that name what went wrong in terms a user can act on."""

from __future__ import annotations


class ParameterError(ValueError):
    """A parameter is outside its allowed range.

    The message always names the parameter, its value and the allowed range,
    e.g. ``nu = 0.7 is outside (-1, 0.5)``.
    """

    def __init__(self, name, value, allowed, hint=""):
        self.name, self.value, self.allowed = name, value, allowed
        message = f"{name} = {value!r} is outside {allowed}"
        super().__init__(message + (f" ({hint})" if hint else ""))


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
