"""Refusals name what the user gave, not a usage line's placeholder.

``mol-shell scenes FILE --toml`` refused a file that is not a run as ``NAME = 'FILE' is not a mol_shell run file``
(``NAME``: no word the user typed; a scene file ``FILE.toml`` said as "not a netCDF file")."""

from __future__ import annotations

import numpy as np
import xarray as xr

from mol_shell.cli.main import main
from mol_shell.results.dataset import RUN_FILE, write_netcdf

SCENE = 'scene = "sphere"\n[parameters]\nh = -1\n'


def _error(capsys):
    """The command's lines on stderr but its warnings."""
    return [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]


def test_scenes_toml_of_a_scene_file_says_it_is_a_scene_file(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(SCENE)
    said = (f"mol-shell: error: file = '{path}' is a scene file (TOML), not a run file; allowed: {RUN_FILE} (--toml "
            f"writes a run file back as a scene file; mol-shell run {path} runs a scene file)")
    for args in (["scenes", str(path), "--toml"], ["scenes", str(path)]):  # without --toml: not "give ... --toml"
        assert main(args) == 2
        assert _error(capsys) == [said], args


def test_scenes_toml_refusals_name_the_file_not_the_placeholder(tmp_path, capsys):
    missing, other = tmp_path / "none.nc", tmp_path / "other.nc"
    write_netcdf(xr.Dataset({"x": ("k", np.zeros(2))}), other)  # a netCDF file that is no run
    assert main(["scenes", str(missing), "--toml"]) == 2
    assert _error(capsys) == [f"mol-shell: error: file = '{missing}' does not exist; allowed: {RUN_FILE}"]
    assert main(["scenes", str(other), "--toml"]) == 2
    said = f"mol-shell: error: file = '{other}' is not a mol_shell run file; allowed: {RUN_FILE} (it holds dims k)"
    assert _error(capsys) == [said]
