"""The compiled-kernel cache on disk: its folder, the record that proves a library whole, its lock files, the
leftovers of killed builds, and its failures said in one line.

Every library in ``$MOL_SHELL_CACHE`` ends in a fixed-length record appended after gcc's output (past the ELF
image, where the dynamic loader never reads): the cache key it was built for, the image's size and a SHA-256
digest of it (the whole image up to :data:`DIGEST_WHOLE` bytes, its first and last halves of that above: under a
millisecond). :func:`damage` checks it before a library is loaded: a file cut short (which ``dlopen`` maps, and the
first call into a missing page then kills the process with SIGBUS), one with bytes changed, or a whole library of
another kernel copied onto the name is compiled again instead
(:func:`mol_shell.discretization.compiled.compile_cached`).

A cache shared by several users works with files it cannot write: the lock files are opened for reading
(``flock`` needs no more) and ``builds.log`` is written where it can be. What the cache truly refuses (a full
disk, a file it may not replace, a path CasADi cannot load from) is one :class:`ParameterError` naming
``MOL_SHELL_CACHE`` (a full disk's a :class:`CacheFull`, which the stresses after a run catch: the run is kept); a gcc
that is missing or fails is a :class:`CompilerError` (exit 2 on the command line). Whether gcc works at all is
:func:`gcc_problem` (a probe build, once per process); whether a library can be had at all, :func:`unavailable`: whole
in the cache (loaded without gcc, wherever it was built), or built by a working gcc.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import hashlib
import os
import platform
import re
import shutil
import stat
import subprocess
import tempfile
import time
from pathlib import Path

import casadi as ca

from mol_shell._core.atomic import too_large
from mol_shell._core.errors import ParameterError
from mol_shell._core.user_files import not_regular

#: the record appended to every cached library: its key, the image's size and digest (fixed length)
_RECORD = b"\n\0mol_shell-library key=%s size=%016d sha256=%s\n"
_RECORD_FORM = re.compile(rb"\n\0mol_shell-library key=([0-9a-f]{20}) size=(\d{16}) sha256=([0-9a-f]{64})\n")
RECORD_BYTES = len(_RECORD % (b"0" * 20, 0, b"0" * 64))
#: part of every cache key: libraries of the versions before the record are under other names (not "damaged")
RECORD_VERSION = "record-1"
#: images up to this size are digested whole (512 KiB: 0.6 ms measured, reading included), larger ones by their
#: first and last halves of it (a cut is caught by the size; a byte changed in the middle of a 300 MB Jacobian is not)
DIGEST_WHOLE = 1 << 19
#: the leftovers of a killed build (its private folders) are removed at a later build once they are this old
#: (seconds) and their process is gone
STALE_AFTER = 3600.0
#: a build's private folders: gcc's (``.<prefix>_<key>.<pid>.<random>``; older builds named no pid) and the
#: atomic rename's (``.<prefix>_<key>.so.<pid>.<hex>.part``, :mod:`mol_shell._core.atomic`)
_LEFTOVER = re.compile(r"\.[A-Za-z0-9_]+_[0-9a-f]{20}"
                       r"(?:\.so\.(\d+)\.[0-9a-f]+\.part|\.(\d+)\.[a-z0-9_]{8}|\.[a-z0-9_]{8})")
_ALLOWED = "a writable directory (created if missing)"
#: errno values that mean the disk is full, and that a file may not be written
_FULL = {errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC)}
_REFUSED = {errno.EACCES, errno.EPERM, errno.EROFS}


class CompilerError(ParameterError):
    """gcc failed (or is not on ``PATH``, :class:`CompilerMissing`): one line with gcc's own last lines."""

    def __init__(self, message, hint=""):
        super().__init__("gcc", None, "a C compiler on PATH that builds the kernel", hint, message=message)


class CompilerMissing(CompilerError):
    """No gcc on ``PATH``: ``what`` needs one (the routes that do not are named in the message)."""

    def __init__(self, what):
        super().__init__(
            f"gcc not found on PATH: building {what} needs a C compiler (install gcc, or add its folder to PATH); "
            "without one leapfrog, dop853-c, rk45-c and casadi-cvodes-c cannot run, and the others run in CasADi's "
            "virtual machine (jacobian=vm where they take a jacobian option)")


