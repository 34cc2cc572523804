"""More of what a new user hit in the views: an MP4 of any allowed width, graded walls drawn at their own
thickness, the radius drawn where a vessel is cylindrical, and plot's refusal listing what it reads."""

import stat

import imageio_ffmpeg
import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """The paper's scene on 6 nodes, two saved times: the smallest run an animation draws."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=[0.0, 2e-6], progress=False, stresses=False)
    path = tmp_path_factory.mktemp("newcomer_views_more") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return path


# -- an MP4 of every allowed width ---------------------------------------------------------------------------
@pytest.mark.parametrize(("width", "size"), [(201, (202, 180)), (210, (210, 190)), (1024, (1024, 922))])
def test_an_mp4_of_an_odd_frame_size_is_written_with_even_sides(short_run, tmp_path, width, size):
    """H.264 in 4:2:0 colour needs even sides: the frame is the nearest even numbers to the width and to 0.9 of it
    (201 x 180.9 -> 202 x 180; 1024 x 921.6 -> 1024 x 922), where ffmpeg refused 201 x 180 and 1024 x 921."""
    out = tmp_path / "w.mp4"
    assert main(["animate", str(short_run), "--n-phi", "6", "--fibres", "2", "--width", str(width), "-o", str(out)]) == 0
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    reader.close()
    assert tuple(meta["size"]) == size
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == 2


def test_an_encoder_that_fails_is_said_in_one_line_and_leaves_no_file(short_run, tmp_path, monkeypatch, capsys):
    """An ffmpeg that refuses (here a stand-in that says why and exits 1): one line naming -o, exit 2, no file
    written, a previous file left as it was, and no temporary file left beside it."""
    fake = tmp_path / "ffmpeg"
    fake.write_text("#!/bin/sh\ncat > /dev/null\necho '[libx264 @ 0x5555] width not divisible by 2' >&2\nexit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setattr(imageio_ffmpeg, "get_ffmpeg_exe", lambda: str(fake))
    folder = tmp_path / "out"
    folder.mkdir()
    argv = ["animate", str(short_run), "--n-phi", "6", "--fibres", "2", "--width", "200"]
    assert main([*argv, "-o", str(folder / "w.mp4")]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: -o = "), err
    assert "could not be encoded ([libx264] width not divisible by 2)" in err and "200 x 180 pixels" in err, err
    assert list(folder.iterdir()) == []
    (folder / "old.mp4").write_bytes(b"previous")
    assert main([*argv, "-o", str(folder / "old.mp4")]) == 2
    assert (folder / "old.mp4").read_bytes() == b"previous" and len(list(folder.iterdir())) == 1
