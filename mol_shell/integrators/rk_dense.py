"""Where ``dop853-c`` and ``rk45-c`` crossed a limit of the model: inside the step that crossed it.

The C driver (:mod:`mol_shell.discretization.rk_driver`) checks the limits at the end of every accepted step and
keeps a step whose end left them whole: its start, its stages and its end. The crossing is then located once, in
Python, on the step's continuous extension (SciPy's: DOP853's 7th-order one, three more stages; the Dormand-Prince
5(4) pair's 4th-order one, from its stages alone) by a bracketing search on the limits that changed sign: the
Illinois variant of the secant method with SUNDIALS' safeguards (CVODE's ``cvRootfind``), each trial one compiled
evaluation of the limits, to :func:`time_tolerance`. What is reported, as CVODE and IDA report a root, is the end of
the last bracket, where a limit is broken (``g <= 0``, within the tolerance of its zero).
"""

from __future__ import annotations

import numpy as np

#: the search's relative tolerance in time (of ``t``; a few ulps where that is less)
RELATIVE = 1e-12
#: trials at most (the bracket shrinks at least ten-fold every few: far fewer are taken)
MAX_TRIALS = 200


def time_tolerance(t):
    """The width of the last bracket: ``1e-12 |t|``, and at least 4 ulp of ``t``."""
    return max(RELATIVE * abs(t), 4 * float(np.spacing(abs(t))))


class DenseStep:
    """``t -> y(t)`` on one accepted step from ``(t0, y0)`` to ``(t1, y1)``: SciPy's continuous extension of its pair.

    ``method``: the ``scipy.integrate`` class (``DOP853``, ``RK45``) whose tableau the step took; ``K``: its stages
    ``(s, N)`` (the first ``f(t0, y0)``); ``f1``: ``f`` at its end; ``evaluate(y, t)``: the right-hand side, called
    three times for DOP853's extra stages (:attr:`n_rhs`).
    """

    def __init__(self, method, t0, y0, t1, K, y1, f1, evaluate):
        self.t0, self.t1, self.y0, self.y1 = t0, t1, np.array(y0), np.array(y1)
        self.h = h = t1 - t0
        K = np.vstack([K, f1])  # the stages and f at the end (first same as last): SciPy's K
        self.n_rhs = 0
        if hasattr(method, "D"):  # DOP853: the 7th-order extension (Hairer, Norsett and Wanner's dense output)
            extended = np.vstack([K, np.empty((len(method.C_EXTRA), K.shape[1]))])
            for j, (a, c) in enumerate(zip(method.A_EXTRA, method.C_EXTRA), start=len(K)):
                extended[j] = evaluate(self.y0 + h * (a[:j] @ extended[:j]), t0 + c * h)
                self.n_rhs += 1
            dy = self.y1 - self.y0
            self.F = [dy, h * K[0] - dy, 2 * dy - h * (f1 + K[0]), *(h * (method.D @ extended))]
            self.Q = None
        else:  # the 4th-order extension of the Dormand-Prince 5(4) pair
            self.Q = h * (method.P.T @ K)  # (4, N): y = y0 + sum_k x^(k+1) Q_k

    def __call__(self, t):
        if t == self.t1:
            return self.y1.copy()
        x = (t - self.t0) / self.h
        if self.Q is not None:
            return self.y0 + np.cumprod(np.full(len(self.Q), x)) @ self.Q
        y = np.zeros_like(self.y0)
        for i, f in enumerate(reversed(self.F)):  # SciPy's Dop853DenseOutput
            y += f
            y *= x if i % 2 == 0 else 1 - x
        return y + self.y0


def first_crossing(limits_at, t0, t1, g0, g1):
    """``(t, g)``: where the limits ``g(t) = limits_at(t)`` (all positive at ``t0``, ``g0``; one not at ``t1``, ``g1``)
    are first broken (``not g > 0``), to :func:`time_tolerance`: the end of the last bracket, and ``g`` there.

    Illinois (secant with the retained end's value halved when the same end is kept twice) on the limit whose secant
    crosses first, as CVODE's ``cvRootfind``, with its guard against trials within half the tolerance of an end;
    bisection where a limit is not finite (no secant there).
    """
    tol = time_tolerance(t1)
    lo, hi, glo, ghi = t0, t1, np.asarray(g0, dtype=float), np.asarray(g1, dtype=float)
    alpha, side, previous = 1.0, 0, 0
    for _ in range(MAX_TRIALS):
        if hi - lo <= tol:
            break
        if side and side == previous:
            alpha = alpha * 2 if side == 2 else alpha / 2
        else:
            alpha = 1.0
        broken = ~(ghi > 0)
        with np.errstate(all="ignore"):
            frac = np.where(broken & (glo > 0), ghi / (ghi - alpha * glo), np.nan)
        if np.all(np.isfinite(frac[broken])) and np.any(broken & (glo > 0)):
            mid = hi - (hi - lo) * float(np.nanmax(frac))
        else:
            mid = lo + 0.5 * (hi - lo)
        width = hi - lo
        if not lo < mid < hi or mid - lo < 0.5 * tol:  # CVODE's guard: a trial a fraction inside the bracket
            mid = lo + (0.1 if width / tol > 5 else 0.5 / (width / tol)) * width
        if hi - mid < 0.5 * tol:
            mid = hi - (0.1 if width / tol > 5 else 0.5 / (width / tol)) * width
        g = np.asarray(limits_at(mid), dtype=float)
        previous = side
        if np.any(~(g > 0)):
            hi, ghi, side = mid, g, 1
        else:
            lo, glo, side = mid, g, 2
    return hi, ghi


__all__ = ["DenseStep", "first_crossing", "time_tolerance"]
