"""The built-in stored energies ``W(C)`` beyond SVK's own route, and the plane-stress condensations of the two
compressible neo-Hookean laws (what :mod:`mol_shell.model.laws` registers as :class:`~mol_shell.model.hyperelastic.Law`).

Each takes the right Cauchy-Green tensor ``C`` (3 x 3 nested lists of CasADi expressions) and the law's parameters
``p`` (numbers by name); the formulas and their sources are in :mod:`mol_shell.model.laws`.
"""

from __future__ import annotations

import functools

import casadi as ca
import numpy as np

from mol_shell.model.hyperelastic import determinant, invariants, with_thickness


def svk(C, p):
    """St Venant-Kirchhoff, ``lambda/2 (tr E)^2 + mu E:E`` with ``E = (C - I)/2`` (the generic route's check)."""
    E = [[0.5 * (C[i][j] - (1.0 if i == j else 0.0)) for j in range(3)] for i in range(3)]
    trace = E[0][0] + E[1][1] + E[2][2]
    return 0.5 * p["lambda"] * trace**2 + p["mu"] * sum(E[i][j] * E[j][i] for i in range(3) for j in range(3))


def neo_hookean(C, p):
    """Compressible neo-Hookean, Ciarlet and Geymonat's: ``mu/2 (I1 - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J)``,
    written ``mu/2 (I1 - 3) - (mu/2 + lambda/4) ln det C + lambda/4 (det C - 1)``."""
    i1, _, i3 = invariants(C)
    lam, mu = p["lambda"], p["mu"]
    return 0.5 * mu * (i1 - 3.0) - (0.5 * mu + 0.25 * lam) * ca.log(i3) + 0.25 * lam * (i3 - 1.0)


def neo_hookean_condense(C, p):
    """``(C_22, det C - 1, -mu/(2M))`` of :func:`neo_hookean` in plane stress, in closed form.

    ``det C = C_22 M + N`` (``M = C_11 C_33 - C_13^2``, ``N`` the determinant at ``C_22 = 0``), so
    ``dW/dC_22 = mu/2 - (mu/2 + lambda/4) M / det C + lambda M / 4``, which vanishes at
    ``det C = M (2 mu + lambda) / (2 mu + lambda M)``; then ``C_22 = (det C - N) / M``. Positive for ``lambda >= 0``
    and ``M > 0``: exact, with no iteration and no range of validity.

    Returned as ``delta = det C - 1 = 2 mu (M - 1) / (2 mu + lambda M)``, to the relative precision of ``M - 1``
    (``det C`` itself, a number near 1 when ``lambda >> mu``, keeps ``delta`` to the absolute round-off of 1 only,
    which the volumetric term's ``lambda`` multiplies), and the volumetric part's slope there,
    ``f'(det C) = lambda/4 - (mu/2 + lambda/4)/det C = -mu/(2M)`` (from ``dW/dC_22 = 0``): the same number as
    the difference of two terms of size ``lambda``, which left the forces a round-off of ``1e-16 lambda/mu`` of
    their scale and the statics unable to converge near ``nu = 0.5`` (``1e-8`` at ``nu = 0.49999999``).
    """
    lam, mu = p["lambda"], p["mu"]
    m = C[0][0] * C[2][2] - C[0][2] * C[2][0]
    # two divisions a point: quotients with a numerator other than 1, which CasADi does not fold into the products
    # that use them (x * (1/y) becomes x/y, a division each)
    q = (2.0 * mu) / (2.0 * mu + lam * m)
    g = (-0.5 * mu) / m
    delta = ((C[0][0] * C[2][2] - 1.0) - C[0][2] * C[2][0]) * q
    d = m * q * (1.0 + 0.5 * lam / mu)  # C_22 from det C itself: 1 + delta loses digits where det C << 1
    return (d - determinant(with_thickness(C, 0.0))) * g * (-2.0 / mu), delta, g


