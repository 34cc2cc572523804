"""Stresses of a run, computed after it from the constitutive law (section 7), not in the right-hand side.

For every cell and saved time the cell's samples (strains ``(q_{i+1} - q_i)/ds``, ``r`` and
``theta`` at the midpoint, ``psi`` at each of the two nodes: the samples the discrete energy
uses) give the deformation gradient ``F`` of :func:`~mol_shell.model.kinematics.deformation_gradient`
through the thickness, the second Piola-Kirchhoff stress ``S = lambda tr(E) I + 2 mu E`` (7.9),
the first Piola-Kirchhoff stress ``T = F S`` and the Cauchy stress ``sigma = F S F^T / det F`` (at the faces, ``F``
with the law's thickness stretch: below).
The reference data per cell come from the same difference formulas applied to the nodal
reference meridian (``r0, z0, theta0``; the cylinder ``r0 = 1, z0 = s, theta0 = 0`` when the
run does not carry one). One CasADi kernel per sample, compiled with gcc (cached on disk),
is mapped over all samples; principal values come from NumPy.

Resultants (eqs. 7.5-7.7). With ``c = r0 + zeta cos theta0`` and ``a = beta1_0 - zeta theta0_s``
(the reference widths of the ``s``- and ``phi``-sections per ``dzeta``), ``e1, e3`` the
reference tangent ``b0_1`` and hoop direction ``b0_3``:

    r0 n^s = int T e1 c dzeta,   r0 m^s = d x int zeta T e1 c dzeta,
    n^phi  = int T e3 a dzeta,   m^phi  = d x int zeta T e3 a dzeta.

``n^s, m^s`` are the force and couple per unit reference length of the parallel circle that the
part at larger ``s`` exerts on the part at smaller ``s``; ``n^phi, m^phi`` those across a
meridional section per unit ``s``. Components are taken in the director frame
``c1 = b1`` (the deformed generator's tangent), ``c2 = d`` (the director), ``c3 = c1 x d``:

=============================  =====================================  =========
name                           component                              units
=============================  =====================================  =========
``axial_force``                ``2 pi r0 n^s . k``                    N
``axial_torque``               ``2 pi r0 (r n^s . a3 + m^s . k)``     N m
``membrane_force_meridional``  ``n^s . c1``                           N m-1
``membrane_shear_force``       ``n^s . c3``                           N m-1
``transverse_shear_force``     ``n^s . d``                            N m-1
``membrane_force_hoop``        ``n^phi . c3``                         N m-1
``bending_moment_meridional``  ``m^s . c3``                           N
``twisting_moment``            ``m^s . c1``                           N
``bending_moment_hoop``        ``m^phi . c1``                         N
=============================  =====================================  =========

``axial_force`` and ``axial_torque`` are ``d(2 pi r0 What)/dz_s`` and ``d(2 pi r0 What)/dchi_s``
(the flux of axial momentum and of axial angular momentum; MODEL_NOTES, last section): an axial
force is positive in tension. A cell's value is the mean over its two samples, as its energy.
Signs of the moments: ``m^s . c3 = -(1/r0) int zeta (T e1 . c1) c dzeta`` is negative and
``m^phi . c1 = int zeta (T e3 . c3) a dzeta`` positive when the fibres at ``zeta > 0`` (outside,
on the cylinder) are pulled harder than those at ``zeta < 0``.

Face stresses: the Cauchy stress at ``zeta1`` (inner face) and ``zeta1 + 2h`` (outer face),
averaged over the cell's two samples, then its principal values and von Mises stress. A graded wall
(``h_profile``) has each cell's own faces ``-h(s), +h(s)`` about the mid-surface: ``zeta`` is then the face in
units of ``h(s)`` and ``zeta_face`` the depths. With
``material = "svk-plane-stress"`` the stress ``S22`` along the director is 0 (the condensation), and the faces'
Cauchy stress takes ``F`` with its director column times the 3-D law's thickness stretch ``sqrt(C_22)``
(:func:`~mol_shell.model.material.plane_stress_thickness`; ``det F = lambda1 lambda2 lambda3``), as the other laws'
(:mod:`mol_shell.results.law_stresses`); ``svk``'s is 1.
The stress normal to the wall is each thickness treatment's: 0 in plane stress (``svk-plane-stress`` and the
plane-stress laws: the condensation) and for an incompressible law (its pressure is the reaction that makes
``S_22 = 0``); where the director is held (``svk``, a law or layer with ``thickness = "director"``) ``S_22`` is the
constraint's reaction, and the face takes the one that makes its normal stress the face's traction
(:mod:`mol_shell.results.face_tractions`: ``-p`` on the face the pressure acts on, 0 on a free face), not the law's
``lambda tr E`` (:func:`~mol_shell.results.stress_samples.held_thickness_stress`); the in-plane stresses are the law's.
With Kelvin-Voigt viscosity the stresses include ``S_visc = eta_lambda tr(E_t) I + 2 eta_mu E_t``
(the pair condensed as the material's elastic one, :func:`~mol_shell.model.material.condensed`; an incompressible
law's ``S_visc`` is the derivative of its Rayleigh function ``eta_mu E_t : E_t`` with the thickness rate that
``det C = 1`` sets, :func:`~mol_shell.model.hyperelastic.incompressible_viscous_stress`, ``S_visc,22 = 0``)
and the viscous part is also given alone (``*_viscous``).
"""

