"""Animations drawn and written a frame at a time: memory that does not grow with the frames, progress on long
ones, a width that cannot fit refused before any frame is drawn, and Ctrl-C during an MP4 said as an interrupt.

A GIF kept every frame until the end (984 MB for 144 frames 1600 pixels wide, 46 s; a run of 686 saved times did
not finish in 180 s and printed nothing), and a Ctrl-C during an MP4 reached ffmpeg too, whose death was said as
"-o = 'v.mp4' could not be encoded (... returned non-zero exit status 255.)", exit 2."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from paper_run_file import SMALL, paper_run_file
from PIL import Image

import mol_shell
from mol_shell.cli.main import main
from mol_shell.views.animate import animate


@pytest.fixture(scope="module")
def long_run(tmp_path_factory):
    """The paper's scene on 6 nodes with 400 saved times: an animation of seconds, long enough to interrupt."""
    return paper_run_file(tmp_path_factory.mktemp("streaming"), 6, 400)


def _children(pid):
    """The processes ``pid`` started (Linux: /proc/PID/task/*/children)."""
    found = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found += (task / "children").read_text().split()
        except OSError:
            pass
    return found


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="reads a process's children in /proc")
def test_ctrl_c_during_an_mp4_is_an_interrupt_and_leaves_no_file(long_run, tmp_path):
    """SIGINT to the whole foreground process group, as a terminal's Ctrl-C sends it: exit 130, "interrupted", no
    file, no temporary left, and no encoder left running."""
    out = tmp_path / "v.mp4"
    child = subprocess.Popen([sys.executable, "-m", "mol_shell", "animate", str(long_run), *SMALL, "-o", str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while not _children(child.pid) and child.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        encoder = _children(child.pid)
        assert encoder, "the encoder never started"
        time.sleep(0.3)  # frames going to it
        os.killpg(child.pid, signal.SIGINT)
        _, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 130, err
    assert err.strip().splitlines() == ["mol-shell: interrupted"], err
    assert list(tmp_path.iterdir()) == []
    assert not Path(f"/proc/{encoder[0]}").exists() or "ffmpeg" not in Path(f"/proc/{encoder[0]}/cmdline").read_text()


GIF_MEMORY = """
import resource, sys
import numpy as np
from mol_shell.views.animate import _write_gif
h, w = 540, 600
frame = np.full((h, w, 4), 255, np.uint8)
def render(k):  # every frame different all over
    frame[..., 0] = (np.arange(w) + 5 * k) % 256
    frame[..., 1] = (np.arange(h)[:, None] * 3 + k) % 256
    return frame
_write_gif(sys.argv[1], render, int(sys.argv[2]), 10)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


def test_a_gif_s_memory_does_not_grow_with_its_frames(tmp_path):
    """Peak memory with 10 and with 70 frames of 600 x 540 pixels (0.3 MB each as palette indices): equal to a few
    MB; keeping the frames took every one of them, and Pillow's copies."""
    peaks = []
    for count in (10, 70):
        out = tmp_path / f"f{count}.gif"
        done = subprocess.run([sys.executable, "-c", GIF_MEMORY, str(out), str(count)], capture_output=True, text=True,
                              timeout=120, check=False)
        assert done.returncode == 0, done.stderr
        peaks.append(int(done.stdout.split()[-1]) * 1024)
        with Image.open(out) as gif:
            assert gif.n_frames == count
            gif.seek(count - 1)
            last = np.asarray(gif.convert("RGB"))
        expected = [(5 * (count - 1)) % 256, (count - 1) % 256, 255]  # the last frame, in one palette of 256 colours
        assert np.abs(last[0, 0].astype(int) - expected).max() <= 12, (last[0, 0], expected)
    assert peaks[1] - peaks[0] < 8e6, peaks


def test_a_width_whose_frames_cannot_fit_is_refused_before_drawing(long_run, tmp_path, capsys, monkeypatch):
    """1 GB (``$MOL_SHELL_MEMORY``, as for a run) is too little for an MP4 4096 pixels wide (its encoder alone takes
    1.5 GB): refused naming --width and the widest that fits; a GIF of that width fits."""
    monkeypatch.setenv("MOL_SHELL_MEMORY", "1G")
    started = time.perf_counter()
    assert main(["animate", str(long_run), "--width", "4096", "-o", str(tmp_path / "w.mp4")]) == 2
    err = capsys.readouterr().err
    assert time.perf_counter() - started < 5.0  # no frame drawn
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: --width = 4096 needs about"), err
    assert "1.07 GB available ($MOL_SHELL_MEMORY)" in err and "allowed: [100, " in err, err
    widest = int(err.rsplit("[100, ", 1)[1].split("]")[0])
    assert 1000 < widest < 4096
    assert list(tmp_path.iterdir()) == []


def test_progress_is_shown_frame_by_frame(long_run, tmp_path, capsys):
    ds = mol_shell.read_netcdf(long_run).isel(time=slice(0, 3))
    assert animate(ds, tmp_path / "p.gif", n_phi=6, fibres=2, width=100, progress=True) == 3
    err = capsys.readouterr().err
    assert "animating" in err and "3/3" in err, err