def neo_hookean_held(C, values, p):
    """:func:`neo_hookean` at ``C_22 = x`` for ``values = (x, delta, g)`` of :func:`neo_hookean_condense`
    (``D = 1 + delta = det C`` there, ``g = f'(D)``): ``mu/2 (I1 - 3) + f(D) + g (det C - D)`` with
    ``f(D) = -(mu/2 + lambda/4) ln D + lambda/4 (D - 1) = -mu/2 ln D + lambda/4 (delta - ln(1 + delta))``.

    The last term vanishes at the root, and its derivative in ``C`` with the values held is ``f'(D) d(det C)``, that
    of the law's volumetric part: the same value and first derivatives (the forces then need no ``log``, and no
    division per point). Through ``values`` as functions of ``C`` the derivatives are the law's too
    (``det C = D`` identically). ``f`` is written with ``log1p(delta)``: its value to round-off relative to ``mu``
    for every ``lambda/mu``.
    """
    x, delta, g = values
    lam, mu = p["lambda"], p["mu"]
    i1 = C[0][0] + x + C[2][2]
    log_d = ca.log1p(delta)
    return (0.5 * mu * (i1 - 3.0) - 0.5 * mu * log_d + 0.25 * lam * (delta - log_d)
            + g * ((determinant(with_thickness(C, x)) - 1.0) - delta))


def neo_hookean_log(C, p):
    """Compressible neo-Hookean with a ``(ln J)^2`` volumetric term: ``mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2``."""
    i1, _, i3 = invariants(C)
    log_j = 0.5 * ca.log(i3)
    return 0.5 * p["mu"] * (i1 - 3.0) - p["mu"] * log_j + 0.5 * p["lambda"] * log_j**2


#: Halley steps of :func:`neo_hookean_log_solve`: from its start, 2 reach round-off in ``v`` for every
#: ``0 <= nu < 0.5`` and in-plane determinant ``M`` of ``C`` in ``[e^-16, e^16] = [1.1e-7, 8.9e6]`` (equibiaxial
#: stretches 0.018..55; the start is within 6e-2 of the root there, 2e-5 after one step); tests/model/test_laws.py
#: checks the residual
HALLEY_STEPS = 2
#: the start's fit: ``ln M`` in ``[-START_RANGE, START_RANGE]`` (held at the ends outside), degree 8
START_RANGE, START_DEGREE = 16.0, 8


@functools.lru_cache(maxsize=64)
def neo_hookean_log_start(k):
    """Coefficients (power basis, of ``t = ln M / START_RANGE``) of the start's correction, for ``k = lambda/(2 mu)``.

    The root of ``mu e^v + lambda M v / 2 - mu M = 0`` solves ``e^v / M + k v = 1``: a function of ``ln M`` alone,
    ``v = ln M / (1 + k) + g(ln M)`` (the first term its linearisation about ``v = ln M``). ``g`` is fitted once per
    ``k`` here: Chebyshev least squares at 64 nodes of the range, the roots there by 60 Halley steps.
    """
    nodes = START_RANGE * np.cos(np.pi * (np.arange(64) + 0.5) / 64)
    v = nodes / (1.0 + k)
    for _ in range(60):
        e = np.exp(v - nodes)
        g, g1 = e + k * v - 1.0, e + k
        v = v - 2.0 * g * g1 / (2.0 * g1 * g1 - g * e)
    fit = np.polynomial.chebyshev.chebfit(nodes / START_RANGE, v - nodes / (1.0 + k), START_DEGREE)
    power = np.polynomial.chebyshev.cheb2poly(fit)  # trimmed when the top ones vanish (k = 0)
    return tuple(float(c) for c in np.pad(power, (0, START_DEGREE + 1 - len(power))))


