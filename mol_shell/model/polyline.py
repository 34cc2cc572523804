"""Whether a meridian's polyline crosses or touches itself (:func:`self_intersects`), in time near linear in its
segments for the curves meridians are.

The candidate pairs are those whose bounding boxes overlap. They are found by a sweep along the coordinate in which
the polyline spreads furthest: sorted by their lower bounds there, a segment's candidates are the run of segments
that start before it ends. A meridian (a curve that advances along ``z`` or ``r`` most of its length) gives each
segment a few candidates, so a table of 5,000 rows (200,000 segments of its dense sampling) is checked in about a
second, where comparing every segment with every other took minutes. Every candidate is then tested exactly as
before (:func:`segments_meet`), in blocks of at most :data:`CHUNK` pairs.
"""

from __future__ import annotations

import numpy as np

#: candidate pairs tested at once (memory: a few hundred bytes each)
CHUNK = 1 << 18


def self_intersects(points):
    """Whether the polyline through ``points`` crosses or touches itself: two non-adjacent segments meet.

    Two segments meet when each one's ends lie strictly on either side of the other's line (a proper crossing) or
    an end of one lies on the other (a touch, or collinear pieces that overlap: a curve running back over itself).
    "On" is within ``1e-12`` of the polyline's size: the round-off of its coordinates. Non-adjacent chords of one
    straight piece (a sampled line, whose direction is not a representable double) are collinear to round-off; the
    intersection of their lines, formerly solved from a cross product of ``1e-36``, fell at random on both chords.
    Adjacent segments share an end and are not compared; so are the first and the last of a closed polyline.
    """
    points = np.asarray(points, dtype=float)
    a, b = points[:-1], points[1:]
    n = len(a)
    if n < 3:
        return False
    size = float(np.max(np.abs(points)))
    tol = 1e-12 * size
    closed = float(np.max(np.abs(points[0] - points[-1]))) <= tol
    lo, hi = np.minimum(a, b) - tol, np.maximum(a, b) + tol  # bounding boxes: only overlapping ones can meet
    axis = int(np.argmax(np.ptp(points, axis=0)))  # sweep along the larger spread
    order = np.argsort(lo[:, axis], kind="stable")
    starts = lo[order, axis]
    # in sorted order, segment k's candidates are k+1 .. end[k]-1: those that start before it ends
    end = np.searchsorted(starts, hi[order, axis], side="right")
    count = np.maximum(end - np.arange(n) - 1, 0)
    total = np.cumsum(count)
    k0 = 0
    while k0 < n:  # blocks of sorted segments with at most CHUNK candidates (or one segment with more)
        k1 = max(int(np.searchsorted(total, (total[k0 - 1] if k0 else 0) + CHUNK, side="right")), k0 + 1)
        if _block_meets(a, b, lo, hi, order, np.arange(k0, k1), count[k0:k1], closed, tol):
            return True
        k0 = k1
    return False


def _block_meets(a, b, lo, hi, order, ks, count, closed, tol):
    """Whether a sorted segment ``k`` in ``ks`` meets one of its ``count[k]`` successors in the sweep's order."""
    n = len(a)
    first = np.repeat(ks, count)
    offsets = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    i, j = order[first], order[first + 1 + offsets]
    keep = (np.abs(i - j) >= 2) & np.all((lo[j] <= hi[i]) & (hi[j] >= lo[i]), axis=1)
    if closed:
        keep &= ~(((i == 0) & (j == n - 1)) | ((i == n - 1) & (j == 0)))
    i, j = i[keep], j[keep]
    return bool(i.size) and segments_meet(a[i], b[i], a[j], b[j], tol)


def _side(p, q, x, tol):
    """Which side of the line through ``p, q`` the points ``x`` lie on: ``+1``, ``-1``, or ``0`` within ``tol`` of it
    (by their distance ``(q - p) x (x - p) / |q - p|``; ``0`` for a segment of no length)."""
    d, length = q - p, np.hypot(*(q - p).T)
    cross = d[..., 0] * (x - p)[..., 1] - d[..., 1] * (x - p)[..., 0]
    dist = np.where(length > 0, cross / np.where(length > 0, length, 1.0), 0.0)
    return np.where(np.abs(dist) <= tol, 0, np.sign(dist))


def _near(x, p, q, tol):
    """Whether the points ``x`` lie within ``tol`` of the segments ``p q`` (the nearest point of each segment)."""
    d = q - p
    dd = np.sum(d * d, axis=-1)
    t = np.clip(np.sum((x - p) * d, axis=-1) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return np.hypot(*(p + t[..., None] * d - x).T) <= tol


def segments_meet(p, q, c, d, tol):
    """Whether any segment ``p[k] q[k]`` meets its segment ``c[k] d[k]`` (see :func:`self_intersects`)."""
    crossing = (_side(p, q, c, tol) * _side(p, q, d, tol) < 0) & (_side(c, d, p, tol) * _side(c, d, q, tol) < 0)
    touching = _near(c, p, q, tol) | _near(d, p, q, tol) | _near(p, c, d, tol) | _near(q, c, d, tol)
    return bool(np.any(crossing | touching))
