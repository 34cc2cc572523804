"""A path's progress line: a path at n = 801 ran 23 s with nothing on stderr (runs and studies show a bar)."""

from __future__ import annotations

from mol_shell import Sphere, path

SCENE = Sphere(nu=0.3, material="svk-plane-stress")


def test_a_path_shows_its_steps_load_and_critical_points_when_asked(capsys):
    ds = path(SCENE, "pressure", 0.0, -260.0, n=10, progress=True)  # its one critical point in the last step
    err = capsys.readouterr().err
    steps = ds.sizes["step"] - 1
    assert "path in pressure (Pa)" in err and f"{steps} steps" in err, err
    assert "pressure = -260 Pa" in err  # the last step lands on stop
    assert err.rstrip().endswith(f"{ds.sizes['point']} critical]") and ds.sizes["point"] >= 1, err[-200:]


def test_no_progress_line_unless_asked_or_on_a_terminal(capsys):
    path(SCENE, "pressure", 0.0, -300.0, n=10)  # pytest's stderr is no terminal
    assert capsys.readouterr().err == ""
