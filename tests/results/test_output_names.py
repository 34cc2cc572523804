"""Output files whose names are legal but long, not UTF-8, or on a full disk: written, or refused in one line.

A new user's probe: an ``-o`` name of 235 to 255 bytes passed the check and failed after the whole run (the hidden
``.NAME.<pid>.<hex>.part`` directory it is written in is 21 bytes longer: ``OSError: [Errno 36] File name too long``,
an internal error, the run lost); one over 255 bytes was an internal error too (``path.is_dir()``); a name that is
not UTF-8 failed after the run in netCDF4's ``_strencode`` (``UnicodeEncodeError``); a full disk ended a finished
run in ``internal error: RuntimeError: NetCDF: HDF error``, nothing saying the disk was full.
"""

import errno
import io
import os
import sys
import types
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell._core import atomic
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf, write_netcdf

RUN = ["run", "twisted-cylinder", "--n", "5", "--t-end", "1e-6", "--no-stresses"]


def _name_max(folder):
    try:
        return os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return 255


def _small():
    return xr.Dataset({"r": (("time", "s"), np.arange(12.0).reshape(3, 4))},
                      coords={"time": [0.0, 0.5, 1.0], "s": np.linspace(0, 1, 4)})


def _errors(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]


def _left(folder):
    """Everything in ``folder`` (hidden temporaries included), as names."""
    return sorted(p.name for p in Path(folder).iterdir())


def _non_utf8(folder, name):
    """``folder / name`` with ``name`` holding the byte 0xe9 (Latin-1 ``é``), as the system decodes it; skipped where
    the file system takes only UTF-8 names."""
    path = Path(folder) / os.fsdecode(name.encode().replace(b"@", b"\xe9"))
    try:
        path.touch()
        path.unlink()
    except (OSError, UnicodeError):
        pytest.skip("this file system takes only UTF-8 names")
    return path


def test_a_name_as_long_as_the_file_system_takes_is_written_by_a_run(tmp_path, capsys):
    """A name of exactly NAME_MAX bytes (255 on Linux): the run is written under it (its temporary directory is a
    short one), where it failed after the run."""
    longest = _name_max(tmp_path)
    out = tmp_path / ("b" * (longest - 3) + ".nc")
    assert len(os.fsencode(out.name)) == longest
    assert main([*RUN, "-o", str(out)]) == 0, _errors(capsys)
    assert read_netcdf(out).sizes["s"] == 5
    assert _left(tmp_path) == [out.name]


@pytest.mark.parametrize("command, extra", [("run", ()), ("plot", ("--figure", "history"))])
def test_a_name_longer_than_the_file_system_takes_is_refused_up_front_naming_o(tmp_path, capsys, command, extra):
    """Over NAME_MAX bytes: one line naming -o, the name's size and the limit, exit 2, before the work."""
    longest = _name_max(tmp_path)
    suffix = ".nc" if command == "run" else ".png"
    out = tmp_path / ("b" * (longest + 4 - len(suffix)) + suffix)  # 4 bytes too long
    args = [*RUN] if command == "run" else ["plot", str(tmp_path / "missing.nc"), *extra]
    assert main([*args, "-o", str(out)]) == 2
    err = _errors(capsys)
    assert len(err) == 1 and err[0].startswith(f"mol-shell: error: -o = '{out}' has a file name of {longest + 4} "
                                               f"bytes, more than the {longest} its file system takes"), err
    assert _left(tmp_path) == []


def test_a_study_whose_cases_folder_name_would_be_too_long_is_refused_naming_o(tmp_path, capsys):
    """``S.nc`` keeps its cases in ``S.cases``, 3 bytes longer: an ``-o`` of NAME_MAX bytes is refused before any
    case runs, naming -o and that folder."""
    longest = _name_max(tmp_path)
    out = tmp_path / ("s" * (longest - 3) + ".nc")
    code = main(["study", "twisted-cylinder", "--vary", "gamma=0.1", "--n", "5", "--t-end", "1e-6", "--workers", "1",
                 "-o", str(out)])
    err = _errors(capsys)
    assert code == 2 and len(err) == 1, err
    assert f"keeps its finished cases in '{'s' * (longest - 3)}.cases', with a directory name of {longest + 3} " \
           f"bytes, more than the {longest}" in err[0]
    assert _left(tmp_path) == []


