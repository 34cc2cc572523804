"""``mol-shell path`` and ``study --path``: a refusal names the command line's option; how far a path that ended
short got (a study's ``reached``, its figure and summary line); a path file back as a scene file that traces it
again (``mol-shell scenes PATH.nc --toml``)."""

from __future__ import annotations

import warnings

import matplotlib
import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.views.path_study_plot import path_study_figure

matplotlib.use("Agg")
STOP = -1000.0  # Pa: far past where two steps of the default sphere get


@pytest.mark.parametrize("argv, option", [
    (["path", "sphere", "--param", "pressure=0:-100", "--max-steps", "10000000000"], "--max-steps"),
    (["path", "sphere", "--param", "pressure=0:-100", "--branch", "-1"], "--branch"),
    (["study", "sphere", "--vary", "h=0.0025,0.003", "--path", "pressure=0:3000", "--max-steps", "10000000000"],
     "--max-steps"),
    (["study", "sphere", "--vary", "h=0.0025,0.003", "--path", "pressure=0:1e-320"], "--path"),
])
def test_a_refused_path_option_is_named_as_the_command_line_gives_it(argv, option, tmp_path, capsys):
    """``--max-steps 1e10`` was refused as ``max_steps = 10000000000 is outside ...`` (the Python keyword)."""
    assert main([*argv, "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mol-shell: error: {option} = "), err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "x.nc").exists()


def test_a_study_says_how_far_each_path_got_that_ended_short(tmp_path, capsys):
    """Two paths cut by max_steps = 2 with no critical point: the file keeps the load each reached (its path's last
    state), the figure's centre and title and the command's line say it; they said "each traced up to -1000" and
    "none, none" (no critical point up to STOP, which neither reached)."""
    from mol_shell.views.path_study_plot import first_critical_said

    out = tmp_path / "s.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["study", "sphere", "--vary", "nu=0.3,0.35", "--path", f"pressure=0:{STOP:g}", "--n", "9",
                     "--max-steps", "2", "--scheduler", "serial", "-o", str(out)]) == 0
        one = mol_shell.path(mol_shell.Sphere(nu=0.3), "pressure", 0.0, STOP, n=9, max_steps=2)
    line = capsys.readouterr().out
    ds = mol_shell.read_netcdf(out)
    reached = ds.reached.values
    assert ds.status.values.tolist() == ["max_steps", "max_steps"]
    assert ds.reached.attrs["units"] == "Pa" and "last state" in ds.reached.attrs["long_name"]
    assert reached[0] == float(one.parameter.values[-1])  # the same path, traced alone
    assert np.all((STOP < reached) & (reached < 0))  # short of STOP, and loaded
    said = [f"none up to {r:.6g} Pa (max_steps)" for r in reached]
    assert first_critical_said(ds) == said
    assert f"first critical pressure: {said[0]}, {said[1]}" in line, line
    fig = path_study_figure(ds)
    ax = fig.axes[0]
    title, texts = " ".join(ax.get_title().split()), [t.get_text() for t in ax.texts]
    matplotlib.pyplot.close(fig)
    assert f"nu = 0.3 (max_steps at {reached[0]:.6g} Pa)" in title, title
    centre = [t for t in texts if t.startswith("no path met")]
    assert centre and "each traced up to" not in centre[0], centre
    assert f"nu = 0.35: none up to {reached[1]:.6g} Pa (max_steps)" in centre[0], centre


def test_a_path_file_back_as_a_scene_file_traces_the_same_path_again(tmp_path, capsys):
    """``scenes PATH.nc --toml`` was refused ("not a mol_shell run file"): it writes the path's scene, [run] n and
    the command; traced again from it with one more step, the path has the same states first."""
    first, toml, again = tmp_path / "p.nc", tmp_path / "p.toml", tmp_path / "again.nc"
    span = f"pressure=0:{STOP:g}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["path", "sphere", "--set", "nu=0.3", "--param", span, "--n", "9", "--max-steps", "2",
                     "-o", str(first)]) == 0
        note = capsys.readouterr().err
        assert f"mol-shell path --from {first} --stop {float(STOP)!r}" in note, note
        assert main(["scenes", str(first), "--toml"]) == 0
        text = capsys.readouterr().out
        toml.write_text(text)
        assert f"mol-shell path THIS.toml --param {span}" in text and "n = 9" in text
        assert f"mol-shell path --from PATH.nc --stop {STOP:g} goes on from its last step" in text, text
        assert main(["path", str(toml), "--param", span, "--max-steps", "3", "-o", str(again)]) == 0
    a, b = mol_shell.read_netcdf(first), mol_shell.read_netcdf(again)
    assert b.sizes["step"] == 4 and b.attrs["nu"] == 0.3 and b.sizes["s"] == 9
    np.testing.assert_array_equal(b.parameter.values[:3], a.parameter.values)
    np.testing.assert_array_equal(b.r.values[:3], a.r.values)
