"""What a run offers to colour and export: its variables by name, on nodes or cells, and the revolved shell.

A run has fields and rates on the nodes ``(time, s)``; with stresses (:mod:`mol_shell.results.stresses`)
resultants on the cells ``(time, s_cell)`` and face stresses on ``(time, s_cell, zeta)``, offered
here as ``NAME_inner`` and ``NAME_outer``.
"""

from __future__ import annotations

import os

import numpy as np
import xarray as xr

from mol_shell._core.constants import FIELDS
from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell.model.thickness_profile import thickness_function
from mol_shell.results.dataset import holdings, is_run, read_run
from mol_shell.results.stresses import FACES, STRESS_NAN

#: what a run the views draw holds finite: the coordinates, the fields and the reference meridian (a run stops
#: before a state that is not finite, so only a hand-edited or damaged file has such values); checked first
FINITE = ("time", "s", *FIELDS, "z0", "r0", "theta0")

#: variables of a run that hold NaN by design (docs/netcdf.md): a reaction where no reaction is computed, the
#: ellipticity margin of a state not checked; a run's stresses (on ``s_cell``) may too, where its ``attrs["stresses"]``
#: says so (:data:`STRESS_NAN`). Inf is refused everywhere.
MAY_BE_NAN = ("reaction_force", "reaction_torque", "ellipticity_margin")
#: ... and, of a run that stopped (``complete = 0``) where a law's energy is not finite (a start outside a law of
#: one's own's domain, kept as its one saved time), the stored and total energies
ENERGY_MAY_BE_NAN = ("stored_energy", "energy")

#: the reference meridian: a run file holds all of it, or none (the views then take its first saved state as the
#: reference); a file with a part of it is damaged, refused naming what is missing
REFERENCE = ("z0", "r0", "theta0")
#: the variables the revolved shell reads (:func:`surface_points`)
SHELL = ("z", "r", "chi", "theta", "psi")
#: the attributes :func:`face_depths` reads of a uniform wall (a graded wall's, ``h_profile``, its own profile)
FACE_ATTRIBUTES = ("zeta1_used", "h")



#: what the views' functions draw, as their refusal of anything else says
RUN_ALLOWED = ("a run's Dataset (mol_shell.simulate, read_netcdf; a study's case: study.isel(...)) or the path of "
               "its netCDF file")


def run_of(ds, view=None, variables=(), faces=False):
    """The run a views function draws: ``ds`` itself (an ``xarray.Dataset``), or the run file at the path ``ds``
    (read by :func:`mol_shell.results.dataset.read_run`), checked by :func:`check_run` (``view``, ``variables``: what
    the view reads, there; ``faces``: it reads the faces' depths too, :func:`face_attributes`).

    Raises
    ------
    ParameterError
        Named ``ds``: neither a Dataset nor a path, a file that does not exist or holds no run, or a Dataset the
        views cannot draw (:func:`check_run`).
    """
    if isinstance(ds, (str, os.PathLike)):
        ds = read_run(ds, name="ds", allowed=RUN_ALLOWED)
    elif not isinstance(ds, xr.Dataset):
        raise ParameterError.not_a("ds", ds, "a run's Dataset or a file path", RUN_ALLOWED)
    check_run(ds, view=view, variables=variables, attributes=face_attributes(ds) if faces else ())
    return ds


def face_attributes(ds):
    """The attributes :func:`face_depths` reads of ``ds``: :data:`FACE_ATTRIBUTES`, none for a graded wall."""
    return () if _profile(ds) not in ("", "none") else FACE_ATTRIBUTES