from __future__ import annotations

import functools
import hashlib
import math
import numbers
import re
import warnings

import casadi as ca
import numpy as np
import xarray as xr

from mol_shell._core.errors import ParameterError, SceneWarning, flag
from mol_shell._core.ranges import Choice, Interval
from mol_shell.discretization.compiled import CompiledFunctions
from mol_shell.model.kinematics import FIELDS
from mol_shell.model.laws import LAWS, ON_REDEFINED, thickness_treatment
from mol_shell.model.material import MATERIALS as SVK_MATERIALS
from mol_shell.model.material import condensed, lame
from mol_shell.model.thickness_profile import thickness_function
from mol_shell.results.cf import coordinates, variables
from mol_shell.results.constraint_stresses import CONSTRAINT_COMMENT, constraint_torque
from mol_shell.results.dataset import holdings
from mol_shell.results.face_tractions import face_parameters, face_tractions
from mol_shell.results.law_stresses import law_of_attrs, route_law, route_stress, unloadable_law
from mol_shell.results.stress_samples import cell_samples, reference_cells, sample_stresses
from mol_shell.results.tensors import principal_stresses, von_mises

#: default limit on cell samples x saved times (2 per cell) above which stresses are skipped unless asked for:
#: 4e6 samples cost 7 s (11 s viscous) and 270 MB on this machine (measured at n = 401, 5,000 saved times)
MAX_SAMPLES = 4_000_000
#: samples per call of the mapped kernel
CHUNK = 20_000

RESULTANT_META = {
    "axial_force": ("N", "axial force through the section at s (2 pi r0 n^s.k; positive in tension)"),
    "axial_torque": ("N m", "axial torque through the section at s (2 pi r0 (r n^s.a3 + m^s.k))"),
    "membrane_force_meridional": ("N m-1", "meridional membrane force per unit length (n^s.c1)"),
    "membrane_shear_force": ("N m-1", "in-surface shear force per unit length on the section at s (n^s.c3)"),
    "transverse_shear_force": ("N m-1", "transverse shear force per unit length (n^s.d, along the director)"),
    "membrane_force_hoop": ("N m-1", "hoop membrane force per unit length of s (n^phi.c3)"),
    "bending_moment_meridional": ("N", "meridional bending moment per unit length (m^s.c3)"),
    "twisting_moment": ("N", "twisting moment per unit length on the section at s (m^s.c1)"),
    "bending_moment_hoop": ("N", "hoop bending moment per unit length of s (m^phi.c1)"),
}
RESULTANTS = tuple(RESULTANT_META)
FACE_META = {
    "principal_stress_max": ("Pa", "largest principal Cauchy stress"),
    "principal_stress_mid": ("Pa", "middle principal Cauchy stress"),
    "principal_stress_min": ("Pa", "smallest principal Cauchy stress"),
    "von_mises_stress": ("Pa", "von Mises equivalent Cauchy stress"),
}
#: how ``attrs["stresses"]`` begins to say that some stresses are NaN (the views allow NaN there: ``check_run``)
STRESS_NAN = "NaN where"
#: face names in the order of the ``zeta`` coordinate
FACES = ("inner", "outer")


