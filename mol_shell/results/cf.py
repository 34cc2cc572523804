"""The parts every mol_shell Dataset shares: the CF header, attribute values, coordinates and variables."""

from __future__ import annotations

import datetime
import inspect

import numpy as np
import pandas as pd
import xarray as xr
from xarray.indexes import PandasIndex

from mol_shell._core.user_files import name_text
from mol_shell._core.version import __version__

REFERENCE = "S. S. Antman and D. Bourne, Rotational symmetry vs. axisymmetry in shell theory, CASA-report 10-46 (2010)"


#: the global ``comment`` of a file that gives none of its own (a run's says how its time is kept)
COMMENT = ("units of the global attributes' dimensional numbers in units_<name> beside them (counts, flags and "
           "indices have none, and a name ending in _s is in seconds); see docs/netcdf.md")


def header(title, comment=COMMENT, **attrs):
    """The global attributes CF asks of every file (``Conventions``, ``title``, ``source``, ``history``,
    ``references``, ``comment``) with mol_shell's version, then ``attrs``: every writer's (run, modes, path, study,
    compare, stability, ring) header."""
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    return {"Conventions": "CF-1.8", "title": title, "source": f"mol_shell {__version__}",
            "mol_shell_version": __version__, "history": f"{now} created by mol_shell {__version__}",
            "references": REFERENCE, "comment": comment, **attrs}


def utf8_words(value):
    """``value`` as netCDF can hold its words: a string as UTF-8 text (:func:`~mol_shell._core.user_files.name_text`:
    a file name's bytes that are not UTF-8 escaped, ``\\xfc``), and so each string of a list or tuple (a list
    attribute: as a list) or of an array of words (a variable's data: an array of its shape); ``value`` itself where
    it holds no string that is not UTF-8 (numbers, other objects: as they are). A list or an array of words holding
    such a name was written raw: netCDF4 refused it (``UnicodeEncodeError ... surrogates not allowed``) once the work
    was done (a study's ``--vary points=`` over such a file)."""
    if isinstance(value, str):
        return name_text(value)
    if isinstance(value, (list, tuple)):
        items = [utf8_words(v) if isinstance(v, (str, list, tuple)) else v for v in value]
        return items if any(a is not b for a, b in zip(items, value)) else value
    if isinstance(value, np.ndarray) and value.dtype.kind in "OU":
        flat = value.ravel().tolist()
        items = [name_text(v) if isinstance(v, str) else v for v in flat]
        if all(a is b for a, b in zip(items, flat)):
            return value
        return np.array(items, dtype=object).reshape(value.shape)
    return value


def attr_value(value):
    """netCDF attributes take numbers and strings only; a string as UTF-8 text, and each of a list of them
    (:func:`utf8_words`: a file name's bytes that are not UTF-8 escaped)."""
    if isinstance(value, (str, list, tuple, np.ndarray)):
        return utf8_words(value)
    if value is None:
        return "none"
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (np.integer, np.floating)):
        return value.item()
    return value


#: xarray's ``Variable(..., fastpath=True)`` (an internal flag of long standing) takes numpy data as given; were
#: it ever removed, the general path is taken, slower but the same
FAST_PATH = {"fastpath": True} if "fastpath" in inspect.signature(xr.Variable).parameters else {}


def coordinates(entries, keep=None):
    """``{name: (dims, values[, attrs])}`` as xarray Coordinates: the Variables of :func:`variables` and a pandas
    index for each dimension coordinate, made here (xarray's own asks whether the values are a dask collection,
    which imports dask: 0.1 s of every process's first Dataset); ``keep``: Coordinates to add as they are."""
    made = variables(entries)
    indexes = {name: PandasIndex(pd.Index(var.values), name, coord_dtype=var.dtype)
               for name, var in made.items() if var.dims == (name,)}
    if keep is not None:
        made.update({name: var for name, var in keep.variables.items() if name not in made})
        indexes.update({name: index for name, index in keep.xindexes.items() if name not in indexes})
    return xr.Coordinates(made, indexes=indexes)


def variables(entries):
    """``{name: (dims, values[, attrs])}`` as xarray Variables of numpy arrays, made on xarray's fast path.

    The general path asks of every array whether it is a dask array, and the first such question imports
    ``dask.array`` when dask is installed (0.3-0.5 s here): most of what a study's worker process spent on its
    first case beyond the case itself. The values are numpy arrays already, so nothing is lost.
    """
    return {name: xr.Variable(dims, np.asarray(values), *attrs, **FAST_PATH)
            for name, (dims, values, *attrs) in entries.items()}


def wide_integer(var):
    """Whether ``var`` holds integers netCDF would store in a type CF 1.8 lacks (64-bit, unsigned) that fit
    32 bits; those are written as ``int32`` (values beyond it, which no count reaches, keep their type)."""
    if var.dtype.kind not in "iu" or var.dtype.kind == "i" and var.dtype.itemsize <= 4:
        return False
    values = var.values
    return values.size == 0 or bool(values.min() >= -(2**31) and values.max() < 2**31)


def described(ds, title, meanings, **attrs):
    """``ds`` as a summary file is written: the CF header (:func:`header` of ``title`` and ``attrs``) and, on every
    variable and coordinate, ``units`` and ``long_name`` from ``meanings`` (``{name: (units, long_name)}``; units
    ``None`` for text) where it has none of its own. A numeric variable left without units, or any without a
    long_name, is a ``ValueError`` naming it: the writer's table misses it (a study script's summary)."""
    ds = ds.copy()
    for name, var in ds.variables.items():
        units, long_name = meanings.get(name, (None, None))
        if units is not None:
            var.attrs.setdefault("units", units)
        if long_name is not None:
            var.attrs.setdefault("long_name", long_name)
    missing = [name for name, var in ds.variables.items()
               if "long_name" not in var.attrs or (var.dtype.kind in "iuf" and "units" not in var.attrs)]
    if missing:
        raise ValueError(f"no units or long_name for {', '.join(map(str, missing))} in the file {title!r}")
    ds.attrs = header(title, **{k: attr_value(v) for k, v in attrs.items()})
    return ds
