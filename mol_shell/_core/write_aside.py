"""A file for writers that cannot survive a failed write: HDF5 (through h5py) on a full disk.

A write that fails under HDF5 (``ENOSPC``) leaves its objects unable to close: every later release of one of them
retries the write and prints ``Exception ignored in: 'h5py._objects.ObjectID.__dealloc__'`` (an XDMF export to a
full disk printed 5,000 of them), and the process ends in a segmentation fault at its exit (exit code 139).
:class:`WriteAside` is the file such a writer is given instead of a path (h5py takes a Python file object): its
writes go to the file until the first one fails, then aside, to memory, with the reads seeing them there, so the
writer never sees a failure and closes cleanly; the writer's caller asks :meth:`WriteAside.check` between its steps,
which raises the failure (an ``OSError``, its ``errno`` as the system gave it). The file is then incomplete and is
for discarding (:func:`mol_shell._core.atomic.staged` removes it). What goes aside is what the writer writes between
the failure and the next check, and what it flushes at its close.
"""

from __future__ import annotations

import io


class WriteAside(io.RawIOBase):
    """A binary file at ``path`` (created, or emptied) whose failed write, and all writes after it, go to memory;
    :meth:`check` raises that failure. Seekable, readable and writable (what h5py's file-object driver calls)."""

    def __init__(self, path):
        super().__init__()
        self._file = open(path, "w+b", buffering=0)  # noqa: SIM115 - closed by close()
        #: the first write (or truncation) that failed (an OSError), or None
        self.error = None
        self._aside = []  # (offset, bytes) written after the failure, in order
        self._pos = 0
        self._size = 0

    def readable(self):
        return True

    def writable(self):
        return True

    def seekable(self):
        return True

    def tell(self):
        return self._pos

    def seek(self, offset, whence=io.SEEK_SET):
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self._pos, io.SEEK_END: self._size}[whence]
        if base + offset < 0:
            raise OSError(22, "Invalid argument: a negative position")
        self._pos = base + offset
        return self._pos

    def write(self, data):
        view = memoryview(data).cast("B")
        done = 0
        if self.error is None:
            try:
                self._file.seek(self._pos)
                while done < len(view):  # a write cut short by a full disk returns less; the next one raises
                    done += self._file.write(view[done:])
            except OSError as exc:
                self.error = exc
        if done < len(view):
            self._aside.append((self._pos + done, bytes(view[done:])))
        self._pos += len(view)
        self._size = max(self._size, self._pos)
        return len(view)

    def readinto(self, buffer):
        view = memoryview(buffer).cast("B")
        n = max(0, min(len(view), self._size - self._pos))
        got = 0
        self._file.seek(self._pos)
        while got < n:
            k = self._file.readinto(view[got:n])
            if not k:
                break
            got += k
        view[got:n] = bytes(n - got)  # past the file's end (what went aside extends it): zeros, as a hole reads
        for offset, data in self._aside:  # what went aside, over the file's bytes, later writes last
            lo, hi = max(offset, self._pos), min(offset + len(data), self._pos + n)
            if lo < hi:
                view[lo - self._pos:hi - self._pos] = data[lo - offset:hi - offset]
        self._pos += n
        return n

    def truncate(self, size=None):
        size = self._pos if size is None else int(size)
        if self.error is None:
            try:
                self._file.truncate(size)
            except OSError as exc:
                self.error = exc
        self._aside = [(offset, data[:max(0, size - offset)]) for offset, data in self._aside if offset < size]
        self._size = size
        return size

    def flush(self):
        """Nothing to flush: the file is unbuffered, and what went aside stays in memory."""

    def close(self):
        if not self.closed:
            self._file.close()
            self._aside = []
        super().close()

    def check(self):
        """Raise the failure of a write (an ``OSError``) if there was one."""
        if self.error is not None:
            raise self.error