# -- the kernel and its evaluation over a run -------------------------------------------------------
#: kernel inputs after the sample's strains, rates and reference data
PARAMETERS = ("zeta1", "h", "lam", "mu", "eta_lambda", "eta_mu", "plane_stress", "traction_inner", "traction_outer")


def route_elastic(route, zeta1, h=None):
    """``(elastic, layers, plane)`` of :func:`sample_stresses` for a route of
    :func:`~mol_shell.results.law_stresses.law_of_attrs` (a layered wall: each layer on its interval from ``zeta1``;
    with ``h``, a graded wall's half-thickness at the sample, each layer keeps its share of the nominal wall)."""
    if route[0] != "layers":
        return route_stress(route), None, float(route[3] or route_law(route).thickness != "director")
    scale = 1.0 if h is None else 2 * h / sum(t for t, _ in route[1])
    bounds = [zeta1 + scale * sum(t for t, _ in route[1][:k]) for k in range(len(route[1]) + 1)]
    return None, [(lo, hi, route_stress(sub)) for lo, hi, (_, sub) in zip(bounds[:-1], bounds[1:], route[1])], \
        float(route[2])


@functools.lru_cache(maxsize=8)
def kernel(n_quad, viscous=False, route=None, graded=False):
    """``(e[8], e_t[8], ref[5], params[9]) -> (resultants[9], sigma[12])``, with ``viscous`` also
    ``(resultants_viscous[9], sigma_viscous[12])`` (SX).

    ``sigma`` holds the six components ``11, 22, 33, 12, 23, 13`` at ``zeta1`` then at ``zeta1 + 2h``.
    Material data are inputs (:data:`PARAMETERS`), so one compiled kernel serves every run with
    ``n_quad`` points; the elastic kernel ignores ``e_t`` and the viscosities. ``route``
    (:func:`~mol_shell.results.law_stresses.law_of_attrs`): another law or fibres, whose stress is in the graph
    (``lam, mu, plane_stress`` inputs unused; the viscous stress condensed unless under the director constraint, an
    incompressible law's from ``det C = 1`` with ``eta_mu`` alone, a layered wall's condensed as the scene's
    material asks). ``graded``: a layered wall's layers scaled to the sample's ``h`` (:func:`route_elastic`).
    """
    e, et, ref, par = ca.SX.sym("e", 8), ca.SX.sym("et", 8), ca.SX.sym("ref", 5), ca.SX.sym("par", len(PARAMETERS))
    zeta1, h, lam, mu, eta_l, eta_m, plane, t_inner, t_outer = ca.vertsplit(par)
    elastic, layers, name = None, None, f"ms_stress_q{n_quad}"
    incompressible = route is not None and route[0] != "layers" and route_law(route).thickness == "incompressible"
    if route is not None:
        graded = graded and route[0] == "layers"
        elastic, layers, plane = route_elastic(route, zeta1, h if graded else None)
        digest = hashlib.sha256(repr(route).encode()).hexdigest()[:12]  # stable across processes: the C cache
        name = f"ms_stress_{re.sub(r'[^A-Za-z0-9]', '_', route[0])}_{digest}_q{n_quad}" + ("_graded" if graded else "")
    out = sample_stresses(ca.vertsplit(e), ca.vertsplit(et) if viscous else None, ca.vertsplit(ref), zeta1, h, n_quad,
                          lam, mu, eta_l, eta_m, plane, elastic=elastic, layers=layers, incompressible=incompressible,
                          tractions=(t_inner, t_outer))
    pairs = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))
    outputs, names = [], []
    for kind in ("elastic", "viscous") if viscous else ("elastic",):
        outputs += [ca.vertcat(*out[kind].values()), ca.vertcat(*[f[i][j] for f in out["sigma_" + kind] for i, j in pairs])]
        names += ["resultants_" + kind, "sigma_" + kind]
    name += "_viscous" if viscous else ""
    return ca.Function(name, [e, et, ref, par], outputs, ["e", "e_t", "ref", "par"], names)


