"""A standard descriptor the caller closed (``2>&-``) is held by /dev/null when the program starts: otherwise the first
file the command opens (a netCDF file being written) takes number 2, and C libraries' messages to stderr would be
written into it."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest


@pytest.mark.parametrize("closed", [[2], [1, 2], [0, 1, 2]])
def test_closed_standard_descriptors_are_held_by_dev_null(closed, tmp_path):
    probe = textwrap.dedent(f"""
        import os
        for fd in {closed}:
            os.close(fd)
        from mol_shell.cli.main import hold_closed_descriptors
        hold_closed_descriptors()
        first = os.open({str(tmp_path / "data.nc")!r}, os.O_WRONLY | os.O_CREAT)  # a file the command would write
        with open({str(tmp_path / "where.txt")!r}, "w") as out:
            out.write(chr(10).join([*(os.readlink(f"/proc/self/fd/{{fd}}") for fd in (0, 1, 2)), str(first)]))
    """)
    subprocess.run([sys.executable, "-c", probe], check=True, timeout=60)
    *standard, first = (tmp_path / "where.txt").read_text().split("\n")
    assert all(target == "/dev/null" for fd, target in enumerate(standard) if fd in closed), standard
    assert int(first) > 2  # the data file took no standard number
