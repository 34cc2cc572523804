"""Reference meridians of shells of revolution, parametrised by arc length (paper, section 2).

A meridian gives, at arc length ``s`` in ``[0, length]``, the reference radius ``r0``, height ``z0``,
tangent angle ``theta0`` and curvature ``theta0_s`` of the base surface, with

    dz0/ds = cos(theta0),   dr0/ds = sin(theta0),

so the reference tangent is ``b0_1 = cos(theta0) k + sin(theta0) j2`` and the reference director
``d0 = b0_2 = -sin(theta0) k + cos(theta0) j2`` (section 2). ``zeta > 0`` lies on the side ``d0``
points to; the body point at depth ``zeta`` sits at radius ``r0 + zeta cos(theta0)`` and its
meridional line element is ``(1 - zeta theta0_s) ds``.

Directors of the built-in meridians (which way ``zeta`` counts):

* cylinder and cone: ``theta0`` is the angle of the generator from the axis; ``d0`` points away from
  the axis (outward) when ``z0`` increases along ``s``;
* sphere and torus segment: the arc is traced from its lowest point upwards
  (``r0 = b + a sin(alpha)``, ``z0 = -a cos(alpha)``, ``alpha`` the polar angle from the bottom), so
  ``theta0 = pi/2 - alpha``, ``theta0_s = -1/a`` and ``d0`` is the outward normal
  (away from the centre of the sphere, or of the tube);
* meridian from points: ``d0`` is the tangent turned by +90 degrees in the ``(z, r)`` plane, which is
  outward for points ordered with ``z`` increasing.

Physics (frequencies, radii, stresses) does not depend on the direction; ``zeta1`` (the lower face of
the thickness interval) does: ``zeta1 = 0`` puts the base surface on the inner face of an outward
director, ``zeta1 = -2h`` on the outer one.

All built-ins are exact formulas; :class:`PointsMeridian` interpolates a table with a cubic spline
(curvature continuous) and re-parametrises it by arc length.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mol_shell._core.errors import ParameterError, SceneWarning
from mol_shell._core.user_files import MAX_USER_FILE_TEXT, UserFileError, read_user_file
from mol_shell.model.pole_tilt import APEX_TILT_DEG, MAX_POLE_TILT_DEG, pole_tilts
from mol_shell.model.polyline import self_intersects

#: an end whose radius is within this fraction of the meridian's size (or of 1 m, if smaller) is on the axis: a pole
POLE_TOLERANCE = 1e-12


def on_axis(r, scale):
    """Whether a radius ``r`` (m) of a meridian of radii up to ``scale`` (m) is on the axis: ``|r| <= 1e-12
    max(1 m, scale)`` (:data:`POLE_TOLERANCE`), so ``sin(pi) = 1.2e-16`` of a unit sphere is."""
    return bool(abs(float(r)) <= POLE_TOLERANCE * max(1.0, abs(float(scale))))


class Meridian:
    """Interface of a reference meridian; subclasses define :meth:`at` and :attr:`length`."""

    length: float

    def at(self, s):
        """``(r0, z0, theta0, theta0_s)`` at arc lengths ``s`` (arrays)."""
        raise NotImplementedError

    @property
    def poles(self):
        """``(start, end)``: whether the meridian meets the axis (``r0 = 0``) at ``s = 0`` / ``s = length``."""
        r0, _, _, _ = self.at(np.array([0.0, self.length]))
        scale = float(np.max(np.abs(self.at(np.linspace(0, self.length, 9))[0])))
        return on_axis(r0[0], scale), on_axis(r0[1], scale)

    def describe(self):
        """One line naming the meridian and its parameters (for a run's attrs)."""
        if isinstance(self, PointsMeridian):
            origin = f" from {self.source}" if self.source else ""
            # the points' digest: a file edited since keeping its count and length is another meridian
            digest = hashlib.sha256(np.ascontiguousarray(self.points, dtype=float).tobytes()).hexdigest()[:12]
            return f"PointsMeridian({len(self.points)} points{origin}, length {self.length:.6g} m, sha256 {digest})"
        args = ", ".join(f"{f.name}={getattr(self, f.name):.10g}" for f in dataclasses.fields(self))
        return f"{type(self).__name__}({args})"


@dataclass(frozen=True)
class CylinderMeridian(Meridian):
    """Cylinder of radius ``a`` and length ``L``: ``r0 = a``, ``z0 = s``, ``theta0 = 0`` (director outward)."""

    a: float
    L: float

    @property
    def length(self):
        return self.L

    def at(self, s):
        s = np.asarray(s, dtype=float)
        return np.full_like(s, self.a), s.copy(), np.zeros_like(s), np.zeros_like(s)


@dataclass(frozen=True)
class ConeMeridian(Meridian):
    """Straight generator from ``(r1, 0)`` to ``(r2, H)``: a frustum (``r1, r2 > 0``), a cylinder when ``r1 = r2``.

    ``theta0 = atan2(r2 - r1, H)`` is constant, ``theta0_s = 0``; the director is outward.
    """

    r1: float
    r2: float
    H: float

    @property
    def length(self):
        return math.hypot(self.H, self.r2 - self.r1)

    @property
    def half_angle(self):
        return math.atan2(self.r2 - self.r1, self.H)

    def at(self, s):
        s = np.asarray(s, dtype=float)
        t = self.half_angle
        return self.r1 + s * math.sin(t), s * math.cos(t), np.full_like(s, t), np.zeros_like(s)


@dataclass(frozen=True)
class ArcMeridian(Meridian):
    """Circular arc of radius ``a`` about the point ``(b, 0)``: a torus segment, a sphere when ``b = 0``.

    ``r0 = b + a sin(alpha)``, ``z0 = -a cos(alpha)``, ``alpha = alpha1 + s/a`` in ``[alpha1, alpha2]``;
    ``theta0 = pi/2 - alpha``, ``theta0_s = -1/a``; the director is the outward normal of the arc.
    A sphere (``b = 0``) has poles where ``alpha`` is 0 or pi.
    """

    a: float
    b: float
    alpha1: float
    alpha2: float

    @property
    def length(self):
        return self.a * (self.alpha2 - self.alpha1)

    def at(self, s):
        s = np.asarray(s, dtype=float)
        alpha = self.alpha1 + s / self.a
        r0 = self.b + self.a * np.sin(alpha)
        if self.b == 0:  # exact zeros at the poles
            r0 = np.where(np.isclose(alpha, 0.0, atol=1e-15) | np.isclose(alpha, math.pi, rtol=0, atol=1e-15), 0.0, r0)
        return r0, -self.a * np.cos(alpha), math.pi / 2 - alpha, np.full_like(s, -1.0 / self.a)


#: coordinates of a table of points beyond this (m) are refused: the spline's and the shell's products of them
#: (r^2, r^3 in the inertias) overflow double precision
MAX_COORDINATE = 1e100
#: 8-point Gauss-Legendre nodes and weights on [-1, 1], for arc lengths (computed once: a meridian's arc-length Newton
#: called numpy's leggauss at every iteration, a quarter of building a points meridian)
GAUSS8 = np.polynomial.legendre.leggauss(8)
#: a table turning by more than this between consecutive chords doubles back on itself (a cusp, not a shell)
MAX_TURN_DEG = 170.0


@dataclass(frozen=True, eq=False)
class PointsMeridian(Meridian):
    """A meridian through a table of points ``(r, z)``, re-parametrised by arc length.

    A parametric cubic spline through the points (chord-length parameter, not-a-knot ends, or the
    tangent clamped perpendicular to the axis at a pole) has continuous curvature;
    arc length is integrated by Gauss-Legendre per spline segment and inverted by Newton's method.

    Refused (ParameterError naming ``name``): fewer than 4 points, non-finite values, repeated
    consecutive points, ``r < 0``, ``r = 0`` anywhere but at an end, a curve that crosses itself or
    the axis, a closed curve (its last row its first: the model has no periodic meridian), an end on the axis whose
    tangent fitted to the rows is more than :data:`APEX_TILT_DEG` from the normal to the axis (an apex; more than
    :data:`MAX_POLE_TILT_DEG`: a warning that the tip is rounded). An end on the axis by :func:`on_axis` (``|r| <= 1e-12`` of the table's size, or of 1 m) is a pole:
    its ``r`` is set to 0 (``sin(pi) = 1.2e-16`` as ``0``). ``source`` (a file, or what the table is) is named in
    messages and in :meth:`describe`;
    ``lines`` (the line of ``source`` each row was read from, counted from 1) places a refused row
    where a user finds it; without it rows are counted from 1.
    """

    points: np.ndarray
    name: str = "points"
    source: str = ""
    lines: tuple | None = None
    _spline: object = field(init=False, repr=False, compare=False)

    def _row(self, i):
        """Where row ``i`` (from 0) is: ``line 7`` of the file it was read from, else ``row 3`` (from 1)."""
        return f"line {self.lines[i]}" if self.lines is not None else f"row {i + 1}"

    def __post_init__(self):
        from scipy.interpolate import CubicSpline

        pts = np.asarray(self.points, dtype=float)
        allowed = ("a table of at least 4 points (r, z), 0 <= r, |z| <= 1e100 m, r = 0 only at an end, a curve that "
                   "neither crosses nor doubles back on itself")
        what = self.source or "table"
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 4:
            count = pts.shape[0] if pts.ndim == 2 else pts.size
            raise ParameterError.invalid(self.name, what, f"has {count} rows, not a table of 4 or more (r, z) rows",
                                         allowed)
        if not np.all(np.isfinite(pts)):
            i = int(np.argmax(~np.all(np.isfinite(pts), axis=1)))
            raise ParameterError.invalid(self.name, what, f"has a non-finite value on {self._row(i)}", allowed)
        if np.any(np.abs(pts) > MAX_COORDINATE):  # beyond it the spline's and the shell's products overflow
            i = int(np.argmax(np.any(np.abs(pts) > MAX_COORDINATE, axis=1)))
            raise ParameterError.invalid(self.name, what, f"has a coordinate beyond {MAX_COORDINATE:g} m on "
                                         f"{self._row(i)} ({pts[i, 0]:g}, {pts[i, 1]:g})", allowed)
        r, z = pts[:, 0], pts[:, 1]
        if np.any(r < 0):
            i = int(np.argmax(r < 0))
            raise ParameterError.invalid(self.name, what, f"has r = {r[i]:g} < 0 on {self._row(i)}", allowed)
        chord = np.hypot(np.diff(r), np.diff(z))
        scale = float(np.max(np.abs(pts)))
        if np.any(chord <= 1e-12 * max(scale, 1e-300)):
            i = int(np.argmax(chord <= 1e-12 * scale))
            problem = (f"repeats a point: {self._row(i)} and {self._row(i + 1)}" if chord[i] == 0 else
                       f"has points {chord[i]:.3g} m apart on {self._row(i)} and {self._row(i + 1)}, closer than "
                       f"1e-12 of its size ({scale:.3g} m)")
            raise ParameterError.invalid(self.name, what, problem, allowed)
        if np.hypot(*(pts[0] - pts[-1])) <= 1e-12 * scale:  # the model has no periodic meridian (meridian_checks)
            raise ParameterError.invalid(
                self.name, what, f"closes on itself: its last row ({self._row(len(pts) - 1)}) is its first "
                f"({self._row(0)}), which would run as a tube slit there (two edges at one point)",
                allowed + ", its first and last rows apart (a closed tube symmetric about a plane z = const runs as "
                "its half between that plane's two circles, with magnet edges there: z and theta imposed, as the "
                "symmetry imposes)")
        step = np.diff(pts, axis=0)
        turn = np.sum(step[:-1] * step[1:], axis=1) / (chord[:-1] * chord[1:])  # cos of the turn at each inner row
        if np.any(turn < math.cos(math.radians(MAX_TURN_DEG))):
            i = 1 + int(np.argmax(turn < math.cos(math.radians(MAX_TURN_DEG))))
            raise ParameterError.invalid(self.name, what, f"doubles back on itself at {self._row(i)} (it turns by more "
                                         f"than {MAX_TURN_DEG:g} degrees there: its arc length stops increasing)", allowed)
        # a row between the ends within the poles' tolerance of the axis (r = 1e-16: round-off of 0) touches it too
        axis = POLE_TOLERANCE * max(1.0, float(np.max(r)))
        if np.any(r[1:-1] <= axis):
            i = 1 + int(np.argmax(r[1:-1] <= axis))
            raise ParameterError.invalid(
                self.name, what, f"touches the axis between its ends, on {self._row(i)} (r = {r[i]:.3g} m)",
                f"rows between the first and the last with r > {axis:.3g} m (1e-12 of the largest r, or of 1 m: "
                "closer is on the axis, which only an end may be, as a pole)")
        # an end on the axis by the poles' rule (sin(pi) = 1.2e-16 of a unit sphere) is a pole: put exactly on it, so
        # the spline leaves the axis at a right angle there (it was clamped only for r == 0: a cone tip of 2.4 degrees)
        ends = [0, len(r) - 1]
        pole = [on_axis(r[i], np.max(r)) for i in ends]
        if any(pole):
            pts = pts.copy()
            pts[[i for i, p in zip(ends, pole) if p], 0] = 0.0
            r = pts[:, 0]
        object.__setattr__(self, "_pole", tuple(pole))
        u = np.concatenate([[0.0], np.cumsum(chord)])
        self._check_apex(pts, CubicSpline(u, pts)(u[[0, -1]], 1))
        bc = ["not-a-knot", "not-a-knot"]
        if r[0] == 0:
            bc[0] = (1, [1.0, 0.0])  # (dr/du, dz/du): leave the axis at a right angle
        if r[-1] == 0:
            bc[1] = (1, [-1.0, 0.0])
        if r[0] == 0 or r[-1] == 0:
            bc = [b if b != "not-a-knot" else (2, [0.0, 0.0]) for b in bc]  # natural where not clamped
        spline = CubicSpline(u, pts, bc_type=tuple(bc))
        object.__setattr__(self, "_spline", spline)
        # arc length per segment by 8-point Gauss-Legendre (the speed is smooth within a segment)
        x, w = GAUSS8
        lengths = []
        for a, b in itertools.pairwise(u):
            uu = (a + b) / 2 + (b - a) / 2 * x
            lengths.append((b - a) / 2 * np.sum(w * np.linalg.norm(spline(uu, 1), axis=1)))
        object.__setattr__(self, "_u", u)
        object.__setattr__(self, "_s", np.concatenate([[0.0], np.cumsum(lengths)]))
        dense = spline(np.linspace(0, u[-1], 40 * len(u)))
        if np.any(dense[1:-1, 0] <= 0):
            raise ParameterError.invalid(self.name, what, "gives a curve that crosses the axis", allowed)
        if self_intersects(dense):
            raise ParameterError.invalid(self.name, what, "gives a curve that crosses itself", allowed)

    def _check_apex(self, pts, tangent):
        """An end on the axis whose tangent (:func:`~mol_shell.model.pole_tilt.pole_tilts`) is more than
        :data:`APEX_TILT_DEG` from the normal to the axis is an apex, not a pole: refused, as the cone's ``r1 = 0`` is
        (the spline made it perpendicular, a rounded tip the table does not draw); more than :data:`MAX_POLE_TILT_DEG`,
        a coarse table's pole: a warning that its tip is rounded."""
        for k, (i, tilt) in enumerate(zip((0, len(pts) - 1), pole_tilts(pts, tangent))):
            if not self._pole[k]:
                continue
            where = f"{'starts' if k == 0 else 'ends'} on the axis on {self._row(i)}"
            if MAX_POLE_TILT_DEG < tilt <= APEX_TILT_DEG:
                warnings.warn(f"{self.name} = {self.source or 'table'!r} {where} with its tangent {tilt:.3g} degrees "
                              "from the normal to the axis (fitted to the rows): the pole makes it normal, which rounds "
                              "the table's tip over its first cells; give more rows near the pole", SceneWarning,
                              stacklevel=2)
            elif tilt > APEX_TILT_DEG:
                raise ParameterError.invalid(
                    self.name, self.source or "table", f"{where} with its tangent {tilt:.3g} degrees from the normal to the axis (fitted to its "
                    f"{'first' if k == 0 else 'last'} rows): an apex is not a smooth shell",
                    f"a table whose ends on the axis are poles, its tangent there within {APEX_TILT_DEG:g} degrees "
                    f"of the normal to the axis (made exactly normal; beyond {MAX_POLE_TILT_DEG:g} with a warning), or "
                    "a table that ends off the axis")

    @property
    def length(self):
        return float(self._s[-1])

    @property
    def poles(self):
        """``(start, end)``: the ends found on the axis when the table was read (and put on it, ``r = 0``)."""
        return self._pole

    def _param(self, s):
        """Spline parameter ``u`` at arc length ``s`` (Newton on the arc length, from the linear guess)."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.length)
        u = np.interp(s, self._s, self._u)
        x, w = GAUSS8
        for _ in range(30):
            seg = np.clip(np.searchsorted(self._u, u, side="right") - 1, 0, len(self._u) - 2)
            a = self._u[seg]
            uu = a[..., None] + (u - a)[..., None] / 2 * (1 + x)
            d1 = self._spline(uu, 1)
            speed = np.hypot(d1[..., 0], d1[..., 1])
            arc = self._s[seg] + (u - a) / 2 * np.sum(w * speed, axis=-1)
            d1 = self._spline(u, 1)
            step = (arc - s) / np.hypot(d1[..., 0], d1[..., 1])
            u = u - step
            if np.all(np.abs(step) < 1e-14 * max(1.0, self._u[-1])):
                break
        return u

    def at(self, s):
        u = self._param(s)
        p, d1, d2 = self._spline(u), self._spline(u, 1), self._spline(u, 2)
        speed = np.hypot(d1[..., 0], d1[..., 1])
        theta0 = np.arctan2(d1[..., 0], d1[..., 1])
        theta0 = np.unwrap(theta0) if theta0.ndim else theta0
        curvature = (d1[..., 1] * d2[..., 0] - d1[..., 0] * d2[..., 1]) / speed**3
        return p[..., 0], p[..., 1], theta0, curvature


def read_points(path, name="points", with_lines=False):
    """A meridian table from a text file: two columns ``r z`` (m), whitespace or comma separated, ``#`` comments.

    A line that is not two numbers is refused naming its number as a user counts it (from 1, blank and
    comment lines included) and the line itself, whole. ``with_lines``: also return the line number of
    each row (for :class:`PointsMeridian`'s messages).
    """
    allowed = f"a text file with two columns r z (m), at least 4 rows, at most {MAX_USER_FILE_TEXT}"
    try:
        p = Path(str(path)).expanduser()
        text = read_user_file(p).decode("utf-8-sig")  # a device or a named pipe: refused before it is read
    except UserFileError as exc:
        raise ParameterError.invalid(name, str(path), exc.problem, allowed) from None
    except (OSError, RuntimeError) as exc:  # missing; a name too long for the file system; ~nosuchuser/p.txt
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else "no user's home directory"
        raise ParameterError.invalid(name, str(path), f"is not a readable file ({reason})", allowed) from None
    except UnicodeDecodeError:
        raise ParameterError.invalid(name, str(path), "cannot be read (not a text file)", allowed) from None
    rows, lines = [], []
    for number, line in enumerate(text.splitlines(), start=1):
        items = line.split("#")[0].replace(",", " ").split()
        if not items:
            continue
        where = f"line {number} ({line.strip()!r})"
        if len(items) != 2:
            raise ParameterError.invalid(name, str(path), f"has {len(items)} values on {where}, not two (r z)", allowed)
        values = []
        for item in items:
            try:
                values.append(float(item))
            except ValueError:
                raise ParameterError.invalid(name, str(path), f"has {item!r} on {where}, not a number",
                                             allowed) from None
        rows.append(values)
        lines.append(number)
    table = np.array(rows, dtype=float).reshape(-1, 2)
    return (table, tuple(lines)) if with_lines else table


def thickness_factors(meridian, zeta, s):
    """``(1 - zeta theta0_s, r0 + zeta cos theta0)`` at arc lengths ``s`` (rows) and depths ``zeta`` (columns): both
    positive while ``zeta`` is inside the centre of curvature and off the axis (past a centre of curvature on the
    axis, a sphere's, both turn negative and their product alone is positive again)."""
    r0, _, th0, th0s = meridian.at(np.asarray(s, dtype=float))
    zeta = np.asarray(zeta, dtype=float)[None, :]
    return 1 - zeta * th0s[:, None], r0[:, None] + zeta * np.cos(th0)[:, None]


def thickness_volume_factor(meridian, zeta, s):
    """``(1 - zeta theta0_s)(r0 + zeta cos theta0)`` at arc lengths ``s`` (rows) and depths ``zeta`` (columns)."""
    curvature, axis = thickness_factors(meridian, zeta, s)
    return curvature * axis


def base_offset(meridian, h, samples=400):
    """Lower face ``zeta1`` of the thickness interval ``[zeta1, zeta1 + 2h]`` that puts the base surface at the centroid.

    The mid-surface offset ``m = zeta1 + h`` solves ``int ds int zeta (1 - zeta theta0_s)(r0 + zeta cos theta0)
    dzeta = 0`` over the whole shell, i.e. ``A m + B (m^2 + h^2/3) - C (m^3 + m h^2) = 0`` with
    ``A = int r0 ds``, ``B = int (cos theta0 - r0 theta0_s) ds``, ``C = int theta0_s cos theta0 ds``.
    For a cylinder and a sphere the integrand's dependence on ``s`` factors out, so ``rhoI = 0`` at every
    ``s`` (the paper's placement); for a cone or a torus ``rhoI(s)`` only vanishes on average and the
    model carries it (it is ``O(h^3)``). Returns the root nearest 0.
    """
    x, w = GAUSS8
    edges = np.linspace(0.0, meridian.length, samples + 1)
    mid, half = (edges[:-1] + edges[1:]) / 2, np.diff(edges) / 2
    s = (mid[:, None] + half[:, None] * x[None, :]).ravel()
    ws = (half[:, None] * w[None, :]).ravel()
    r0, _, th0, th0s = meridian.at(s)
    A, B, C = (float(np.sum(ws * f)) for f in (r0, np.cos(th0) - r0 * th0s, th0s * np.cos(th0)))
    coeffs = [-C, B, A - C * h * h, B * h * h / 3]  # -C m^3 + B m^2 + (A - C h^2) m + B h^2 / 3
    allowed = "values for which the base surface can be placed at the shell's centroid (or give zeta1)"
    if not np.all(np.isfinite(coeffs)):
        raise ParameterError("h", h, allowed, hint="the centroid's equation overflows for these dimensions")
    with np.errstate(all="ignore"):
        roots = np.roots(coeffs) if C != 0 else np.roots(coeffs[1:])
    real = roots[np.abs(roots.imag) <= 1e-12 * max(1.0, h)].real
    real = real[np.abs(real) <= h]  # the base surface inside the shell
    if real.size == 0:
        raise ParameterError("h", h, allowed, hint="no centroidal placement inside the thickness")
    m = real[np.argmin(np.abs(real))]
    return float(m - h)


def node_inertias(meridian, s_nodes, rho, thickness, gauss=6):
    """Lumped nodal inertias ``(mA, mI, mJ)`` (``3 x n``): exact integrals over each node's dual cell.

    ``m_k,i = 2 pi int_{dual cell of node i} int rho zeta^k (1 - zeta theta0_s)(r0 + zeta cos theta0) dzeta ds``,
    the dual cell running from the midpoint of the cell on the left to that on the right (half a cell at
    an edge). ``zeta`` by the thickness rule (exact for these polynomials), ``s`` by ``gauss``-point
    Gauss-Legendre per half cell. On a cylinder this is the trapezoidal lumping ``2 pi r0 w_i rho{A,I,J}``;
    at a pole (``r0 = 0``) it stays positive, so the pole's axial motion has mass.
    """
    s_nodes = np.asarray(s_nodes, dtype=float)
    zeta, wz = (np.asarray(a) for a in thickness.nodes_weights)
    x, w = np.polynomial.legendre.leggauss(gauss)
    mids = (s_nodes[:-1] + s_nodes[1:]) / 2
    left = np.concatenate([[s_nodes[0]], mids])
    right = np.concatenate([mids, [s_nodes[-1]]])
    out = np.zeros((3, s_nodes.size))
    for lo, hi in ((left, s_nodes), (s_nodes, right)):
        half = (hi - lo) / 2
        s = ((lo + hi) / 2)[:, None] + half[:, None] * x[None, :]
        vol = thickness_volume_factor(meridian, zeta, s.ravel()).reshape(s.shape + (zeta.size,))
        for k in range(3):
            out[k] += 2 * math.pi * rho * np.einsum("ij,ijq,q->i", half[:, None] * w[None, :], vol, wz * zeta**k)
    return out
