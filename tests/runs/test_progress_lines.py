"""Progress when stderr is not a terminal: with ``progress=None`` a run, study or path redirected to a file
(``2> log.txt``, a batch job, a notebook) printed nothing until it ended; now plain lines at most once every
``LOG_INTERVAL_S`` s of wall time, and a last one at the end (nothing for work shorter than the interval)."""

from __future__ import annotations

import io
import sys

import pytest

import mol_shell
from mol_shell._core import progress as progress_module
from mol_shell._core.progress import ProgressLines, progress_meter, progress_mode
from mol_shell.analysis.path import _steps_done


class Clock:
    """A wall clock the test sets by hand (seconds)."""

    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


def lines_of(stream):
    text = stream.getvalue()
    assert "\r" not in text and (not text or text.endswith("\n")), repr(text)
    return text.splitlines()


def test_a_line_at_each_interval_none_before_and_a_last_one_at_the_end():
    clock, out = Clock(), io.StringIO()
    meter = ProgressLines("simulating", "t = {n:.4g} of {total:.4g} s", total=0.143, interval=60.0, clock=clock,
                          stream=out)
    for now, done in ((10.0, 0.01), (59.9, 0.0412)):  # before the first interval: nothing
        clock.now = 1000.0 + now
        meter.update(done - meter.n)
    assert out.getvalue() == ""
    clock.now = 1060.0
    meter.update(0.0512 - meter.n)
    # 36 % done (0.0512 / 0.143 = 0.358); the rest at the same rate: 60 s * (0.143 - 0.0512) / 0.0512 = 107.6 s
    assert lines_of(out) == ["mol-shell: simulating: t = 0.0512 of 0.143 s (36 %), 1 min elapsed, about 1.79 min left"]
    clock.now = 1100.0  # 40 s after the line: none
    meter.update(0.01)
    assert len(lines_of(out)) == 1
    clock.now = 1120.0  # 60 s after it: the next; 0.1 of 0.143 in 120 s, 0.043 left at that rate: 51.6 s
    meter.update(0.1 - meter.n)
    assert lines_of(out)[1] == "mol-shell: simulating: t = 0.1 of 0.143 s (70 %), 2 min elapsed, about 51.6 s left"
    clock.now = 1150.0
    meter.update(0.143 - meter.n)
    meter.close()
    meter.close()  # once only
    assert lines_of(out)[2:] == ["mol-shell: simulating: t = 0.143 of 0.143 s (100 %), ended after 2.5 min"]


def test_work_shorter_than_the_interval_prints_nothing_even_at_its_end():
    clock, out = Clock(), io.StringIO()
    meter = ProgressLines("study", "{n} of {total} cases", total=4, interval=60.0, clock=clock, stream=out)
    for _ in range(4):
        clock.now += 14.0
        meter.set_postfix_str("complete")
        meter.update(1)
    meter.close()
    assert out.getvalue() == ""


def test_a_study_counts_cases_from_those_reused_with_the_last_status():
    """Two of six cases read back from a file: the rate is of the cases run here (one a minute), three left."""
    clock, out = Clock(), io.StringIO()
    meter = ProgressLines("study", "{n} of {total} cases", postfix="last case {}", total=6, initial=2,
                          interval=60.0, clock=clock, stream=out)
    clock.now += 60.0
    meter.set_postfix_str("limit")
    meter.update(1)
    assert lines_of(out) == ["mol-shell: study: 3 of 6 cases (50 %), last case limit, 1 min elapsed, about 3 min left"]


def test_a_path_line_has_no_total_hence_no_percentage_nor_time_left():
    clock, out = Clock(), io.StringIO()
    meter = ProgressLines("path in pressure (Pa)", "{n} steps", interval=60.0, clock=clock, stream=out)
    clock.now += 61.0
    meter.set_postfix_str("pressure = -120 Pa, 1 critical")
    meter.update(17)
    meter.close()
    head = "mol-shell: path in pressure (Pa): 17 steps, pressure = -120 Pa, 1 critical"  # 61 s = 1.02 min
    assert lines_of(out) == [f"{head}, 1.02 min elapsed", f"{head}, ended after 1.02 min"]


def test_a_path_of_one_step_says_step():
    """The path's count is a function of the steps: "1 step", as its messages say, not tqdm's "1 steps"."""
    clock, out = Clock(), io.StringIO()
    meter = ProgressLines("path in pressure (Pa)", _steps_done, interval=60.0, clock=clock, stream=out)
    clock.now += 61.0
    meter.update(1)
    assert lines_of(out) == ["mol-shell: path in pressure (Pa): 1 step, 1.02 min elapsed"]


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_the_default_is_a_bar_on_a_terminal_lines_elsewhere_and_nothing_without_stderr(monkeypatch):
    monkeypatch.setattr(sys, "stderr", Terminal())
    assert progress_mode(None) == "bar"
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert progress_mode(None) == "lines" and progress_mode(True) == "bar" and progress_mode(False) is None
    assert isinstance(progress_meter("lines", "study", count="{n}"), ProgressLines)
    assert progress_meter(None, "study", count="{n}") is None
    monkeypatch.setattr(sys, "stderr", None)  # pythonw
    assert progress_mode(None) is None


@pytest.mark.parametrize("run", [
    lambda: mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=None, stresses=False),
    # the unshearable scene's runs ignored progress altogether
    lambda: mol_shell.simulate_unshearable("unshearable", n=8, t_end=2e-4, constrained=False, progress=None),
    lambda: mol_shell.simulate_unshearable("unshearable", n=8, times=[0, 1e-4, 2e-4], progress=None),
], ids=["simulate", "unshearable-leapfrog", "unshearable-ida"])
def test_a_run_with_stderr_captured_prints_plain_lines(monkeypatch, capsys, run):
    """A real run under pytest's captured stderr (no terminal), the interval set to 0: a line per chunk of steps,
    each ended by a newline, no carriage return (a tqdm bar's), and a last line at the run's end, t_end reached."""
    monkeypatch.setattr(progress_module, "LOG_INTERVAL_S", 0.0)
    ds = run()
    assert ds.attrs["complete"] == 1
    err = capsys.readouterr().err
    assert "\r" not in err and err.endswith("\n"), repr(err[-300:])
    lines = [line for line in err.splitlines() if line.startswith("mol-shell: simulating: t = ")]
    assert len(lines) >= 2, err
    assert lines[-1].startswith("mol-shell: simulating: t = 0.0002 of 0.0002 s (100 %), ended after "), lines[-1]
    assert all(" elapsed" in line for line in lines[:-1]), lines


@pytest.mark.parametrize("progress", [False, None])
def test_a_short_run_stays_silent_by_default_and_when_told(capsys, progress):
    mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=progress, stresses=False)
    assert "simulating" not in capsys.readouterr().err
