"""Labelled results: xarray Datasets with units, and their netCDF4 files."""

from __future__ import annotations

import datetime

import numpy as np
import xarray as xr

from . import __version__
from .model.kinematics import FIELDS
from .scenes import UNITS

FIELD_META = {
    "z": ("m", "axial position of the base surface"),
    "r": ("m", "radius of the base surface"),
    "chi": ("rad", "azimuthal rotation"),
    "theta": ("rad", "angle of the generator tangent from the axis"),
    "psi": ("rad", "shear angle of the director out of the meridional plane"),
}
RATE_UNITS = {"m": "m s-1", "rad": "rad s-1"}
REFERENCE = "S. S. Antman and D. Bourne, Rotational symmetry vs. axisymmetry in shell theory, CASA-report 10-46 (2010)"


def _attr(value):
    """netCDF attributes take numbers and strings only."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (np.integer, np.floating)):
        return value.item()
    return value


def build_dataset(system, scene, traj, velocities, totals, attrs):
    """Assemble the Dataset of one run.

    Parameters
    ----------
    system : ShellSystem
    scene : TwistedCylinder
        With ``R`` resolved.
    traj : Trajectory
    velocities : ndarray
        ``(time, 5, s)`` rates of the fields.
    totals : dict
        Per-time arrays ``kinetic``, ``stored``, ``angular_momentum``, ``delta_min``.
    attrs : dict
        Integrator name and settings, graph statistics and the like.
    """
    fields = system.unpack(traj.y)
    data = {}
    for k, name in enumerate(FIELDS):
        units, long_name = FIELD_META[name]
        data[name] = (("time", "s"), fields[:, k], {"units": units, "long_name": long_name})
        data[name + "_t"] = (
            ("time", "s"),
            velocities[:, k],
            {"units": RATE_UNITS[units], "long_name": f"rate of change of {name}"},
        )
    data["kinetic_energy"] = (("time",), totals["kinetic"], {"units": "J", "long_name": "kinetic energy of the shell"})
    data["stored_energy"] = (("time",), totals["stored"], {"units": "J", "long_name": "stored (strain) energy"})
    data["energy"] = (
        ("time",),
        totals["kinetic"] + totals["stored"],
        {"units": "J", "long_name": "total energy (kinetic + stored)"},
    )
    data["angular_momentum"] = (
        ("time",),
        totals["angular_momentum"],
        {"units": "kg m2 s-1", "long_name": "angular momentum of the whole shell about the axis"},
    )
    data["delta_min"] = (
        ("time",),
        totals["delta_min"],
        {"units": "m", "long_name": "minimum over s of delta = r beta1 cos(psi) (must stay positive)"},
    )
    if system.viscous:
        data["dissipation"] = (
            ("time",),
            totals["dissipation"],
            {"units": "W", "long_name": "power dissipated by the Kelvin-Voigt stress (= -d energy/dt)"},
        )
    coords = {
        "time": ("time", traj.t, {"units": "s", "long_name": "time"}),
        "s": ("s", system.s, {"units": "m", "long_name": "arc length of the reference generator"}),
    }
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    meta = {
        "Conventions": "CF-1.8",
        "title": f"mol_shell run of scene {scene.name}",
        "source": f"mol_shell {__version__}",
        "mol_shell_version": __version__,
        "history": f"{now} created by mol_shell {__version__}",
        "references": REFERENCE,
        "scene": scene.name,
        "n": system.n,
        "status": traj.status,
        "complete": int(traj.status == "complete"),
        "message": traj.message,
        "failure_time": traj.failure_time,
        "rho_A": system.rho_a,
        "rho_I": float(system.rho_i),
        "rho_J": system.rho_j,
        "zeta1_used": system.thickness.zeta1,
    }
    for name, value in scene.params().items():
        meta[name] = value
        meta[f"units_{name}"] = UNITS.get(name, "1")
    meta.update(traj.stats)
    meta.update(attrs)
    ds = xr.Dataset(data, coords=coords, attrs={k: _attr(v) for k, v in meta.items()})
    return ds


def write_netcdf(ds, path):
    """Write a run as netCDF4 (model time in plain seconds, no CF calendar decoding)."""
    ds.to_netcdf(path, engine="netcdf4", format="NETCDF4")


def read_netcdf(path):
    """Read a run back into memory (times stay float seconds)."""
    with xr.open_dataset(path, engine="netcdf4", decode_times=False) as ds:
        return ds.load()