def check_run(ds, source=None, view=None, variables=(), attributes=()):
    """Refuse a Dataset the views cannot draw, in one line: one that is not a single run's (a study, a path,
    modes: :func:`mol_shell.results.dataset.is_run`), one without saved times or with fewer than two nodes, or whose
    values are not finite somewhere: Inf anywhere, NaN anywhere but in :data:`MAY_BE_NAN` and in stresses that
    ``attrs["stresses"]`` declares NaN (the views draw those as gaps). ``source``: the file the command line read ``ds``
    from, then named ``FILE``. A damaged or hand-edited file is refused too where it lacks a part of the reference
    meridian (:data:`REFERENCE`: all or none), or what ``view`` (its name, as the refusal says it) reads: each of
    ``variables``, and each of ``attributes`` as a finite number (each view's list: :data:`SHELL`, ...).

    Raises
    ------
    ParameterError
        ``FILE = 'run.nc' has no saved times; allowed: ...``, ``FILE = 'run.nc' has no variable psi, which export reads;
        allowed: ...`` or ``FILE = 'run.nc': r is not finite at t = 0 s,
        s = 0 m (11 of 11 values); allowed: ...``; from Python named ``ds`` (its value the file it was read from,
        if any): ``ds is a parameter study (mol-shell study) over gamma, not one run; allowed: a run's Dataset ...``.
    """
    name = "FILE" if source is not None else "ds"
    source = source if source is not None else ds.encoding.get("source") if isinstance(ds, xr.Dataset) else None
    value = None if source is None else str(source)
    said = name if value is None else f"{name} = {show(value)}"  # a Dataset made in Python: named ds alone

    def refuse(problem, allowed):
        raise ParameterError(name, value, allowed, message=f"{said} {problem}; allowed: {allowed}")

    if not is_run(ds):
        refuse(f"is {holdings(ds)}, not one run", RUN_ALLOWED)
    allowed = "a run file with saved times, two nodes or more and finite values, as mol-shell run writes it"
    times, nodes = ds.sizes.get("time", 0), ds.sizes.get("s", 0)
    if times == 0:
        refuse("has no saved times", allowed)
    if nodes < 2:
        refuse(f"has {nodes} node{'' if nodes == 1 else 's'} in s", allowed)
    _check_holds(ds, refuse, view, variables, attributes)
    nan_stresses = STRESS_NAN in str(ds.attrs.get("stresses", ""))
    stopped = not int(ds.attrs.get("complete", 1))
    others = [v for v in ds.variables if v not in FINITE and ds[v].dtype.kind in "fc" and ds[v].ndim]
    for var in [v for v in FINITE if v in ds.variables] + others:
        values = np.asarray(ds[var].values, dtype=float)
        nan_ok = (var in MAY_BE_NAN or nan_stresses and "s_cell" in ds[var].dims
                  or stopped and var in ENERGY_MAY_BE_NAN)
        bad = np.isinf(values) if nan_ok else ~np.isfinite(values)
        if not bad.any():
            continue
        first = dict(zip(ds[var].dims, np.unravel_index(np.argmax(bad), values.shape)))
        where = ", ".join(_at(ds, var, dim, int(k)) for dim, k in first.items())
        refuse_at = (f"{said}: {var} is not finite at {where} ({int(bad.sum())} of {bad.size} values"
                     + (", Inf: NaN may be there, Inf not" if nan_ok else "") + ")")
        raise ParameterError(name, value, allowed, message=f"{refuse_at}; allowed: {allowed}")


def _check_holds(ds, refuse, view, variables, attributes):
    """Refuse (``refuse(problem, allowed)``) a run without a part of its reference meridian, or without what ``view``
    reads: a variable of ``variables``, an attribute of ``attributes`` (or one that is not a finite number)."""
    partial = [name for name in REFERENCE if name not in ds.variables]
    if 0 < len(partial) < len(REFERENCE):
        refuse(f"has no variable {partial[0]}, a part of the reference meridian ({', '.join(REFERENCE)}: a run file "
               "holds all of them)", "a run file as mol-shell run writes it, with its reference meridian whole")
    reads = (f"variables {', '.join(variables)}" if variables else "") + (
        f"{' and ' if variables else ''}attributes {', '.join(attributes)}" if attributes else "")
    allowed = f"a run file as mol-shell run writes it ({view} reads its {reads})"
    for name in variables:
        if name not in ds.variables:
            refuse(f"has no variable {name}, which {view} reads", allowed)
    for name in attributes:
        if name not in ds.attrs:
            refuse(f"has no attribute {name}, which {view} reads", allowed)
        if not (is_number(ds.attrs[name]) and np.isfinite(float(ds.attrs[name]))):
            refuse(f"has attribute {name} = {show(ds.attrs[name])}, not a finite number, which {view} reads", allowed)


