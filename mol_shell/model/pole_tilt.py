"""How far a table's end on the axis is from a pole: the angle of its tangent there from the normal to the axis.

A pole's tangent is normal to the axis (a sphere's, a dome's); a cone's tip meets the axis at an angle, an apex,
which is not a smooth shell. From the rows alone the tangent at an end is estimated twice: by the circle through the
three rows nearest it (exact for a sphere's rows; a line's angle for a cone's), and by the table's not-a-knot
spline (before the pole's clamping makes it normal). Each alone is off on some coarse smooth tables (the circle on a
4-row ellipse, 33 degrees; the spline on a 5-row dome, 27): the smaller is taken, so an end is an apex where both say
so.
"""

from __future__ import annotations

import math

import numpy as np

#: an end of a table on the axis is a pole when its tangent is within this of the normal to the axis (a sphere of 4
#: rows from pole to pole: 0 by the circle, 3.7 by the spline); up to :data:`APEX_TILT_DEG` a coarse table's pole,
#: made normal with a warning that the tip is rounded; beyond it an apex (a cone's 35 or 45 degrees): refused
MAX_POLE_TILT_DEG = 5.0
APEX_TILT_DEG = 30.0


def pole_tilts(pts, tangent):
    """``(start, end)``: degrees of the table ``pts``' (rows ``(r, z)``) tangent at its two ends from the normal to the
    axis, the smaller of the circle's through the three rows nearest the end and the spline's ``tangent`` (``(dr/du,
    dz/du)`` at the two ends). Meaningful where the end is on the axis."""
    out = []
    for k in (0, 1):
        p0, p1, p2 = pts[:3] if k == 0 else pts[::-1][:3]  # from the end inwards
        A = 2.0 * np.array([p1 - p0, p2 - p0])
        b = np.array([p1 @ p1 - p0 @ p0, p2 @ p2 - p0 @ p0])
        if abs(np.linalg.det(A)) > 1e-12 * np.abs(A).max() ** 2:  # the circle through the three: the end's tangent is
            centre = np.linalg.solve(A, b)  # normal to its radius there, level where its centre is on the axis
            tilt = math.degrees(math.atan2(abs(centre[0] - p0[0]), abs(p0[1] - centre[1])))
        else:  # in a line (a cone's tip): the line's angle
            tilt = math.degrees(math.atan2(abs(p1[1] - p0[1]), abs(p1[0] - p0[0])))
        spline = math.degrees(math.atan2(abs(tangent[k, 1]), (1.0 if k == 0 else -1.0) * tangent[k, 0]))
        out.append(min(tilt, spline))
    return out
