"""Shells of revolution beyond the cylinder: sphere (closed, cap, zone), cone or frustum, torus segment, a meridian from points.

Each scene starts from its natural shell, dilated (``R`` for the sphere, ``dilation`` elsewhere), twisted
(``gamma``: ``chi = gamma (s - L/2)``) and spun (``omega``: rigid ``chi_t``). ``R``/``dilation`` = auto
(the default) is the static equilibrium under the loads at ``t = 0`` (``chi`` solved for too, unless ``gamma``
asks for a twist: then it is kept as given while the other fields come to rest): without
loads, the natural state at rest (an equilibrium, so ``mol-shell modes`` takes it as it is).
"""

from __future__ import annotations

import hashlib
import itertools
import math
import os
import sys
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType

import numpy as np

from mol_shell._core.errors import ParameterError, is_number
from mol_shell._core.ranges import Interval, finite, non_negative, positive
from mol_shell._core.user_files import read_user_file
from mol_shell.model.geometry import ArcMeridian, ConeMeridian, PointsMeridian, read_points
from mol_shell.model.meridian_checks import HALF_TUBE, check_meridian
from mol_shell.model.thickness_profile import thickness_function
from mol_shell.scenes.base import ShellScene, _check, fitted_scale


@dataclass(frozen=True)
class _Excited(ShellScene):
    """Initial data shared by the general shells: a uniform dilation, a twist and a rigid spin."""

    gamma: float = 0.0
    omega: float = 0.0

    initial = ("gamma", "omega")

    def _validate(self):
        _check("gamma", self.gamma, finite("rad/m"))
        _check("omega", self.omega, finite("rad/s"))

    def scale(self):
        """Factor applied to the natural ``(z0, r0)`` at ``t = 0``."""
        return 1.0

    def initial_fields(self, s, reference):
        Q, V = super().initial_fields(s, reference)
        Q[:2] *= self.scale()
        Q[2] = self.gamma * (np.asarray(s) - self.meridian().length / 2)
        V[2] = self.omega
        return Q, V


@dataclass(frozen=True)
class _Dilated(_Excited):
    dilation: float | None = None

    initial = ("gamma", "omega", "dilation")

    def _validate(self):
        super()._validate()
        if isinstance(self.dilation, str) and self.dilation.strip().lower() in ("auto", "none"):
            object.__setattr__(self, "dilation", None)
        if self.dilation is not None:
            _check("dilation", self.dilation, Interval(0.5, 2.0, shown="(0.5, 2), or auto"))

    def scale(self):
        return 1.0 if self.dilation is None else self.dilation

    def at_equilibrium(self):
        return self.dilation is None

    def auto_values(self, initial, reference):
        """``dilation`` = auto: the uniform scale of the starting state (its least-squares fit about the origin):
        1 for the natural state; for an equilibrium under load, which is no uniform dilation, its mean scale."""
        return {"dilation": fitted_scale(initial, reference)} if self.dilation is None else {}


