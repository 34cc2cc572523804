"""Reading a file a user names (a scene file, a meridian's table of points): a regular file of bounded size.

A device, a named pipe or a socket given where a file is read was read without limit (``points = "/dev/zero"``
grew to 22 GB and was killed; a named pipe nobody writes to hung the run silently): :func:`read_user_file` looks at
what the path is before opening it (a named pipe is never opened), refuses anything but a regular file and a file
larger than :data:`MAX_USER_FILE_BYTES`, and reads at most that many bytes (a file that grows as it is read too).
"""

from __future__ import annotations

import errno
import os
import re
import stat

#: the largest file a command reads as a user's text (a scene file, a table of points): 64 MB holds some two million
#: rows of ``r z``, far beyond any meridian a run can take (a run's nodes are at most some thousands)
MAX_USER_FILE_BYTES = 64_000_000
#: how the bound is said in a message
MAX_USER_FILE_TEXT = f"{MAX_USER_FILE_BYTES / 1e6:g} MB"

_KINDS = ((stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a directory"))


class UserFileError(OSError):
    """A file a user named that is no regular file, or is larger than :data:`MAX_USER_FILE_BYTES`: an ``OSError``
    (callers that say a file cannot be read say it by its ``strerror``: ``it is a character device, not a regular
    file``) whose ``problem`` completes a message ``points = '/dev/zero' ...``: ``is a character device, not a
    regular file``."""

    def __init__(self, code, problem):
        self.problem = problem
        super().__init__(code, f"it {problem}")


def _kind(mode):
    """What a file of mode ``mode`` (not a regular file) is, in words."""
    return next((words for test, words in _KINDS if test(mode)), "not a regular file")


def not_regular(path):
    """How a path that exists but is no regular file is refused (``is a named pipe (FIFO), not a regular file``),
    found without opening it; ``None`` for a regular file or a path that is not there (or cannot be looked at)."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return None
    return None if stat.S_ISREG(mode) else f"is {_kind(mode)}, not a regular file"


#: a byte of a file name that is not UTF-8, as :func:`name_text` writes it (``\\xfc``)
_ESCAPED_BYTE = re.compile(r"\\x([89a-f][0-9a-f])")


def name_text(text):
    """``text`` as UTF-8 can hold it (a netCDF attribute, a scene file): a file name's bytes that are not UTF-8 (held
    as surrogates, ``'lat\\udcfc.txt'``: netCDF4 refused them with a ``UnicodeEncodeError`` after the run) as
    ``\\xfc``, the escape Python writes for them (``os.fsencode``, then ``backslashreplace``); ``text`` itself where
    it is UTF-8. :func:`name_from_text` reads such a name back."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return os.fsencode(text).decode("utf-8", "backslashreplace")
    return text


def name_from_text(text):
    """The file name ``text`` holds (:func:`name_text`): ``text`` where a file of that name exists, else its escaped
    bytes (``\\xfc``) back as the name's own where a file of that name exists; ``text`` otherwise."""
    if not isinstance(text, str) or not _ESCAPED_BYTE.search(text) or os.path.lexists(text):
        return text
    name = _ESCAPED_BYTE.sub(lambda m: chr(0xDC00 + int(m[1], 16)), text)
    return name if os.path.lexists(name) else text


def absent(path):
    """Why no file can be read at ``path``: ``"does not exist"`` (nor its folder), ``"cannot be read (File name too
    long)"`` where the system refuses to look (a name longer than its file system takes: ``Path.exists`` raised that,
    an internal error), or ``None`` where something is there."""
    try:
        os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return "does not exist"
    except (OSError, ValueError) as exc:
        return f"cannot be read ({getattr(exc, 'strerror', None) or exc})"
    return None


def read_user_file(path, limit=MAX_USER_FILE_BYTES):
    """The bytes of the file at ``path``, a regular file of at most ``limit`` bytes.

    Raises
    ------
    UserFileError
        ``path`` is a named pipe, a device, a socket or a directory (found before it is opened), or holds more than
        ``limit`` bytes.
    OSError
        It cannot be read otherwise (missing, no permission, a name too long).
    """
    mode = os.stat(path).st_mode  # follows symbolic links: a link to /dev/zero is a device
    if not stat.S_ISREG(mode):
        raise UserFileError(errno.EINVAL, f"is {_kind(mode)}, not a regular file")
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # replaced by a pipe since: not waited on
    with os.fdopen(fd, "rb") as file:
        info = os.fstat(file.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise UserFileError(errno.EINVAL, f"is {_kind(info.st_mode)}, not a regular file")
        bound = MAX_USER_FILE_TEXT if limit == MAX_USER_FILE_BYTES else f"{limit} bytes"
        too_large = UserFileError(errno.EFBIG, f"is larger than {bound}, the most a file read as a scene file or a "
                                  "table of points may hold")
        if info.st_size > limit:
            raise too_large
        data = file.read(limit + 1)
    if len(data) > limit:
        raise too_large
    return data
