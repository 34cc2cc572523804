"""Meridians made of segments with a continuous tangent, and the closed vessel built from them.

A segment is a straight line (``("line", length)``) or a circular arc (``("arc", radius, angle)``: the tangent angle
``theta0`` turns by ``angle``, rad, over the length ``radius |angle|``); each starts where the previous one ends, with
its tangent, so the tangent is continuous and the curvature ``theta0_s`` jumps at the junctions. From a start
``(r, z, theta)``, with ``dz0/ds = cos(theta0)`` and ``dr0/ds = sin(theta0)`` (:mod:`mol_shell.model.geometry`):

    arc of curvature k = angle / length:  theta0 = theta_a + k (s - s_a),
                                          r0 = r_a + (cos theta_a - cos theta0) / k,   z0 = z_a + (sin theta0 - sin theta_a) / k;
    line:                                 r0 = r_a + sin(theta_a) (s - s_a),            z0 = z_a + cos(theta_a) (s - s_a).

The vessel scene starts at the bottom pole heading outward (``theta = pi/2``), so the director ``d0`` (the tangent
turned +90 degrees in the ``(z, r)`` plane) is the outward normal everywhere (``-k`` at the bottom pole, as the
sphere's) for a meridian that goes up from it: the heads' arcs turn by negative angles. Segments that turn it down
instead (``arc 1 90, line 2, arc 1 90``) would run from the top pole with the director into the vessel, its faces'
"inner" and "outer" swapped: such a meridian (enclosing a negative volume: :func:`goes_down`) is traversed from its
other end (:func:`upward`): the segments in reverse order, each run backwards (an arc's angle negated, as the tangent
``theta0 + pi`` of the way back turns the other way), from the last point with the tangent reversed. The curve stays
where the segments draw it (``z``, and with it gravity and the axial end loads, are the user's) and the director,
``d0`` of the reversed tangent, is ``-d0``: outward. ``s = 0`` (``end1``) is then the segments' last point: the
bottom pole of a closed vessel, the open edge of an open one (a dome drawn from its top pole). (Mirrored in ``z``
instead, as it was, an asymmetric vessel stood upside down under gravity and the axial end loads.)
What the user gave along the drawn direction runs with the opposite sign (:meth:`Vessel.ran_values`): the tangent
``b0_1`` is reversed and ``b0_3 = +phi`` is not, so a fibre ``cos(a) b0_1 + sin(a) b0_3`` of the drawing is
``cos(-a) b0_1' + sin(-a) b0_3`` of the run (one family at ``-a``; a pair ``+-a`` is itself), a twist
``chi = gamma (s - L/2)`` of the drawing's ``s`` is ``-gamma (s' - L/2)`` of the run's ``s' = L - s``, and a graded
wall's ``h(s)`` of the drawing's ``s`` is ``h(L - s')`` of the run's.
A torispherical head is a crown arc of radius ``Rc`` turning by ``phi1`` and a knuckle of radius ``rk``
turning by ``pi/2 - phi1``, with ``sin(phi1) = (a - rk) / (Rc - rk)`` so that the knuckle ends on the cylinder
``r = a`` (``Rc sin(phi1) + rk (1 - sin(phi1)) = a``); ``Rc = a`` is the hemispherical head, one arc ``(a, -pi/2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Interval, positive
from mol_shell.model.edges import resolve_edges
from mol_shell.model.geometry import Meridian, on_axis
from mol_shell.model.layers import layer_value, parse_layers
from mol_shell.model.meridian_checks import check_meridian
from mol_shell.model.polyline import self_intersects
from mol_shell.model.thickness_profile import check_profile_fits, reversed_profile, thickness_function
from mol_shell.scenes.base import DISPLACEMENTS, DRIVES, LOADS, _check
from mol_shell.scenes.shells import _Dilated
from mol_shell.scenes.shells import goes_down as shells_goes_down


@dataclass(frozen=True, eq=False)
class SegmentedMeridian(Meridian):
    """A meridian of line and arc segments (see the module's docstring), from ``start = (r, z, theta)``."""

    segments: tuple
    start: tuple = (0.0, 0.0, math.pi / 2)

    def __post_init__(self):
        rows, (r, z, theta), s = [], self.start, 0.0
        for seg in self.segments:
            kind = seg[0]
            if kind == "line" and len(seg) == 2 and seg[1] > 0:
                length, k = float(seg[1]), 0.0
            elif kind == "arc" and len(seg) == 3 and seg[1] > 0 and 0 < abs(seg[2]) < 2 * math.pi:
                length, k = float(seg[1]) * abs(seg[2]), float(seg[2]) / (float(seg[1]) * abs(seg[2]))
            else:
                full = kind == "arc" and len(seg) == 3 and abs(seg[2]) >= 2 * math.pi
                raise ParameterError("segments", seg, "('line', length > 0) or ('arc', radius > 0, 0 < |angle| < 2 pi)",
                                     hint="an arc turning a full circle or more overlaps itself" if full else "")
            rows.append((s, length, r, z, theta, k))
            r, z, theta = self._point(r, z, theta, k, length)
            s += length
        object.__setattr__(self, "_rows", tuple(rows))
        object.__setattr__(self, "_length", s)
        object.__setattr__(self, "_end", (float(r), float(z), float(theta)))  # the last point and its tangent

    @staticmethod
    def _point(r, z, theta, k, ds):
        if k == 0:
            return r + np.sin(theta) * ds, z + np.cos(theta) * ds, theta + 0 * ds
        end = theta + k * ds
        return r + (np.cos(theta) - np.cos(end)) / k, z + (np.sin(end) - np.sin(theta)) / k, end

    @property
    def length(self):
        return self._length

    def at(self, s):
        s = np.asarray(s, dtype=float)
        out = [np.zeros_like(s) for _ in range(4)]
        for i, (s0, length, r, z, theta, k) in enumerate(self._rows):
            last = i == len(self._rows) - 1
            mask = (s >= s0) & ((s <= s0 + length) if last else (s < s0 + length))
            r0, z0, th0 = self._point(r, z, theta, k, s[mask] - s0)
            out[0][mask], out[1][mask], out[2][mask], out[3][mask] = r0, z0, th0, k
        scale = max(abs(row[2]) for row in self._rows) + self._length
        out[0] = np.where(np.abs(out[0]) <= 1e-13 * scale, 0.0, out[0])  # exact zeros at the poles
        return tuple(out)

    def curvature_pieces(self):
        """Each segment's ``(s0, s1, k, k)``: its exact, constant curvature (:mod:`mol_shell.model.wall_fit`)."""
        return [(s0, s0 + length, k, k) for s0, length, _, _, _, k in self._rows]

    def turning_points(self):
        """Where an arc's tangent ``theta0 = theta_a + k (s - s0)`` passes a multiple of pi (along the axis)."""
        out = []
        for s0, length, _, _, theta, k in (row for row in self._rows if row[5]):
            lo, hi = sorted((theta, theta + k * length))
            out += [s0 + (m * math.pi - theta) / k for m in range(math.ceil(lo / math.pi), math.floor(hi / math.pi) + 1)]
        return out

    def describe(self):
        parts = ", ".join(f"{seg[0]} " + " ".join(f"{x:.6g}" for x in seg[1:]) for seg in self.segments)
        start = "" if tuple(self.start) == (0.0, 0.0, math.pi / 2) else (
            "; from (r, z, theta) = (" + ", ".join(f"{x:.10g}" for x in self.start) + ")")
        return f"SegmentedMeridian({parts}{start}; length {self.length:.6g} m)"


def goes_down(meridian):
    """Whether a meridian of segments encloses a negative volume ``pi int r0^2 dz0`` with the axis (and the plane
    ``z = z0(L)`` of its end, when that is off the axis): it goes down from its first pole, its director pointing into
    that volume (:func:`mol_shell.scenes.shells.goes_down`, between the segments' ends: exact to round-off)."""
    return shells_goes_down(meridian, [row[0] for row in meridian._rows] + [meridian.length])


def backwards(meridian):
    """The same curve traversed from its other end: the segments in reverse order, each run backwards (an arc of
    radius ``R`` turning by ``-angle``: the tangent of the way back, ``theta0 + pi``, turns the other way), from the
    last point with the tangent reversed (reduced to ``[-pi, pi]``). ``s`` is ``L - s``, ``theta0`` is ``theta0 + pi``
    (mod ``2 pi``), ``theta0_s`` is ``-theta0_s``, and the director ``d0 = (-sin theta0, cos theta0)`` is ``-d0``. An
    end on the axis (:func:`~mol_shell.model.geometry.on_axis`, the round-off of the segments' sums) is put on it,
    its tangent set to ``pi/2`` when within 1e-12 rad of it (the normal to the axis)."""
    r, z, theta = meridian._end
    size = max(max(abs(row[2]) for row in meridian._rows), abs(r)) + meridian.length
    theta = math.remainder(theta + math.pi, 2 * math.pi)
    if on_axis(r, size):
        r = 0.0
        theta = math.pi / 2 if abs(theta - math.pi / 2) <= 1e-12 else theta
    segments = tuple(("arc", seg[1], -seg[2]) if seg[0] == "arc" else seg for seg in reversed(meridian.segments))
    return SegmentedMeridian(segments, (r, z, theta))


def upward(meridian):
    """``meridian``, or, when it goes down from its first pole (:func:`goes_down`: its director would point into the
    volume it encloses), the same curve traversed from its other end (:func:`backwards`): where the segments draw
    it, with the director out of it."""
    return backwards(meridian) if goes_down(meridian) else meridian


def head(a, crown, knuckle):
    """The segments of a torispherical head from its pole to the cylinder ``r = a``: a crown arc (radius ``crown``)
    and a knuckle (radius ``knuckle``); ``crown = a`` is the hemisphere (the knuckle then turns by 0 and is left out)."""
    phi1 = math.asin(min(1.0, (a - knuckle) / (crown - knuckle)))
    out = [("arc", crown, -phi1)]
    if math.pi / 2 - phi1 > 1e-12:
        out.append(("arc", knuckle, -(math.pi / 2 - phi1)))
    return out


def _axis_roots(row):
    """The arc lengths ``t`` in ``[0, length]`` from the start of a segment (a row of :class:`SegmentedMeridian`)
    where its ``r0`` is 0: a line's ``r_a + sin(theta_a) t``, an arc's ``r_a + (cos theta_a - cos(theta_a + k t))/k``
    (``cos(theta_a + k t) = cos theta_a + k r_a``), sorted."""
    _, length, r, _, theta, k = row
    tol = 1e-12 * length
    if k == 0:
        sine = math.sin(theta)
        roots = [] if sine == 0 else [-r / sine]
    else:
        c = math.cos(theta) + k * r
        if abs(c) > 1 + 1e-12:
            return []
        acos, span = math.acos(max(-1.0, min(1.0, c))), sorted((theta, theta + k * length))
        phis = (acos, -acos)
        roots = [(phi + 2 * math.pi * m - theta) / k for phi in phis
                 for m in range(math.floor((span[0] - phi) / (2 * math.pi)) - 1,
                                math.ceil((span[1] - phi) / (2 * math.pi)) + 2)]
    return sorted(min(max(t, 0.0), length) for t in roots if -tol <= t <= length + tol)


def _on_the_axis(text, drawn, sampled):
    """Where the segments as drawn (``drawn``: from the first segment's start) first reach the axis between their
    ends: ``"segment I ('TEXT') reaches the axis at s = ... m"``, ``s`` from the first segment's start (exact, on the
    segment's line or circle); ``sampled``, the drawn ``s`` of the first sample found there, where no root is."""
    parts = [part.strip() for part in text.split(",")]
    ends = 1e-12 * drawn.length
    for i, row in enumerate(drawn._rows):
        for t in _axis_roots(row):
            where = row[0] + t
            if ends < where < drawn.length - ends:
                return (f"segment {i + 1} ({parts[i]!r}) reaches the axis at s = {where:.4g} m along the segments "
                        "as drawn, from the start of the first")
    i = next(i for i, row in enumerate(drawn._rows) if sampled <= row[0] + row[1] or i == len(drawn._rows) - 1)
    return (f"segment {i + 1} ({parts[i]!r}) reaches the axis at about s = {sampled:.4g} m along the segments as drawn, "
            "from the start of the first")


def check_segmented(text, meridian):
    """Refuse, naming ``segments``, a meridian of segments that crosses the axis or itself (sampled densely), or that
    the model cannot run (:func:`~mol_shell.model.meridian_checks.check_meridian`: an end past the axis, an apex).
    Where it reaches the axis is said on the segments as drawn (``meridian`` may run them backwards: :func:`upward`),
    naming the segment (it named the first sample of the reversed curve, 1/40 of an arc from its start)."""
    drawn = SegmentedMeridian(tuple(parse_segments(text)))
    allowed = "segments whose meridian stays off the axis between its ends and does not cross itself"
    s = np.linspace(0.0, drawn.length, 40 * len(drawn.segments) + 1)
    r, z = drawn.at(s)[:2]
    scale = max(float(np.max(np.abs(r))), float(np.max(np.abs(z))), drawn.length)
    if np.any(r[1:-1] <= 1e-12 * scale):
        sampled = s[1 + int(np.argmax(r[1:-1] <= 1e-12 * scale))]
        raise ParameterError("segments", text, allowed, hint=_on_the_axis(text, drawn, sampled))
    r, z = meridian.at(s)[:2]  # the same curve, as it runs (its length the same)
    if self_intersects(np.column_stack([r, z])):
        raise ParameterError("segments", text, allowed, hint="it crosses itself")
    check_meridian(meridian, "segments", text, "segments whose meridian has r > 0 but at a pole, its ends included, "
                   "and leaves or reaches the axis at a right angle there", samples=s.size)


def parse_segments(text):
    """``"arc R DEG, line L, ..."`` as segments (angles in degrees), or a ParameterError naming ``segments``."""
    out = []
    allowed = ("'arc RADIUS ANGLE_DEG' and 'line LENGTH' separated by commas (radius, length > 0, m; "
               "0 < |ANGLE_DEG| < 360)")
    for part in text.split(","):
        words = part.split()
        try:
            if words[0] == "arc" and len(words) == 3:
                if not 0 < abs(float(words[2])) < 360:
                    why = "a full circle or more overlaps itself" if float(words[2]) != 0 else "an arc must turn"
                    raise ParameterError("segments", text, allowed, hint=f"the arc {part.strip()!r} turns by "
                                         f"{float(words[2]):g} degrees: {why}")
                out.append(("arc", float(words[1]), math.radians(float(words[2]))))
            elif words[0] == "line" and len(words) == 2:
                out.append(("line", float(words[1])))
            else:
                raise ValueError(part)
            if not (math.isfinite(out[-1][1]) and out[-1][1] > 0):
                raise ParameterError("segments", text, allowed, hint=f"the {words[0]} {part.strip()!r} has a "
                                     f"{'radius' if words[0] == 'arc' else 'length'} that is not positive and finite")
        except ParameterError:
            raise
        except (ValueError, IndexError):
            raise ParameterError("segments", text, allowed, hint=f"cannot read {part.strip()!r}") from None
    return out


@dataclass(frozen=True)
class Vessel(_Dilated):
    """A closed pressure vessel: a cylinder of radius ``a`` and length ``Lc`` with two torispherical heads (crown
    radius ``crown``, default (auto) ``2a``; knuckle radius ``knuckle``, default ``0.2 a``; ``crown = a``:
    hemispherical heads, a capsule), or any meridian from
    the bottom pole given as ``segments`` (``"arc R DEG, line L, ..."``, degrees; it overrides the others).

    The meridian starts at the bottom pole heading outward (director outward), so an equatorial closed shell has
    two poles. Segments that turn it down from there (positive angles: ``"arc 1 90, line 2, arc 1 90"``, drawn from
    the top pole) are run from their other end, the same curve traversed backwards, so that the director points out
    of the vessel and the stresses' "inner" face is the one toward the enclosed volume whatever the angles' sign,
    while the vessel stays where the segments draw it (``z``, gravity and the axial end loads as given). ``s = 0``
    (``end1``) is then the segments' last point: the bottom pole of a closed vessel, the open edge of an open one
    (``"arc 1 90"``, a dome, from its rim up to its pole); the command line says so in a note.

    Parameters
    ----------
    a : float
        Radius of the cylinder's base surface, m, ``> 0`` (default 1); the heads end on it.
    Lc : float
        Length of the cylinder, m, ``>= 0`` (default 2; 0: the heads meet).
    crown : float or None
        Crown radius of the heads, m, ``>= a`` (``a``: hemispherical heads); ``None`` (default, ``"auto"``): ``2a``.
    knuckle : float or None
        Knuckle radius of the heads, m, in (0, a); ``None`` (default, ``"auto"``): ``0.2 a``.
    segments : str
        The meridian from the bottom pole as ``"arc RADIUS DEG, line LENGTH, ..."`` (m, degrees; each segment
        turns the tangent on from the last), overriding ``a, Lc, crown, knuckle``; ``''`` (default): the heads
        and cylinder they give.
    dilation : float or None
        Initial uniform dilation of the natural shell, in (0.5, 2); ``None`` (default, ``"auto"``): the static
        equilibrium under the loads at ``t = 0`` (the natural shell without loads).
    gamma, omega : float
        Initial twist ``chi_s``, rad/m (``chi = gamma (s - L/2)``, ``L`` the meridian's length), and rigid spin
        rate ``chi_t``, rad/s (defaults 0).
    """

    descriptions = MappingProxyType({"a": "radius of the vessel's cylinder (its heads end on it)",
                                     "h_profile": "half-thickness along the meridian: 'table s0:h0 s1:h1 ...' or an "
                                     "expression of s ('': h), s along the segments as drawn"})
    defaults_mean = MappingProxyType({"segments": "the heads and cylinder of a, Lc, crown and knuckle"})

    a: float = 1.0
    Lc: float = 2.0
    crown: float | None = None
    knuckle: float | None = None
    segments: str = ""

    name = "vessel"

    def _validate(self):
        super()._validate()
        _check("a", self.a, positive("m"))
        _check("Lc", self.Lc, Interval(0.0, math.inf, low_closed=True, unit="m"))
        for name in ("crown", "knuckle"):
            if isinstance(getattr(self, name), str) and getattr(self, name).strip().lower() in ("auto", "none"):
                object.__setattr__(self, name, None)
        if self.crown is not None:
            _check("crown", self.crown, Interval(self.a, math.inf, low_closed=True, unit="m",
                                                 shown=f"[a, inf) = [{self.a:g}, inf) m (a: hemispherical heads), or auto"))
        if self.knuckle is not None:
            _check("knuckle", self.knuckle, Interval(0.0, self.a, unit="m", shown=f"(0, a) = (0, {self.a:g}) m, or auto"))
        if not isinstance(self.segments, str):
            raise ParameterError.not_a("segments", self.segments, "a string", "'arc R DEG, line L, ...'")
        try:
            mer = self.meridian()
        except ParameterError as exc:
            if self.segments.strip():
                raise
            blame = "a" if self.crown is None or self.knuckle is None else "crown"
            raise ParameterError(blame, getattr(self, blame), "values whose heads have positive, finite radii",
                                 hint=str(exc)) from None
        if self.segments.strip():
            check_segmented(self.segments, mer)
            if self._backwards():
                self._check_ends(mer)

    def _backwards(self):
        """Whether ``segments`` turn the meridian down from its first pole, so that it runs backwards (:func:`upward`)."""
        return bool(self.segments.strip()) and goes_down(SegmentedMeridian(tuple(parse_segments(self.segments))))

    def ran_values(self):
        """``{name: value}``: the parameters that run with another value than given, because the segments run
        backwards (:func:`upward`): a twist ``gamma`` and one fibre family's ``fibre_angle`` (a layer's too: ``layers``
        with the angle it runs with written into it) with the opposite sign, and a graded wall's ``h_profile``, given
        along the segments as drawn, as ``h(L - s)`` of the run's ``s`` (:func:`~mol_shell.model.thickness_profile.
        reversed_profile`): the helix, twist and wall the user drew (module docstring); ``{}`` for a meridian run as
        drawn."""
        if not self._backwards():
            return {}
        out = {}
        if self.gamma:
            out["gamma"] = -self.gamma
        if self.fibre_E and self.fibre_families == 1 and self.fibre_angle:
            out["fibre_angle"] = -self.fibre_angle
        layers = self._layers_backwards()
        if layers != self.layers:
            out["layers"] = layers
        profile = reversed_profile(self.h_profile, self.meridian().length) if self.h_profile else ""
        if profile != self.h_profile:
            out["h_profile"] = profile
        return out

    def _layers_backwards(self):
        """``layers`` with ``fibre_angle = -a`` written into each layer of one fibre family at ``a != 0`` (its own or
        the scene's), the others as given."""
        if not self.layers:
            return self.layers
        parts, turned = self.layers.split(";"), False
        for k, (_, _, changes) in enumerate(parse_layers(self.layers)):
            E, families, angle = (layer_value(key, changes[key]) if key in changes else getattr(self, key)
                                  for key in ("fibre_E", "fibre_families", "fibre_angle"))
            if E and families == 1 and angle:
                words = [w for w in parts[k].split() if not w.startswith("fibre_angle=")]
                parts[k], turned = " ".join(words + [f"fibre_angle={-float(angle)!r}"]), True
        return "; ".join(part.strip() for part in parts) if turned else self.layers

    def _check_profile(self):
        """A graded wall's ``h_profile`` of segments run backwards is given along them as drawn (``s`` from their
        first pole; it runs as ``h(L - s)``: :meth:`ran_values`): read and checked on the segments as drawn (the
        distances to the axis and to the centres of curvature are the run's at ``L - s``), its refusals in their
        ``s``."""
        if not self._backwards():
            super()._check_profile()
            return
        if not isinstance(self.h_profile, str):
            raise ParameterError.not_a("h_profile", self.h_profile, "a string", "'table s0:h0 ...' or an expression of s")
        drawn = SegmentedMeridian(tuple(parse_segments(self.segments)))
        h = thickness_function(self.h_profile, drawn.length)
        if self.zeta1 is not None:
            raise ParameterError("zeta1", self.zeta1, "auto with h_profile (the mid-surface is the base surface)")
        check_profile_fits(self.h_profile, h, drawn)

    def initial_fields(self, s, reference):
        Q, V = super().initial_fields(s, reference)
        if "gamma" in self.ran_values():  # the twist drawn: chi = -gamma (s - L/2) of the run's s
            Q[2] = -Q[2]
        return Q, V

    def _ends_said(self, mer):
        """Which end of the segments is ``end1`` and which ``end2`` when they run backwards."""
        r, z = mer.start[:2]
        what = "the bottom pole" if mer.poles[0] else "the open edge"
        return (f"s = 0 and end1 at the segments' last point, {what} at (r, z) = ({r:.6g}, {z:.6g}) m, end2 at their "
                "first pole (z = 0)")

    def _check_ends(self, mer):
        """``end1``/``end2`` asked of the wrong kind for the ends of a meridian run backwards (``end2 = clamped`` meant
        for the open edge of a dome drawn from its pole, which is ``end1``): refused saying which end is which."""
        try:
            resolve_edges(self.end1, self.end2, mer.poles)
        except ParameterError as exc:
            on_axis_ = mer.poles[0 if exc.name == "end1" else 1]
            raise ParameterError(exc.name, exc.value, exc.range if exc.range is not None else exc.allowed,
                                 hint=f"this edge is {'on the axis' if on_axis_ else 'open'}: segments = "
                                 f"{self.segments!r} turn down from their first pole and run backwards, "
                                 + self._ends_said(mer)) from None

    def stand_ins(self):
        """A note when ``segments`` turn the meridian down from its first pole and it runs backwards (:func:`upward`):
        which end is ``end1``."""
        if not self._backwards():
            return []
        return [(f"segments = {self.segments!r} turn the meridian down from its first pole (its director into the "
                 "vessel): run from their other end, the same curve traversed backwards, so that the director points "
                 "outward and the inner face is the one toward the enclosed volume; the vessel stays where the "
                 "segments draw it (z, gravity and the end loads as given), " + self._ends_said(self.meridian()) +
                 "; s counts from end1, a graded wall's h_profile is given in the drawing's s (from their first "
                 "pole) and runs as h(L - s), and a twist gamma and one fibre family's fibre_angle, given along the "
                 "segments, run with the opposite sign (the wall, helix and twist as drawn; attrs NAME as run, "
                 "NAME_requested as given)" + self._end_values_said())]

    def _end_values_said(self):
        """Where the end loads, drives and displacements given act when the segments run backwards: ``end2_force``
        meant for the rim of a dome drawn from its pole acts at its pole (``end2``), so the note names each."""
        given = [name for name in (*LOADS, *DRIVES, *DISPLACEMENTS)
                 if name.startswith(("end1_", "end2_")) and getattr(self, name)]
        at = {"end1": "end1 (the segments' last point)", "end2": "end2 (their first pole)"}
        return "".join(f"; {name} acts at {at[name[:4]]}" for name in given)

    def _heads(self):
        """The heads' crown and knuckle radii, the defaults (``2a``, ``0.2a``) for those left to the code."""
        return (2 * self.a if self.crown is None else self.crown,
                0.2 * self.a if self.knuckle is None else self.knuckle)

    def geometry_values(self):
        """``crown``/``knuckle`` left to the code, as the meridian uses them (none when ``segments`` replaces them)."""
        if self.segments.strip():
            return {}
        crown, knuckle = self._heads()
        return {name: value for name, value in (("crown", crown), ("knuckle", knuckle)) if getattr(self, name) is None}

    def meridian(self):
        if self.segments.strip():
            return upward(SegmentedMeridian(tuple(parse_segments(self.segments))))
        crown, knuckle = self._heads()
        bottom = head(self.a, crown, knuckle)
        middle = [("line", self.Lc)] if self.Lc > 0 else []
        return SegmentedMeridian(tuple(bottom + middle + bottom[::-1]))
