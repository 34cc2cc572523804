"""An XDMF export to a full disk stops in one line: HDF5 never sees the failed write, so its objects close cleanly
(h5py printed thousands of "Exception ignored" tracebacks, then the process died of a segmentation fault)."""

import errno
import gc
import io
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mol_shell
from mol_shell._core.atomic import NoSpaceError
from mol_shell.views import export as exporting

try:
    from mol_shell._core import write_aside
except ImportError:  # each test below fails on its own where the module is missing
    write_aside = None

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The paper's scene on 8 nodes over 10 us (11 saved times), without stresses, and its file."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False)
    path = tmp_path_factory.mktemp("full") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path


def _disk_of(limit):
    """A file class whose files take ``limit`` bytes in all, as a disk that fills: a write past it writes what fits
    and fails with ENOSPC (as write(2) does)."""
    used = [0]

    class Disk(io.FileIO):
        def write(self, data):
            data = memoryview(data).cast("B")
            room = max(0, limit - used[0])
            if not room:
                raise OSError(errno.ENOSPC, "No space left on device")
            done = super().write(data[:room])
            used[0] += done
            return done

    return Disk


def test_hdf5_never_sees_a_full_disk_and_closes_cleanly(run, tmp_path, monkeypatch):
    """The export's HDF5 file on a disk that fills at 20 kB (of about 100 kB): the failure is raised as ENOSPC at the
    next step (the staging says it in one line naming the file and removes everything), and nothing is left for
    h5py to retry: no error is ever raised where Python can only print it ("Exception ignored")."""
    ds, _ = run
    disk = _disk_of(20_000)
    monkeypatch.setattr(write_aside, "open", lambda path, mode, buffering: disk(path, "w+"), raising=False)
    ignored = []
    monkeypatch.setattr(sys, "unraisablehook", ignored.append)
    target = tmp_path / "out" / "shell.xdmf"
    with pytest.raises(NoSpaceError, match="No space left on device") as raised:
        exporting.export(ds, target, n_phi=8)
    assert raised.value.errno == errno.ENOSPC and raised.value.filename == str(target)
    del raised
    gc.collect()  # the h5py objects of the failed export: released, and nothing to write at their release
    assert ignored == []
    assert list((tmp_path / "out").iterdir()) == []


def test_write_aside_reads_what_went_aside_over_the_files_bytes(tmp_path, monkeypatch):
    """After the failure the file is the bytes written before it with what went aside over them (what HDF5 reads
    back while it closes): checked against the same writes into memory."""
    monkeypatch.setattr(write_aside, "open", lambda path, mode, buffering: _disk_of(10)(path, "w+"), raising=False)
    writes = [(0, b"abcdefgh"), (4, b"XYZW1234"), (20, b"tail"), (2, b"--")]
    expected = bytearray()
    with write_aside.WriteAside(tmp_path / "f") as f:
        for at, data in writes:
            f.seek(at)
            assert f.write(data) == len(data)
            expected[len(expected):at] = bytes(max(0, at - len(expected)))
            expected[at:at + len(data)] = data
        assert isinstance(f.error, OSError) and f.error.errno == errno.ENOSPC
        f.seek(0)
        assert f.read() == bytes(expected)
        assert (tmp_path / "f").read_bytes() == b"abcdXYgh"  # the 10 bytes the disk took: 8, and 2 of the next write
        f.truncate(6)
        f.seek(0, io.SEEK_END)
        assert f.tell() == 6 and (f.seek(0), f.read())[1] == bytes(expected[:6])
        with pytest.raises(OSError, match="No space left"):
            f.check()


@pytest.mark.skipif(shutil.which("unshare") is None, reason="unshare (util-linux) mounts a small file system")
def test_an_xdmf_export_to_a_full_file_system_says_so_in_one_line(run, tmp_path):
    """A real full file system: a 64 kB tmpfs, mounted in a user namespace of its own (skipped where the system allows
    none). The export printed 5,000 lines of h5py's "Exception ignored" tracebacks after its one line, then died of a
    segmentation fault (exit code 139); now the one line, exit code 2, and nothing left on the file system."""
    _, path = run
    small = tmp_path / "small"
    small.mkdir()
    if subprocess.run(["unshare", "-rm", "sh", "-c", f"mount -t tmpfs -o size=64k none {small}"],
                      capture_output=True, check=False).returncode:
        pytest.skip("no user namespaces here to mount a small file system in")
    script = (f"mount -t tmpfs -o size=64k none {small} && {sys.executable} -m mol_shell export {path} "
              f"-o {small}/shell.xdmf; code=$?; ls -A {small}; exit $code")
    done = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=120,
                          check=False, env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1"})
    assert done.returncode == 2, (done.returncode, done.stderr[-600:])
    assert done.stderr.splitlines() == [(f"mol-shell: error: -o = '{small}/shell.xdmf' cannot be written: No space "
                                         f"left on device ('{small}' has 0 bytes free); nothing was written")]
    assert done.stdout == ""  # ls: the file system empty
