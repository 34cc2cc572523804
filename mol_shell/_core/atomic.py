"""Files that are either the previous version or the new one, never half of either.

Every file mol_shell writes for later use (run and study netCDF files, finished study cases,
compiled libraries in the cache, figures) is written under its own name in a hidden temporary directory
``.NAME.*.part`` beside it, flushed to disk (``fsync``) and then renamed onto its name with :func:`os.replace`,
which is atomic on POSIX file systems. The writer sees the final name, so a file that records its own name
carries that one (an ``.svgz`` figure's gzip header, an ``.eps`` figure's ``%%Title``), never the temporary one.
A process killed while writing leaves the previous file intact (and the hidden ``.NAME.*.part`` directory
behind, which nothing reads); a reader never sees a half-written file, even while several processes write the
same name at once.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
from pathlib import Path

from mol_shell._core.errors import ParameterError, show

#: temporary directories are ``.<name>.<pid>.<random>.part`` next to the target
PART_SUFFIX = ".part"


def temporary_name(path):
    """A fresh hidden name next to ``path`` (same directory, so the rename stays on one file system): the directory
    :func:`atomic_path` writes ``path`` in."""
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}{PART_SUFFIX}")


def fsync_path(path, directory=False):
    """Flush a file (or a directory's entries) to disk; file systems that cannot are skipped."""
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:  # e.g. directories on some network file systems
        pass
    finally:
        os.close(fd)


@contextlib.contextmanager
def staged(path, only=None):
    """A fresh hidden directory beside ``path`` (:func:`temporary_name`) to write ``path`` in, and the files written
    beside it (an export's ``.h5`` or ``.vtu`` steps); on success each file (``only``: just those names) is flushed and
    moved onto its place with :func:`os.replace`, ``path``'s own name last, so the previous files stay whole until
    the new ones are; on failure (an error, Ctrl-C) the directory goes and the previous files are left as they were."""
    path = Path(path)
    stage = temporary_name(path)
    stage.mkdir()
    try:
        yield stage
        for part in sorted(stage.iterdir(), key=lambda f: f.name == path.name):
            if only is None or part.name in only:
                fsync_path(part)
                os.replace(part, path.parent / part.name)
        fsync_path(path.parent, directory=True)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path to write ``path`` through; on success it replaces ``path`` atomically.

    The temporary path has ``path``'s own file name, in a fresh hidden directory beside it (:func:`staged`): what a
    writer records of the name it writes (gzip's ``FNAME``, PostScript's ``%%Title``) is the final one. The writer
    creates the temporary file itself (so it gets the usual permissions). When the ``with`` block raises (or the
    writer never created the file), the temporary directory is removed and ``path`` is left as it was.

    Examples
    --------
    >>> with atomic_path("run.nc") as tmp:          # doctest: +SKIP
    ...     ds.to_netcdf(tmp)
    """
    path = Path(path)
    with staged(path, only={path.name}) as stage:
        tmp = stage / path.name
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{tmp} was not written")


def write_text(path, text):
    """``Path(path).write_text(text)``, atomically (a report beside a netCDF file)."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text)
    return Path(path)


def same_file(a, b):
    """Whether paths ``a`` and ``b`` name one existing file (:func:`os.path.samefile`: a symbolic or hard link, or
    ``./run.nc`` and ``run.nc``, is the file itself); ``False`` when either does not exist."""
    try:
        return os.path.samefile(os.path.expanduser(os.fspath(a)), os.path.expanduser(os.fspath(b)))
    except (OSError, TypeError, ValueError):
        return False


def up_out_of(path):
    """The directory a ``..`` of ``path`` goes back out of where that is no directory (``sub`` of ``sub/../x.nc``
    without ``sub``), else ``None``: the system resolves ``..`` only in a directory that exists (``open`` fails there,
    as a shell's ``> sub/../x.nc`` does), so such a path names no file that can be written."""
    parts = Path(path).parts
    for i, part in enumerate(parts[1:-1], start=1):
        if part == ".." and not Path(*parts[:i]).is_dir():
            return Path(*parts[:i])
    return None


def keep_inputs(inputs, writes, name, value):
    """Refuse, naming the output ``name = value`` (``-o``), a write over one of the files the work reads: a run's
    netCDF named ``run.h5`` and exported to ``run.xdmf`` was replaced by the export's HDF5 data, its run lost.

    Parameters
    ----------
    inputs : dict
        ``{label: path}`` of the files read (``FILE``, ``--from``; ``None`` for one not given).
    writes : iterable of str or os.PathLike
        The files the work would write: the output and the files written beside it.
    name, value : str
        The option (or keyword) that names the output, and its value, as the refusal says them.

    Raises
    ------
    ParameterError
        A file of ``writes`` is one of ``inputs`` (:func:`same_file`).
    """
    for path in writes:
        for label, source in inputs.items():
            if source is not None and same_file(path, source):
                whose = "is" if same_file(path, value) else f"would write {Path(path).name} beside it, which is"
                raise ParameterError.invalid(
                    name, str(value), f"{whose} the input file {label} = {show(str(source))}: its data would be lost",
                    f"an output that writes none of the command's input files (give {name} another name)")
