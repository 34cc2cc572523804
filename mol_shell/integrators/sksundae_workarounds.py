"""Workarounds of scikit-sundae's defects, for its Python-callback routes (``sksundae-*``, and the compiled routes'
fallback): a constraint type it takes and stores as "no constraint" (:data:`UNCONSTRAINED`, with
:func:`~mol_shell.integrators.sundials.full_constraints`: every entry listed, since a partial list leaves the rest of
its constraints vector uninitialised), and SUNDIALS statuses missing from its table of messages
(:func:`unlisted_status`)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np


class _Unconstrained:
    """A constraint type that passes scikit-sundae's check ``x in (-2, -1, 1, 2)`` and is stored as 0.0."""

    def __eq__(self, other):
        return other == 1

    def __hash__(self):
        return hash(1)

    def __float__(self):
        return 0.0

    def __repr__(self):
        return "UNCONSTRAINED"


UNCONSTRAINED = _Unconstrained()


def unlisted_status(call, *args, **kwargs):
    """``call`` of scikit-sundae's solver, a SUNDIALS status missing from its table of messages (IDA's -60, "tout too
    close to t0", raised as a ``KeyError`` inside it) returned as the failed result it is, not a traceback."""
    try:
        return call(*args, **kwargs)
    except KeyError as exc:
        if not (exc.args and isinstance(exc.args[0], int) and exc.args[0] < 0):
            raise
        return SimpleNamespace(status=exc.args[0], success=False, unlisted=True, t=np.nan, y=None, yp=None,
                               message="SUNDIALS refused the call (its message is not in scikit-sundae's table; see "
                               "SUNDIALS' return codes)")