def _at(ds, var, dim, k):
    """Where index ``k`` along ``dim`` of ``var`` is, as a refusal says it."""
    if dim == "zeta" and k < len(FACES):
        return f"{FACES[k]} face"
    if dim == var or dim not in ds.coords:
        return f"{ {'time': 'saved time', 's': 'node'}.get(dim, dim)} {k}"
    return f"{'t' if dim == 'time' else dim} = {float(ds[dim][k]):.6g} {'s' if dim == 'time' else 'm'}"


#: displacements :func:`field` derives from a run with its reference meridian: name -> (field, reference, long_name)
DISPLACEMENTS = {"r_displacement": ("r", "r0", "radial displacement r - r0"),
                 "z_displacement": ("z", "z0", "axial displacement z - z0")}


def field_names(ds, derived=False):
    """Names :func:`field` accepts: node variables, cell variables, and face variables per face; ``derived``: also
    the :data:`DISPLACEMENTS` a run with its reference meridian offers (after its node variables)."""
    names = [v for v in ds.data_vars if ds[v].dims == ("time", "s")]
    if derived:
        names += [name for name, (var, ref, _) in DISPLACEMENTS.items() if var in ds and ref in ds]
    names += [v for v in ds.data_vars if ds[v].dims == ("time", "s_cell")]
    names += [f"{v}_{face}" for v in ds.data_vars if ds[v].dims == ("time", "s_cell", "zeta") for face in FACES]
    return names


def field(ds, name, where="cells", option="field"):
    """Values of ``name`` on the cells ``(time, n - 1)`` or on the nodes ``(time, n)``, with units and a label.

    Node values go to a cell as the mean of its two nodes; cell values to an interior node as the
    mean of its two cells (an end node takes its cell's value). An unknown name is refused by
    :class:`~mol_shell._core.errors.ParameterError` naming ``option`` (the caller's keyword) and the names the run
    offers. ``r_displacement`` and ``z_displacement`` (:data:`DISPLACEMENTS`) are derived from the reference meridian.

    Returns
    -------
    values : ndarray
    units : str
    label : str
        ``long_name [units]``, or the name with spaces when the variable has no ``long_name``.
    """
    names = field_names(ds, derived=True)
    if name not in names:
        why = str(ds.attrs.get("stresses", ""))
        if "axial_torque" in ds:
            hint = ""
        elif why.startswith("skipped"):
            hint = f"this run has no stresses ({why})"
        else:
            hint = "this run has no stresses: rerun without --no-stresses"
        raise ParameterError(option, name, "{" + ", ".join(names) + "}", hint=hint)
    face = None
    base = name
    for k, suffix in enumerate(FACES):
        if name.endswith("_" + suffix) and name not in ds:
            base, face = name[: -len(suffix) - 1], k
    if name in DISPLACEMENTS and name not in ds:
        current, reference, long_name = DISPLACEMENTS[name]
        var = (ds[current] - ds[reference]).transpose("time", "s")
        var.attrs = {"units": ds[current].attrs.get("units", "m"), "long_name": long_name}
    else:
        var = ds[base] if face is None else ds[base].isel(zeta=face)
    values = np.asarray(var.values, dtype=float)
    on_nodes = var.dims == ("time", "s")
    if where == "cells" and on_nodes:
        values = (values[:, 1:] + values[:, :-1]) / 2
    elif where == "nodes" and not on_nodes:
        values = np.concatenate([values[:, :1], (values[:, 1:] + values[:, :-1]) / 2, values[:, -1:]], axis=1)
    units = str(var.attrs.get("units", "1"))
    label = str(var.attrs.get("long_name", name.replace("_", " ")))
    if face is not None:
        label = f"{label.replace(' at the inner and outer faces', '')}, {FACES[face]} face"
    return values, units, f"{label} [{units}]"


def azimuths(n_phi):
    """Reference azimuths ``phi_j = 2 pi j / n_phi``."""
    return 2 * np.pi * np.arange(n_phi) / n_phi


