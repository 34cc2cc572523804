"""Scenes: frozen dataclasses holding every physical parameter of a run.

Vary a scene with :func:`dataclasses.replace` (or :func:`with_params` from
strings, as the CLI does); a bad value raises :class:`~mol_shell.errors.ParameterError`
naming the parameter and its allowed range.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass

import numpy as np

from .errors import ParameterError, is_number
from .model.material import MATERIALS, centroidal_offset

UNITS = {
    "L": "m", "h": "m", "E": "Pa", "nu": "1", "rho": "kg m-3", "R": "m",
    "gamma": "rad m-1", "omega": "rad s-1", "psi0": "rad", "n_quad": "1", "zeta1": "m",
    "eta_lambda": "Pa s", "eta_mu": "Pa s", "material": "1", "dR": "m",
    # integrator options (varied in studies)
    "dt": "s", "rtol": "1", "atol": "1", "max_step": "s",
}
#: what each parameter is (long_name of a study's coordinates)
DESCRIPTIONS = {
    "L": "length of the shell", "h": "half-thickness", "E": "Young's modulus", "nu": "Poisson's ratio",
    "rho": "density", "R": "initial radius", "gamma": "initial twist chi_s", "omega": "initial spin rate chi_t",
    "psi0": "initial shear angle psi", "n_quad": "Gauss-Legendre points through the thickness",
    "zeta1": "lower face of the thickness interval from the base surface", "eta_lambda": "Kelvin-Voigt viscosity eta_lambda",
    "eta_mu": "Kelvin-Voigt viscosity eta_mu", "material": "material law", "dR": "amplitude of the initial radius variation",
    "dt": "leap-frog time step", "rtol": "relative tolerance", "atol": "absolute tolerance (m or rad per field)",
    "max_step": "largest step of the adaptive integrator",
}


#: Gauss-Legendre points through the thickness: one point makes the director's inertia rhoJ = rhoI^2/rhoA,
#: a singular mass matrix. Above 32 nothing is gained and the kernels grow too large to compile in
#: reasonable time: with the base surface centroidal, 12-16 points integrate What to round-off for every
#: h < 0.5 m (32 with the inner face at r = 0.1 m); at n = 40 the exact Jacobian of cvode-bdf compiled in
#: 3.8, 13, 54, 108 and 767 s at 4, 8, 16, 32, 64 points (docs/reliability.md)
N_QUAD_RANGE = (2, 32)


def _check(name, value, ok, allowed):
    if not is_number(value):
        raise ParameterError.not_a(name, value, "a number", allowed)
    if not (math.isfinite(value) and ok(value)):
        raise ParameterError(name, value, allowed)


def zeta1_used(h, zeta1=None):
    """The lower face of the thickness interval as the model uses it (``zeta1``, or the centroidal offset)."""
    return centroidal_offset(h) if zeta1 is None else zeta1


def check_radius(R, h, zeta1=None, hint=""):
    """``R > -zeta1_used``: the inner face ``r + zeta1`` of the initial cylinder at a positive radius."""
    low = -zeta1_used(h, zeta1)
    _check("R", R, lambda v: v > low,
           f"({low:.4g}, inf) m: the inner face r + zeta1 must be at a positive radius (zeta1 = {-low:.4g} m)"
           + (f"; {hint}" if hint else ""))


@dataclass(frozen=True)
class ShellScene:
    """Parameters shared by every scene: a cylinder of natural radius 1 m (section 6).

    Parameters
    ----------
    L : float
        Length, m (paper: 4).
    h : float
        Half-thickness, m (paper: 2 pi 1e-3).
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio (paper: 1e6 Pa = 1e-3 GPa, 0.49).
    rho : float
        Density, kg/m^3. Lost from the paper; 1000 is our assumption (it only rescales time).
    R : float or None
        Initial radius, m, above ``-zeta1`` (the inner face at a positive radius). ``None`` (or
        ``"auto"``) computes the radius at which the uniformly twisted cylinder is in radial
        equilibrium (:func:`mol_shell.equilibrium.equilibrium_radius`).
    n_quad : int
        Gauss-Legendre points through the thickness, 2..32 (beyond, nothing is gained and the kernels take
        minutes to compile).
    zeta1 : float or None
        Lower face of the thickness interval, measured from the base surface along the
        director. ``None`` places the base surface so that ``rhoI = 0`` (as the paper).
    eta_lambda, eta_mu : float
        Kelvin-Voigt viscosities, Pa s (``S_visc = eta_lambda tr(E_t) I + 2 eta_mu E_t``);
        0 (default) is the elastic shell, and leaves the viscous terms out of the graph.
    material : str
        ``"svk"`` (the paper: 3-D St Venant-Kirchhoff with the inextensible director) or
        ``"svk-plane-stress"`` (thickness stress condensed out; see
        :func:`mol_shell.model.material.effective_lame`).

    Notes
    -----
    Values inside these ranges can still leave the discretised shell's numbers outside double
    precision (``h = 1e-300``: ``rho_J ~ h^3`` underflows; ``rho = 1e300``: the mass matrix's products
    overflow). A run refuses them when it starts, naming the parameter and the range over which the
    numbers are finite with the others as given (:mod:`mol_shell.degenerate`, docs/reliability.md).
    """

    L: float = 4.0
    h: float = 2.0 * math.pi * 1e-3
    E: float = 1.0e6
    nu: float = 0.49
    rho: float = 1000.0
    R: float | None = None
    n_quad: int = 4
    zeta1: float | None = None
    eta_lambda: float = 0.0
    eta_mu: float = 0.0
    material: str = "svk"

    name = "shell"
    #: indices into ``mol_shell.model.FIELDS`` of the fields this scene moves
    fields = (0, 1, 2, 3, 4)
    #: initial data not present as parameters are zero
    gamma = omega = psi0 = 0.0

    def __post_init__(self):
        _check("L", self.L, lambda v: v > 0, "(0, inf) m")
        _check("h", self.h, lambda v: 0 < v < 0.5, "(0, 0.5) m: 2h must be below the natural radius 1 m")
        _check("E", self.E, lambda v: v > 0, "(0, inf) Pa")
        _check("nu", self.nu, lambda v: -1 < v < 0.5, "(-1, 0.5)")
        _check("rho", self.rho, lambda v: v > 0, "(0, inf) kg/m^3")
        lo, hi = N_QUAD_RANGE
        allowed = f"integers {lo}..{hi}"
        if not isinstance(self.n_quad, numbers.Integral) or isinstance(self.n_quad, (bool, np.bool_)):
            raise ParameterError.not_a("n_quad", self.n_quad, "an integer", allowed)
        if not lo <= self.n_quad <= hi:
            raise ParameterError("n_quad", self.n_quad, allowed,
                                 hint="one point makes the director's inertia singular" if self.n_quad == 1 else
                                 "more points gain nothing and take minutes to compile" if self.n_quad > hi else "")
        object.__setattr__(self, "n_quad", int(self.n_quad))
        _check("eta_lambda", self.eta_lambda, lambda v: v >= 0, "[0, inf) Pa s")
        _check("eta_mu", self.eta_mu, lambda v: v >= 0, "[0, inf) Pa s")
        if self.material not in MATERIALS:
            raise ParameterError("material", self.material, "{" + ", ".join(MATERIALS) + "}")
        if self.zeta1 is not None:
            _check("zeta1", self.zeta1, lambda v: -2 * self.h <= v <= 0, f"[-2h, 0] = [{-2 * self.h:.4g}, 0] m")
        if isinstance(self.R, str) and self.R.strip().lower() in ("auto", "none"):
            object.__setattr__(self, "R", None)  # as from the command line: computed
        if self.R is not None:
            check_radius(self.R, self.h, self.zeta1)

    def params(self):
        """All parameters as a plain dict (``R`` and ``zeta1`` may be ``None``)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}


