"""A run file written back as a scene file (``mol-shell scenes RUN.nc --toml``) runs the run that was asked for, or
says why it cannot: the saved times a stopped run asked for (``times_requested``), a points file edited since (its
digest), hand-edited attributes, another version; a run ``--from`` a path records the file (``started_from``); a
path continued ``--from`` a file whose scene attributes were edited is refused by the residual modes uses, and a
run from one is noted."""

from __future__ import annotations

import os

import numpy as np
import pytest
import tomllib
import xarray as xr

import mol_shell
from mol_shell import ParameterError
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf
from mol_shell.runs.asked_times import times_of, times_text

POINTS = "1.0 0.0\n0.9 0.3\n0.7 0.5\n0.4 0.55\n0.0 0.6\n"
MIRRORED = "1.0 0.0\n0.9 -0.3\n0.7 -0.5\n0.4 -0.55\n0.0 -0.6\n"  # the same count and length, another shell


@pytest.fixture(scope="module")
def traced(tmp_path_factory):
    """``(folder, points file, path file, run file)``: a path on a points meridian (3 steps) and a run from its
    step 1."""
    folder = tmp_path_factory.mktemp("prov")
    points, path_file, run_file = folder / "p.txt", folder / "p.nc", folder / "r.nc"
    points.write_text(POINTS)
    assert main(["path", "meridian", "--set", f"points={points}", "--param", "pressure=0:100", "--n", "10",
                 "--max-steps", "2", "-o", str(path_file)]) == 0
    assert main(["run", "--from", str(path_file), "--step", "1", "--t-end", "1e-5", "--no-stresses",
                 "-o", str(run_file)]) == 0
    return folder, points, path_file, run_file


def _error(err):
    """The one line of an error (warnings about the scene before it aside)."""
    lines = [line for line in err.splitlines() if line.startswith("mol-shell: error:")]
    assert len(lines) == 1 and not err.rstrip("\n").partition(lines[0])[2], err
    return lines[0]


def _edited(source, target, **attrs):
    with xr.open_dataset(source) as ds:
        ds = ds.load()
    ds.attrs.update(attrs)
    ds.to_netcdf(target)
    return target


def test_the_times_text_gives_the_times_back_exactly():
    """A range (its values to 12 digits, as --times gives them) and an irregular list."""
    regular = np.array([float(f"{k * 0.0005:.12g}") for k in range(21)])  # --times 0:0.01:0.0005
    assert times_text(regular) == "0.0:0.01:0.0005"
    assert np.array_equal(times_of(times_text(regular)), regular)
    irregular = np.array([0.0, 0.1, 0.3, 1.0 / 3.0])
    assert np.array_equal(times_of(times_text(irregular)), irregular)


def test_a_stopped_runs_scene_file_asks_the_times_it_asked_for_and_stops_where_it_stopped(tmp_path, capsys):
    """The scene file of a run that stopped at a limit listed only the times it saved: its run was complete, another
    run. A cylinder of R = 3 m whose wall cannot hold that radius reaches r = 0 on the axis before 0.05 s
    (tests/results/test_t_end_requested.py); 0:0.05:0.0025 is not t_end's default spacing (0.005)."""
    first, again, toml = tmp_path / "limit.nc", tmp_path / "again.nc", tmp_path / "limit.toml"
    run = ["run", "twisted-cylinder", "--set", "R=3", "--set", "gamma=0", "--set", "law_limit=false", "--n", "9",
           "--times", "0:0.05:0.0025", "--no-stresses"]
    assert main([*run, "-o", str(first)]) == 3
    a = read_netcdf(first)
    assert a.sizes["time"] < 21 and a.attrs["times_requested"] == "0.0:0.05:0.0025"
    assert a.attrs["threads"] == mol_shell.build(mol_shell.TwistedCylinder(R=3.0, gamma=0.0, law_limit=False), 9)[1].threads
    capsys.readouterr()
    assert main(["scenes", str(first), "--toml"]) == 0
    text = capsys.readouterr().out
    asked = [round(k * 0.0025, 12) for k in range(21)]
    assert tomllib.loads(text)["run"]["times"] == asked and "times are those it asked for" in text
    toml.write_text(text)
    assert main(["run", str(toml), "--no-stresses", "-o", str(again)]) == 3
    b = read_netcdf(again)
    assert b.attrs["failure_time"] == a.attrs["failure_time"] and np.array_equal(a.time.values, b.time.values)