@dataclass(frozen=True)
class Sphere(_Excited):
    """A spherical shell of natural radius ``a``: closed (default), a cap or a zone.

    The meridian runs from the polar angle ``alpha1`` to ``alpha2``, measured from the pole at the
    bottom (``z = -a``) where ``s = 0``; an edge at polar angle 0 or pi is a pole. The director is the
    outward normal (``zeta > 0`` outside). Initial data: the natural sphere dilated to radius ``R``
    (default auto: the static equilibrium under the loads at ``t = 0``, the natural sphere without loads),
    optionally twisted and spun.

    Parameters
    ----------
    a : float
        Natural radius of the base surface, m, ``> 0`` (default 1).
    alpha1, alpha2 : float
        Polar angles of the edges, rad, ``0 <= alpha1 < alpha2 <= pi`` (defaults 0 and pi: closed).
    R : float or None
        Initial radius of the base surface, m, in (a/2, 2a); ``None`` (default, ``"auto"``): the static
        equilibrium under the loads at ``t = 0``, the natural radius ``a`` without loads.
    gamma, omega : float
        Initial twist ``chi_s``, rad/m (``chi = gamma (s - L/2)``, ``L`` the meridian's length), and rigid spin
        rate ``chi_t``, rad/s (defaults 0).
    """

    descriptions = MappingProxyType({"a": "natural radius of the sphere's base surface"})

    a: float = 1.0
    alpha1: float = 0.0
    alpha2: float = math.pi
    R: float | None = None

    name = "sphere"
    initial = ("gamma", "omega", "R")

    def _validate(self):
        super()._validate()
        _check("a", self.a, positive("m"))
        _check("alpha1", self.alpha1, Interval(0.0, math.pi, low_closed=True, unit="rad", shown="[0, pi) rad"))
        _check("alpha2", self.alpha2, Interval(self.alpha1, math.pi, high_closed=True, unit="rad",
                                               shown=f"({self.alpha1:.4g}, pi] rad"))
        if isinstance(self.R, str) and self.R.strip().lower() in ("auto", "none"):
            object.__setattr__(self, "R", None)
        if self.R is not None:
            _check("R", self.R, Interval(0.5 * self.a, 2 * self.a, unit="m",
                                         shown=f"(a/2, 2a) = ({self.a / 2:.4g}, {2 * self.a:.4g}) m, or auto"))

    def meridian(self):
        return ArcMeridian(self.a, 0.0, self.alpha1, self.alpha2)

    def scale(self):
        return 1.0 if self.R is None else self.R / self.a

    def at_equilibrium(self):
        return self.R is None

    def auto_values(self, initial, reference):
        """``R`` = auto: the radius of the starting state, ``a`` times its uniform scale (least-squares fit about
        the centre): ``a`` for the natural state, the mean radius of an equilibrium under load (a sphere only to
        the grid's accuracy, and not at all for a cap)."""
        return {"R": self.a * fitted_scale(initial, reference)} if self.R is None else {}


@dataclass(frozen=True)
class Cone(_Dilated):
    """A conical shell (frustum) from radius ``r1`` at ``z = 0`` to ``r2`` at ``z = H``; a cylinder when ``r1 = r2``.

    Straight generator at the half-angle ``atan2(r2 - r1, H)`` from the axis; the director points away
    from the axis. Both radii must be positive (an apex is not a smooth shell), ``H >= 0`` (``H = 0``:
    an annular plate).

    Parameters
    ----------
    r1, r2 : float
        Radii of the base surface at ``s = 0`` (``z = 0``) and ``s = L`` (``z = H``), m, ``> 0`` (defaults 1, 0.5).
    H : float
        Axial length, m, ``>= 0`` (default 1); 0 only with ``r1 != r2``.
    dilation : float or None
        Initial uniform dilation of the natural shell, in (0.5, 2); ``None`` (default, ``"auto"``): the static
        equilibrium under the loads at ``t = 0`` (the natural shell without loads).
    gamma, omega : float
        Initial twist ``chi_s``, rad/m (``chi = gamma (s - L/2)``, ``L`` the meridian's length), and rigid spin
        rate ``chi_t``, rad/s (defaults 0).
    """

    r1: float = 1.0
    r2: float = 0.5
    H: float = 1.0

    name = "cone"

    def _validate(self):
        super()._validate()
        _check("r1", self.r1, positive("m"), hint="an apex is not a smooth shell")
        _check("r2", self.r2, positive("m"), hint="an apex is not a smooth shell")
        ring = self.r1 != self.r2  # H = 0 is a flat ring, which needs two radii (a meridian of positive length)
        _check("H", self.H, non_negative("m") if ring else Interval(0.0, math.inf, unit="m", shown="(0, inf) m where "
                                                                        "r1 = r2 (a flat ring needs r1 != r2)"))

    def meridian(self):
        return ConeMeridian(self.r1, self.r2, self.H)


