"""Whether a wall fits its meridian: exactly, from each meridian's curvature extremes, not from samples.

A face at depth ``zeta`` has the meridional line element ``(1 - zeta theta0_s) ds`` and the radius
``r0 + zeta cos theta0`` (:mod:`mol_shell.model.geometry`); the wall fits where both are positive for both faces.
The first is linear in the curvature ``theta0_s``, so it holds on a piece of the meridian iff it holds at the
piece's least and greatest curvature (:func:`curvature_pieces`: a line's 0, an arc's ``-1/radius``, a cubic spline
piece's extremes as the roots of a polynomial). Where it holds, ``d/ds (r0 + zeta cos theta0) = sin theta0
(1 - zeta theta0_s)`` changes sign only where ``sin theta0`` does, so a face's radius is least at an end or at a
:func:`turning_points` (the tangent along the axis). A short sharp arc (a 1 mm knuckle) then cannot slip between
samples, and the same input is refused at every ``n``.

A meridian may say both itself (methods ``curvature_pieces()`` and ``turning_points()``, as
:class:`mol_shell.scenes.segments.SegmentedMeridian` does); the built-ins are known here; any other is sampled.
"""

from __future__ import annotations

import math

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.model.geometry import GAUSS8, ArcMeridian, ConeMeridian, CylinderMeridian, PointsMeridian

#: samples of a meridian that says nothing of its curvature (none of the package's)
FALLBACK_SAMPLES = 4001


def curvature_pieces(meridian):
    """``[(s0, s1, kmin, kmax), ...]`` covering ``[0, L]``: the least and greatest curvature ``theta0_s`` on each
    piece, exact (to round-off) for the package's meridians."""
    own = getattr(meridian, "curvature_pieces", None)
    if own is not None:
        return list(own())
    L = float(meridian.length)
    if isinstance(meridian, (CylinderMeridian, ConeMeridian)):
        return [(0.0, L, 0.0, 0.0)]
    if isinstance(meridian, ArcMeridian):
        return [(0.0, L, -1.0 / meridian.a, -1.0 / meridian.a)]
    if isinstance(meridian, PointsMeridian):
        return _spline_pieces(meridian)
    k = meridian.at(np.linspace(0.0, L, FALLBACK_SAMPLES))[3]
    return [(0.0, L, float(np.min(k)), float(np.max(k)))]


def turning_points(meridian):
    """Arc lengths inside ``(0, L)`` where ``sin theta0`` can change sign (the tangent along the axis): with the
    ends, where a face's radius ``r0 + zeta cos theta0`` can be least."""
    own = getattr(meridian, "turning_points", None)
    if own is not None:
        return np.asarray(own(), dtype=float)
    L = float(meridian.length)
    if isinstance(meridian, (CylinderMeridian, ConeMeridian)):
        return np.zeros(0)
    if isinstance(meridian, ArcMeridian):  # theta0 = pi/2 - alpha = m pi
        a1, a2 = meridian.alpha1, meridian.alpha2
        alpha = [math.pi / 2 + m * math.pi for m in range(math.floor(a1 / math.pi) - 1, math.ceil(a2 / math.pi) + 1)]
        return np.array([meridian.a * (x - a1) for x in alpha if a1 < x < a2])
    if isinstance(meridian, PointsMeridian):
        return _spline_turning_points(meridian)
    return np.linspace(0.0, L, FALLBACK_SAMPLES)


def _pmul(a, b):
    """Products of the polynomials in the rows of ``a`` and ``b`` (coefficients highest first), row by row."""
    out = np.zeros((a.shape[0], a.shape[1] + b.shape[1] - 1))
    for i in range(a.shape[1]):
        out[:, i:i + b.shape[1]] += a[:, i:i + 1] * b
    return out


def _pder(a):
    """Derivatives of the polynomials in the rows of ``a`` (coefficients highest first)."""
    return a[:, :-1] * np.arange(a.shape[1] - 1, 0, -1)


def _psub(a, b):
    """``a - b`` for rows of polynomials of possibly different degrees."""
    width = max(a.shape[1], b.shape[1])
    return np.pad(a, ((0, 0), (width - a.shape[1], 0))) - np.pad(b, ((0, 0), (width - b.shape[1], 0)))


def _pval(a, t):
    """The polynomials in the rows of ``a`` at the points ``t`` (one row of points per polynomial), by Horner."""
    out = np.zeros_like(t)
    for k in range(a.shape[1]):
        out = out * t + a[:, k:k + 1]
    return out


def _real_roots_inside(p, span):
    """Per row of ``p`` (coefficients highest first), its real roots in ``(0, span)``, NaN where none: an array of
    rows. The roots are the eigenvalues of each polynomial's companion matrix, its leading zeros dropped (as
    ``numpy.roots``), batched by degree."""
    m, width = p.shape
    out = np.full((m, width - 1), np.nan)
    lead = np.argmax(p != 0, axis=1)  # leading zeros of each row (all-zero rows: no roots)
    lead[~np.any(p != 0, axis=1)] = width - 1
    for start in np.unique(lead):
        rows = np.flatnonzero(lead == start)
        degree = width - 1 - start
        if degree < 1:
            continue
        q = p[rows, start:]
        companion = np.zeros((len(rows), degree, degree))
        companion[:, 0, :] = -q[:, 1:] / q[:, :1]
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        roots = np.linalg.eigvals(companion)
        real = (np.abs(roots.imag) <= 1e-12 * np.maximum(1.0, np.abs(roots))) & (roots.real > 0) \
            & (roots.real < span[rows, None])
        out[rows, :degree] = np.where(real, roots.real, np.nan)
    return out


