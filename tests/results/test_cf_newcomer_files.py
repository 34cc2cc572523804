"""A newcomer's checks of the written files against docs/netcdf.md and docs/cli.md: 32-bit integers in every file
(CF 1.8 has none wider), NaN stresses said on stderr, non-finite values refused by the views, final names inside."""

from __future__ import annotations

import gzip
import shutil
import warnings

import matplotlib
import matplotlib.pyplot as plt
import netCDF4
import numpy as np
import pytest
import xarray as xr

from mol_shell.analysis.modes import modes
from mol_shell.analysis.stability import Case, report
from mol_shell.analysis.workprecision import work_precision
from mol_shell.cli.main import main
from mol_shell.results.dataset import write_netcdf
from mol_shell.scenes import TwistedCylinder
from mol_shell.views.figures import save_figure

matplotlib.use("Agg")


def _wide_integers(path):
    """Variables of the file at ``path`` stored as an integer type CF 1.8 lacks (64-bit or unsigned)."""
    with netCDF4.Dataset(path) as nc:
        return {name: str(var.dtype) for name, var in nc.variables.items()
                if isinstance(var.dtype, np.dtype) and var.dtype.kind in "iu"
                and (var.dtype.kind == "u" or var.dtype.itemsize > 4)}


def test_every_integer_variable_and_coordinate_is_written_32_bit(tmp_path):
    ds = xr.Dataset({"count": (("k",), np.array([1, 2, 3], dtype=np.int64), {"units": "1", "long_name": "c"}),
                     "flag": (("k",), np.array([0, 1, 255], dtype=np.uint8), {"units": "1", "long_name": "f"})},
                    coords={"k": ("k", np.arange(3), {"units": "1", "long_name": "index"})})
    write_netcdf(ds, tmp_path / "i.nc")
    assert _wide_integers(tmp_path / "i.nc") == {}
    back = xr.open_dataset(tmp_path / "i.nc")
    assert back["count"].values.tolist() == [1, 2, 3] and back["flag"].values.tolist() == [0, 1, 255]
    assert back["k"].values.tolist() == [0, 1, 2]


def test_compare_modes_and_stability_files_hold_no_64_bit_integer(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wp = work_precision("twisted-cylinder", ["cvode-bdf"], n=11, times=[0, 0.005, 0.01], repeats=1,
                            sweeps={"cvode-bdf": {"rtol": [1e-4]}}, log=lambda *a: None)
        md = modes("sphere", n=11, count=3)
        st = report([Case("n=5", TwistedCylinder(), n=5, t_end=0.002)], bisect=False)
    for name, ds in {"wp.nc": wp, "m.nc": md, "s.nc": st}.items():
        write_netcdf(ds, tmp_path / name)
        assert _wide_integers(tmp_path / name) == {}, name
    with netCDF4.Dataset(tmp_path / "m.nc") as nc:
        assert nc["mode"][:].tolist() == [1, 2, 3]  # modes are numbered from 1


PLANE_STRESS = ["sphere", "--set", "material=svk-plane-stress", "--set", "pressure=40000", "--n", "11",
                "--t-end", "0.001"]


@pytest.fixture(scope="module")
def plane_stress_run(tmp_path_factory):
    """A sphere blown past the svk plane-stress law's thinning limit (an equal two-way stretch of 1.47 at
    nu = 0.3, docs/status.md): every stress sample NaN, 11 saved times x 10 cells x 2 faces = 220."""
    path = tmp_path_factory.mktemp("ps") / "ps.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["run", *PLANE_STRESS, "-o", str(path)]) == 0
    return path


def test_a_run_whose_stresses_hold_nan_says_so_on_stderr(tmp_path, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["run", *PLANE_STRESS, "-o", str(tmp_path / "ps.nc")]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if line.startswith("mol-shell: note:") and "NaN" in line]
    assert len(notes) == 1, err
    assert "220 of 220 stress samples" in notes[0] and "attrs['stresses']" in notes[0]
    assert "svk-plane-stress" in notes[0]  # why


def test_a_run_without_nan_stresses_prints_no_such_note(tmp_path, capsys):
    assert main(["run", "twisted-cylinder", "--n", "11", "--t-end", "0.001", "-o", str(tmp_path / "r.nc")]) == 0
    assert "stress samples" not in capsys.readouterr().err


@pytest.mark.parametrize("var, index, value", [("axial_torque", (3, 5), np.inf), ("energy", (3,), np.nan),
                                               ("von_mises_stress", (2, 1, 0), -np.inf)])
def test_plot_refuses_a_stress_or_energy_that_is_not_finite(tmp_path, capsys, var, index, value):
    run = tmp_path / "r.nc"
    assert main(["run", "twisted-cylinder", "--n", "11", "--t-end", "0.001", "-o", str(run)]) == 0
    capsys.readouterr()
    with netCDF4.Dataset(run, "a") as nc:
        nc[var][index] = value
    assert main(["plot", str(run), "-o", str(tmp_path / "p.png")]) == 2
    err = capsys.readouterr().err
    assert f"{var} is not finite" in err and "FILE" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "p.png").exists()


def test_stresses_declared_nan_are_drawn_but_inf_among_them_is_refused(plane_stress_run, tmp_path, capsys):
    ok = tmp_path / "ok.nc"
    shutil.copy(plane_stress_run, ok)
    assert main(["export", str(ok), "--n-phi", "3", "-o", str(tmp_path / "ok.xdmf")]) == 0
    bad = tmp_path / "bad.nc"
    shutil.copy(plane_stress_run, bad)
    with netCDF4.Dataset(bad, "a") as nc:
        nc["von_mises_stress"][1, 2, 1] = np.inf
    capsys.readouterr()
    assert main(["export", str(bad), "-o", str(tmp_path / "bad.xdmf")]) == 2
    assert "von_mises_stress is not finite" in capsys.readouterr().err


@pytest.mark.parametrize("suffix", ["svgz", "eps"])
def test_a_figure_carries_its_own_name_not_the_temporary_one(tmp_path, suffix):
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    path = tmp_path / f"pl.{suffix}"
    save_figure(fig, path)
    data = path.read_bytes()
    assert b".part" not in (gzip.decompress(data) if suffix == "svgz" else data)
    if suffix == "svgz":  # gzip header (RFC 1952): FLG bit 3 (FNAME), then the name after the 10 fixed bytes
        assert data[:2] == b"\x1f\x8b" and data[3] & 0x08
        assert data[10:data.index(b"\0", 10)] == b"pl.svgz"
    else:
        assert b"%%Title: pl.eps\n" in data
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # no temporary left behind
