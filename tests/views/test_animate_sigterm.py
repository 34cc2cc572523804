"""SIGTERM (a scheduler's wall-time limit, ``kill``) during ``mol-shell animate -o X.mp4`` ends it as Ctrl-C does:
exit 143, one line, no file and no temporary left beside the output, and no encoder left running. A SIGTERM that
landed as the encoder started (inside ``subprocess.Popen``, the encoder not yet ours to stop) left ffmpeg running on
its own, unwaited for.

The signal is sent at a fixed point of the work (a patched function, as tests/cli/test_sigterm.py does), in this
process: the command line's watch takes SIGTERM over while ``main`` runs (and leaves its default action after one)."""

from __future__ import annotations

import os
import signal
import subprocess
from pathlib import Path

import pytest
from paper_run_file import SMALL, paper_run_file

from mol_shell._core import interrupts
from mol_shell.cli.main import main
from mol_shell.views import animate


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """The paper's scene on 5 nodes, 6 saved times."""
    return paper_run_file(tmp_path_factory.mktemp("sigterm"), 5, 6)


@pytest.fixture
def sigterm_default():
    """SIGTERM at its default action, as the command line finds it (it takes that over), and as it was after."""
    previous = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    yield
    signal.signal(signal.SIGTERM, previous)
    interrupts._TERMINATED.clear()  # as the next command does


def _said(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]


def test_sigterm_while_frames_go_to_the_encoder_exits_143_and_leaves_nothing(run_file, tmp_path, capsys, monkeypatch,
                                                                             sigterm_default):
    real, calls = animate._surface, []

    def surface(*args, **kwargs):  # the third frame: the encoder has the first two
        calls.append(1)
        if len(calls) == 3:
            signal.raise_signal(signal.SIGTERM)
        return real(*args, **kwargs)

    monkeypatch.setattr(animate, "_surface", surface)
    out = tmp_path / "out" / "v.mp4"
    assert main(["animate", str(run_file), *SMALL, "-o", str(out)]) == 143
    assert _said(capsys) == ["mol-shell: terminated (SIGTERM)"]
    assert list(out.parent.iterdir()) == []  # no file, no .v.mp4.*.part


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="looks for the encoder's process in /proc")
def test_sigterm_as_the_encoder_starts_stops_it_too(run_file, tmp_path, capsys, monkeypatch, sigterm_default):
    real, started = subprocess._fork_exec, []

    def fork_exec(args, *rest, **kwargs):
        pid = real(args, *rest, **kwargs)
        if any(os.fsdecode(arg) == "rawvideo" for arg in args):  # the encoder, not imageio-ffmpeg's check of ffmpeg
            started.append(pid)
            signal.raise_signal(signal.SIGTERM)
        return pid

    monkeypatch.setattr(subprocess, "_fork_exec", fork_exec)
    out = tmp_path / "out" / "v.mp4"
    assert main(["animate", str(run_file), *SMALL, "-o", str(out)]) == 143
    assert _said(capsys) == ["mol-shell: terminated (SIGTERM)"]
    assert len(started) == 1 and not Path(f"/proc/{started[0]}").exists()  # stopped and waited for: not even a zombie
    assert list(out.parent.iterdir()) == []