def test_a_run_on_a_points_file_edited_since_is_refused_by_scenes_toml(traced, tmp_path, capsys):
    """The run recorded the points' digest, but its scene file was written (and ran another shell) without a word."""
    _, points, _, run_file = traced
    moved = tmp_path / "r.nc"
    moved.write_bytes(run_file.read_bytes())
    points.write_text(MIRRORED)
    try:
        capsys.readouterr()
        assert main(["scenes", str(moved), "--toml"]) == 2
        err = _error(capsys.readouterr().err)
        assert f"FILE = '{moved}' was run on the points file '{points}', edited since the " \
            "run (digest " in err
    finally:
        points.write_text(POINTS)


def test_a_run_from_a_path_records_the_path_and_its_scene_file_names_the_command(traced, capsys):
    """``initial_state`` said the step, not the file."""
    _, _, path_file, run_file = traced
    ds = read_netcdf(run_file)
    assert ds.attrs["started_from"].startswith(f"{os.path.abspath(path_file)}, step 1 of 3 (pressure = ")
    capsys.readouterr()
    assert main(["scenes", str(run_file), "--toml"]) == 0
    text = capsys.readouterr().out
    assert "this file starts from the scene's own initial data, not the path's state" in text
    assert f"# mol-shell run --from {path_file} --step 1 (" in text


@pytest.mark.parametrize(("attrs", "said"), [
    ({"dt": -1.0}, "attribute dt = -1.0 is outside (0, inf) s"),
    ({"n": 11}, "holds attribute n = 11, but its coordinate s has 10 nodes"),
    ({"times_requested": "0:1:x", "complete": 0}, "holds times_requested = '0:1:x', not increasing times"),
])
def test_scenes_toml_refuses_attributes_a_run_would_refuse(traced, tmp_path, capsys, attrs, said):
    """They were written into the scene file (``n = 11`` against 10 nodes), refused only by its run, if at all."""
    edited = _edited(traced[3], tmp_path / "e.nc", **attrs)
    capsys.readouterr()
    assert main(["scenes", str(edited), "--toml"]) == 2
    err = _error(capsys.readouterr().err)
    assert err.startswith(f"mol-shell: error: FILE = '{edited}'") and said in err, err


def test_a_run_of_another_version_is_written_with_a_warning(traced, tmp_path, capsys):
    edited = _edited(traced[3], tmp_path / "v.nc", mol_shell_version="0.4.0")
    capsys.readouterr()
    assert main(["scenes", str(edited), "--toml"]) == 0
    out, err = capsys.readouterr()
    assert "the run was computed by mol_shell 0.4.0, this is " in err and "not to the bit" in err
    assert "# The run was computed by mol_shell 0.4.0" in out


def test_a_path_whose_scene_attributes_were_edited_is_refused_by_from(traced, tmp_path, capsys):
    """E three times the path's: its step 1 (at 50 Pa) is no equilibrium under the file's scene. ``path --from``
    polished it into another state (21 % away in the probe) and went on; modes --from refused it; run --from runs
    it (a dynamic run from a state out of equilibrium is legitimate) with a note."""
    _, _, path_file, _ = traced
    with xr.open_dataset(path_file) as ds:
        E = float(ds.attrs["E"])
    edited = _edited(path_file, tmp_path / "pe.nc", E=3 * E)
    capsys.readouterr()
    assert main(["path", "--from", str(edited), "--step", "1", "--stop", "100", "--max-steps", "1",
                 "-o", str(tmp_path / "c.nc")]) == 2
    err = capsys.readouterr().err
    assert f"--from = '{edited}' holds a state at step 1 that is no equilibrium under its scene (residual force " in err
    with pytest.raises(ParameterError, match="holds a state at step 1 that is no equilibrium under its scene"):
        mol_shell.continue_path(read_netcdf(edited), 100.0, step=1, max_steps=1)
    assert main(["run", "--from", str(edited), "--step", "1", "--t-end", "1e-5", "--no-stresses",
                 "-o", str(tmp_path / "r.nc")]) == 0
    assert f"the state at step 1 of {edited} is out of equilibrium under the run's scene (residual force " in \
        capsys.readouterr().err