def test_an_export_whose_step_files_would_have_names_too_long_is_refused_naming_o(tmp_path, capsys):
    """``E.pvd`` writes ``E_0000.vtu`` beside it, 5 bytes longer."""
    run = tmp_path / "run.nc"
    write_netcdf(mol_shell.simulate("twisted-cylinder", n=5, times=[0, 1e-6], progress=False), run)
    longest = _name_max(tmp_path)
    out = tmp_path / ("e" * (longest - 4) + ".pvd")
    assert main(["export", str(run), "-o", str(out)]) == 2
    err = _errors(capsys)
    assert len(err) == 1 and f"writes '{'e' * (longest - 4)}_0000.vtu' beside it, with a file name of " \
                               f"{longest + 5} bytes" in err[0], err
    assert _left(tmp_path) == ["run.nc"]


def test_a_file_name_that_is_not_utf8_is_written_and_read_back(tmp_path):
    """netCDF's library encodes its paths as UTF-8: the file is written under a stand-in name and renamed."""
    path = _non_utf8(tmp_path, "lat@1.nc")
    write_netcdf(_small(), path)
    assert _left(tmp_path) == [path.name]
    np.testing.assert_array_equal(read_netcdf(path).r.values, np.arange(12.0).reshape(3, 4))


def test_a_directory_whose_name_is_not_utf8_takes_a_netcdf_file(tmp_path):
    folder = _non_utf8(tmp_path, "r@sultats")
    path = folder / "run.nc"
    write_netcdf(_small(), path)
    assert _left(folder) == ["run.nc"]
    np.testing.assert_array_equal(read_netcdf(path).r.values, np.arange(12.0).reshape(3, 4))


def test_a_run_to_a_name_that_is_not_utf8_says_so_on_a_strict_stream(tmp_path, monkeypatch):
    """The run is written, and its summary line shows the name's byte as Python's repr does (a locale whose standard
    output is strict UTF-8 raised UnicodeEncodeError there)."""
    out = _non_utf8(tmp_path, "r@.nc")
    stream = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict")
    monkeypatch.setattr(sys, "stdout", stream)
    assert main([*RUN, "-o", str(out)]) == 0
    stream.flush()
    said = stream.buffer.getvalue().decode()
    assert said.startswith(f"wrote {tmp_path}/r\\udce9.nc: ") and read_netcdf(out).sizes["s"] == 5


def _full(monkeypatch, folder, free=0):
    """``os.statvfs`` saying ``folder`` has ``free`` bytes left (as a full file system does after a failed write)."""
    real = os.statvfs

    def statvfs(path):
        if Path(path) == Path(folder):
            return types.SimpleNamespace(f_bavail=free // 4096, f_frsize=4096, f_files=1000, f_favail=900)
        return real(path)

    monkeypatch.setattr(os, "statvfs", statvfs)


def test_netcdfs_hdf_error_on_a_full_disk_is_said_in_one_line_naming_o(tmp_path, monkeypatch, capsys):
    """netCDF4 raises ``RuntimeError: NetCDF: HDF error`` when HDF5's write fails for want of space (measured on a
    full tmpfs: 0 bytes were free after it). The run ends in one line naming -o, saying the disk is full and that
    nothing was written; no temporary left; exit 2 (a place that cannot be written, not a bug)."""
    def to_netcdf(self, path, *args, **kwargs):
        Path(path).write_bytes(b"\x89HDF\r\n\x1a\n half a file")
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    _full(monkeypatch, tmp_path / "sub")
    out = tmp_path / "sub" / "run.nc"
    assert main([*RUN, "-o", str(out)]) == 2
    err = _errors(capsys)
    assert err == [(f"mol-shell: error: -o = '{out}' cannot be written: No space left on device ('{tmp_path}/sub' "
                    "has 0 bytes free); nothing was written")]
    assert _left(tmp_path) == []  # the directory made for -o is gone again, and the temporary with it


def test_an_enospc_of_a_writer_is_a_no_space_error_naming_the_file(tmp_path, monkeypatch):
    """The Python API: an ``OSError`` (errno ENOSPC) naming the file it was to write, the previous file whole."""
    path = tmp_path / "run.nc"
    write_netcdf(_small(), path)
    before = path.read_bytes()

    def to_netcdf(self, target, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    with pytest.raises(OSError, match="No space left on device") as caught:
        write_netcdf(_small(), path)
    assert isinstance(caught.value, atomic.NoSpaceError)
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(path)
    assert path.read_bytes() == before and _left(tmp_path) == ["run.nc"]


def test_another_failure_with_space_left_is_not_taken_for_a_full_disk(tmp_path, monkeypatch):
    def to_netcdf(self, target, *args, **kwargs):
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    _full(monkeypatch, tmp_path, free=10 * atomic.LOW_SPACE)
    with pytest.raises(RuntimeError, match="HDF error") as caught:
        write_netcdf(_small(), tmp_path / "run.nc")
    assert not isinstance(caught.value, OSError) and _left(tmp_path) == []