#: the environment variable that sets gcc's optimisation of the right-hand sides and stencils (1, 2, 3 or s)
OPT_VARIABLE = "MOL_SHELL_OPT_LEVEL"


def optimised(flags):
    """``flags`` with their ``-O3`` at ``$MOL_SHELL_OPT_LEVEL`` (1, 2, 3 or s for ``-Os``; unset: 3; else a
    ParameterError).

    Without ``-ffast-math`` (and with ``-ffp-contract=off``) gcc's levels may not reassociate or fuse floating-point
    operations, so a kernel is expected to give the same bits at each, and is tested to on x86-64
    (tests/discretization/test_opt_level.py); one caveat: a libm call whose argument a level finds constant may be
    folded to the correctly rounded value, which glibc's need not be (CasADi folds its constants before gcc sees
    them). Another level compiles faster and runs slower. The paper scene's right-hand side at n = 40 (gcc's seconds, then a leap-frog
    step's): ``-O3`` 2.7 s and 8.6 us, ``-O2`` 1.9 s and 1.05x, ``-Os`` 1.55 s and 1.1-1.2x, ``-O1`` 1.45 s and
    1.3-1.5x. The test suite builds at ``-Os`` (tests/conftest.py), where gcc took a third of its time; so may a
    session whose kernels are built often and run briefly.
    """
    text = os.environ.get(OPT_VARIABLE, "").strip()
    if not text or "-O3" not in flags:
        return tuple(flags)
    if text not in ("1", "2", "3", "s"):
        raise ParameterError.invalid(OPT_VARIABLE, text, "is not 1, 2, 3 or s",
                                     "1, 2, 3 or s (gcc's -O1, -O2, -O3 or -Os for the right-hand sides and stencils; "
                                     "unset for 3)")
    return tuple(f"-O{text}" if flag == "-O3" else flag for flag in flags)


def check_opt_level():
    """Refuse a ``$MOL_SHELL_OPT_LEVEL`` that :func:`optimised` would refuse, before any work: a command as it starts,
    a study before its cases (each case refused it, after the study had written its file)."""
    optimised(("-O3",))


@functools.cache
def machine_key(flags):
    """What a library built with gcc ``flags`` that hold ``-march=native`` depends on: the processor's model and
    instruction sets.

    Part of the cache key, so that a cache shared between machines (a network home directory) never hands
    one processor code for another's instructions; empty for portable flags.
    """
    if "-march=native" not in flags:
        return ""
    text = platform.machine() + platform.processor()
    with contextlib.suppress(OSError):
        lines = Path("/proc/cpuinfo").read_text().splitlines()
        text += "".join(sorted({line for line in lines if line.startswith(("model name", "flags", "Features"))}))
    return text


def _variable():
    text = os.environ.get("MOL_SHELL_CACHE", "").strip()
    return text, ("" if text else "the default cache; set MOL_SHELL_CACHE to a writable directory")


class CacheFull(ParameterError):
    """``MOL_SHELL_CACHE`` has no space left for a library: what can do without the library (the stresses after a
    run, :func:`mol_shell.runs.simulate.simulate`) catches it by this class and goes on without."""


def refusal(folder, problem, allowed=_ALLOWED, kind=ParameterError):
    """The :class:`ParameterError` (``kind``) that says ``MOL_SHELL_CACHE = folder <problem>`` (exit 2 on the command
    line); ``folder`` as bytes when its path is not UTF-8 (shown as ``b'/tmp/lat\\xe9'``)."""
    _, hint = _variable()
    return kind.invalid("MOL_SHELL_CACHE", folder if isinstance(folder, bytes) else str(folder), problem, allowed, hint)


