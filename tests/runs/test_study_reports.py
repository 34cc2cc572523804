"""What a study reads and says: a string parameter's values as typed, the long build up front, an interrupted case's
progress line, the notes of the cases' own scenes, and each case's warnings about its own course."""

import collections
import warnings

import numpy as np
import pytest

from mol_shell._core import progress
from mol_shell._core.errors import MaterialWarning
from mol_shell.cli.main import main
from mol_shell.cli.study import parse_vary
from mol_shell.runs import resources
from mol_shell.runs.simulate import as_scene
from mol_shell.runs.study import run_cases, study
from mol_shell.runs.study_design import design


def test_vary_reads_a_string_parameter_as_set_does(tmp_path, capsys):
    """``h_profile=0.006`` is a constant thickness (an expression of s), not the number 0.006 the scene refused
    (``h_profile = 0.006 is not a string``); a range on a string parameter gives its numbers as text."""
    scene = as_scene("twisted-cylinder")
    vary = parse_vary(["h_profile=0.006,0.005+0.0005*s", "end1_spin_history=table 0:0 1:1", "gamma=0.1:0.2:0.1"],
                      11, scene)
    assert vary == {"h_profile": ["0.006", "0.005+0.0005*s"], "end1_spin_history": ["table 0:0 1:1"],
                    "gamma": [0.1, 0.2]}
    assert parse_vary(["h_profile=0.005:0.007:0.001"], 11, scene)["h_profile"] == ["0.005", "0.006", "0.007"]
    assert parse_vary(["material=my_laws:rubber"], 11, scene)["material"] == ["my_laws:rubber"]
    assert design(scene, vary)[1]["h_profile"] == ["0.006", "0.005+0.0005*s"]
    code = main(["study", "twisted-cylinder", "--vary", "h_profile=0.006", "--t-end", "0.001", "--n", "5",
                 "--scheduler", "serial", "-o", str(tmp_path / "hp.nc")])
    assert code == 0, capsys.readouterr().err


def test_a_study_says_a_long_build_up_front_as_a_run_does(monkeypatch):
    monkeypatch.setattr(resources, "LONG_BUILD_S", 0.0)
    with pytest.warns(resources.LongRunWarning, match=r"^building the graphs and the spectrum at n = 11 takes about "
                      r".* before the first step"):
        resources.check_before_build(11, [0.0, 0.001], dt=1e-6)
    with pytest.warns(resources.LongRunWarning, match=r"^building the graphs and the spectrum at n = 11 takes about "
                      r".* before each case's first step"):
        resources.check_study(2, 11, [0.0, 0.001], dt=1e-6, workers=1)


@pytest.mark.parametrize("stop, done", [(1, "1 of 3 cases (33 %)"), (0, "0 of 3 cases (0 %)")])
def test_an_interrupted_case_is_not_counted_done_nor_given_a_time_left(stop, done, monkeypatch, capsys):
    monkeypatch.setattr(progress, "LOG_INTERVAL_S", 0.0)  # a line at every case
    Task = collections.namedtuple("Task", "index")

    def run(task):
        status = "interrupted" if task.index == (stop,) else "complete"
        return task.index, None, {"status": status, "message": ""}

    with pytest.raises(KeyboardInterrupt):
        run_cases(run, [Task((i,)) for i in range(3)], {}, output=None, final=("complete",), scheduler="serial",
                  workers=None, client=None, progress=None, total=3)
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1].startswith(f"mol-shell: study: {done}, last case interrupted, ended after"), lines
    assert not [line for line in lines if "interrupted" in line and " left" in line], lines


def test_a_study_over_meridian_files_says_no_note_of_the_dome(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    t = np.linspace(0, np.pi / 2, 9)
    for name, a in (("a", 1.0), ("b", 0.9)):
        np.savetxt(f"{name}.txt", np.column_stack([a * np.cos(t), 0.6 * np.sin(t)]))
    common = ["--set", "pressure=1000", "--set", "material=svk-plane-stress", "--n", "5", "--t-end", "0.0005",
              "--scheduler", "serial"]
    assert main(["study", "meridian", "--vary", "points=a.txt,b.txt", *common, "-o", "mp.nc"]) == 0
    assert "built-in dome" not in capsys.readouterr().err
    assert main(["study", "meridian", "--vary", "points=a.txt,", *common, "-o", "mp2.nc"]) == 2  # an empty entry
    capsys.readouterr()
    assert main(["study", "meridian", "--vary", "h=0.01,0.02", *common, "-o", "mp3.nc"]) == 0
    assert capsys.readouterr().err.count("note: the meridian is the built-in dome") == 1  # its cases run it


def test_a_study_says_each_cases_loss_of_ellipticity_naming_the_case():
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        ds = study("twisted-cylinder", {"psi0": [0.0, 1.5]}, n=5, t_end=0.002, scheduler="serial")
    lost = [str(w.message) for w in said if issubclass(w.category, MaterialWarning) and "ellipticity" in str(w.message)]
    assert lost == [f"case psi0=1.5: {ds.ellipticity_warning.sel(psi0=1.5).item()}"], lost
