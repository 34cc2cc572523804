"""Files the views write, read back by other tools: an XDMF named with ':' by meshio, a GIF's frame delays by Pillow,
an EPS figure without matplotlib's bare line on stderr; and every file of a scene with its ``zeta1_used``."""

import logging

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import meshio
import pytest
from PIL import Image

import mol_shell
from mol_shell.analysis.workprecision import work_precision
from mol_shell.cli.main import main
from mol_shell.runs.ring import simulate_ring
from mol_shell.views.figures import save_figure

#: a lower face set by hand (the paper's h = 2 pi 1e-3 m: the wall from -5 mm to 7.57 mm), what zeta1_used must hold
ZETA1 = -5e-3


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """The paper's scene on 8 nodes (as the other view tests), two saved times."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, times=[0.0, 1e-5], progress=False, stresses=False)
    path = tmp_path_factory.mktemp("interop") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return path


def test_xdmf_named_with_a_colon_reads_back_with_meshio(run_file, capsys):
    out = run_file.parent / "run_18:00.xdmf"
    assert main(["export", str(run_file), "--n-phi", "3", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert err == ("mol-shell: note: the HDF5 data of run_18:00.xdmf are in run_18_00.h5 (XDMF separates a data "
                   "file's name from its data set by ':', so its name has none)\n"), err
    assert (run_file.parent / "run_18_00.h5").is_file() and not (run_file.parent / "run_18:00.h5").exists()
    with meshio.xdmf.TimeSeriesReader(out) as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == 2
        _, point_data, _ = reader.read_data(1)
    # a cylinder (no pole): 8 circles of 3 points, 7 x 3 quads
    assert points.shape == (24, 3) and cells[0].data.shape == (21, 4)
    assert point_data["displacement"].shape == (24, 3)


def gif_delays(path):
    """Each frame's duration (ms) as Pillow reads the GIF back."""
    with Image.open(path) as gif:
        delays = []
        for k in range(gif.n_frames):
            gif.seek(k)
            delays.append(gif.info["duration"])
    return delays


def test_gif_delays_are_the_nearest_hundredths_and_above_50_fps_refused(run_file, capsys):
    folder = run_file.parent
    argv = ["animate", str(run_file), "--n-phi", "3", "--fibres", "1", "--width", "100"]
    # 100 / 30 = 3.33 cs: 3 cs a frame, 33.3 fps (11 % off: said); 100 / 50 = 2 cs exactly (nothing said)
    assert main([*argv, "--fps", "30", "-o", str(folder / "a30.gif")]) == 0
    err = capsys.readouterr().err
    assert err == ("mol-shell: note: the GIF plays at 33.3 frames per second, not --fps 30: a GIF's frame delay is in "
                   "whole hundredths of a second (3 here)\n"), err
    assert gif_delays(folder / "a30.gif") == [30, 30]
    assert main([*argv, "--fps", "50", "-o", str(folder / "a50.gif")]) == 0
    assert capsys.readouterr().err == ""
    assert gif_delays(folder / "a50.gif") == [20, 20]
    # 60 fps would be 1.67 cs: 2 cs (50 fps) at best, 1 cs shown as 10 cs by browsers: refused, no file
    assert main([*argv, "--fps", "60", "-o", str(folder / "a60.gif")]) == 2
    err = capsys.readouterr().err
    assert err.splitlines() == [("mol-shell: error: --fps = 60 is outside [0.002, 50] frames per second for a .gif (a "
                                 "GIF's delays are whole hundredths of a second; an .mp4 takes up to 100)")], err
    assert not (folder / "a60.gif").exists()


def test_compare_and_ring_files_carry_zeta1_used(tmp_path):
    scene = mol_shell.TwistedCylinder(zeta1=ZETA1)
    compared = work_precision(scene, ["leapfrog"], n=6, times=[0.0, 1e-5], repeats=1, log=lambda *_: None)
    mol_shell.write_netcdf(simulate_ring(mol_shell.SpinningRing(zeta1=ZETA1), times=[0.0, 0.01]), tmp_path / "ring.nc")
    ring = mol_shell.read_netcdf(tmp_path / "ring.nc")
    for attrs in (compared.attrs, ring.attrs):
        assert attrs["zeta1_used"] == ZETA1 and attrs["units_zeta1_used"] == "m"


def test_eps_figure_has_no_transparency_to_say(tmp_path, caplog):
    """A line of alpha 0.5 in black is drawn opaque as it looks on white, 0.5 grey; a grid of alpha 0.3 and a legend's
    frame (alpha 0.8) too: matplotlib's PostScript backend has nothing to log."""
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], color="k", alpha=0.5, label="faded")
    ax.fill_between([0, 1], [0, 0], [1, 1], color="b", alpha=0.25)
    ax.grid(alpha=0.3)
    ax.legend()
    with caplog.at_level(logging.WARNING, logger="matplotlib"):
        save_figure(fig, tmp_path / "x.eps")
    assert not caplog.records, [r.getMessage() for r in caplog.records]
    text = (tmp_path / "x.eps").read_text(errors="replace")
    assert "0.5 setgray" in text  # 0.5 x black + 0.5 x white
    assert "0.75 0.75 1 setrgbcolor" in text  # 0.25 x blue + 0.75 x white
