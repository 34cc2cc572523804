"""Output paths, checked before anything is computed: a place that can be written, names the file system takes.

Every command's ``-o`` (and the Python functions' ``path`` or ``output``) goes through :func:`writable_path` before
the work starts, so a run is never lost to a file that could not be written at its end: a symbolic link is written
through (its target replaced, :func:`link_target`), its missing directories are created, and a directory where the file would stand, a suffix the writer does not write, a place without write
permission, or a name longer than its file system takes (:func:`check_lengths`) is refused in one line naming the
parameter.
"""

from __future__ import annotations

import os
from pathlib import Path

from mol_shell._core.atomic import SHORT_PART_BYTES, limits, up_out_of
from mol_shell._core.errors import ParameterError
from mol_shell._core.user_files import not_regular

#: what every refusal of :func:`writable_path` allows
ALLOWED = "a file path in a writable place (missing directories are created)"


def check_lengths(path, name="path", value=None, what=""):
    """Refuse, naming ``name = value`` (``value``: ``path``), a ``path`` with a name (of a directory or the file)
    longer than its file system takes, or longer as a whole than a file written through a temporary directory beside
    it can be (:func:`mol_shell._core.atomic.staged`: the path, ``/`` and
    :data:`~mol_shell._core.atomic.SHORT_PART_BYTES`). ``what``: what ``path`` is to ``value`` where it is another
    file (``"writes 'run_0000.vtu' beside it"``). The limits are the file system's (``os.pathconf`` of the nearest
    directory that exists): 255 bytes a name and 4096 a path on Linux's. Without this check such a name failed when
    the file was written, after the run (``OSError: [Errno 36] File name too long``, an internal error, the run
    lost)."""
    path = Path(path)
    value = path if value is None else value
    subject = f"{what}, with" if what else "has"
    longest_name, longest_path = limits(path.parent)
    for part in path.parts:
        size = len(os.fsencode(part))
        if size > longest_name and part != path.anchor:
            kind = "file name" if part == path.name else "directory name" + ("" if what else f" {part!r}")
            raise ParameterError.invalid(name, str(value), f"{subject} a {kind} of {size} bytes, more than the "
                                         f"{longest_name} its file system takes", f"{ALLOWED}, each name in it of "
                                         f"at most {longest_name} bytes", hint="give a shorter name")
    size, most = len(os.fsencode(str(path))), longest_path - SHORT_PART_BYTES - 2  # "/" and the final NUL
    if size > most:
        raise ParameterError.invalid(name, str(value), f"{subject} a path of {size} bytes, more than the {most} a file "
                                     "written through a temporary directory beside it can be (the file system's "
                                     f"longest path: {longest_path} bytes)", f"{ALLOWED}, of at most {most} bytes",
                                     hint="give a shorter path")


#: the most symbolic links :func:`link_target` follows (Linux's ``MAXSYMLINKS``)
MAX_LINKS = 40


def link_target(path, name="path"):
    """``path``, or where it is a symbolic link, the file it points to (its links followed, each relative to its own
    folder), which a write replaces, as a shell's ``>`` writes through a link: the atomic rename onto the link's name
    replaced the link by a regular file and left its target with the old data, and a dangling link was refused as
    ``cannot be written (File exists)``. A chain of more than :data:`MAX_LINKS` links (a loop) is refused naming
    ``name``."""
    given = path = Path(path)
    for _ in range(MAX_LINKS):
        try:
            if not os.path.islink(path):
                return path
            path = path.parent / os.readlink(path)
        except OSError:  # a folder on the way that cannot be read: the probe of writable_path says why
            return path
    raise ParameterError.invalid(name, str(given), f"is a chain of more than {MAX_LINKS} symbolic links (a loop)",
                                 ALLOWED)