@dataclass(frozen=True)
class Torus(_Dilated):
    """A toroidal shell segment: tube radius ``a`` about a centre circle of radius ``b``.

    ``r0 = b + a sin(alpha)``, ``z0 = -a cos(alpha)`` for ``alpha`` from ``alpha1`` to ``alpha2``
    (polar angle in the tube from its lowest point; ``pi/2`` is the outer equator). Default: the
    outer half of the tube. The director is the tube's outward normal. The segment must stay off the
    axis (``r0 > 0``).

    Parameters
    ----------
    a : float
        Tube radius of the base surface, m, ``> 0`` (default 0.25).
    b : float
        Radius of the centre circle, m, ``> 0`` with ``b + a sin(alpha) > 0`` on the segment (default 1).
    alpha1, alpha2 : float
        Polar angles in the tube of the edges at ``s = 0`` and ``s = L``, rad: ``alpha1`` in [-pi, pi) (default 0),
        ``alpha2`` in (alpha1, alpha1 + 2 pi) (default pi): a closed tube has no edges the model can run (a whole
        torus under pressure runs as its half, ``alpha1 = -pi/2``, ``alpha2 = pi/2``, magnet edges on its mid-plane).
    dilation : float or None
        Initial uniform dilation of the natural shell, in (0.5, 2); ``None`` (default, ``"auto"``): the static
        equilibrium under the loads at ``t = 0`` (the natural shell without loads).
    gamma, omega : float
        Initial twist ``chi_s``, rad/m (``chi = gamma (s - L/2)``, ``L`` the meridian's length), and rigid spin
        rate ``chi_t``, rad/s (defaults 0).
    """

    descriptions = MappingProxyType({"a": "tube radius (of the base surface about the centre circle)"})

    a: float = 0.25
    b: float = 1.0
    alpha1: float = 0.0
    alpha2: float = math.pi

    name = "torus"

    def _validate(self):
        super()._validate()
        _check("a", self.a, positive("m"))
        _check("b", self.b, positive("m"))
        _check("alpha1", self.alpha1, Interval(-math.pi, math.pi, low_closed=True, unit="rad", shown="[-pi, pi) rad"))
        full = is_number(self.alpha2) and self.alpha2 >= self.alpha1 + 2 * math.pi
        _check("alpha2", self.alpha2, Interval(self.alpha1, self.alpha1 + 2 * math.pi, unit="rad",
                                               shown=f"({self.alpha1:.6g}, {self.alpha1 + 2 * math.pi:.6g}) rad "
                                                     "(alpha1 + 2 pi: a closed tube)"),
               hint=f"a tube turning by 2 pi or more is closed; {HALF_TUBE}" if full else "")
        alpha = np.linspace(self.alpha1, self.alpha2, 2001)
        if np.min(self.b + self.a * np.sin(alpha)) <= 0:
            raise ParameterError("b", self.b, f"values above a = {self.a:g} m for this segment",
                                 hint="the segment reaches the axis")
        span = self.alpha2 - self.alpha1
        if span > 2 * math.pi - 1e-6 or span < 1e-6:  # ends meeting near a full turn, or no turn: alpha2's doing
            check_meridian(self.meridian(), "alpha2", self.alpha2, f"({self.alpha1:.6g}, "
                           f"{self.alpha1 + 2 * math.pi:.6g}) rad, a segment with its ends apart")
        else:  # ends meeting to round-off on a shorter segment: a tube too thin beside its distance from the axis for
            # doubles (a = 5e-324, or b = 1e30): the one of a, b farther from its default named
            far = {k: abs(math.log(getattr(self, k) / getattr(type(self), k))) for k in ("a", "b")}
            name = max(far, key=far.get)
            check_meridian(self.meridian(), name, getattr(self, name), "(0, inf) m, a tube whose segment's ends stay "
                           "apart in double precision (a / b not too small)")

    def meridian(self):
        return ArcMeridian(self.a, self.b, self.alpha1, self.alpha2)


#: the largest axial moment of inertia of a shell from points, kg m^2: a node's spin inertia ``mA r^2`` (a part of it)
#: must stay finite, with room for the few products of it the kinetic energy's kernel forms (measured: a 5-node
#: cylinder's edge node overflows the right-hand side when its ``mA r^2`` reaches the largest double)
MAX_AXIAL_INERTIA = 1e-2 * sys.float_info.max