@dataclass(frozen=True)
class TwistedCylinder(ShellScene):
    """The initial-boundary-value problem of section 6 (and, with ``gamma = 0``, section 5).

    Ends welded to lubricated magnets a fixed distance ``L`` apart (``z = s``,
    ``theta = 0``, ``n.a2 = n.a3 = m.c1 = 0``). Initial data (6.9), extended: ``r = R``,
    ``z = s``, ``chi = gamma (s - L/2)``, ``theta = 0``, ``psi = psi0``, ``chi_t = omega``,
    the other rates zero. See :class:`ShellScene` for the material parameters.

    Parameters
    ----------
    gamma : float
        Initial twist ``chi_s``, rad/m (paper value lost; 0.1 fits its figures).
    omega : float
        Initial uniform spin rate ``chi_t``, rad/s.
    psi0 : float
        Initial uniform shear angle ``psi``, rad, in (-pi/2, pi/2).
    """

    gamma: float = 0.1
    omega: float = 0.0
    psi0: float = 0.0

    name = "twisted-cylinder"

    def __post_init__(self):
        super().__post_init__()
        _check("gamma", self.gamma, lambda v: True, "finite values (rad/m)")
        _check("omega", self.omega, lambda v: True, "finite values (rad/s)")
        _check("psi0", self.psi0, lambda v: abs(v) < math.pi / 2, "(-pi/2, pi/2) rad")


