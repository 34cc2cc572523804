"""``compare`` checks its run inputs as ``run`` does, before the reference runs: ``--t-end 1e-320`` reached them and
ended as "the reference runs did not complete" (exit 3, after SUNDIALS' status -22 at t = 0) where ``run`` refused
the same value."""

import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.analysis.workprecision import work_precision
from mol_shell.cli.main import main


@pytest.mark.parametrize("t_end", ["1e-320", "5e-154"])
def test_compare_refuses_a_t_end_its_saved_times_cannot_tell_apart(t_end, tmp_path, capsys):
    out = tmp_path / "c.nc"
    assert main(["compare", "sphere", "--n", "8", "--t-end", t_end, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"mol-shell: error: --t-end = {t_end} is outside [6e-154, inf) s (its 4 saved intervals"), err
    assert len(err.splitlines()) == 1 and not out.exists()


def test_compare_refuses_a_scene_file_s_times_and_python_s_as_a_run_does(tmp_path, capsys):
    scene, out = tmp_path / "c.toml", tmp_path / "c.nc"
    scene.write_text('scene = "sphere"\n[run]\nn = 8\ntimes = [0, 1e-320]\n')
    assert main(["compare", str(scene), "-o", str(out)]) == 2
    # the file's value, said with the file and its table (it named the key alone)
    assert capsys.readouterr().err.startswith(f"mol-shell: error: {scene}: [run] times = [0.0, 1e-320] is outside ")
    with pytest.raises(ParameterError, match=r"^times = .* consecutive ones at least 1.4917e-154 s"):
        work_precision("sphere", ["dop853-c"], n=8, times=[0.0, 1e-200, 1e-4], repeats=1, log=lambda *a: None)
