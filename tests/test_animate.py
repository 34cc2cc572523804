"""Animations and the fibre figure: one frame per saved time, not blank; bad input refused in one line."""

import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

import mol_shell
from mol_shell.cli import main
from mol_shell.stresses import add_stresses

SMALL = ["--n-phi", "12", "--fibres", "4", "--width", "200"]


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """The paper's scene on 8 nodes over 10 us (11 saved times) with stresses, and the same without."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False)
    folder = tmp_path_factory.mktemp("animate")
    mol_shell.write_netcdf(add_stresses(ds), folder / "run.nc")
    mol_shell.write_netcdf(ds, folder / "bare.nc")
    return folder / "run.nc", folder / "bare.nc"


def not_blank(rgb):
    """A frame with a drawing: many colours, and a good share of saturated (coloured, not grey) pixels."""
    rgb = np.asarray(rgb, dtype=float)
    colours = len(np.unique(rgb.reshape(-1, 3), axis=0))
    saturation = rgb.max(axis=-1) - rgb.min(axis=-1)
    return colours > 20 and (saturation > 60).mean() > 0.02 and rgb.std() > 20


def test_gif_has_one_frame_per_saved_time(run_file, tmp_path):
    out = tmp_path / "shell.gif"
    assert main(["animate", str(run_file[0]), "--field", "von_mises_stress_outer", *SMALL, "-o", str(out)]) == 0
    with Image.open(out) as gif:
        assert gif.n_frames == 11
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    assert all(not_blank(f) for f in frames)
    assert np.any(frames[0] != frames[-1])  # the time in the frame changes


def test_mp4_has_one_frame_per_saved_time(run_file, tmp_path):
    out = tmp_path / "shell.mp4"
    assert main(["animate", str(run_file[0]), "--field", "axial_torque", *SMALL, "-o", str(out)]) == 0
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert frames == 11
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    first = np.frombuffer(next(reader), dtype=np.uint8).reshape(meta["size"][1], meta["size"][0], 3)
    reader.close()
    assert not_blank(first)


def test_bad_input_is_refused_in_one_line(run_file, tmp_path, capsys):
    run, bare = run_file
    (tmp_path / "d.gif").mkdir()
    text = tmp_path / "notes.nc"
    text.write_text("not netCDF")
    cases = [
        ([str(run), "--field", "colour", "-o", str(tmp_path / "a.gif")], "--field = 'colour' is outside {z, z_t"),
        ([str(bare), "--field", "axial_torque", "-o", str(tmp_path / "a.gif")], "this run has no stresses"),
        ([str(text), "-o", str(tmp_path / "a.gif")], "is not a mol_shell run file"),
        ([str(run), "-o", str(tmp_path / "a.avi")], "-o = "),
        ([str(run), "-o", "/proc/no/such/a.gif"], "cannot be written"),
        ([str(run), "-o", str(tmp_path / "d.gif")], "is a directory"),
        ([str(run), "--fps", "0", "-o", str(tmp_path / "a.gif")], "--fps = 0 is outside"),
    ]
    for argv, words in cases:
        code = main(["animate", *argv])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("mol-shell: error: ") and len(err.splitlines()) == 1, (argv, err)
        assert words in err, (argv, err)
    assert not (tmp_path / "a.gif").exists()
