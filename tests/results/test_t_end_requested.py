"""A run records the end time it was asked to reach (``t_end_requested``, in s): one that stops early (a model limit,
exit 3; Ctrl-C, exit 130: tests/integrators/test_interrupted_runs.py) held only what it reached (its times,
``failure_time``, the message), and its views' ``[INCOMPLETE: ...]`` could not say what was asked."""

from __future__ import annotations

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf
from mol_shell.views.figures import incomplete_note


def test_a_run_stopped_at_a_limit_records_the_end_it_was_asked_and_its_views_say_it(tmp_path):
    """A cylinder of R = 3 m whose wall cannot hold that radius (tests/cli/test_cli.py) reaches r = 0 on the axis
    before 0.05 s."""
    out = tmp_path / "limit.nc"
    assert main(["run", "twisted-cylinder", "--set", "R=3", "--set", "gamma=0", "--set", "law_limit=false", "--n", "9",
                 "--times", "0:0.05:0.005", "--no-stresses", "-o", str(out)]) == 3
    ds = read_netcdf(out)
    assert ds.attrs["complete"] == 0 and ds.attrs["status"] == "limit"
    assert ds.time.values[-1] < 0.05
    assert ds.attrs["t_end_requested"] == 0.05 and ds.attrs["units_t_end_requested"] == "s"
    said = incomplete_note(ds.attrs)  # what every view's [INCOMPLETE: ...] says
    assert said.startswith("INCOMPLETE: r = ") and said.endswith(" (asked: t_end = 0.05 s)"), said


@pytest.mark.parametrize("integrator", ["leapfrog", "ida"])
def test_a_complete_run_and_an_unshearable_one_record_it_too(integrator):
    scene = "unshearable" if integrator == "ida" else "twisted-cylinder"
    ds = mol_shell.simulate(scene, integrator, n=6, times=[0.0, 1e-5, 3e-5], progress=False, stresses=False,
                            **({"dt": 1e-6} if integrator == "leapfrog" else {}))
    assert ds.attrs["complete"] == 1 and ds.attrs["t_end_requested"] == 3e-5 and ds.attrs["units_t_end_requested"] == "s"
    assert incomplete_note(ds.attrs) == ""


def test_a_stopped_runs_scene_file_asks_its_t_end_and_runs_to_the_same_stop(tmp_path, capsys):
    """``scenes RUN.nc --toml`` of a run that stopped early wrote the saved times, so the file's run ended where the
    first stopped, complete: with ``t_end_requested`` it asks the end time the first run asked (its saved times are
    that t_end's default ones), and its run stops at the same time and state."""
    first, again, toml = tmp_path / "limit.nc", tmp_path / "again.nc", tmp_path / "limit.toml"
    assert main(["run", "twisted-cylinder", "--set", "R=3", "--set", "gamma=0", "--set", "law_limit=false", "--n", "9",
                 "--t-end", "0.05", "--no-stresses", "-o", str(first)]) == 3
    capsys.readouterr()
    assert main(["scenes", str(first), "--toml"]) == 0
    text = capsys.readouterr().out
    assert "t_end = 0.05\n" in text and "times = " not in text and "t_end is the one it asked" in text
    toml.write_text(text)
    assert main(["run", str(toml), "--no-stresses", "-o", str(again)]) == 3
    a, b = read_netcdf(first), read_netcdf(again)
    assert b.attrs["t_end_requested"] == 0.05 and b.attrs["failure_time"] == a.attrs["failure_time"]
    assert (a.time.values == b.time.values).all() and (a.r.values == b.r.values).all()