def cache_dir():
    """``$MOL_SHELL_CACHE`` (default ``~/.cache/mol_shell``), created if missing; one that cannot be a writable
    directory, or whose path is not UTF-8 (CasADi loads libraries by a UTF-8 path: it found none and every run
    compiled twice, then failed), is refused naming the variable (a ParameterError: exit 2 on the command line)."""
    text, _ = _variable()
    path = Path(text).expanduser() if text else Path.home() / ".cache" / "mol_shell"
    try:
        str(path).encode("utf-8")
    except UnicodeEncodeError:
        raise refusal(os.fsencode(path), "is not a UTF-8 path (CasADi loads libraries by a UTF-8 path)",
                      "a writable directory whose path is UTF-8") from None
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        problem = "is a file" if isinstance(exc, FileExistsError) else f"cannot be created ({exc.strerror or exc})"
        raise refusal(path, problem) from None
    try:  # a probe: permission bits do not tell (root, read-only mounts, /proc)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as exc:
        raise refusal(path, f"cannot be written ({exc.strerror or exc})") from None
    return path


def said_by_cache(exc, folder, doing):
    """A full disk, a file larger than the process may write (``ulimit -f``), or a file the cache may not write, met
    while ``doing`` in ``folder``: the one-line :func:`refusal`; ``None`` for another error (raised as it is)."""
    if isinstance(exc, OSError) and exc.errno == errno.EFBIG:
        return refusal(folder, f"cannot be written ({doing}: {too_large(exc)})",
                       "a writable directory, and a file size limit (ulimit -f) that holds a library", CacheFull)
    if isinstance(exc, OSError) and exc.errno in _FULL:
        return refusal(folder, f"has no space left on device ({doing})", "a writable directory with free space",
                       CacheFull)
    if isinstance(exc, OSError) and exc.errno in _REFUSED:
        where = f": {exc.filename}" if exc.filename else ""
        return refusal(folder, f"cannot be written ({doing}: {exc.strerror or exc}{where})")
    return None


def build_failed(exc, folder, what, name):
    """The one-line error of a build of library ``name`` (of ``what``) in ``folder`` that ``exc`` stopped (gcc
    failed, a file could not be written), or ``None`` for another error (raised as it is). A cache folder removed
    during the build is said so, naming ``MOL_SHELL_CACHE`` (it surfaced as gcc's ``cannot open output file``, or a
    ``FileNotFoundError`` sealing the library: an internal error)."""
    if not os.path.isdir(folder):
        return refusal(folder, f"vanished while {name} was built in it (removed during the build): nothing was cached",
                       "a writable directory that stays while a run builds its kernels")
    if isinstance(exc, subprocess.CalledProcessError):
        return compiler_failed(exc.returncode, exc.stderr, what, folder)
    if isinstance(exc, FileNotFoundError) and exc.filename == "gcc":
        return CompilerMissing(what)
    return said_by_cache(exc, folder, f"building {name}")


def _tail(stderr):
    """gcc's last lines (of ``stderr``, bytes) on one line, and whether they say that its disk is full (or a file
    grew past the process's size limit, ``ulimit -f``)."""
    lines = [line.strip() for line in (stderr or b"").decode(errors="replace").splitlines() if line.strip()]
    tail = " / ".join(line[:200] for line in lines[-3:]) or "no message"
    return tail, any(words in line for line in lines
                     for words in ("No space left on device", "Disk quota exceeded", "File too large"))


def compiler_failed(returncode, stderr, what, folder):
    """gcc exited with ``returncode``: a :class:`CompilerError` with the last lines of its ``stderr`` (bytes), or the
    cache's :func:`refusal` (:class:`CacheFull`) when it ran out of space."""
    tail, full = _tail(stderr)
    if full and "File too large" in tail:
        return refusal(folder, f"cannot be written (gcc building {what}: {too_large(OSError(errno.EFBIG, ''))}: {tail})",
                       "a writable directory, and a file size limit (ulimit -f) that holds a library", CacheFull)
    if full:
        return refusal(folder, f"has no space left on device (gcc building {what}: {tail})",
                       "a writable directory with free space (gcc writes its temporary files to TMPDIR, too)", CacheFull)
    status = f"killed by signal {-returncode}" if returncode < 0 else f"exit status {returncode}"
    return CompilerError(f"gcc failed building {what} ({status}): {tail}")


def _digest(f, size):
    """SHA-256 of the first ``size`` bytes of the open file ``f`` (whole up to :data:`DIGEST_WHOLE`, else its ends)."""
    h = hashlib.sha256()
    f.seek(0)
    if size <= DIGEST_WHOLE:
        h.update(f.read(size))
    else:
        half = DIGEST_WHOLE // 2
        h.update(f.read(half))
        f.seek(size - half)
        h.update(f.read(half))
    return h.hexdigest()