@functools.lru_cache(maxsize=8)
def compiled_kernel(n_quad, viscous=False, route=None, graded=False):
    """:func:`kernel` as generated C (gcc, cached on disk; one build per ``n_quad``, ``viscous`` and law); without gcc
    on PATH, in CasADi's virtual machine (a run's stresses are not lost for want of a compiler)."""
    f = kernel(n_quad, viscous, route, graded)
    return CompiledFunctions([f], vm_without_gcc=True).functions[f.name()]


class Evaluator:
    """The kernel mapped over ``size`` samples, called through a CasADi buffer (no ``DM`` conversions,
    which cost 4x the evaluation).

    ``evaluator(e, et, ref, par)`` with ``e, et`` ``(M, 8)``, ``ref`` ``(M, 5)`` (``M <= size``),
    ``par`` ``(9,)`` or ``(M, 9)`` returns the kernel's outputs as arrays ``(M, 9), (M, 12)`` (twice with
    ``viscous``): views into the buffer, overwritten by the next call.
    """

    def __init__(self, n_quad, viscous=False, size=CHUNK, compiled=True, route=None, graded=False):
        f = compiled_kernel(n_quad, viscous, route, graded) if compiled else kernel(n_quad, viscous, route, graded)
        self.size = size
        self._buf, self._trigger = f.map(size).buffer()
        self._ins = [np.zeros((size, f.nnz_in(i))) for i in range(4)]
        self._outs = [np.zeros((size, f.nnz_out(i))) for i in range(f.n_out())]
        for i, x in enumerate(self._ins):
            self._buf.set_arg(i, memoryview(x))
        for i, x in enumerate(self._outs):
            self._buf.set_res(i, memoryview(x))

    def __call__(self, e, et, ref, par):
        M = e.shape[0]
        for x, source in zip(self._ins, (e, et, ref, np.broadcast_to(par, (M, len(PARAMETERS))))):
            x[:M] = source
            x[M:] = source[M - 1]  # padding: a valid sample, discarded
        self._trigger()
        return [x[:M] for x in self._outs]


def _material(attrs):
    """Condensed Lame constants, viscosities, the plane-stress flag and the stress route
    (:func:`~mol_shell.results.law_stresses.law_of_attrs`) from a run's attrs."""
    material = str(attrs.get("material", "svk"))
    route = law_of_attrs(attrs)
    if route is not None and route[0] == "layers" and any(sub[1] is None for _, sub in route[1]):
        raise ParameterError("layers", attrs["layers"], "layers of the built-in laws",
                             hint="stresses and resultants are computed for the built-in laws")
    if route is not None and route[0] != "layers" and route[1] is None:  # a material this version does not know: refuse rather than guess
        reason = unloadable_law(attrs)
        if reason:  # a law of one's own whose module this process cannot import: say why
            raise ParameterError("material", material, "a law this process can load (its module importable here)",
                                 message=f"material = {material!r} cannot be loaded in this process, and the stresses "
                                 f"need its energy: {reason}")
        raise ParameterError("material", material, Choice(tuple(SVK_MATERIALS) + tuple(LAWS)),
                             hint="stresses and resultants are computed for the built-in laws and laws of one's own")
    if route is not None and route[0] == "layers":  # the viscosities condensed as the run's (the scene's material)
        how = "svk" if thickness_treatment(material) == "director" else "svk-plane-stress"
    else:
        how = material if route is None else ("svk" if route_law(route).thickness == "director" and not route[3]
                                              else "svk-plane-stress")
    lam, mu = condensed(*lame(float(attrs["E"]), float(attrs["nu"])), how)
    eta_lambda, eta_mu = condensed(float(attrs.get("eta_lambda", 0.0)), float(attrs.get("eta_mu", 0.0)), how)
    return lam, mu, eta_lambda, eta_mu, how == "svk-plane-stress", route


def graded_half_thickness(ds):
    """A graded wall's half-thickness at the cell centres (``h_profile`` of the run's attrs, as the run's cells
    took it), or ``None`` for a uniform wall."""
    profile = str(ds.attrs.get("h_profile", "") or "")
    if profile in ("", "none"):
        return None
    s = ds["s"].values
    return np.asarray(thickness_function(profile, float(s[-1] - s[0]))((s[1:] + s[:-1]) / 2), dtype=float)