def _spline_coefficients(meridian):
    """``(dr, dz, span)``: the derivatives of each cubic piece's ``r(t), z(t)`` (rows, highest first), the pieces'
    parameter spans."""
    c = meridian._spline.c
    r, z = c[:, :, 0].T, c[:, :, 1].T
    return _pder(r), _pder(z), np.diff(meridian._u)


def _spline_pieces(meridian):
    """Each cubic piece of a :class:`PointsMeridian`'s spline ``(r(t), z(t))``: its curvature ``N / S^(3/2)``,
    ``N = z' r'' - r' z''`` (degree 2), ``S = r'^2 + z'^2`` (degree 4), is extreme at its ends or where
    ``N' S - 3/2 N S'`` (degree 5) vanishes. All pieces at once (a table of 5,000 rows in milliseconds)."""
    dr, dz, span = _spline_coefficients(meridian)
    s = meridian._s
    N = _psub(_pmul(dz, _pder(dr)), _pmul(dr, _pder(dz)))
    S = _pmul(dr, dr) + _pmul(dz, dz)
    t = np.column_stack([np.zeros_like(span), span, _real_roots_inside(
        _psub(_pmul(_pder(N), S), 1.5 * _pmul(N, _pder(S))), span)])
    k = np.where(np.isnan(t), np.nan, _pval(N, np.nan_to_num(t)) / _pval(S, np.nan_to_num(t)) ** 1.5)
    kmin, kmax = np.nanmin(k, axis=1), np.nanmax(k, axis=1)
    return [(float(s[i]), float(s[i + 1]), float(kmin[i]), float(kmax[i])) for i in range(len(span))]


def _spline_turning_points(meridian):
    """The arc lengths where a :class:`PointsMeridian`'s ``dr/dt`` (a quadratic on each piece) vanishes."""
    dr, dz, span = _spline_coefficients(meridian)
    x, w = GAUSS8
    t = _real_roots_inside(dr, span)
    rows, cols = np.nonzero(~np.isnan(t))
    t = t[rows, cols]
    tt = t[:, None] / 2 * (1 + x)  # the arc length to it, by Gauss-Legendre as the meridian's own
    speed = np.sqrt(_pval(dr[rows], tt) ** 2 + _pval(dz[rows], tt) ** 2)
    return np.sort(meridian._s[rows] + t / 2 * np.sum(w * speed, axis=1))


def check_wall_fits(meridian, zeta1, h, samples=801):
    """Refuse (naming ``h``) a wall ``[zeta1, zeta1 + 2h]`` one of whose faces passes a centre of curvature of
    ``meridian`` (``1 - zeta theta0_s <= 0`` on a piece: exact) or reaches the axis (``r0 + zeta cos theta0 <= 0``
    at an end, a turning point or one of ``samples``, off the poles, whose factor is 0 by geometry)."""
    faces = (float(zeta1), float(zeta1) + 2 * float(h))
    allowed = "values whose thickness interval stays off the axis and inside every centre of curvature of the meridian"
    for s0, s1, kmin, kmax in curvature_pieces(meridian):
        for zeta in faces:
            for k in (kmin, kmax):
                if not 1 - zeta * k > 0:
                    raise ParameterError("h", h, allowed, hint=f"zeta1 = {zeta1:.4g} m; the face at zeta = "
                                         f"{zeta:.4g} m passes the centre of curvature of radius {1 / abs(k) if k else math.inf:.4g} m "
                                         f"on s in [{s0:.4g}, {s1:.4g}] m")
    s = np.unique(np.concatenate([np.linspace(0.0, meridian.length, samples), turning_points(meridian)]))
    r0, _, th0, _ = meridian.at(s)
    keep = r0 > 1e-9 * float(np.max(np.abs(r0)))  # off the poles (their factor is 0 by geometry), at any size
    for zeta in faces:
        bad = np.flatnonzero(keep & ~(r0 + zeta * np.cos(th0) > 0))
        if bad.size:
            raise ParameterError("h", h, allowed, hint=f"zeta1 = {zeta1:.4g} m; the face at zeta = {zeta:.4g} m "
                                 f"reaches the axis at s = {s[bad[0]]:.4g} m")


def piece_samples(meridian, per_piece=17):
    """``(s, k)``: arc lengths on every curvature piece (its ends and ``per_piece`` between) with the piece's own
    curvature there (at a junction of a line and an arc, both sides': a sharp arc between samples is not missed)."""
    out_s, out_k = [], []
    for s0, s1, kmin, kmax in curvature_pieces(meridian):
        s = np.linspace(s0, s1, per_piece + 2)
        out_s.append(s)
        out_k.append(np.full_like(s, kmin) if kmin == kmax else meridian.at(s)[3])
    return np.concatenate(out_s), np.concatenate(out_k)