@dataclass(frozen=True)
class SpinningRing(TwistedCylinder):
    """Section 5: spatially uniform breathing, spinning and shearing (``gamma = 0``).

    The same boundary-value problem as :class:`TwistedCylinder` with uniform initial data
    ``r = R``, ``chi_t = omega``, ``psi = psi0``; the motion stays uniform in ``s`` and
    follows the ODEs of section 5.
    """

    R: float | None = 1.01
    gamma: float = 0.0
    omega: float = 20.0
    psi0: float = 0.05

    name = "spinning-ring"


@dataclass(frozen=True)
class Axisymmetric(ShellScene):
    """Axisymmetric motions: no twist and no shear (``chi = psi = 0`` identically).

    Only ``z, r, theta`` are unknowns; the graph holds nothing of ``chi`` and ``psi``.
    Initial data: ``r = R`` (default 1.01 m, a breathing cylinder), ``z = s``, at rest.
    """

    R: float | None = 1.01

    name = "axisymmetric"
    fields = (0, 1, 3)


SCENES = {cls.name: cls for cls in (TwistedCylinder, SpinningRing, Axisymmetric)}


def get_scene(name, **params):
    """The scene registered as ``name`` with parameters replaced by ``params``."""
    if name not in SCENES:
        raise ParameterError("scene", name, "{" + ", ".join(sorted(SCENES)) + "}")
    return with_params(SCENES[name](), params)


def with_params(scene, params):
    """``dataclasses.replace`` that accepts strings (as from ``--set NAME=VALUE``) and names unknown parameters."""
    fields = {f.name: f for f in dataclasses.fields(scene)}
    changes = {}
    for name, value in params.items():
        if name not in fields:
            raise ParameterError("parameter", name, "{" + ", ".join(fields) + "}", hint=f"for scene {scene.name}")
        changes[name] = _coerce(name, value, fields[name].type)
    return dataclasses.replace(scene, **changes)


def _coerce(name, value, annotation):
    """A string from the command line as the field wants it; what does not convert is passed on unchanged,
    so the scene's own check names the parameter and its allowed range."""
    if not isinstance(value, str) or annotation in (str, "str"):
        return value
    text = value.strip()
    if text.lower() in ("none", "auto") and "None" in str(annotation):
        return None
    try:
        number = float(text)
    except ValueError:
        return value
    if "int" in str(annotation) and number.is_integer():
        return int(number)
    return number