def beside(path, tail, stem=None, named_inside=False):
    """The file ``<stem><tail>`` written beside the output ``path`` (``~`` expanded): a figure's ``.png`` or a table's
    ``.md`` beside a comparison, a study's ``.cases`` folder, an export's ``.h5`` or ``_NNNN.vtu``; ``stem``: the
    name's stem where it is not the output's own.

    Where ``path`` is a symbolic link (the output itself is written through it: :func:`link_target`), the files
    beside it go beside the link, in its folder and named by its stem: the user named the link and looks for them
    there, and the command line checks them there before the work. Those the output names inside itself by a relative
    name (``named_inside``: an ``.xdmf``'s ``.h5``, a ``.pvd``'s steps) go beside the file written, the link's
    target, named by its stem: readers look for them beside the file they read with the link resolved (meshio's
    reader, the XDMF library's ``realpath``), and it reads so by any name. (``export`` checked its ``.h5`` beside the
    link and wrote it beside the target, its note naming the one it did not write; a study script put its ``.md``
    and ``.png`` beside the target, the command line beside the link.)"""
    path = Path(os.fspath(path)).expanduser()
    if named_inside:
        path = link_target(path)
    return path.with_name(f"{path.stem if stem is None else stem}{tail}")


def writable_path(path, name="path", suffixes=None, created=None):
    """Check, before anything is computed, that ``path`` can be written; create its missing directories.

    Parameters
    ----------
    path : str or os.PathLike
        The file to be written (an existing file is replaced).
    name : str
        How the message names the parameter (``-o`` on the command line).
    suffixes : collection of str, optional
        Allowed file name suffixes without the dot (e.g. image formats).
    created : list, optional
        Directories made here are appended (outermost first), so a caller can remove them again.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ParameterError
        Empty path, a name longer than the file system takes (:func:`check_lengths`), an existing directory, a
        suffix outside ``suffixes``, a ``..`` out of a directory that is not there
        (:func:`~mol_shell._core.atomic.up_out_of`), a directory that cannot be created, or a place without write
        permission.
    """
    allowed = ALLOWED
    if path is None or not str(path).strip():
        raise ParameterError.invalid(name, "" if path is None else str(path), "is empty", allowed)
    if not isinstance(path, (str, os.PathLike)):
        raise ParameterError.not_a(name, path, "a file path", allowed)
    path = Path(os.fspath(path)).expanduser()
    check_lengths(path, name)  # before any look at the path: the system refuses a name too long there too
    given, path = path, link_target(path, name)  # a symbolic link: its target written (a dangling link's created)
    link = f"is a symbolic link to {str(path)!r}, which " if path != given else ""
    if link:
        check_lengths(path, name, given, link.removesuffix(", which "))
    if os.path.isdir(path):
        raise ParameterError.invalid(name, str(given), f"{link}is a directory", allowed)
    if suffixes is not None:
        suffix = path.suffix.lower().lstrip(".")
        if suffix not in suffixes:
            raise ParameterError.invalid(name, str(given), f"{link}ends in .{suffix}, a kind of file this command does "
                                         "not write" if suffix else f"{link}has no suffix",
                                         "a file ending in one of ." + ", .".join(sorted(suffixes)))
    folder = path.parent
    above = up_out_of(path)  # sub/../x.nc without sub: the system's refusal (open), not "cannot create 'sub/..'"
    if above is not None:
        raise ParameterError.invalid(name, str(path), f"cannot be written: {str(above)!r} "
                                     f"{'is not a directory' if above.exists() else 'does not exist'}, and the path "
                                     "goes back out of it with '..' (which the system resolves only in a directory "
                                     "that exists)", allowed, hint=("" if above.exists() else f"create {str(above)!r} "
                                                                    "first, or ") + f"leave out '{above.name}/..'")
    missing = [p for p in [folder, *folder.parents] if not os.path.exists(p)][::-1]
    try:
        for p in missing:
            p.mkdir()
            if created is not None:
                created.append(p)
    except OSError as exc:
        raise ParameterError.invalid(name, str(path), f"cannot be written: cannot create directory {str(folder)!r} "
                                     f"({exc.strerror or exc})", allowed) from None
    if not os.path.isdir(folder):
        raise ParameterError.invalid(name, str(path), f"cannot be written: {str(folder)!r} is not a directory", allowed)
    problem = not_regular(path)  # a named pipe: the probe's open waited for a reader, deaf to Ctrl-C's handler
    if problem:
        raise ParameterError.invalid(name, str(path), problem, allowed)
    try:  # a probe: permission bits do not tell (root, read-only mounts, /proc)
        if os.path.exists(path):
            with open(path, "ab"):
                pass
        else:
            with open(path, "xb"):
                pass
            path.unlink()
    except OSError as exc:
        raise ParameterError.invalid(name, str(path), f"cannot be written ({exc.strerror or exc})", allowed) from None
    return path