def seal(path, key):
    """Append the record of ``key`` (the cache key, 20 hex digits) to gcc's output at ``path``."""
    with open(path, "r+b") as f:
        size = os.fstat(f.fileno()).st_size
        digest = _digest(f, size)
        f.seek(size)
        f.write(_RECORD % (key.encode(), size, digest.encode()))


#: :func:`damage`'s answer for a library not in the cache
MISSING = "missing"
#: :func:`damage`'s answer for a directory where the library goes (:func:`clear_directory` before a build)
DIRECTORY = "a directory, not a library"


def damage(path, key):
    """``None`` if the library at ``path`` is whole (its record names ``key``, its size and its digest), :data:`MISSING`
    if there is none, :data:`DIRECTORY` for a directory there, else why it is not (a short phrase, for the note that it
    is compiled again). Not a regular file (a FIFO, which ``open`` would wait on forever) is said without opening it."""
    try:
        if stat.S_ISDIR(os.lstat(path).st_mode):
            return DIRECTORY
        other = not_regular(path)  # a FIFO, a socket, a device: said without opening it
        if other:
            return other.removeprefix("is ")
        with open(path, "rb") as f:
            size = os.fstat(f.fileno()).st_size
            if size < RECORD_BYTES:
                return f"{size:,} bytes, too short for the record of its build: cut short"
            f.seek(size - RECORD_BYTES)
            found = _RECORD_FORM.fullmatch(f.read(RECORD_BYTES))
            if found is None:
                return f"{size:,} bytes and no record of its build at its end: cut short, or not written by mol_shell"
            if found[1].decode() != key:
                return f"the library of another kernel: its record names key {found[1].decode()}"
            image = int(found[2])
            if image != size - RECORD_BYTES:
                return f"{size:,} bytes where its record says {image + RECORD_BYTES:,}"
            if _digest(f, image) != found[3].decode():
                return "its bytes differ from the SHA-256 digest recorded at its build"
    except FileNotFoundError:
        return MISSING
    except OSError as exc:
        return f"it cannot be read: {exc.strerror or exc}"
    return None


def clear_directory(path):
    """Remove the directory at ``path`` where a library goes (the rename of a build cannot replace it), if it is
    empty; one that is not, or cannot be removed, is refused naming ``MOL_SHELL_CACHE`` and the path (nothing of
    it removed, nothing built)."""
    try:
        os.rmdir(path)
    except OSError as exc:
        why = "not empty" if exc.errno in (errno.ENOTEMPTY, errno.EEXIST) else exc.strerror or str(exc)
        raise refusal(path.parent, f"holds a directory where a library goes ({path}: {why})",
                      "a writable directory whose libraries are files (remove that directory)") from None


@contextlib.contextmanager
def locked(path):
    """An exclusive ``flock`` on ``path`` (created if missing) for the ``with`` block: concurrent builders of one
    library wait for the first. The file is opened for writing (NFS emulates ``flock`` by byte-range locks, and an
    exclusive one needs a file open for writing), else for reading, so another user's read-only lock file serves too
    on a local disk; where it cannot be opened or locked at all (no ``fcntl``, a file system without locks), the block
    runs unlocked: concurrent builders may then both compile, and the atomic rename keeps that safe."""
    fd = None
    for flags in (os.O_RDWR | os.O_CREAT, os.O_RDONLY | os.O_CREAT):
        try:
            fd = os.open(path, flags, 0o666)
            break
        except OSError:
            continue
    try:
        if fd is not None:
            try:
                import fcntl

                fcntl.flock(fd, fcntl.LOCK_EX)
            except (ImportError, OSError):  # no fcntl (Windows), or no locks here
                pass
        yield
    finally:
        if fd is not None:
            os.close(fd)


def log_build(folder, line):
    """Append ``line`` to the cache's ``builds.log``, where it can be (another user's log, a full disk: skipped)."""
    with contextlib.suppress(OSError), open(Path(folder) / "builds.log", "a") as log:
        log.write(line + "\n")


