"""The data side of parameter studies: finished cases on disk, summaries (the Dataset of a study:
:mod:`mol_shell.results.study_dataset`)."""

from __future__ import annotations

import hashlib
import tempfile

import numpy as np
import xarray as xr

from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell._core.paths import beside, check_lengths
from mol_shell.results.cf import utf8_words
from mol_shell.results.dataset import read_netcdf, write_netcdf

#: hexadecimal digits of a stored case's key, its file's name (:attr:`mol_shell.runs.study.Task.key`)
KEY_LENGTH = 20


def cases_folder(output):
    """``<output stem>.cases``: where a study (or a study of paths) writing ``output`` keeps its finished cases,
    beside ``output`` as given (a symbolic link's own folder: :func:`~mol_shell._core.paths.beside`)."""
    return beside(output, ".cases")


def check_cases_folder(output, name="output"):
    """:func:`cases_folder` of ``output``; a name too long for its file system (an output's of 253 to 255 bytes:
    ``.nc`` becomes ``.cases``) is refused naming ``name = output``, before any case runs."""
    folder = cases_folder(output)
    check_lengths(folder / f"{'0' * KEY_LENGTH}.nc", name, output, what=f"keeps its finished cases in {folder.name!r}")
    if folder.is_dir():
        writable_cases(folder, output, name)
    return folder