def axial_inertia_log10(meridian, rho, h):
    """``log10`` of a bound on the shell's moment of inertia about the axis: ``2 pi rho int int (r0 + zeta cos
    theta0)^3 (1 - zeta theta0_s) dzeta ds <= 8 pi rho h (r_max + 2h)^3 L`` (``|zeta| <= 2h``, ``1 - zeta theta0_s < 2``
    inside the centres of curvature), in logarithms so that it is finite whatever the table's size."""
    r_max = float(np.max(np.abs(meridian.at(np.linspace(0.0, meridian.length, 201))[0])))
    return (math.log10(8 * math.pi) + math.log10(rho) + math.log10(h) + 3 * math.log10(r_max + 2 * h)
            + math.log10(meridian.length))


def goes_down(meridian, breaks):
    """Whether ``meridian`` encloses a negative volume ``pi int r0^2 dz0`` with the axis (and the planes of its ends
    off the axis): it goes down along ``s`` (from a first pole, or a table listed from the top down), its director
    ``d0`` (``dr``-component ``cos theta0 = dz0/ds``) pointing toward the axis, into that volume. The integral in units
    of the length (no overflow at any scale), by Gauss-Legendre with 16 points between consecutive ``breaks`` (the
    arc lengths where the meridian's formula changes): exact to round-off on lines and arcs, to the spline's
    smoothness on a table; a flat disc (``0``) does not go down."""
    x, w = np.polynomial.legendre.leggauss(16)
    scale, total = meridian.length, 0.0
    for s0, s1 in itertools.pairwise(breaks):
        r, _, theta, _ = meridian.at(s0 + (s1 - s0) * (x + 1) / 2)
        total += (s1 - s0) / scale / 2 * float(np.sum(w * (r / scale) ** 2 * np.cos(theta)))
    return total < -1e-12


#: what the meridian scene runs without a file of points (``points = ''``)
DEFAULT_DOME = "the built-in dome (a half ellipsoid of equatorial radius 1 m and height 0.6 m, points = '')"


@lru_cache(maxsize=8)
def _points_meridian(path, stamp):
    table, lines = read_points(path, with_lines=True)
    return PointsMeridian(table, name="points", source=path, lines=lines)


