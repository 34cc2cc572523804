"""The scene base class: material, thickness and edges, and the checks every parameter goes through.

Vary a scene with :func:`dataclasses.replace` (or :func:`~mol_shell.scenes.setting.with_params` from
strings, as the CLI does); a bad value raises :class:`~mol_shell._core.errors.ParameterError`
naming the parameter and its allowed range.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import numbers
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ParameterError, UnknownParameterError, is_number
from mol_shell._core.ranges import TINY, Choice, Interval, finite, modulus, non_negative, subnormal
from mol_shell.model.edges import EDGE_PARAMETERS, check_displacements, check_edge, resolve_edges
from mol_shell.model.fibres import FIBRE_ANGLES, fibre_angle_hint
from mol_shell.model.geometry import base_offset
from mol_shell.model.laws import (
    COMPRESSIBLE_WHY,
    MATERIALS,
    layer_scenes,
    resolve_material,
)
from mol_shell.model.layers import MAX_LAYERS, layer_word, layers_text, parse_layers
from mol_shell.model.loads import normal_history, parse_history
from mol_shell.model.material import centroidal_offset
from mol_shell.model.thickness_profile import check_profile_fits, thickness_function
from mol_shell.model.wall_fit import check_wall_fits
from mol_shell.model.wall_parameters import check_layer_parameters, checked_material_parameters
from mol_shell.scenes.descriptions import DESCRIPTIONS, UNITS, describe  # noqa: F401 - the scenes' vocabulary

#: the loads a scene can carry (each with a ``NAME_history`` but drag)
LOADS = ("pressure", "gravity", "drag", "end1_force", "end2_force", "end1_torque", "end2_torque")
#: driven edges: prescribed rates of an edge's chi and z (each with a ``NAME_history``)
DRIVES = ("end1_spin", "end2_spin", "end1_axial_speed", "end2_axial_speed")
#: static edge displacements: an imposed z (m) or chi (rad) moved from its reference value (displacement control)
DISPLACEMENTS = ("end1_dz", "end2_dz", "end1_dchi", "end2_dchi")
#: the wall's law: none of these decides whether a wall of thickness h fits the meridian
WALL_LAW = ("E", "nu", "rho", "n_quad", "eta_lambda", "eta_mu", "material", "material_parameters", "c10", "c01",
            "fibre_E", "fibre_angle", "fibre_families", "fibre_compression", "law_limit", "ellipticity_limit", "layers")

#: Gauss-Legendre points through the thickness: one point makes the director's inertia rhoJ = rhoI^2/rhoA,
#: a singular mass matrix. Above 32 nothing is gained and the kernels grow too large to compile in
#: reasonable time: with the base surface centroidal, 12-16 points integrate What to round-off for every
#: h < 0.5 m (32 with the inner face at r = 0.1 m); at n = 40 the exact Jacobian of cvode-bdf compiled in
#: 3.8, 13, 54, 108 and 767 s at 4, 8, 16, 32, 64 points (docs/reliability.md)
N_QUAD_RANGE = (2, 32)
#: layers' thicknesses must add up to the wall 2h to this fraction of it (what a user types: 7 digits); they are then
#: scaled to add up to 2h exactly
LAYERS_RTOL = 1e-6


class Flag(Choice):
    """A yes/no parameter: ``True``/``False`` (or 1/0, as netCDF stores them), or the strings ``true``/``false``."""

    def __init__(self):
        super().__init__(("true", "false"))

    def __contains__(self, value):
        return value in self.values or isinstance(value, (bool, np.bool_)) or (
            isinstance(value, numbers.Integral) and value in (0, 1))


def _check(name, value, allowed, ok=None, hint=""):
    """Refuse ``value`` unless it is a finite number in the declared range ``allowed`` (an
    :class:`~mol_shell._core.ranges.Interval`), and ``ok(value)`` where a condition says more than the range."""
    if not is_number(value):
        raise ParameterError.not_a(name, value, "a number", allowed, hint)
    if not (math.isfinite(value) and value in allowed and (ok is None or ok(value))):
        if getattr(allowed, "normal", False) and subnormal(value) and not hint:
            hint = "a subnormal number: the products it enters lose their digits or vanish"
        raise ParameterError(name, value, allowed, hint)


def fitted_scale(initial, reference):
    """The uniform scale ``k`` about the origin that best fits (least squares) the nodal ``(z, r)`` of ``initial``
    to ``k`` times those of ``reference``: exactly the factor of a uniformly dilated natural shell."""
    (z, r), (z0, r0) = (np.asarray(x, dtype=float) for x in initial), (np.asarray(x, dtype=float) for x in reference)
    return float(np.sum(z * z0 + r * r0) / np.sum(z0 * z0 + r0 * r0))


def mean_over(values, coordinate):
    """The mean of nodal ``values`` over the meridian (trapezoidal in ``coordinate``, the nodes' ``s`` or ``z``):
    exactly their value where they are all one (a uniform start)."""
    v, x = np.asarray(values, dtype=float), np.asarray(coordinate, dtype=float)
    if np.all(v == v[0]) or x[-1] == x[0]:
        return float(v[0])
    return float(np.trapezoid(v, x) / (x[-1] - x[0]))


def zeta1_used(h, zeta1=None, a=1.0):
    """The lower face of a cylinder's thickness interval as the model uses it (``zeta1``, or the centroidal offset)."""
    return centroidal_offset(h, a) if zeta1 is None else zeta1


@dataclass(frozen=True)
class ShellScene:
    """Material, thickness and edges shared by every scene; subclasses add a meridian and initial data.

    Parameters
    ----------
    h : float
        Half-thickness, m (paper: 2 pi 1e-3). The thickness interval must stay off the axis and inside
        every centre of curvature of the meridian.
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio (paper: 1e6 Pa = 1e-3 GPa, 0.49).
    rho : float
        Density, kg/m^3. Lost from the paper; 1000 is our assumption (it only rescales time).
    n_quad : int
        Gauss-Legendre points through the thickness, 2..32 (beyond, nothing is gained and the kernels take
        minutes to compile).
    zeta1 : float or None
        Lower face of the thickness interval, measured from the base surface along the
        director (:mod:`mol_shell.model.geometry` says which way it points). ``None`` places the
        base surface at the shell's centroid: ``rhoI = 0`` at every ``s`` on a cylinder or sphere, on
        average elsewhere (:func:`~mol_shell.model.geometry.base_offset`).
    eta_lambda, eta_mu : float
        Kelvin-Voigt viscosities, Pa s (``S_visc = eta_lambda tr(E_t) I + 2 eta_mu E_t``);
        0 (default) is the elastic shell, and leaves the viscous terms out of the graph.
    material : str or mol_shell.Material
        A built-in law: ``"svk"`` (default; the paper: 3-D St Venant-Kirchhoff with the inextensible director),
        ``"svk-plane-stress"`` (thickness stress condensed out; :func:`mol_shell.model.material.effective_lame`),
        ``"neo-hookean"`` (compressible, ``E, nu``, plane stress; Ciarlet and Geymonat's volumetric term),
        ``"neo-hookean-log"`` (the same with a ``(ln J)^2`` volumetric term), ``"neo-hookean-incompressible"``
        (shear modulus ``E/3``) or ``"mooney-rivlin"`` (incompressible, ``c10, c01``) (:mod:`mol_shell.model.laws`);
        or a law of one's own: a :class:`mol_shell.Material` (stored as its name), or its import path ``"package.module:attr"``
        (scene files, ``--set``, a study's workers; stored as the path). See docs/materials.md.
    material_parameters : str or dict
        A law of one's own (:class:`mol_shell.Material`) with some of its parameters changed: ``"mu=3e5 k=1e4"`` or
        ``{"mu": 3e5}`` (stored as the string); ``""`` (default): the Material's own. Built-in laws take theirs as
        scene parameters (``E, nu, c10, c01``). ``with_params``, ``--set`` and studies also take ``material.NAME``.
    c10, c01 : float
        Mooney-Rivlin constants, Pa (``W = c10 (I1 - 3) + c01 (I2 - 3)``; ``c10 > 0``, ``c01 >= 0``); read by
        ``material = "mooney-rivlin"`` only.
    fibre_E, fibre_angle, fibre_families, fibre_compression : float, float, int, bool
        Fibre reinforcement on the law (:mod:`mol_shell.model.fibres`): modulus, Pa (``>= 0``; 0, the default, is
        no fibres and nothing of them in the graph); angle, rad, from the meridian towards ``+phi``; 1 family
        (a helix: stretch couples with twist) or 2 (``+-angle``, balanced); ``False``: tension only.
    layers : str or list of dict
        A layered wall (:mod:`mol_shell.model.layers`): ``"T1 MATERIAL key=value ...; T2 ..."`` from the lower face
        (``T`` full thicknesses adding up to ``2h``; keys ``E, nu, c10, c01, fibre_E, fibre_angle, fibre_families,
        fibre_compression``, the scene's where left out), or a list of dicts ``{"thickness": T, "material": M, ...}``
        (stored as the string). ``""`` (default): one layer of ``material``. With ``h_profile`` each layer keeps its
        share of the wall (its thickness times ``h(s)/h``).
    h_profile : str
        A graded wall (:mod:`mol_shell.model.thickness_profile`): ``h(s)`` as ``"table s0:h0 s1:h1 ..."`` (m, covering
        the meridian) or an expression of ``s``; each cell integrated through its own ``[-h, h]`` about the
        mid-surface (``zeta1`` must be auto), ``h`` the nominal half-thickness. ``""`` (default): the uniform wall.
    law_limit : bool
        Stop a run, as a limit of the model, where the law leaves its range: for the SVK laws (without fibres; a
        layered wall with a layer of one) an in-plane stretch of ``1/sqrt(3)`` in compression, past which their stress
        turns back
        (:func:`~mol_shell.model.material.svk_turning_limit`). ``False``: the law as written, without that stop.
    ellipticity_limit : bool
        Stop a run, as a limit of the model, where the shell's equations stop being elliptic in ``s`` (the leading
        minors of each cell's principal symbol as root functions: about one more right-hand side per step).
        ``False`` (default): the run goes on and its saved states are checked afterwards
        (:mod:`mol_shell.runs.ellipticity`).
    end1, end2 : str or None
        Edge conditions at ``s = 0`` and ``s = L``: ``magnet``, ``clamped``, ``pinned``, ``free``, or the fields it
        imposes (``"r,theta"``; :mod:`mol_shell.model.edges`); ``None`` (default, ``auto``): a pole on the axis,
        ``magnet`` elsewhere.
    pressure : float
        Pressure on the base surface, Pa, a follower load, positive inflating (edges closed by lids in
        their planes); ``pressure_history`` its time history (:mod:`mol_shell.model.loads`).
    gravity : float
        Gravitational acceleration along ``-k``, m s-2; ``gravity_history``.
    drag : float
        Ambient viscous fluid, N s m-3: force ``-drag x (velocity of the base surface)`` per unit reference area.
    end1_force, end2_force : float
        Axial force (along ``k``) on an edge, N; the edge's ``z`` must be free (``free`` edge); ``*_history``.
    end1_torque, end2_torque : float
        Axial torque (about ``k``) on an edge, N m; the edge's ``chi`` must be free (``magnet`` or ``free``); ``*_history``.
    end1_spin, end2_spin : float
        Driven edge: its ``chi`` turned at this rate, rad s-1, times ``*_spin_history`` (``chi_t`` prescribed; the
        reaction torque is in the run's ``reaction_torque``). Not at a pole.
    end1_axial_speed, end2_axial_speed : float
        Driven edge: its ``z`` moved at this speed, m s-1, times ``*_axial_speed_history``. Not at a pole.
    end1_dz, end2_dz, end1_dchi, end2_dchi : float
        Static edge displacements: the edge's imposed ``z`` (m) or ``chi`` (rad) moved this far from its reference
        value (the initial state; ``mol_shell.path`` continues in them: displacement control). The edge must
        impose the field.

    Notes
    -----
    Every load and drive is 0 (off) by default and then has no term in the graph. Histories: ``constant``,
    ``step T0``, ``ramp T1``, ``sine F`` or ``table t0:h0 t1:h1 ...`` (a factor on the load or rate).

    Values inside these ranges can still leave the discretised shell's numbers outside double
    precision (``h = 1e-300``: ``rho_J ~ h^3`` underflows; ``rho = 1e300``: the mass matrix's products
    overflow). A run refuses them when it starts, naming the parameter and the range over which the
    numbers are finite with the others as given (:mod:`mol_shell.runs.checks`, docs/reliability.md).
    """

    h: float = 2.0 * math.pi * 1e-3
    E: float = 1.0e6
    nu: float = 0.49
    rho: float = 1000.0
    n_quad: int = 4
    zeta1: float | None = None
    eta_lambda: float = 0.0
    eta_mu: float = 0.0
    material: str = "svk"
    material_parameters: str = ""
    c10: float = 1.5e5
    c01: float = 0.0
    fibre_E: float = 0.0
    fibre_angle: float = 0.0
    fibre_families: int = 1
    fibre_compression: bool = True
    law_limit: bool = True
    ellipticity_limit: bool = False
    h_profile: str = ""
    layers: str = ""
    end1: str | None = None
    end2: str | None = None
    pressure: float = 0.0
    pressure_history: str = "constant"
    gravity: float = 0.0
    gravity_history: str = "constant"
    drag: float = 0.0
    end1_force: float = 0.0
    end1_force_history: str = "constant"
    end2_force: float = 0.0
    end2_force_history: str = "constant"
    end1_torque: float = 0.0
    end1_torque_history: str = "constant"
    end2_torque: float = 0.0
    end2_torque_history: str = "constant"
    end1_spin: float = 0.0
    end1_spin_history: str = "constant"
    end2_spin: float = 0.0
    end2_spin_history: str = "constant"
    end1_axial_speed: float = 0.0
    end1_axial_speed_history: str = "constant"
    end2_axial_speed: float = 0.0
    end2_axial_speed_history: str = "constant"
    end1_dz: float = 0.0
    end2_dz: float = 0.0
    end1_dchi: float = 0.0
    end2_dchi: float = 0.0

    name = "shell"
    #: indices into ``mol_shell.model.FIELDS`` of the fields this scene moves
    fields = (0, 1, 2, 3, 4)
    #: parameters that only set the initial data (the equations do not depend on them)
    initial = ()
    #: initial data not present as parameters are zero
    gamma = omega = psi0 = 0.0

    def __new__(cls, *args, **kwargs):
        """An unknown keyword is refused as :func:`with_params` refuses it (Python's own TypeError said only that)."""
        names = _keywords(cls)  # None: an __init__ of a subclass's own that takes any keyword
        for name in (k for k in kwargs if names is not None and k not in names):
            raise UnknownParameterError("parameter", name, Choice(names), hint=f"for scene {cls.name}")
        return super().__new__(cls)

    def __post_init__(self):
        for f in dataclasses.fields(self):  # numpy scalars as Python's (np.float32 hashed equal to a float64), and
            value = getattr(self, f.name)  # "auto" as None where None (auto) is the default, as in scene files
            auto = f.default is None and isinstance(value, str) and value.strip().lower() in (
                ("auto",) if f.name in EDGE_PARAMETERS else ("auto", "none"))  # an edge's "none": refused
            object.__setattr__(self, f.name, None if auto else value.item() if isinstance(value, np.generic) else value)
        _check("h", self.h, Interval(0.0, math.inf, unit="m", shown="(0, inf) m, and the thickness off the axis"))
        _check("E", self.E, modulus("Pa"))
        tiny = f", 0 or at least {TINY!r} in magnitude" if subnormal(self.nu) else ""  # nu is 0 or normal, as E is
        if isinstance(self.material, str) and self.material in COMPRESSIBLE_WHY:  # their condensations hold there
            # (a material of the wrong type, unhashable, is refused by its own check below)
            _check("nu", self.nu, Interval(0.0, 0.5, low_closed=True, normal=True, shown=tiny and f"[0, 0.5){tiny}"),
                   hint="" if tiny else f"material = {self.material}: {COMPRESSIBLE_WHY[self.material]}")
        else:
            _check("nu", self.nu, Interval(-1.0, 0.5, normal=True, shown=tiny and f"(-1, 0.5){tiny}"))
        _check("rho", self.rho, modulus("kg/m^3"))
        lo, hi = N_QUAD_RANGE
        allowed = Interval(lo, hi, True, True, integer=True)
        if not isinstance(self.n_quad, numbers.Integral) or isinstance(self.n_quad, (bool, np.bool_)):
            raise ParameterError.not_a("n_quad", self.n_quad, "an integer", allowed)
        if not lo <= self.n_quad <= hi:
            raise ParameterError("n_quad", self.n_quad, allowed,
                                 hint="one point makes the director's inertia singular" if self.n_quad == 1 else
                                 "more points gain nothing and take minutes to compile" if self.n_quad > hi else "")
        object.__setattr__(self, "n_quad", int(self.n_quad))
        _check("eta_lambda", self.eta_lambda, modulus("Pa s", zero=True))
        _check("eta_mu", self.eta_mu, modulus("Pa s", zero=True))
        if self.material not in MATERIALS:  # a law of one's own: its name, kept in this process, or import path
            object.__setattr__(self, "material", resolve_material(self.material))
        self._check_material_parameters()
        _check("c10", self.c10, modulus("Pa"))
        _check("c01", self.c01, modulus("Pa", zero=True))
        self._check_fibres()
        self._check_layers()
        if self.zeta1 is not None:
            _check("zeta1", self.zeta1, Interval(-2 * self.h, 0.0, True, True, unit="m",
                                                 shown=f"[-2h, 0] = [{-2 * self.h:.4g}, 0] m, or auto"))
        for end in ("end1", "end2"):
            object.__setattr__(self, end, check_edge(end, getattr(self, end)))
        for name in DISPLACEMENTS:
            _check(name, getattr(self, name), finite(UNITS[name]))
        for load in LOADS + DRIVES:
            _check(load, getattr(self, load), non_negative(UNITS[load]) if load == "drag" else finite(UNITS[load]))
            if load != "drag":  # in one normal form: a file's inline table and the string typed are one history
                object.__setattr__(self, f"{load}_history", normal_history(f"{load}_history", getattr(
                    self, f"{load}_history"), rate=load in DRIVES))
        try:
            self._validate()
            self._check_displacements()
            self._check_thickness()
        except ParameterError as exc:
            raise self._blame(exc) from None

    def _check_material_parameters(self):
        """``material_parameters`` read (a dict becomes the string form) and checked against a law of one's own."""
        object.__setattr__(self, "material_parameters", checked_material_parameters(self))

    def _check_fibres(self):
        """``fibre_E >= 0``, ``fibre_angle`` in [-pi/2, pi/2], ``fibre_families`` 1 or 2, ``fibre_compression`` a bool."""
        _check("fibre_E", self.fibre_E, modulus("Pa", zero=True))
        _check("fibre_angle", self.fibre_angle, FIBRE_ANGLES, hint=fibre_angle_hint(self.fibre_angle))
        families = Interval(1, 2, True, True, integer=True, shown="{1, 2}")
        if not isinstance(self.fibre_families, numbers.Integral) or isinstance(self.fibre_families, (bool, np.bool_)):
            raise ParameterError.not_a("fibre_families", self.fibre_families, "an integer", families)
        if self.fibre_families not in families:
            raise ParameterError("fibre_families", self.fibre_families, families)
        object.__setattr__(self, "fibre_families", int(self.fibre_families))
        for name in ("fibre_compression", "law_limit", "ellipticity_limit"):
            self._check_flag(name)

    def _check_flag(self, name):
        """A true/false parameter: a bool, ``"true"``/``"false"`` (``--set``), or 0/1 (as a netCDF file stores it)."""
        value = getattr(self, name)
        flag = {"true": True, "false": False}.get(value, value) if isinstance(value, str) else value
        if isinstance(flag, numbers.Integral) and not isinstance(flag, (bool, np.bool_)) and flag in (0, 1):
            flag = bool(flag)
        if not isinstance(flag, (bool, np.bool_)):
            raise ParameterError(name, value, Flag())
        object.__setattr__(self, name, bool(flag))

    def _check_layers(self):
        """``layers`` read (a list becomes the string form), each layer's parameters checked as a scene's, their
        thicknesses adding up to the wall ``2h`` (with ``h_profile`` the nominal wall: each layer keeps its share)."""
        if isinstance(self.layers, (list, tuple)):  # a Material in a layer's dict: its registered name, as material
            object.__setattr__(self, "layers", [{**x, "material": resolve_material(x["material"])} if isinstance(
                x, dict) and "material" in x and not isinstance(x["material"], str) else x for x in self.layers])
        object.__setattr__(self, "layers", layers_text(self.layers))
        if not self.layers.strip():
            return
        parsed = parse_layers(self.layers)
        count = len(parsed)
        if count > MAX_LAYERS:  # before the layers' scenes are made: each is a scene checked in full
            allowed = Interval(1, MAX_LAYERS, True, True, integer=True, shown=f"1..{MAX_LAYERS} layers")
            raise ParameterError("layers", count, allowed, hint="each layer adds its Gauss points to every cell's "
                                 "compiled kernel", message=f"layers holds {count} layers; allowed: {allowed}")
        try:
            layers = layer_scenes(self)
        except ParameterError as exc:
            raise ParameterError("layers", self.layers, "layers whose parameters are in range",
                                 hint=str(exc)) from None
        check_layer_parameters(self)  # a material_parameters no layer's law has: named as it
        # stored as the layers' scenes took each key (fibre_compression=0 as false, fibre_families=2.0 as 2): the
        # run's file is read back by its stresses and by later runs
        words = [" ".join([f"{float(t)!r} {m}"] + [f"{k}={layer_word(getattr(scene, k))}" for k in changes])
                 for (t, m, changes), (_, scene) in zip(parsed, layers)]
        object.__setattr__(self, "layers", "; ".join(words))
        total = sum(t for t, _ in layers)  # to LAYERS_RTOL: the layers are then scaled to 2h (layered_thickness)
        if abs(total - 2 * self.h) > LAYERS_RTOL * 2 * self.h:
            raise ParameterError("layers", self.layers, f"thicknesses adding up to the wall, 2h = {2 * self.h:.10g} m, "
                                 f"to {LAYERS_RTOL:g} of it", hint=f"they add up to {total:.10g} m")

    def _check_displacements(self):
        """A static edge displacement only at an edge that holds its field (refused before anything is built)."""
        given = {name: getattr(self, name) for name in DISPLACEMENTS if getattr(self, name)}
        if given:
            edges = resolve_edges(self.end1, self.end2, self.meridian().poles)
            check_displacements(given, edges, getattr(self, "fields", range(5)))

    def _blame(self, exc):
        """A refusal of ``h`` caused by a changed geometry parameter (``a = 5e-324``) names that parameter."""
        if exc.name != "h" or self.h != type(self).h:
            return exc
        skip = set(LOADS + DRIVES + DISPLACEMENTS + WALL_LAW) | set(getattr(self, "initial", ())) | {"h", "zeta1",
                                                                                                  "end1", "end2"}
        for f in dataclasses.fields(self):
            if f.name not in skip and not f.name.endswith("_history") and getattr(self, f.name) != f.default:
                return ParameterError(f.name, getattr(self, f.name), f"values for which h = {self.h:.4g} m fits: "
                                      + str(exc))
        return exc

    def auto_values(self, initial, reference):
        """``{name: value}``: the initial-data parameters left to the code (``None``, "auto") as the run used them.

        ``initial`` and ``reference`` are the nodal ``(z, r)`` of the initial state and of the natural shell.
        """
        return {}

    def geometry_values(self):
        """``{name: value}``: the geometric parameters left to the code (``None``, "auto") as the meridian uses them."""
        return {}

    def stand_ins(self):
        """One line for each built-in stand-in the scene runs with in place of data a user is expected to give
        (the meridian scene without a file of points); the command line prints them as notes."""
        return []

    def at_equilibrium(self):
        """Whether the run starts from the static equilibrium under the loads at ``t = 0`` (``R``/``dilation`` auto)."""
        return False

    def loads_on(self):
        """The names of the loads that are on (not 0), in the order of :data:`LOADS`."""
        return [load for load in LOADS if getattr(self, load) != 0]

    @property
    def loaded(self):
        """Whether any load or drive is on (then the run accounts the work done on the shell and the energy dissipated)."""
        return any(getattr(self, load) != 0 for load in LOADS + DRIVES)

    def drives(self):
        """``{(end node 0 or 1, field 0 = z or 2 = chi): (rate, parsed history)}`` of the driven edges."""
        out = {}
        for end in (0, 1):
            for kind, field in (("axial_speed", 0), ("spin", 2)):
                name = f"end{end + 1}_{kind}"
                value = getattr(self, name)
                if value:
                    out[(end, field)] = (value, parse_history(name + "_history", getattr(self, name + "_history")))
        return out

    def load_histories(self):
        """``{load: parsed history}`` of the loads that are on."""
        return {load: parse_history(load + "_history", getattr(self, load + "_history", None)) if load != "drag"
                else ("constant", ()) for load in LOADS if getattr(self, load) != 0}

    def _validate(self):
        """Checks of the subclass's own parameters (geometry and initial data)."""

    def meridian(self):
        """The reference meridian (:mod:`mol_shell.model.geometry`)."""
        raise NotImplementedError

    def zeta1_used(self):
        """The lower face of the thickness interval as the model uses it (``zeta1``, or the centroidal placement)."""
        return base_offset(self.meridian(), self.h) if self.zeta1 is None else self.zeta1

    def _check_thickness(self):
        """The thickness interval stays off the axis and inside every centre of curvature (``det G0 > 0``;
        :func:`~mol_shell.model.wall_fit.check_wall_fits`)."""
        if not isinstance(self.h_profile, str) or self.h_profile:
            self._check_profile()
            return
        check_wall_fits(self.meridian(), self.zeta1_used(), self.h)  # exact: a 1 mm knuckle is not missed

    def _check_profile(self):
        """A graded wall: ``h_profile`` read, ``zeta1`` auto, every cell's ``[-h(s), h(s)]`` with ``det G0 > 0``."""
        if not isinstance(self.h_profile, str):
            raise ParameterError.not_a("h_profile", self.h_profile, "a string", "'table s0:h0 ...' or an expression of s")
        mer = self.meridian()
        h = thickness_function(self.h_profile, mer.length)
        if self.zeta1 is not None:
            raise ParameterError("zeta1", self.zeta1, "auto with h_profile (the mid-surface is the base surface)")
        check_profile_fits(self.h_profile, h, mer)

    def initial_fields(self, s, reference):
        """``(Q, V)``, each ``5 x n``: the fields and rates of the initial data at nodes ``s``.

        ``reference`` is the nodal ``(z0, r0, theta0)``. The default: the natural state at rest.
        """
        z0, r0, th0 = reference
        Q = np.array([z0, r0, np.zeros_like(s), th0, np.zeros_like(s)])
        return Q, np.zeros_like(Q)

    def params(self):
        """All parameters as a plain dict (``R`` and ``zeta1`` may be ``None``)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}


@functools.lru_cache(maxsize=None)
def _keywords(cls):
    """The keywords ``cls.__init__`` takes (the dataclass's fields, and a subclass's ``InitVar``), ``None`` for any."""
    parameters = list(inspect.signature(cls.__init__).parameters.values())[1:]
    return None if any(p.kind is p.VAR_KEYWORD for p in parameters) else tuple(p.name for p in parameters)


def refuse_loads(scene, what):
    """A ParameterError naming the first load or drive of ``scene`` if it has any: ``what`` takes none."""
    for name in LOADS + DRIVES + ("end_omega",):
        value = getattr(scene, name, 0.0)
        if value:
            raise ParameterError(name, value, "0", hint=f"{what} takes no loads or driven edges")