def writable_cases(folder, output, name="output"):
    """Refuse, naming ``name = output`` (the study's ``-o``), a cases folder that cannot be written (a probe file:
    permission bits do not tell), before any case runs: it was refused at the first case's write, naming an internal
    ``path = '.../X.cases/8c4c....nc'``."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise ParameterError.invalid(name, str(output), f"keeps its finished cases in {folder}/, which cannot be "
                                     f"written ({exc.strerror or exc})", "an output beside which <stem>.cases/ is a "
                                     "writable directory") from None


class Store:
    """Finished cases as ``<output stem>.cases/<key>.nc`` (the key hashes the whole case).

    Each file is written atomically (:func:`mol_shell.results.dataset.write_netcdf`) and carries a checksum
    of its values and attributes, the case's record among them (``case_checksum``); a file that cannot be read, or
    whose values no longer match it (truncated or corrupted), is not reused: the case runs again.
    """

    #: the attrs of a case record, stored as ``case_<name>``
    RECORD = ("label", "status", "message", "worker", "wall_time_s")

    def __init__(self, output):
        self.folder = check_cases_folder(output)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except (FileExistsError, NotADirectoryError):  # a file where the folder goes: refused before any case runs
            raise ParameterError.invalid("output", str(output), f"keeps its finished cases in {self.folder}/, where a "
                                         "file stands", "an output beside which <stem>.cases/ can be a directory "
                                         "(move that file away)") from None
        writable_cases(self.folder, output)
        self.rejected = []  # (path, reason) of case files found unusable by load

    def path(self, task):
        return self.folder / f"{task.key}.nc"

    def load(self, task):
        """``(dataset or None, info)`` of a stored case, or ``None`` if there is no usable file."""
        path = self.path(task)
        if not path.exists():
            return None
        try:
            ds = read_netcdf(path)
        except Exception as exc:  # noqa: BLE001 - any unreadable file (HDF5 raises many kinds): run again
            self.rejected.append((path, f"unreadable: {type(exc).__name__}"))
            return None
        stored = ds.attrs.pop("case_checksum", None)
        if "case_status" not in ds.attrs or stored != checksum(ds):
            self.rejected.append((path, "checksum mismatch" if stored else "no case record"))
            return None
        info = {k: ds.attrs.pop(f"case_{k}") for k in self.RECORD}
        info.pop("label")
        info["case_wall_time_s"] = info.pop("wall_time_s")
        return (ds if ds.data_vars else None), info

    def save(self, task, ds, info):
        ds = xr.Dataset() if ds is None else ds.copy()
        ds.attrs.update({"case_label": task.label, "case_status": info["status"], "case_message": info["message"],
                         "case_worker": info["worker"], "case_wall_time_s": info["case_wall_time_s"]})
        ds.attrs["case_checksum"] = checksum(ds)
        write_netcdf(ds, self.path(task))  # atomic: a killed study never leaves half a case behind


def checksum(ds):
    """SHA-256 of a case's values (every variable and coordinate) and of its attributes (the ``case_*`` record and
    the run's: its parameters, how it started, its status).

    NaN payloads are normalised, so the value survives a netCDF round trip; any changed byte of
    data, a missing variable, a changed record or a run attribute edited by hand changes it.
    """
    digest = hashlib.sha256()
    for name in sorted(map(str, ds.variables)):
        var = ds.variables[name]
        values = np.asarray(var.values)
        digest.update(f"{name}|{','.join(map(str, var.dims))}|{values.shape}|".encode())
        if values.dtype.kind in "fiub":
            values = values.astype(np.float64)
            digest.update(np.where(np.isnan(values), np.nan, values).tobytes())
        else:  # words as written (escaped where not UTF-8): the checksum read back is the one written
            digest.update(repr(utf8_words(values).tolist()).encode())
    for key in sorted(k for k in ds.attrs if k != "case_checksum"):
        digest.update(f"{key}={_as_stored(ds.attrs[key])!r};".encode())
    return digest.hexdigest()


def _as_stored(value):
    """An attribute as netCDF gives it back: numpy numbers as Python's, sequences as lists (one element: that
    element), words that are not UTF-8 escaped (:func:`~mol_shell.results.cf.utf8_words`: a case's label naming such
    a file was never reused, its checksum taken of the raw name and checked against the escaped one)."""
    value = utf8_words(value)
    if isinstance(value, (list, tuple, np.ndarray)):
        items = np.asarray(value).ravel().tolist()
        return items[0] if len(items) == 1 else items
    return value.item() if isinstance(value, np.generic) else value


def grid_mode(da, dim="s", local=False):
    """Split ``da`` into its ``(-1)^i`` node-to-node component along ``dim`` and the rest.

    The component's amplitude is the mean of ``da (-1)^i`` over ``dim``; with ``local``, its three-point mean
    ``(1/4, 1/2, 1/4)`` about each node (NaN at the two end nodes), the pattern under a slowly varying envelope that
    may change sign (a mode's): ``(u_i - (u_(i-1) + u_(i+1)) / 2) / 2`` times ``(-1)^i``, all of a ``(-1)^i`` pattern,
    ``(1 - cos k ds)^2 / 4`` of a wave's amplitude squared (1/4 at four nodes a wavelength), ``O(k ds)^4`` of a
    smooth one.

    A diagnostic for grid-scale content. With ``psi`` taken at cell midpoints the ``(-1)^i``
    pattern of ``psi`` vanished from the transverse shear and was a soft spurious mode (about
    ``(2/ds) sqrt(mu/rho)``, 357 rad/s on 40 nodes); the cell energy now samples ``psi`` at the
    cell's two nodes, so the pattern has the full shear stiffness (5,063 rad/s on 40 nodes, just
    above the uniform shear mode's 5,050 rad/s) and stays small (3.3e-6 .. 5.4e-6 rad in the paper
    scene on 40 .. 320 nodes, against max ``|psi|`` of 6.6e-5 .. 2.1e-4 rad, both on 20 us samples). Returns
    ``(amplitude, remainder)``, the amplitude without ``dim`` (along it with ``local``).
    """
    sign = xr.DataArray((-1.0) ** np.arange(da.sizes[dim]), dims=dim)
    demodulated = da * sign
    amplitude = ((demodulated.shift({dim: 1}) + 2 * demodulated + demodulated.shift({dim: -1})) / 4 if local
                 else demodulated.mean(dim))
    return amplitude, da - amplitude * sign


def summarize(ds):
    """Amplitudes of a run or study Dataset, reduced over ``time`` and ``s`` (NaN after a stop is skipped).

    Returns a Dataset with ``dr_max`` (max ``|r - R|``), ``theta_max``, ``psi_max`` and its split
    into ``psi_grid_mode_max`` and ``psi_smooth_max`` (see :func:`grid_mode`), ``chi_s_max``,
    and ``energy_drift`` (max relative change of the total energy).

    A study none of whose cases computed anything has no fields to reduce: where every case was refused (its
    input out of range) that is a :class:`ParameterError` saying the cases' reasons, as ``mol-shell study`` says
    them; where they stopped before their first saved time, a :class:`ModelLimitError` with their messages.
    """
    if "r" not in ds.variables:
        _nothing_computed(ds)
    R = ds["R"] if "R" in ds.variables else float(ds.attrs["R"])
    s = ds["s_case"] if "s_case" in ds.coords else ds["s"]  # the grids of a study of L differ between cases
    both = ("time", "s")
    mode, rest = grid_mode(ds.psi)
    e0 = ds.energy.isel(time=0, drop=True)
    out = {
        "dr_max": (abs(ds.r - R).max(both), "m", "largest change of the radius from R"),
        "theta_max": (abs(ds.theta).max(both), "rad", "largest |theta|"),
        "psi_max": (abs(ds.psi).max(both), "rad", "largest |psi|"),
        "psi_grid_mode_max": (abs(mode).max("time"), "rad", "largest amplitude of the (-1)^i node pattern of psi"),
        "psi_smooth_max": (abs(rest).max(both), "rad", "largest |psi| without its (-1)^i node pattern"),
        "chi_s_max": (abs(ds.chi.diff("s") / s.diff("s")).max(both), "rad m-1", "largest |chi_s|"),
        "energy_drift": (abs(ds.energy - e0).max("time") / abs(e0), "1", "largest relative change of the energy"),
    }
    return xr.Dataset({k: v.assign_attrs(units=u, long_name=n) for k, (v, u, n) in out.items()})


def _nothing_computed(ds):
    """Raise why the study ``ds`` has no fields (:func:`summarize`): its cases' reasons, each once."""
    status = np.asarray(ds["status"].values if "status" in ds.variables else [], dtype=object).ravel()
    messages = np.asarray(ds["message"].values if "message" in ds.variables else [""] * status.size,
                          dtype=object).ravel()
    reasons = list(dict.fromkeys(str(m) for m in messages if str(m)))
    said = "; ".join(reasons[:3]) + (f"; and {len(reasons) - 3} more" if len(reasons) > 3 else "")
    if status.size and all(st == "refused" for st in status):
        first = reasons[0] if reasons else ""
        name = first.split(" ", 1)[0] if first else "study"
        raise ParameterError(name, None, "", message=f"every case of the study was refused ({status.size} of "
                             f"{status.size}): {said or 'no reason recorded'}")
    kinds = ", ".join(sorted(set(map(str, status)))) or "none"
    raise ModelLimitError(f"no case of the study saved a state (statuses: {kinds}){': ' + said if said else ''}",
                          float("nan"), "")