def _nodal(ds, name):
    """A reference coordinate on the nodes if the run carries it (``r0``, ``z0``, ``theta0``), else None."""
    if name in ds and ds[name].dims == ("s",):
        return ds[name].values
    return None


def _face_values(sigma):
    """Principal and von Mises stresses from the six components at the two faces, ``(12, ...)``."""
    tensor = np.empty((*sigma.shape[1:], 2, 3, 3))
    for face in range(2):
        for c, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
            tensor[..., face, i, j] = tensor[..., face, j, i] = sigma[6 * face + c]
    bad = ~np.isfinite(tensor).all(axis=(-2, -1))  # det F = 0 at a face: left NaN (and said in attrs)
    tensor[bad] = 0.0
    principal, mises = principal_stresses(tensor), von_mises(tensor)
    principal[bad], mises[bad] = np.nan, np.nan
    return {"principal_stress_max": principal[..., 0], "principal_stress_mid": principal[..., 1],
            "principal_stress_min": principal[..., 2], "von_mises_stress": mises}


def _block(outs, viscous):
    """Variables of a block of saved times from the kernel's outputs (each ``(component, time, cells)``)."""
    parts = [("", outs[0] + outs[2], outs[1] + outs[3]), ("_viscous", outs[2], outs[3])] if viscous else \
        [("", outs[0], outs[1])]  # a viscous run: the totals, then the viscous part alone
    values = {}
    for suffix, resultants, sigma in parts:
        values.update({name + suffix: resultants[k] for k, name in enumerate(RESULTANTS)})
        values.update({name + suffix: v for name, v in _face_values(sigma).items()})
    return values


def _check_limit(limit):
    """``limit`` of :func:`add_stresses`: ``None`` or an integer >= 1 (``4e6`` too), else a ParameterError naming it."""
    allowed = Interval(1, math.inf, low_closed=True, integer=True, shown="integers >= 1, or None (no limit)")
    if limit is None:
        return
    if isinstance(limit, (bool, np.bool_)) or not isinstance(limit, numbers.Real):
        raise ParameterError.not_a("limit", limit, "an integer", allowed)
    if limit not in allowed:
        raise ParameterError("limit", limit, allowed)


