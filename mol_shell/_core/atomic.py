"""Files that are either the previous version or the new one, never half of either.

Every file mol_shell writes for later use (run and study netCDF files, finished study cases,
compiled libraries in the cache, figures) is written under its own name in a hidden temporary directory
``.NAME.*.part`` beside it, flushed to disk (``fsync``) and then renamed onto its name with :func:`os.replace`,
which is atomic on POSIX file systems. The writer sees the final name, so a file that records its own name
carries that one (an ``.svgz`` figure's gzip header, an ``.eps`` figure's ``%%Title``), never the temporary one.
A process killed while writing leaves the previous file intact (and the hidden ``.NAME.*.part`` directory
behind, which nothing reads); a reader never sees a half-written file, even while several processes write the
same name at once. The temporary directory is ``.mol_shell.*.part`` instead where ``.NAME.*.part`` would be too long
for the file system (a name of 235 to 255 bytes), and a file name that is not UTF-8 (bytes a locale's file names may
hold, which netCDF's library cannot encode) is written under a stand-in name there and renamed onto its own
(:func:`atomic_path`), in a directory that is not UTF-8 through a symbolic link of a UTF-8 name (:func:`utf8_alias`).
A write that fails for want of space raises :class:`NoSpaceError`, saying so, and leaves nothing behind; so does one
that the process's limit on a file's size (``ulimit -f``, ``RLIMIT_FSIZE``: ``EFBIG``) cut short.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import shutil
import tempfile
from pathlib import Path

try:
    import resource
except ImportError:  # pragma: no cover - Windows: no limit on a file's size
    resource = None

from mol_shell._core import interrupts
from mol_shell._core.errors import ParameterError, show

#: temporary directories are ``.<name>.<pid>.<random>.part`` next to the target
PART_SUFFIX = ".part"
#: the ``<name>`` of a temporary directory whose target's own name does not fit in it (or is not UTF-8)
SHORT_STEM = "mol_shell"
#: the longest file name and path (bytes) where a file system does not say (:func:`limits`): Linux's
NAME_MAX, PATH_MAX = 255, 4096
#: the longest temporary directory name that :func:`temporary_name` falls back to: ``.mol_shell.<pid>.<8 hex>.part``
#: with a pid of up to 10 digits; a path written through it is this many bytes (and a ``/``) longer than the target
SHORT_PART_BYTES = len(f".{SHORT_STEM}.{'9' * 10}.{'0' * 8}{PART_SUFFIX}")
#: bytes free below which a write that failed is taken to have failed for want of space (:func:`no_space`): a full
#: file system is written up to its last block (0 bytes were free after netCDF's ``NetCDF: HDF error`` on a full
#: tmpfs), a failure for another reason leaves the space as it was
LOW_SPACE = 1 << 20


def limits(folder):
    """``(longest file name, longest path)`` in bytes on the file system of ``folder``, or of its nearest existing
    ancestor (``os.pathconf``); :data:`NAME_MAX` and :data:`PATH_MAX` where the system does not say."""
    folder = Path(os.path.abspath(os.fspath(folder)))
    for place in (folder, *folder.parents):
        try:
            return os.pathconf(place, "PC_NAME_MAX"), os.pathconf(place, "PC_PATH_MAX")
        except (OSError, ValueError, AttributeError):  # missing, too long, or no pathconf (Windows)
            continue
    return NAME_MAX, PATH_MAX


def encodable(name):
    """Whether ``name`` is UTF-8 text (a file name the system decoded from bytes that are not UTF-8 holds
    surrogates, ``'\\udce9'``, which netCDF's library cannot encode)."""
    try:
        str(name).encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def temporary_name(path):
    """A fresh hidden name next to ``path`` (same directory, so the rename stays on one file system): the directory
    :func:`atomic_path` writes ``path`` in. ``.NAME.<pid>.<random>.part`` where that fits the file system (with
    ``path``'s name inside it), else ``.mol_shell.<pid>.<random>.part`` (:data:`SHORT_STEM`), which always does
    where ``path`` can be written (:func:`mol_shell._core.paths.writable_path`); also for a name that is not UTF-8."""
    path = Path(path)
    tail = f".{os.getpid()}.{secrets.token_hex(4)}{PART_SUFFIX}"
    stage = path.with_name(f".{path.name}{tail}")
    longest_name, longest_path = limits(path.parent)
    if (not encodable(path.name) or len(os.fsencode(stage.name)) > longest_name
            or len(os.fsencode(str(stage / path.name))) >= longest_path):
        stage = path.with_name(f".{SHORT_STEM}{tail}")
    return stage


def stand_in(path):
    """The name :func:`atomic_path` has ``path`` written under in its temporary directory: its own, where that is
    UTF-8 (so a file that records its name, an ``.svgz`` figure's gzip header, records its own), else ``output``
    with ``path``'s suffix."""
    path = Path(path)
    if encodable(path.name):
        return path.name
    return "output" + (path.suffix if encodable(path.suffix) else "")


class NoSpaceError(OSError):
    """A file could not be written for want of space (``ENOSPC``, a quota's ``EDQUOT``, a file larger than the
    process may write, ``EFBIG``, or a library's own error, netCDF's ``NetCDF: HDF error``, on a file system left
    full or a file at the size limit): ``errno``, ``filename`` (the file that was to be written) and a ``strerror``
    that says so, how much space is left and that nothing was written."""

    def __init__(self, path, reason, code=errno.ENOSPC):
        super().__init__(code, f"{reason}; nothing was written", os.fspath(path))


def size_limit():
    """The most bytes this process may write into one file (``ulimit -f``, the soft ``RLIMIT_FSIZE``), or ``None``
    where there is no limit (or no way to ask: Windows)."""
    if resource is None:
        return None
    try:
        soft, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
    except (OSError, ValueError):
        return None
    return None if soft == resource.RLIM_INFINITY or soft < 0 else soft


def too_large(exc, stage=None):
    """Why ``exc``, raised writing the files in directory ``stage``, is the process's limit on a file's size
    (``File too large (the file size limit, ulimit -f, is 204800 bytes)``), or ``None`` where it is not: an
    ``EFBIG``, or an ``OSError`` or ``RuntimeError`` (netCDF's ``NetCDF: HDF error``, which keeps no errno) with a file
    in ``stage`` that fills the limit to within :data:`LOW_SPACE` bytes or an eighth of it, the lesser (a write cut
    short by the limit fills the file up to it; a 64 KB file under a limit of 900 KB is a full disk's, not this)."""
    limit = size_limit()
    said = os.strerror(errno.EFBIG) + (f" (the file size limit, ulimit -f, is {limit} bytes)" if limit else "")
    if getattr(exc, "errno", None) == errno.EFBIG:
        return said
    if limit is None or stage is None or not isinstance(exc, (OSError, RuntimeError)):
        return None
    try:
        largest = max((entry.stat(follow_symlinks=False).st_size for entry in os.scandir(stage)
                       if entry.is_file(follow_symlinks=False)), default=0)
    except OSError:
        return None
    return said if largest > limit - min(LOW_SPACE, limit // 8) else None


def no_space(exc, folder):
    """Why ``exc``, raised writing in ``folder``, is a file system's lack of space (``No space left on device
    ('/tmp/small' has 0 bytes free)``), or ``None`` where it is not: an ``ENOSPC`` or ``EDQUOT``, or an ``OSError`` or
    ``RuntimeError`` (netCDF's) with less than :data:`LOW_SPACE` bytes (or no inode) left in ``folder``."""
    code = getattr(exc, "errno", None)
    if code is not None and code == getattr(errno, "EDQUOT", None):
        return os.strerror(code)
    try:
        stat = os.statvfs(folder)
    except (OSError, AttributeError):  # gone, or no statvfs (Windows)
        stat = None
    free = f" ({str(folder)!r} has {stat.f_bavail * stat.f_frsize} bytes free)" if stat is not None else ""
    full = stat is not None and (stat.f_bavail * stat.f_frsize < LOW_SPACE or stat.f_files and not stat.f_favail)
    if code == errno.ENOSPC or isinstance(exc, (OSError, RuntimeError)) and full:
        return os.strerror(errno.ENOSPC) + free
    return None


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
    the new ones are; on failure (an error, Ctrl-C) the directory goes and the previous files are left as they were.
    A failure for want of space (:func:`no_space`) raises :class:`NoSpaceError` naming ``path``."""
    path = Path(path)
    stage = temporary_name(path)
    try:
        stage.mkdir()
    except OSError as exc:
        _if_full(exc, path)
        raise
    try:
        yield stage
        for part in sorted(stage.iterdir(), key=lambda f: f.name == path.name):
            if only is None or part.name in only:
                fsync_path(part)
                os.replace(part, path.parent / part.name)
        fsync_path(path.parent, directory=True)
    except (OSError, RuntimeError) as exc:
        _if_full(exc, path, stage)  # before the temporary directory goes: it holds what filled the file system
        raise
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def _if_full(exc, path, stage=None):
    """Raise :class:`NoSpaceError` (from ``exc``) where writing ``path`` (in directory ``stage``) failed for want of
    space (an ``ENOSPC`` or ``EDQUOT`` said first: it has the errno), or at the process's limit on a file's size
    (:func:`too_large`)."""
    if getattr(exc, "errno", None) not in (errno.ENOSPC, getattr(errno, "EDQUOT", None)):
        large = too_large(exc, stage)
        if large is not None:
            raise NoSpaceError(path, large, errno.EFBIG) from exc
    full = no_space(exc, path.parent)
    if full is not None:
        raise NoSpaceError(path, full) from exc


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path to write ``path`` through; on success it replaces ``path`` atomically.

    The temporary path has ``path``'s own file name, in a fresh hidden directory beside it (:func:`staged`): what a
    writer records of the name it writes (gzip's ``FNAME``, PostScript's ``%%Title``) is the final one; a name that
    is not UTF-8 is written under a UTF-8 stand-in there (:func:`stand_in`) and renamed onto its own, and a directory
    that is not UTF-8 is given to the writer as a link of a UTF-8 name (:func:`utf8_alias`): netCDF's library could
    write neither. The writer creates the temporary file itself (so it gets the usual
    permissions). When the ``with`` block raises (or the writer never created the file), the temporary directory is
    removed and ``path`` is left as it was.

    Examples
    --------
    >>> with atomic_path("run.nc") as tmp:          # doctest: +SKIP
    ...     ds.to_netcdf(tmp)
    """
    path = Path(path)
    with staged(path, only={path.name}) as stage, utf8_alias(stage) as folder:
        tmp = folder / stand_in(path)
        yield tmp
        if not (stage / tmp.name).exists():
            raise FileNotFoundError(f"{tmp} was not written")
        if tmp.name != path.name:
            os.rename(stage / tmp.name, stage / path.name)


@contextlib.contextmanager
def utf8_alias(path):
    """``path`` where it is UTF-8, else a symbolic link to it (a file or a directory) in a fresh temporary directory,
    removed after the block: a name netCDF's library can encode for a path whose directories' names are not UTF-8
    (``/data/r\\udce9sultats/run.nc``, from bytes a locale's file names may hold). Where no such link can be made (a
    system without symbolic links, a temporary directory that is not UTF-8 either), ``path`` itself."""
    path = Path(path)
    if encodable(str(path)):
        yield path
        return
    try:
        folder = Path(tempfile.mkdtemp(prefix="mol_shell."))
    except OSError:
        yield path
        return
    try:
        link = folder / ("link" + (path.suffix if encodable(path.suffix) else ""))
        try:
            os.symlink(os.path.abspath(path), link)
        except (OSError, NotImplementedError):
            link = path
        yield link if encodable(str(link)) else path
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def write_text(path, text):
    """``Path(path).write_text(text)``, atomically (a report beside a netCDF file)."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text)
    interrupts.wrote(path)  # an interrupt from here on: said after writing it
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
