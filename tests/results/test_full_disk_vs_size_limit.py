"""A full disk under a file-size limit is said as a full disk: a write cut short by ``ulimit -f`` fills the file up to
the limit, so a file far below it (64 KB under a limit of 900 KB) did not meet the limit; an ENOSPC says itself."""

from __future__ import annotations

import errno

import pytest

from mol_shell._core import atomic

LIMIT = 900 * 1024


@pytest.fixture
def limited(monkeypatch):
    monkeypatch.setattr(atomic, "size_limit", lambda: LIMIT)


@pytest.mark.parametrize("size,said", [(64 * 1024, False), (LIMIT - 1024, True), (LIMIT, True)])
def test_a_file_far_below_the_limit_did_not_meet_it(limited, tmp_path, size, said):
    (tmp_path / "part.nc").write_bytes(b"\0" * size)
    reason = atomic.too_large(RuntimeError("NetCDF: HDF error"), tmp_path)  # netCDF's error keeps no errno
    assert (reason is not None) == said


def test_an_enospc_is_a_full_disk_even_at_the_limit(limited, tmp_path):
    (tmp_path / "part.nc").write_bytes(b"\0" * LIMIT)
    with pytest.raises(atomic.NoSpaceError) as refused:
        atomic._if_full(OSError(errno.ENOSPC, "No space left on device"), tmp_path / "a.nc", tmp_path)
    assert refused.value.errno == errno.ENOSPC and "No space left" in refused.value.strerror
