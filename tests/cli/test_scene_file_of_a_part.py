"""``scenes FILE --toml`` of a part of a run (``ds.isel(time=...)``, or times reordered by hand) is refused in one
line: it wrote a ``[run] times`` list (``[0.004]``) that ``run`` then refused, though plot, export and animate take
such a file."""

from __future__ import annotations

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("part") / "whole.nc"
    mol_shell.write_netcdf(mol_shell.simulate("twisted-cylinder", "cvode-bdf", n=9, t_end=0.004), str(path))
    return path


@pytest.mark.parametrize("pick", [[4], [3, 2, 1, 0], [0, 0, 1]])
def test_a_part_of_a_run_is_refused_naming_the_file(run_file, pick, capsys):
    part = run_file.parent / f"part{len(pick)}.nc"
    read_netcdf(str(run_file)).isel(time=pick).to_netcdf(part)
    assert main(["scenes", str(part), "--toml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mol-shell: error: FILE = ") and "not increasing times from 0" in err[0]


def test_the_whole_run_still_gives_its_scene_file(run_file, capsys):
    assert main(["scenes", str(run_file), "--toml"]) == 0
    assert "t_end = 0.004" in capsys.readouterr().out


def test_a_stopped_run_of_an_earlier_version_with_one_saved_time_is_said_by_its_times(run_file, capsys):
    """A file of a version before ``t_end_requested`` that stopped at t = 0 (one saved time): its times are the file's
    coordinate, said as such, not as an "attribute times"."""
    part = run_file.parent / "stopped_at_0.nc"
    ds = read_netcdf(str(run_file)).isel(time=[0])
    ds.attrs.update(complete=0, status="failed")
    for name in ("t_end_requested", "times_requested"):
        ds.attrs.pop(name, None)
    ds.to_netcdf(part)
    assert main(["scenes", str(part), "--toml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds the saved times [0.0]" in err[0] and "attribute" not in err[0], err


def test_a_points_file_gone_since_the_run_is_not_blamed_on_the_version(tmp_path, capsys):
    """This version wrote the run: a points file deleted since is why its scene cannot run again, not the version."""
    points = tmp_path / "dome.txt"
    points.write_text("1 0\n0.9 0.3\n0.6 0.6\n0 0.8\n")
    run = tmp_path / "m.nc"
    assert main(["run", "meridian", "--set", f"points={points}", "--n", "9", "--t-end", "1e-5", "-o", str(run)]) == 0
    points.unlink()
    capsys.readouterr()
    assert main(["scenes", str(run), "--toml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot run again" in err[0] and "by this version" not in err[0], err
