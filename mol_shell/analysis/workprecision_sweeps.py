"""What a work-precision comparison sweeps (:mod:`mol_shell.analysis.workprecision`): the integrators, each one's
sweep of tolerances (of ``dt`` for leap-frog), and the points of a sweep that are not run and why.

A sweep given to :func:`~mol_shell.analysis.workprecision.work_precision` (``sweeps``) is a mapping
``{integrator: {"rtol": [values]}}``, ``{"leapfrog": {"dt": [values in s]}}``; it replaces the default sweep
(:data:`SWEEPS`) of each integrator it names and is checked here as a whole before anything runs.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell.integrators import INTEGRATORS

RTOLS = (1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 1e-8, 1e-9, 1e-10)
SWEEPS = {
    "leapfrog": {"dt": (1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 4e-6, 2e-6, 1e-6)},
    "cvode-bdf": {"rtol": RTOLS},
    "cvode-adams": {"rtol": RTOLS},
    "ida": {"rtol": RTOLS},
    "sksundae-cvode-adams": {"rtol": RTOLS[:9]},  # 0.5.0's route (scikit-sundae's Python loop), for comparison
    "scipy-rk45": {"rtol": RTOLS[:8]},
    "scipy-dop853": {"rtol": RTOLS},
    "scipy-radau": {"rtol": RTOLS[:7]},
    "scipy-bdf": {"rtol": RTOLS[:7]},
    "casadi-cvodes": {"rtol": RTOLS[:9]},
    "casadi-idas": {"rtol": RTOLS[:7]},
    "casadi-cvodes-c": {"rtol": RTOLS},
    "dop853-c": {"rtol": RTOLS},
    "rk45-c": {"rtol": RTOLS[:8]},
}
#: compared by default: every route but scikit-sundae's BDF and IDA, 0.5.0's (their Python loops take minutes on the
#: tighter tolerances; named, they run on the sweep below)
DEFAULT_INTEGRATORS = tuple(SWEEPS)
SWEEPS.update({"sksundae-cvode-bdf": {"rtol": RTOLS[:7]}, "sksundae-ida": {"rtol": RTOLS[:7]}})
#: what ``sweeps`` may be, as its errors say it
SWEEPS_ALLOWED = ('a mapping {integrator: {"rtol": [values]}}, {"leapfrog": {"dt": [values in s]}} for leap-frog, '
                  'e.g. {"dop853-c": {"rtol": [1e-6, 1e-8]}}')


def swept(name):
    """What the sweep of integrator ``name`` varies: ``"dt"`` (leap-frog's step, s) or ``"rtol"``."""
    return next(iter(SWEEPS.get(name, {"rtol": ()})))


def options(name, value):
    """Integrator options for one sweep point."""
    return {"dt": value} if swept(name) == "dt" else {"rtol": value, "atol": 1e-3 * value}


def check_integrators(integrators, name="integrators"):
    """A non-empty list of distinct registered integrator names, or a named error; a lone name (a string) is a list
    of one (it was read letter by letter: ``integrators = 'd' is outside ...``)."""
    allowed = "a comma-separated list of {" + ", ".join(INTEGRATORS) + "}"
    names = [integrators] if isinstance(integrators, str) else list(integrators)
    if not names:
        raise ParameterError.invalid(name, ",".join(names), "is empty", allowed)
    if any(not str(item).strip() for item in names):
        raise ParameterError.invalid(name, ",".join(map(str, names)), "has an empty entry", allowed)
    for item in names:
        if item not in INTEGRATORS:
            raise ParameterError(name, item, allowed)
        if names.count(item) > 1:
            raise ParameterError.invalid(name, ",".join(names), f"names {item} twice", allowed)
    return names


def check_sweeps(sweeps, defaults=None):
    """``defaults`` (:data:`SWEEPS` where ``None``) with those of ``sweeps`` (:data:`SWEEPS_ALLOWED`; ``None``: none) in place of their integrators'
    defaults, ``{name: {key: tuple of floats}}``; anything else is one :class:`ParameterError` naming ``sweeps`` (a
    list where the mapping of ``rtol`` belongs raised an AttributeError, an unknown key ran silently as ``rtol``)."""
    defaults = dict(SWEEPS if defaults is None else defaults)
    if sweeps is None:
        return defaults
    if not isinstance(sweeps, Mapping):
        raise ParameterError.not_a("sweeps", sweeps, "a mapping", SWEEPS_ALLOWED)
    out = defaults
    for name, sweep in sweeps.items():
        if not isinstance(name, str) or name not in INTEGRATORS:
            raise ParameterError.invalid("sweeps", sweeps, f"names {show(name)}, no integrator ({{"
                                         + ", ".join(INTEGRATORS) + "})", SWEEPS_ALLOWED)
        key = swept(name)
        if not (isinstance(sweep, Mapping) and list(sweep) == [key]):
            raise ParameterError.invalid(f"sweeps[{name!r}]", sweep, f"is not {{{key!r}: [values]}} ({name} sweeps "
                                         f"{key} alone)", SWEEPS_ALLOWED)
        values = sweep[key]
        if not isinstance(values, (list, tuple, np.ndarray)) or np.asarray(values, dtype=object).ndim != 1 or (
                len(values) == 0):
            raise ParameterError.invalid(f"sweeps[{name!r}][{key!r}]", values, "is not a non-empty list of numbers",
                                         SWEEPS_ALLOWED)
        for value in values:
            if not is_number(value) or isinstance(value, np.floating) and value.dtype != np.float64:
                raise ParameterError.invalid(f"sweeps[{name!r}][{key!r}]", values, f"holds {show(value)}",
                                             SWEEPS_ALLOWED, hint="not a number" if not is_number(value) else
                                             "a single-precision value: give it in double precision")
            try:
                INTEGRATORS[name](**options(name, value))
            except ParameterError as exc:  # the integrator's own range, said for the sweep
                raise ParameterError.invalid(f"sweeps[{name!r}][{key!r}]", values, f"holds {show(value)}",
                                             SWEEPS_ALLOWED, hint=str(exc)) from None
        out[name] = {key: tuple(float(v) for v in values)}
    return out


def skip_reason(name, value, times):
    """Why a sweep point cannot run on ``times`` (``""`` when it can): a leap-frog step that misses a saved time."""
    method = INTEGRATORS[name](**options(name, value))
    if hasattr(method, "step_counts"):
        try:
            method.step_counts(np.asarray(times))
        except ParameterError as exc:
            return f"skipped: {exc}"
    return ""


def unstable_reason(name, value, omega_max):
    """Why a leap-frog step is not run on a scene whose Jacobian at the start has ``max |eig| = omega_max``: past its
    stability bound ``1 / omega_max``, which :func:`~mol_shell.runs.simulate.simulate` refuses, in simulate's words
    (``""`` for a step within it and for every other integrator). Such a point used to run, and its blow-up was
    recorded as a measured instability (``unstable``)."""
    if swept(name) != "dt" or value * omega_max < 1.0:
        return ""
    refused = ParameterError("dt", value, f"(0, {1.0 / omega_max:.4g}) s", hint="leap-frog stability bound "
                             "1/max|eig J(y0)|")
    return f"skipped: {refused} (simulate refuses it)"
