"""Cylinder scenes: the paper's twisted cylinder (section 6), the spinning ring (section 5), axisymmetric motion."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Interval, finite, positive
from mol_shell.model.edges import EDGE_FIELDS, EDGE_PARAMETERS, EDGES, resolve_edges
from mol_shell.model.geometry import CylinderMeridian
from mol_shell.model.laws import layer_scenes
from mol_shell.model.layers import MAKING_LAYERS
from mol_shell.model.thickness_profile import table_points, thickness_function
from mol_shell.scenes.base import DISPLACEMENTS, DRIVES, LOADS, ShellScene, _check, mean_over, zeta1_used


def check_radius(R, h, zeta1=None, hint="", a=1.0):
    """``R > -zeta1_used``: the inner face ``r + zeta1`` of the initial cylinder at a positive radius."""
    low = -zeta1_used(h, zeta1, a)
    if isinstance(R, str):  # a word other than auto
        raise ParameterError.not_a("R", R, "a number", f"({low:.4g}, inf) m, or auto")
    _check("R", R, Interval(low, math.inf, unit="m", shown=f"({low:.4g}, inf) m: the inner face r + zeta1 must be at "
                                                       f"a positive radius (zeta1 = {-low:.4g} m)" + (f"; {hint}" if hint else "")))


#: a fibre angle this close to 0 or +-pi/2 (rad) is along the meridian or the hoop (as typed: 1.5708, 1.571; the
#: tolerance of FIBRE_ANGLES), not a helix
AXIAL_OR_HOOP_TOL = 1e-3


def _helical_couplings(scene, thickness=1.0):
    """``(sum t E_f cos^3 sin, sum t E_f cos sin^3, sum t E_f)`` of one family of fibres at ``fibre_angle`` in a wall
    (a layer) ``thickness`` thick: the fibres' stretch-shear couplings of lamination theory (``A16``, ``A26``); zero for
    two families ``+-fibre_angle``, no fibres, or fibres along the meridian or the hoop."""
    angle, stiffness = scene.fibre_angle, float(scene.fibre_E) * thickness
    if not scene.fibre_E or scene.fibre_families != 1 or min(abs(angle), abs(abs(angle) - math.pi / 2)) <= \
            AXIAL_OR_HOOP_TOL:
        return 0.0, 0.0, abs(stiffness)
    c, s = math.cos(angle), math.sin(angle)
    return stiffness * c ** 3 * s, stiffness * c * s ** 3, abs(stiffness)


def unbalanced_helix(scene):
    """``"layers"`` or ``"fibre_families"``, the parameter that gives ``scene`` helical fibres whose stretch-twist
    couplings do not balance (a layered wall judged whole), or None where they balance or there are none."""
    if MAKING_LAYERS.get():  # a layer of a layered wall: the wall is judged whole, on the layered scene
        return None
    if scene.layers.strip():
        parts = [_helical_couplings(sub, t) for t, sub in layer_scenes(scene)]
        a16, a26, total = (sum(x) for x in zip(*parts))
        return None if max(abs(a16), abs(a26)) <= 1e-9 * max(total, 1e-300) else "layers"
    return None if _helical_couplings(scene)[:2] == (0.0, 0.0) else "fibre_families"


def check_no_helix(scene):
    """Refuse, naming ``fibre_families`` (or ``layers``), helical fibres that do not balance on a scene without the
    twist ``chi`` (the axisymmetric scene): ``C_13 = r^2 chi_s ...`` carries the twist and a family's ``2 cos sin C_13``
    couples stretch to it (:mod:`mol_shell.model.fibres`), so with ``chi`` held at 0 the scene would carry a torque no
    edge is given (a tube under an axial force stretches as lamination theory's tube with its twist held, not as a
    free one). Two families ``+-fibre_angle`` cancel the coupling, and so do layers of one family each whose
    couplings add up to zero (an angle-ply wall ``+a; -a``): a layered wall is judged whole."""
    unbalanced = unbalanced_helix(scene)
    if unbalanced is None:
        return
    if unbalanced == "layers":
        raise ParameterError("layers", scene.layers, "layers whose helical fibres balance (sum of t fibre_E cos^3 "
                             "sin and of t fibre_E cos sin^3 over the layers of one family each zero: +-angle in "
                             "layers of one thickness and fibre_E), or two families in a layer",
                             hint=f"scene {scene.name} holds the twist chi at 0, and unbalanced helical fibres couple "
                             "stretch to twist: the held twist would be a torque no edge is given; for a twisting "
                             "tube use scene cone with r1 = r2, or twisted-cylinder")
    raise ParameterError("fibre_families", 1, f"2 (families at +-fibre_angle, which balance) at fibre_angle = "
                         f"{scene.fibre_angle:g} rad, or 1 at fibre_angle 0 or +-pi/2",
                         hint=f"scene {scene.name} holds the twist chi at 0, and one helical family couples stretch to "
                         "twist: the held twist would be a torque no edge is given; for a twisting tube use scene cone "
                         "with r1 = r2, or twisted-cylinder")


@dataclass(frozen=True)
class CylinderScene(ShellScene):
    """A circular cylinder of natural radius ``a`` and length ``L``, its ends magnets by default.

    Parameters
    ----------
    L : float
        Length, m, ``> 0`` (default 4, the paper's).
    a : float
        Natural radius of the base surface, m, ``> 0`` and above ``2h`` (default 1, the paper's). The director
        points outward.
    R : float or None
        Initial radius, m, above ``-zeta1`` (the inner face at a positive radius). ``None`` (or
        ``"auto"``) computes the radius at which the uniformly twisted cylinder is in radial
        equilibrium (:func:`mol_shell.model.equilibrium.equilibrium_radius`); untwisted (``gamma = 0``) under
        loads the run starts from the static equilibrium found from it (:func:`mol_shell.runs.simulate.starting_state`).
    """

    #: what R = auto is, and the scene's own words for a shared parameter (mol-shell scenes NAME)
    defaults_mean = MappingProxyType({"R": "the radius of radial equilibrium of the cylinder twisted by gamma (under "
                                           "the pressure at t = 0); untwisted under loads, the static equilibrium "
                                           "found from it"})
    descriptions = MappingProxyType({"a": "natural radius of the cylinder's base surface"})

    L: float = 4.0
    a: float = 1.0
    R: float | None = None

    initial = ("R",)

    def initial_radius(self):
        """``R`` for the initial fields; ``None`` (auto) is computed by :func:`mol_shell.runs.checks.resolve`, which
        the public routes call first (a system built directly from an unresolved scene got NaN radii)."""
        if self.R is None:
            raise ParameterError("R", None, "a radius in m for the initial fields",
                                 hint="R = auto is computed by mol_shell.runs.checks.resolve(scene), as simulate does")
        return self.R

    def auto_values(self, initial, reference):
        """``R`` = auto: the radius the run starts at, ``r(t = 0)`` where the start is uniform (the radial
        equilibrium of the twisted cylinder, or the static equilibrium under loads found from it, whose twist the
        loads may change: one fibre family), else its mean over the length (edges that hold the radius)."""
        return {"R": mean_over(initial[1], reference[0])} if self.R is None else {}

    def _validate(self):
        _check("L", self.L, positive("m"))
        _check("a", self.a, positive("m"))
        if self.h >= self.a / 2:
            raise ParameterError("h", self.h, Interval(0.0, self.a / 2, unit="m", shown=f"(0, a/2) = (0, {self.a / 2:.4g}) m"),
                                 hint="the thickness 2h must stay below the natural radius a")
        if isinstance(self.R, str) and self.R.strip().lower() in ("auto", "none"):
            object.__setattr__(self, "R", None)  # as from the command line: computed
        if self.R is not None:
            check_radius(self.R, self.h, self.zeta1, a=self.a)

    def meridian(self):
        return CylinderMeridian(self.a, self.L)

    def zeta1_used(self):
        """``zeta1``, or the offset with ``int zeta (a + zeta) dzeta = 0`` (``rhoI = 0``, as the paper)."""
        return zeta1_used(self.h, self.zeta1, self.a)

    def _check_profile(self):
        """A graded wall's ``h(s)`` below ``a/2``, the bound of a uniform ``h`` (the wall thinner than the natural
        radius); the general check (the faces off the axis) let ``h(s)`` reach ``a``."""
        if isinstance(self.h_profile, str) and self.h_profile:
            s = np.linspace(0.0, self.L, 801)
            s = np.concatenate([s, [p for p in table_points(self.h_profile) if 0.0 < p < self.L]])  # a table's peak
            hs = thickness_function(self.h_profile, self.L)(s)
            k = int(np.argmax(np.where(np.isfinite(hs), hs, np.inf)))
            if not hs[k] < self.a / 2:
                raise ParameterError("h_profile", self.h_profile, f"values with h(s) below a/2 = {self.a / 2:.4g} m, as "
                                     "h's (the thickness 2h must stay below the natural radius a)",
                                     hint=f"h = {hs[k]:.4g} m at s = {s[k]:.4g} m")
        super()._check_profile()


@dataclass(frozen=True)
class TwistedCylinder(CylinderScene):
    """The initial-boundary-value problem of section 6 (and, with ``gamma = 0``, section 5).

    Ends welded to lubricated magnets a fixed distance ``L`` apart (``z = s``,
    ``theta = 0``, ``n.a2 = n.a3 = m.c1 = 0``; ``end1``/``end2`` choose others). Initial data (6.9),
    extended: ``r = R``, ``z = s``, ``chi = gamma (s - L/2)``, ``theta = 0``, ``psi = psi0``,
    ``chi_t = omega``, the other rates zero. See :class:`ShellScene` for the material parameters.

    Parameters
    ----------
    L : float
        Length, m, ``> 0`` (default 4, the paper's): the distance between the magnets.
    a : float
        Natural radius of the base surface, m, ``> 0`` and above ``2h`` (default 1, the paper's).
    R : float or None
        Initial radius, m, above ``-zeta1``. ``None`` (default, ``"auto"``): the radius at which the cylinder
        twisted by ``gamma`` is in radial equilibrium (under the pressure at ``t = 0``), as the paper starts;
        with ``gamma = psi0 = 0`` under loads, the static equilibrium found from it.
    gamma : float
        Initial twist ``chi_s``, rad/m (default 0.1: the paper's value is lost; 0.1 fits its figures).
    omega : float
        Initial uniform spin rate ``chi_t``, rad/s (default 0).
    psi0 : float
        Initial uniform shear angle ``psi``, rad, in (-pi/2, pi/2) (default 0).
    end_omega : float
        Both ends turned at this rate from ``t = 0`` (the magnets spun up), rad s-1: ``end1_spin`` and
        ``end2_spin`` where those are 0 (default 0).
    """

    gamma: float = 0.1
    omega: float = 0.0
    psi0: float = 0.0
    end_omega: float = 0.0

    name = "twisted-cylinder"
    #: the two defaults that are not the paper's own (its values are lost in the text: docs/model.md)
    descriptions = MappingProxyType({**CylinderScene.descriptions,
                                     "rho": "density (the paper's value is lost: 1000 assumed; the motion's times "
                                            "scale as sqrt(rho))",
                                     "gamma": "initial twist chi_s (the paper's value is lost: 0.1 inferred from its "
                                              "figures' chi axis)"})
    initial = ("R", "gamma", "omega", "psi0")

    def _validate(self):
        super()._validate()
        _check("gamma", self.gamma, finite("rad/m"))
        _check("omega", self.omega, finite("rad/s"))
        _check("psi0", self.psi0, Interval(-math.pi / 2, math.pi / 2, unit="rad", shown="(-pi/2, pi/2) rad"))
        _check("end_omega", self.end_omega, finite("rad/s"))

    @property
    def loaded(self):
        return super().loaded or self.end_omega != 0

    def drives(self):
        out = super().drives()
        if self.end_omega:
            for end in (0, 1):
                out.setdefault((end, 2), (float(self.end_omega), ("constant", ())))
        return out

    def initial_fields(self, s, reference):
        Q, V = super().initial_fields(s, reference)
        Q[1] = self.initial_radius()
        Q[2] = self.gamma * (np.asarray(s) - self.L / 2)
        Q[4] = self.psi0
        V[2] = self.omega
        return Q, V


#: the loads, drives and edge displacements that make a cylinder's motion depend on ``s`` (pressure and drag do not)
NOT_UNIFORM = tuple(name for name in LOADS + DRIVES + DISPLACEMENTS if name not in ("pressure", "drag")) + ("end_omega",)
#: where :class:`SpinningRing`'s refusals point
RING_ELSEWHERE = "scene twisted-cylinder with gamma = 0 runs it"


def check_uniform(scene, where, elsewhere):
    """Refuse, by name, what makes a cylinder's motion depend on ``s`` where a uniform motion is assumed (``where``:
    the spinning-ring scene, the ring ODE; ``elsewhere``: what runs it): an edge other than the magnet (it bends the
    shell near it: ``r`` 0.008-0.026 m off within 10 ms at the defaults), a thickness that varies along the meridian,
    and helical fibres whose stretch-twist couplings do not balance (the ends are free to twist: one family at
    0.5 rad, ``r`` varies by 5.9e-4 m along ``s``)."""
    for name, edge in zip(("end1", "end2"), resolve_edges(scene.end1, scene.end2, scene.meridian().poles)):
        if edge != "magnet":
            raise ParameterError(name, getattr(scene, name), f"{{magnet, auto}} for {where}",
                                 hint=f"other edges bend the shell near them: not uniform in s; {elsewhere}")
    if getattr(scene, "h_profile", ""):
        raise ParameterError("h_profile", scene.h_profile, f"'' (a uniform wall) for {where}",
                             hint=f"a graded wall makes the motion depend on s; {elsewhere}")
    helix = unbalanced_helix(scene)
    if helix is not None:
        allowed = ("layers whose helical fibres balance (+-angle), or two families in a layer" if helix == "layers"
                   else "2 (families at +-fibre_angle, which balance), or 1 at fibre_angle 0 or +-pi/2")
        raise ParameterError(helix, getattr(scene, helix), f"{allowed} for {where}",
                             hint=f"one helical family couples stretch to twist, and the ends are free to twist: not "
                             f"uniform in s; {elsewhere}")


@dataclass(frozen=True)
class SpinningRing(TwistedCylinder):
    """Section 5: spatially uniform breathing, spinning and shearing (``gamma = 0``).

    The same boundary-value problem as :class:`TwistedCylinder` with uniform initial data
    ``r = R``, ``chi_t = omega``, ``psi = psi0``; the motion stays uniform in ``s`` and
    follows the ODEs of section 5.

    Parameters
    ----------
    R : float or None
        Initial radius, m (default 1.01: breathing about the natural radius); ``None`` (``"auto"``): as
        :class:`TwistedCylinder`'s.
    omega : float
        Initial spin rate ``chi_t``, rad/s (default 20).
    psi0 : float
        Initial shear angle ``psi``, rad, in (-pi/2, pi/2) (default 0.05).
    gamma : float
        Initial twist ``chi_s``, rad/m: 0 only (section 5: twisted motions are not uniform in ``s``; scene
        ``twisted-cylinder`` runs them). Edges other than the magnet, a graded wall (``h_profile``) and loads other
        than pressure and drag (at the edges, along the axis) are refused too: they make the motion depend on ``s``.
    L, a, end_omega : float
        Length and natural radius (m; defaults 4 and 1), the ends' spin rate (rad/s; default 0): as
        :class:`TwistedCylinder`.
    """

    R: float | None = 1.01
    gamma: float = 0.0
    omega: float = 20.0
    psi0: float = 0.05

    name = "spinning-ring"
    descriptions = MappingProxyType({**CylinderScene.descriptions,
                                     "gamma": "initial twist chi_s: 0 only (twisted motions are not uniform in s)"})

    def _validate(self):
        """What makes the motion depend on ``s`` refused by name, pointing to ``twisted-cylinder``, which runs it:
        a twist (section 5: no twisted motion is uniform in ``s``), an edge other than the magnet (it bends the
        shell near it), a graded wall, and the loads, drives and edge displacements that act at the edges or along
        the axis. Pressure and drag act alike at every ``s`` and are kept."""
        super()._validate()
        if self.gamma != 0:
            raise ParameterError("gamma", self.gamma, "{0} for scene spinning-ring", hint="section 5: twisted motions "
                                 "are not uniform in s; scene twisted-cylinder runs them")
        check_uniform(self, "scene spinning-ring", RING_ELSEWHERE)
        for name in NOT_UNIFORM:
            if getattr(self, name):
                raise ParameterError(name, getattr(self, name), "0 for scene spinning-ring",
                                     hint=f"it acts at the edges or along the axis: not uniform in s; {RING_ELSEWHERE}")


@dataclass(frozen=True)
class Axisymmetric(CylinderScene):
    """Axisymmetric motions: no twist and no shear (``chi = psi = 0`` identically).

    Only ``z, r, theta`` are unknowns; the graph holds nothing of ``chi`` and ``psi``.
    Initial data: ``r = R`` (default 1.01 m, a breathing cylinder), ``z = s``, at rest. Fibres: two balanced
    families (``fibre_families = 2``), or one along the meridian or the hoop (``fibre_angle`` 0 or ``+-pi/2``): one
    helical family couples stretch to twist, which this scene holds at 0 (:func:`check_no_helix`).

    Parameters
    ----------
    L : float
        Length, m, ``> 0`` (default 4).
    a : float
        Natural radius of the base surface, m, ``> 0`` and above ``2h`` (default 1).
    R : float or None
        Initial radius, m, above ``-zeta1`` (default 1.01). ``None`` (``"auto"``): the radius of radial
        equilibrium under the pressure at ``t = 0`` (``a`` without it); under loads, the static equilibrium
        found from it.
    """

    R: float | None = 1.01

    name = "axisymmetric"
    fields = (0, 1, 3)
    defaults_mean = MappingProxyType({"R": "the radius of radial equilibrium of the cylinder under the pressure at "
                                           "t = 0 (a without it); under loads, the static equilibrium found from it"})

    def _validate(self):
        super()._validate()
        check_no_helix(self)
        self._check_edge_fields()

    def _check_edge_fields(self):
        """Refuse an edge given as a set of fields that names ``chi`` or ``psi`` (``end1=chi``): the scene has neither,
        so it imposed nothing, silently, where ``end1_dchi`` is refused (the kinds hold them at 0 as they are)."""
        for name in EDGE_PARAMETERS:
            edge = getattr(self, name)  # canonical (ShellScene._validate): a kind, a set of fields, or None (auto)
            if edge is None or edge in (*EDGES, "pole"):
                continue
            absent = [f for f in edge.split(",") if EDGE_FIELDS.index(f) not in self.fields]
            if absent:
                raise ParameterError.invalid(name, edge, f"cannot be imposed: the scene has no {absent[0]} field",
                                             f"an edge kind ({', '.join(EDGES)}, auto) or a set of the fields z, r, "
                                             "theta for scene axisymmetric (chi = psi = 0 identically)")

    def initial_fields(self, s, reference):
        Q, V = super().initial_fields(s, reference)
        Q[1] = self.initial_radius()
        return Q, V