def neo_hookean_log_solve(C, p, steps=HALLEY_STEPS):
    """``(C_22, v, e^v)`` of :func:`neo_hookean_log` in plane stress: ``v = ln det C`` at the root of a
    scalar equation, ``e^v = det C`` and ``C_22 = (e^v - N) / M``.

    ``det C = C_22 M + N`` (``M = C_11 C_33 - C_13^2``, ``N`` the determinant at ``C_22 = 0``) and
    ``dW/dC_22 = mu/2 + (lambda ln J - mu) M / (2 det C)``, so ``dW/dC_22 = 0`` reads
    ``f(v) = mu e^v + lambda M v / 2 - mu M = 0``: increasing and convex in ``v`` for ``lambda >= 0``. Started from
    ``v0 = ln M / (1 + k) + g(ln M)`` (:func:`neo_hookean_log_start`; outside its range ``g`` keeps its end value,
    a start no worse than the linearisation's); ``steps`` (at least 1) Halley iterations
    ``v -= 2 f f' / (2 f'^2 - f f'')`` (cubic convergence; ``f' = mu e^v + lambda M / 2``, ``f'' = mu e^v``: one
    ``exp`` each). The last step ``s`` is small (at most 2e-5 over the range of :data:`HALLEY_STEPS`), so
    ``e^v`` after it is the last ``exp`` times ``e^-s`` to third order (error ``s^4/24 < 7e-21``) rather than one
    more ``exp``. Constants multiply rather than divide: the solve is a chain of dependent operations at every
    thickness point, so its length is what it costs.
    """
    lam, mu = p["lambda"], p["mu"]
    m = C[0][0] * C[2][2] - C[0][2] * C[2][0]
    n = determinant(with_thickness(C, 0.0))
    a = 0.5 * lam * m
    k = 0.5 * float(lam) / float(mu)
    log_m = ca.log(m)
    t = 0.5 * (ca.fabs(log_m + START_RANGE) - ca.fabs(log_m - START_RANGE))  # ln M held in the range, no call
    c = [ci / START_RANGE**i for i, ci in enumerate(neo_hookean_log_start(k))]  # in ln M itself; Estrin's scheme
    t2 = t * t
    t4 = t2 * t2
    correction = (((c[0] + c[1] * t) + t2 * (c[2] + c[3] * t))
                  + t4 * (((c[4] + c[5] * t) + t2 * (c[6] + c[7] * t)) + t4 * c[8]))
    v = log_m * (1.0 / (1.0 + k)) + correction
    for _ in range(steps):
        ev = ca.exp(v)
        f2 = mu * ev
        f, f1 = f2 + a * v - mu * m, f2 + a
        s = 2.0 * f * f1 / (2.0 * f1 * f1 - f * f2)
        v = v - s
    ev = ev * (1.0 - s * (1.0 - s * (0.5 - s * (1.0 / 6.0))))
    return (ev - n) / m, v, ev


def neo_hookean_log_thickness(C, p, steps=HALLEY_STEPS):
    """``C_22`` of :func:`neo_hookean_log` in plane stress (:func:`neo_hookean_log_solve`)."""
    return neo_hookean_log_solve(C, p, steps)[0]


def neo_hookean_log_held(C, values, p):
    """:func:`neo_hookean_log` at ``C_22 = x`` for ``values = (x, v, e^v)`` of :func:`neo_hookean_log_solve`, where
    ``v = ln det C``: ``mu/2 (I1 - 3) - mu v/2 + lambda v^2/8 + (lambda v/4 - mu/2) (det C / e^v - 1)``.

    The last term vanishes there, and its derivative in ``C`` at ``v`` held, ``(lambda v/4 - mu/2) d(det C)/e^v``,
    is that of ``-mu ln J + lambda/2 (ln J)^2``: the same value and first derivatives as the law without a ``log``.
    Through ``values`` as functions of ``C`` the derivatives are the law's too (``ln det C = v`` identically).
    """
    x, v, ev = values
    lam, mu = p["lambda"], p["mu"]
    Cx = with_thickness(C, x)
    i1 = C[0][0] + x + C[2][2]
    return (0.5 * mu * (i1 - 3.0) + (0.125 * lam * v - 0.5 * mu) * v
            + (0.25 * lam * v - 0.5 * mu) * (determinant(Cx) / ev - 1.0))


def neo_hookean_incompressible(C, p):
    """Incompressible neo-Hookean: ``mu/2 (I1 - 3)`` (``det C = 1`` imposed by the thickness treatment)."""
    return 0.5 * p["mu"] * (invariants(C)[0] - 3.0)


def mooney_rivlin(C, p):
    """Mooney-Rivlin: ``c10 (I1 - 3) + c01 (I2 - 3)`` (``det C = 1`` imposed by the thickness treatment)."""
    i1, i2, _ = invariants(C)
    return p["c10"] * (i1 - 3.0) + p["c01"] * (i2 - 3.0)