def surface_points(ds, n_phi, zeta=0.0, times=None):
    """Cartesian positions ``(time, s, phi, 3)`` of the material points at depth ``zeta`` (m: one depth, or one per
    node, as :func:`face_depths` gives a graded wall's faces).

    The rotationally symmetric map: the material line at reference azimuth ``phi`` sits at azimuth
    ``phi + chi(s, t)``; the base surface point is ``z k + r a2``, ``a2 = (cos, sin, 0)(phi + chi)``
    (2.6), and the point at depth ``zeta`` along the director is ``r + zeta d``,
    ``d = cos(psi) b2 + sin(psi) a3``, ``b2 = -sin(theta) k + cos(theta) a2`` (2.8, 2.11).
    ``zeta = 0``: ``(r cos(phi + chi), r sin(phi + chi), z)``.
    """
    sel = slice(None) if times is None else times
    z, r, chi, theta, psi = (np.asarray(ds[f].values[sel], dtype=float)[..., None] for f in SHELL)
    return _revolve(z, r, chi, theta, psi, n_phi, zeta)


def drawn_rows(count, most):
    """Indices of the ``count`` nodes a picture draws where it has room for ``most`` rows: all of them up to ``most``,
    else ``most + 1`` nearly even ones with both ends (a band narrower than a pixel shows nothing, and a frame of
    5,000 nodes x 48 azimuths took 3 s to draw)."""
    if count <= most + 1:
        return np.arange(count)
    return np.unique(np.linspace(0, count - 1, most + 1).round().astype(int))


def row_means(values, rows):
    """The cell values ``values`` (one per cell between nodes, last axis) averaged over the cells between the drawn
    ``rows`` (:func:`drawn_rows`): the band between two drawn nodes shows the mean of the cells it spans."""
    values = np.asarray(values, dtype=float)
    if len(rows) == values.shape[-1] + 1:
        return values
    return np.add.reduceat(values, rows[:-1], axis=-1) / np.diff(rows)


def reference_points(ds, n_phi, zeta=0.0):
    """Cartesian positions ``(s, phi, 3)`` of the material points at depth ``zeta`` in the reference (natural)
    shell: the map of :func:`surface_points` at ``z0, r0, theta0``, ``chi = psi = 0`` (``zeta`` one depth or one per
    node). A run without the reference meridian (the ring ODE's) takes its first saved state as the reference."""
    if not all(name in ds for name in ("z0", "r0", "theta0")):
        return surface_points(ds, n_phi, zeta, times=[0])[0]
    z, r, theta = (np.asarray(ds[f].values, dtype=float)[..., None] for f in ("z0", "r0", "theta0"))
    return _revolve(z, r, np.zeros_like(r), theta, np.zeros_like(r), n_phi, zeta)


def _revolve(z, r, chi, theta, psi, n_phi, zeta):
    zeta = np.asarray(zeta, dtype=float)
    zeta = zeta[:, None] if zeta.ndim else zeta  # one depth per node: along s, the same for every phi
    angle = azimuths(n_phi) + chi
    cos_a, sin_a = np.cos(angle), np.sin(angle)
    radial = r + zeta * np.cos(psi) * np.cos(theta)  # along a2
    spin = zeta * np.sin(psi)  # along a3 = (-sin, cos, 0)
    axial = z - zeta * np.cos(psi) * np.sin(theta)
    x = radial * cos_a - spin * sin_a
    y = radial * sin_a + spin * cos_a
    return np.stack([x, y, np.broadcast_to(axial, x.shape)], axis=-1)


def face_depths(ds):
    """The depths ``(inner, outer)`` of the faces from the base surface at each node (m, two arrays along ``s``):
    ``zeta1`` and ``zeta1 + 2h`` of a uniform wall; a graded wall's (``h_profile``) own ``-h(s)`` and ``+h(s)`` about
    its mid-surface, ``h(s)`` from the run's profile at the nodes, as the run took it (its ``zeta_face`` holds the
    same at the cell centres)."""
    s = np.asarray(ds["s"].values, dtype=float)
    profile = _profile(ds)
    if profile not in ("", "none"):
        h = np.asarray(thickness_function(profile, float(s[-1] - s[0]))(s), dtype=float)
        return -h, h
    zeta1, h = (float(ds.attrs[name]) for name in FACE_ATTRIBUTES)
    return np.full(s.shape, zeta1), np.full(s.shape, zeta1 + 2 * h)


def _profile(ds):
    return str(ds.attrs.get("h_profile", "") or "")
