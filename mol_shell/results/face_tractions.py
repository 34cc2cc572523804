"""The normal tractions on a run's faces, which give the face stress normal to the wall where the director is held.

Under the director constraint (``svk``) the thickness stress is the constraint's reaction, not the law's: the faces
take it from their tractions (:func:`~mol_shell.results.stress_samples.held_thickness_stress`), which this module
gives per saved time from the run's attrs. The only load on a face is the pressure (which the model applies at the
base surface; gravity and drag are not tractions on a face).
"""

from __future__ import annotations

import numpy as np

from mol_shell.model.loads import history, parse_history


def face_tractions(ds):
    """``(time, 2)``: the normal traction on the inner and outer face at each saved time: ``-p h(t)`` on the face the
    pressure acts on, 0 on the other (and on both without a pressure). The pressure acts on the side of the enclosed
    volume (``pi sum r^2 dz`` of the reference meridian, made positive as the load's,
    :func:`~mol_shell.discretization.loading.volume_sign`): the inner face when ``z0`` rises along ``s`` (the director
    then points out of it), else the outer face."""
    out = np.zeros((ds.sizes["time"], 2))
    pressure = float(ds.attrs.get("pressure", 0.0) or 0.0)
    if not pressure:
        return out
    parsed = parse_history("pressure_history", str(ds.attrs.get("pressure_history", "constant") or "constant"))
    s = ds["s"].values
    r0 = ds["r0"].values if "r0" in ds and ds["r0"].dims == ("s",) else np.ones_like(s)  # the cylinder's without
    z0 = ds["z0"].values if "z0" in ds and ds["z0"].dims == ("s",) else s
    rising = np.sum(((r0[1:] + r0[:-1]) / 2) ** 2 * np.diff(z0)) >= 0
    out[:, 0 if rising else 1] = [-pressure * history(parsed, float(t)) for t in ds["time"].values]
    return out


def face_parameters(par, tractions, n):
    """The kernel's parameters per sample of a block of saved times: ``par`` (``(P,)``, or per sample of the cells
    ``(2 (n - 1), P)``) with the faces' tractions of each saved time (``tractions`` ``(times, 2)``)."""
    size = par.shape[-1]
    out = np.empty((len(tractions), n - 1, 2, size))
    out[...] = par.reshape(1, -1, 2, size) if par.ndim == 2 else par
    out[..., -2:] = tractions[:, None, None, :]
    return out.reshape(-1, size)