def add_stresses(ds, *, limit=MAX_SAMPLES, compiled=True):
    """The run ``ds`` with its resultants and face stresses (a new Dataset; ``ds`` is not changed).

    Adds on ``(time, s_cell)`` the resultants of the module's table and on ``(time, s_cell, zeta)``
    the principal Cauchy stresses and the von Mises stress at the faces ``zeta1`` (``inner``) and
    ``zeta1 + 2h`` (``outer``): the Cauchy stress of the cell's two samples averaged, then its
    principal values. For a viscous run every variable includes the Kelvin-Voigt stress and its
    viscous part is added as ``NAME_viscous``. ``mol-shell run`` calls this (``--no-stresses`` to
    skip), and so does :func:`~mol_shell.runs.simulate.simulate` after a run: ``stresses=None`` (its default)
    with the default ``limit``, ``True`` with ``limit=None``, ``False`` not at all.

    Parameters
    ----------
    ds : xarray.Dataset
        A run (fields and rates on ``(time, s)``, the scene's parameters in attrs).
    limit : int or None
        Skip (and say so in ``attrs["stresses"]``) when cell samples x saved times exceed it
        (two samples per cell): an integer >= 1 (default :data:`MAX_SAMPLES`); ``None``: no limit. About 2 us per sample (3 with viscosity) and
        136 bytes per cell and saved time (224 with viscosity).
    compiled : bool
        Evaluate generated C (built once per ``n_quad`` and cached); False: CasADi's virtual machine.

    Returns
    -------
    xarray.Dataset
    """
    _check_limit(limit)
    compiled = flag("compiled", compiled)  # "no" was taken as True
    if not isinstance(ds, xr.Dataset):  # a file name: read_netcdf first
        raise ParameterError.not_a("ds", ds, "an xarray.Dataset",
                                   "a Dataset from simulate or mol-shell run (mol_shell.read_netcdf(PATH) reads a file)")
    _refuse_study(ds)
    needed = [*FIELDS, *(f + "_t" for f in FIELDS)]
    missing = [v for v in needed if v not in ds or ds[v].dims != ("time", "s")]
    if missing or not all(k in ds.attrs for k in ("E", "nu", "h", "zeta1_used", "n_quad")):
        raise ParameterError.invalid("ds", "Dataset", "is not a mol_shell run", "a Dataset from simulate or mol-shell run",
                                     hint="missing " + ", ".join(missing or ["attrs E, nu, h, zeta1_used, n_quad"]))
    n_t, n = ds.sizes["time"], ds.sizes["s"]
    _refuse_gaps(ds)
    ds = _without_stale_stresses(ds)
    samples = 2 * (n - 1) * n_t
    material = str(ds.attrs.get("material", "svk"))
    route = law_of_attrs(ds.attrs) if limit is not None else None
    if route is not None and route[1] is None:  # a law this process cannot load, or that this version does not know
        out = ds.copy()
        reason = unloadable_law(ds.attrs)
        why = (f"material = {material} cannot be loaded in this process ({reason})" if reason else
               f"not computed for material = {material} (neither a built-in law nor a mol_shell.Material made in "
               "this process)")
        out.attrs["stresses"] = f"skipped: {why}"
        warnings.warn(f"stresses not computed: {why}", SceneWarning, stacklevel=2)
        return out
    if limit is not None and samples > limit:
        out = ds.copy()
        out.attrs["stresses"] = (f"skipped: {samples:.3g} cell samples x saved times exceed the limit {limit:.3g}; "
                                 "call mol_shell.add_stresses(ds, limit=None)")
        return out
    ref = reference_cells(ds["s"].values, _nodal(ds, "r0"), _nodal(ds, "z0"), _nodal(ds, "theta0"))
    lam, mu, eta_lambda, eta_mu, plane, route = _material(ds.attrs)
    zeta1, h, n_quad = float(ds.attrs["zeta1_used"]), float(ds.attrs["h"]), int(ds.attrs["n_quad"])
    par = np.array([zeta1, h, lam, mu, eta_lambda, eta_mu, float(plane), 0.0, 0.0])
    s = ds["s"].values
    half = graded_half_thickness(ds)  # a graded wall: each cell's own [-h, h] about the mid-surface, as the run's
    if half is not None:
        par = np.tile(par, (n - 1, 2, 1))
        par[:, :, 0], par[:, :, 1] = -half[:, None], half[:, None]
        par = par.reshape(-1, len(PARAMETERS))
    viscous = eta_lambda > 0 or eta_mu > 0
    tractions = face_tractions(ds)
    ref_cells = np.stack([ref[k] for k in ("r0", "theta0", "theta0_s", "beta1_0", "beta2_0")], axis=-1)  # (cells, 5)
    per_time = 2 * (n - 1)
    block_t = max(1, CHUNK // per_time)
    run = Evaluator(n_quad, viscous, block_t * per_time if n_t > block_t else n_t * per_time, compiled, route,
                    half is not None)
    data = {}
    for t0 in range(0, n_t, block_t):
        t1 = min(t0 + block_t, n_t)
        Q = np.stack([ds[f].values[t0:t1] for f in FIELDS], axis=1)  # (times, 5, s)
        V = np.stack([ds[f + "_t"].values[t0:t1] for f in FIELDS], axis=1)
        e, et = (np.moveaxis(cell_samples(x, ref["ds"]), 1, -1).reshape(-1, 8) for x in (Q, V))
        refs = np.broadcast_to(ref_cells[None, :, None, :], (t1 - t0, n - 1, 2, 5)).reshape(-1, 5)
        pars = face_parameters(par, tractions[t0:t1], n)
        outs = [np.moveaxis(x.reshape(t1 - t0, n - 1, 2, -1).mean(axis=2), -1, 0) for x in run(e, et, refs, pars)]
        for name, value in _block(outs, viscous).items():
            if name not in data:
                data[name] = np.empty((n_t, *value.shape[1:]))
            data[name][t0:t1] = value
    constraint = constraint_torque(ds)  # a constrained unshearable run: chi_s = 0 carries the torque (its module)
    if constraint is not None:
        data["axial_torque"] = data["axial_torque"] + constraint
    coords = {
        "s_cell": ("s_cell", (s[1:] + s[:-1]) / 2,
                   {"units": "m", "long_name": "arc length of the reference generator at the cell centres"}),
        "zeta": ("zeta", np.array([zeta1, zeta1 + 2 * h]), {
            "units": "m", "long_name": "thickness coordinate of the faces along the reference director from the base "
            "surface: zeta1 (inner face) and zeta1 + 2h (outer face)"}),
    }
    if half is not None:  # the faces move with h(s): the dimension in units of h, the depths beside it
        coords["zeta"] = ("zeta", np.array([-1.0, 1.0]), {
            "units": "1", "long_name": "face of the graded wall in units of the local half-thickness h(s): -1 inner "
            "face, +1 outer face (depths in zeta_face)"})
        coords["zeta_face"] = (("s_cell", "zeta"), np.stack([-half, half], axis=-1), {
            "units": "m", "long_name": "thickness coordinate of the faces from the mid-surface (the base surface of a "
            "graded wall): -h(s) inner, +h(s) outer"})
    entries = {}
    for name, value in data.items():
        base = name.removesuffix("_viscous")
        units, long_name = (RESULTANT_META if base in RESULTANT_META else FACE_META)[base]
        if base in FACE_META:
            long_name += " at the inner and outer faces"
        if name != base:
            long_name = "viscous part of the " + long_name
        dims = ("time", "s_cell") if value.ndim == 2 else ("time", "s_cell", "zeta")
        entries[name] = (dims, value, {"units": units, "long_name": long_name})
    if constraint is not None:
        entries["axial_torque"][2]["comment"] = CONSTRAINT_COMMENT
    out = ds.assign_coords(coordinates(coords)).assign(variables(entries))
    out.attrs["stresses"] = "included (mol_shell.add_stresses" + (
        ", axial_torque with the torque of the constraint chi_s = 0)" if constraint is not None else ")")
    if not all(np.isfinite(v).all() for v in data.values()):
        out.attrs["stresses"] += f"; {STRESS_NAN} det F <= 0 at a face or the state is not finite"
        if "svk-plane-stress" in f"{material} {ds.attrs.get('layers', '')}":  # SVK's thinning has a bound
            out.attrs["stresses"] += (" (svk-plane-stress: also where its thickness stretch has no real value, "
                                      "C_22 = 1 - 2 nu/(1 - nu) (E_11 + E_33) <= 0)")
    return out


def _refuse_gaps(ds):
    """Refuse nodes ``s`` that are not neighbours in the run (``isel(s=[0, 2, 5, 9])``, a stride): each pair of
    consecutive nodes is taken for a cell, and the stresses of such "cells" were returned without a word, wrong.
    The run's node spacing is ``meridian_length / (n - 1)`` of its attrs (without them: the nodes' own spacing)."""
    step = np.diff(ds["s"].values)
    if not step.size:
        return
    attrs = ds.attrs
    spacing = float(attrs["meridian_length"]) / (int(attrs["n"]) - 1) if "meridian_length" in attrs and int(
        attrs.get("n", 0)) > 1 else abs(float(step[0]))
    if not (np.allclose(step, spacing, rtol=1e-6, atol=0) or np.allclose(step, -spacing, rtol=1e-6, atol=0)):
        raise ParameterError.invalid("ds", "Dataset", f"holds nodes s that are not neighbours in the run (its node "
                                     f"spacing {spacing:.6g} m)", "consecutive nodes of a run",
                                     hint="stresses need neighbouring nodes: select with a slice, isel(s=slice(i, j))")


def _without_stale_stresses(ds):
    """``ds`` without the stresses it holds when they are not on the cells of its nodes ``s``: a part of a run
    taken with ``isel(s=...)`` keeps the run's ``s_cell`` (and its stresses there), and the new stresses on its own
    cells met them as xarray's "conflicting sizes for dimension 's_cell'". A variable on the old cells that is not
    a stress (a constrained unshearable run's ``lambda_chi``) cannot be recomputed: refused naming ``ds``."""
    if "s_cell" not in ds.dims:
        return ds
    s = ds["s"].values
    if ds.sizes["s_cell"] == len(s) - 1 and "s_cell" in ds.coords and np.array_equal(
            ds["s_cell"].values, (s[1:] + s[:-1]) / 2):
        return ds
    stresses = {*RESULTANT_META, *FACE_META}
    stale = [v for v in ds.data_vars if v.removesuffix("_viscous") in stresses]
    out = ds.drop_vars(stale + [c for c in ("s_cell", "zeta", "zeta_face") if c in ds.coords])
    others = [v for v in out.variables if "s_cell" in out[v].dims]
    if others:
        raise ParameterError.invalid("ds", "Dataset", f"holds {', '.join(others)} on {ds.sizes['s_cell']} cells, not "
                                     f"on the {len(s) - 1} cells of its {len(s)} nodes s", "a run whose variables on "
                                     "s_cell are on the cells of its nodes", hint="a part of a run taken with "
                                     "isel(s=...) or sel(s=...): take the stresses of the whole run, then the part")
    return out


def nan_stresses(ds):
    """``(nan, total, why)``: the stress samples of a run (saved time x cell x face) where a stress or resultant is NaN,
    of all, and why (``attrs["stresses"]`` after its first ``"; "``); ``(0, total, "")`` when none is."""
    names = [v for v in ds.data_vars if "s_cell" in ds[v].dims and ds[v].dtype.kind == "f"]
    if not names:
        return 0, 0, ""
    shape = tuple(ds.sizes[d] for d in ("time", "s_cell", "zeta") if d in ds.dims)
    dims = ("time", "s_cell", "zeta")[:len(shape)]
    bad = np.zeros(shape, dtype=bool)
    for name in names:
        bad |= np.isnan(ds[name].transpose(*(d for d in dims if d in ds[name].dims)).values).reshape(
            tuple(ds.sizes[d] if d in ds[name].dims else 1 for d in dims))
    why = str(ds.attrs.get("stresses", "")).partition("; ")[2]
    return int(bad.sum()), bad.size, why if bad.any() else ""


def _refuse_study(ds):
    """Refuse a study's Dataset (its fields on ``(*study dims, time, s)``) as one, and a case of it taken with
    ``sel`` (its parameters coordinates and variables, not attrs), saying how to take one case as its run (it was
    "not a mol_shell run ... missing z, r, chi", though it holds them)."""
    if "status" not in ds or "r" not in ds or ds["r"].dims[-2:] != ("time", "s"):
        return
    dims = ds["status"].dims
    if not dims:  # one case, selected: fine where its parameters are all attrs (a study of gamma, say)
        if "study_vary" not in ds.attrs or "s" in ds.coords and all(
                k in ds.attrs for k in ("E", "nu", "h", "zeta1_used", "n_quad")):
            return
        names = ["case"] if "case" in ds.coords else [n.strip() for n in str(ds.attrs["study_vary"]).split(",")]
        which = ", ".join(f"{n}={ds[n].values.item()!r}" for n in names if n in ds.coords and ds[n].ndim == 0)
        raise ParameterError.invalid("ds", "Dataset", "is a case of a parameter study taken with sel or isel, its "
                                     "parameters coordinates and variables", "one run (a Dataset from simulate or "
                                     "mol-shell run)", hint=f"mol_shell.results.study_dataset.study_case(STUDY, "
                                     f"{which or '...'}) gives the case as its run")
    example = ", ".join(f"{d}={ds[d].values.ravel()[0].item()!r}" if d in ds.coords else f"{d}=0" for d in dims)
    raise ParameterError.invalid("ds", "Dataset", f"is {holdings(ds)}, not one run", "one run (a Dataset from simulate "
                                 "or mol-shell run)", hint="one case of the study as its run: mol_shell.results."
                                 f"study_dataset.study_case(ds, {example})")


# a mol_shell.Material's name given to another law: its stress kernels afresh (keyed by the law's name)
ON_REDEFINED.extend([kernel.cache_clear, compiled_kernel.cache_clear])