@dataclass(frozen=True)
class MeridianShell(_Dilated):
    """A shell whose meridian is a table of points ``(r, z)`` read from a file (two columns, metres).

    The points are interpolated by a cubic spline with continuous curvature and re-parametrised by
    arc length (:class:`~mol_shell.model.geometry.PointsMeridian`); ``s = 0`` is the first row.
    An end on the axis (``r = 0``, or within 1e-12 of the table's size: ``sin(pi)``) is a pole, put on the axis, and
    the curve leaves it at a right angle there. Coordinates are refused beyond the size at which the shell's moment
    of inertia about the axis overflows with the given ``rho`` and ``h`` (about 1e76 m with the defaults). The director is
    the tangent turned by +90 degrees in the ``(z, r)`` plane: outward for rows ordered by increasing ``z``. A table
    listed from the top down (enclosing a negative volume, :func:`goes_down`) is run as given, not traversed backwards
    as a vessel's downward segments are (``end1`` stays the first row): ``z`` is where the user put the shell, and
    gravity (along ``-k``), the end forces (along ``k``) and the edges' axial motions act on it there. Its director then points toward the axis and
    the stresses' "inner" face is the geometric outer one, which a note says (:meth:`stand_ins`).
    ``points = ''`` (the default) is a built-in half ellipsoid (equatorial radius 1 m, height 0.6 m), so
    the scene runs as it is; a run says so (its ``meridian`` attr, and a note of the command line).

    Parameters
    ----------
    points : str or os.PathLike
        Path of the file of points (``~`` expanded, stored absolute; a ``pathlib.Path`` kept as its text); ``''``
        (default): the built-in dome.
    dilation : float or None
        Initial uniform dilation of the natural shell, in (0.5, 2); ``None`` (default, ``"auto"``): the static
        equilibrium under the loads at ``t = 0`` (the natural shell without loads).
    gamma, omega : float
        Initial twist ``chi_s``, rad/m (``chi = gamma (s - L/2)``, ``L`` the meridian's length), and rigid spin
        rate ``chi_t``, rad/s (defaults 0).
    """

    points: str = ""

    name = "meridian"

    def _validate(self):
        super()._validate()
        if isinstance(self.points, os.PathLike) and isinstance(os.fspath(self.points), str):  # a pathlib.Path: as
            object.__setattr__(self, "points", os.fspath(self.points))  # its text (files and records unchanged)
        if not isinstance(self.points, str):
            raise ParameterError.not_a("points", self.points, "a file name",
                                       "a file with two columns r z (m), at least 4 rows, or '' (a built-in dome)")
        if self.points.strip():  # absolute: a run's or a path's file names it wherever it is read again (--from)
            object.__setattr__(self, "points", os.path.abspath(os.path.expanduser(self.points)))
            self._check_size(self.meridian())  # the built-in dome's 1 m overflows only by rho or h, named by range

    def _check_size(self, meridian):
        """A table so large that the shell's spin inertia overflows with this ``rho`` and ``h`` (a 1e90 m table, inside
        the points' 1e100 m) is refused naming ``points`` and the size that fits (the inertia grows as size^4)."""
        h = self.h
        if isinstance(self.h_profile, str) and self.h_profile.strip():
            h = float(np.max(thickness_function(self.h_profile, meridian.length)(np.linspace(0, meridian.length, 201))))
        excess = axial_inertia_log10(meridian, self.rho, h) - math.log10(MAX_AXIAL_INERTIA)
        if excess <= 0:
            return
        size = float(np.max(np.abs(meridian.points)))
        fits = 10.0 ** (math.log10(size) - excess / 4)
        raise ParameterError.invalid(
            "points", self.points, f"has coordinates up to {size:.3g} m: the shell's moment of inertia about the axis "
            f"(about 1e{excess + math.log10(MAX_AXIAL_INERTIA):.0f} kg m2 with rho = {self.rho:g} kg/m3, "
            f"h = {h:.4g} m) overflows double precision",
            f"a table with coordinates up to about {fits:.2g} m with this rho and h (the inertia grows as size^4)")

    def meridian(self):
        if not self.points.strip():
            return _default_dome()
        p = Path(self.points).expanduser()
        # the file's contents, not its time: two writes within one tick of the file system's clock keep the time
        try:
            stamp = hashlib.sha256(read_user_file(p)).hexdigest()  # a device or a pipe: refused, not read
        except OSError:  # missing, unreadable, no regular file or too large: read_points says so by name
            stamp = ""
        return _points_meridian(str(p), stamp)

    def stand_ins(self):
        """The built-in dome, when no file is given; a table listed from the top down (:func:`goes_down`), run as
        given, its faces named after the director's sides: which face is "inner" then."""
        if not self.points.strip():
            return [f"the meridian is {DEFAULT_DOME}: give your own with points = FILE (two columns r z, m)"]
        meridian = self.meridian()
        if not goes_down(meridian, meridian._s):
            return []
        return [(f"points = {self.points!r} are listed from the top down (z decreasing along the rows) and run as "
                 "given, not mirrored in z (gravity, end forces and z act where the table puts the shell): the director "
                 "points toward the axis, into the side the shell encloses, so the stresses' \"inner\" face (zeta1) "
                 "is its geometric outer face and \"outer\" its inner one (zeta1 = 0 puts the base surface on the "
                 "outer face); list the rows from the bottom up (end1 then at the bottom) for an outward director")]


@lru_cache(maxsize=1)
def _default_dome():
    """The meridian scene's default table: a half ellipsoid of equatorial radius 1 m and height 0.6 m, 17 points
    from the equator (z = 0) to the pole, so the scene runs as it is (``points = ''``)."""
    t = np.linspace(0.0, np.pi / 2, 17)
    return PointsMeridian(np.column_stack([np.cos(t), 0.6 * np.sin(t)]), name="points", source=DEFAULT_DOME)
