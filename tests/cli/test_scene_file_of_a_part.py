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