def _gone(pid):
    """Whether no process ``pid`` runs here (POSIX; elsewhere every process counts as running)."""
    if os.name != "posix" or pid == os.getpid():
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:  # another user's process
        return False
    return False


def sweep(folder, now=None):
    """Remove the private folders that killed builds left in ``folder`` (:data:`_LEFTOVER`), once they are
    :data:`STALE_AFTER` seconds old and the process named in them is gone (one ``scandir``: done at every build).
    Returns the names removed."""
    now = time.time() if now is None else now
    removed = []
    with contextlib.suppress(OSError), os.scandir(folder) as entries:
        for entry in entries:
            found = _LEFTOVER.fullmatch(entry.name)
            if found is None:
                continue
            try:
                young = now - entry.stat(follow_symlinks=False).st_mtime < STALE_AFTER
                if young or not entry.is_dir(follow_symlinks=False):
                    continue
            except OSError:
                continue
            pid = found[1] or found[2]
            if pid is None or _gone(int(pid)):
                shutil.rmtree(entry.path, ignore_errors=True)
                removed.append(entry.name)
    return removed


def library(source, prefix, flags, link=()):
    """``(path, key)``: where the library of C ``source`` built with gcc ``flags`` (``link`` after the source) is
    cached in :func:`cache_dir` (``<prefix>_<key>.so``), and its key: a hash of them, of CasADi's version, of the
    processor where the flags need it (:func:`machine_key`) and of the record's version."""
    key = hashlib.sha256((source + " ".join(flags) + " ".join(link) + ca.__version__ + machine_key(tuple(flags))
                          + RECORD_VERSION).encode()).hexdigest()[:20]
    return cache_dir() / f"{prefix}_{key}.so", key


def unavailable(source, prefix, flags, link=()):
    """Why the library of ``source`` (as :func:`library` names it) cannot be had here, or ``None`` where it can: it
    is in the cache and whole (its record checked, :func:`damage`: it is loaded, without gcc, wherever it was built),
    or a working gcc builds it (:func:`gcc_problem`: its reason otherwise). Only a build needs gcc: what a default or
    a fallback follows (the ``jacobian`` default, the SUNDIALS driver, the leap-frog's stencil) asks this."""
    lib, key = library(source, prefix, flags, link)
    return None if damage(lib, key) is None else gcc_problem()


def have_gcc():
    """Whether ``gcc`` is on ``PATH``."""
    return shutil.which("gcc") is not None


#: seconds the probe of :func:`gcc_problem` may take (a gcc that hangs is one that does not work)
PROBE_TIMEOUT = 60.0
#: the probe's source: a library of one function, as the kernels are built (``-fPIC -shared``)
_PROBE = "int ms_probe(void) { return 0; }\n"


@functools.cache
def _probe(gcc):
    """Why the gcc at ``gcc`` cannot build a shared library (its last lines), or ``None`` where it can; once per
    process and gcc (about 20 ms), in a temporary folder outside the cache."""
    try:
        with tempfile.TemporaryDirectory(prefix="mol_shell_probe.") as tmp:
            src = Path(tmp, "probe.c")
            src.write_text(_PROBE)
            done = subprocess.run([gcc, "-fPIC", "-shared", str(src), "-o", str(Path(tmp, "probe.so"))],
                                  stdin=subprocess.DEVNULL, capture_output=True, timeout=PROBE_TIMEOUT, check=False)
    except subprocess.TimeoutExpired:
        return f"gcc did not build a probe library in {PROBE_TIMEOUT:g} s"
    except OSError as exc:
        return f"gcc could not be run ({exc.strerror or exc})"
    if done.returncode == 0:
        return None
    status = f"killed by signal {-done.returncode}" if done.returncode < 0 else f"exit status {done.returncode}"
    return f"gcc failed building a probe library ({status}): {_tail(done.stderr)[0]}"


def gcc_problem():
    """Why no working gcc is at hand (``"gcc not found on PATH"``, or the failure of a probe build with gcc's last
    lines), or ``None`` where ``gcc`` on ``PATH`` builds a shared library (:func:`_probe`, cached per process and
    gcc): what decides a default that needs one (``jacobian``) before any kernel is built."""
    gcc = shutil.which("gcc")
    return "gcc not found on PATH" if gcc is None else _probe(gcc)
