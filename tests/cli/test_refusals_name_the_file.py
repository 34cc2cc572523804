"""Refusals name what the user gave, not a usage line's placeholder, and the scene file where it set the value.

``mol-shell scenes FILE --toml`` refused a file that is not a run as ``NAME = 'FILE' is not a mol_shell run file``
(``NAME``: no word the user typed; a scene file ``FILE.toml`` said as "not a netCDF file"); a study of a scene file
said a case refused for a value of the file (``[run] dt`` beyond the leap-frog's bound at one of the grid's moduli)
without the file and table a single run's refusal names."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from mol_shell.analysis.run_scene import RUN_OR_PATH_FILE
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf, write_netcdf

SCENE = 'scene = "sphere"\n[parameters]\nh = -1\n'


def _error(capsys):
    """The command's lines on stderr but its warnings."""
    return [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]


def test_scenes_toml_of_a_scene_file_says_it_is_a_scene_file(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(SCENE)
    said = (f"mol-shell: error: FILE = '{path}' is a scene file (TOML), not a run file; allowed: {RUN_OR_PATH_FILE} (--toml "
            f"writes a run file back as a scene file; mol-shell run {path} runs a scene file)")
    for args in (["scenes", str(path), "--toml"], ["scenes", str(path)]):  # without --toml: not "give ... --toml"
        assert main(args) == 2
        assert _error(capsys) == [said], args


def test_scenes_toml_refusals_name_the_file_not_the_placeholder(tmp_path, capsys):
    missing, other = tmp_path / "none.nc", tmp_path / "other.nc"
    write_netcdf(xr.Dataset({"x": ("k", np.zeros(2))}), other)  # a netCDF file that is no run
    assert main(["scenes", str(missing), "--toml"]) == 2
    assert _error(capsys) == [f"mol-shell: error: FILE = '{missing}' does not exist; allowed: {RUN_OR_PATH_FILE}"]
    assert main(["scenes", str(other), "--toml"]) == 2
    said = (f"mol-shell: error: FILE = '{other}' is not a mol_shell run or path file; allowed: {RUN_OR_PATH_FILE} "
            "(it holds dims k)")  # a path file is written back as a scene file too
    assert _error(capsys) == [said]


def test_a_study_s_refused_case_names_the_scene_file_and_table_that_set_the_value(tmp_path, capsys, monkeypatch):
    """E = 1e9 Pa makes the waves ~32 times faster than at 1e6 Pa (sqrt(E / rho)): the file's dt = 1e-4 s, within
    the leap-frog's bound at 1e6 Pa, is beyond it there; that case is refused, the other runs (exit 3)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('scene = "sphere"\n[material]\nE = 1e6\n[run]\nn = 5\ndt = 1e-4\nt_end = 2e-4\n')
    code = main(["study", "s.toml", "--vary", "E=1e6,1e9", "--workers", "1", "-o", "st.nc"])
    err = _error(capsys)
    assert code == 3, err
    assert err[0].startswith("mol-shell: error: 1 of 2 cases refused: s.toml: [run] dt = 0.0001 is outside (0, "), err
    assert len(err) == 1, err
    ds = read_netcdf(tmp_path / "st.nc")
    assert ds.status.values.tolist() == ["complete", "refused"]
    assert str(ds.message.values[1]).startswith("dt = 0.0001 is outside (0, ")  # the file's data: as the run said it


def test_a_study_s_refused_case_of_a_varied_value_names_it_alone(tmp_path, capsys, monkeypatch):
    """A value the grid gives (``--vary``, as ``--set``) is no value of the file: said without it."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('scene = "sphere"\n[material]\nh = 0.01\n[run]\nn = 5\nt_end = 2e-5\n')
    code = main(["study", "s.toml", "--vary", "h=-1,0.01", "--workers", "1", "-o", "st.nc"])
    err = _error(capsys)
    assert code == 3, err
    assert err[0].startswith("mol-shell: error: 1 of 2 cases refused: h = -1.0 is outside (0, inf) m"), err


def test_scenes_of_a_file_that_is_not_there_says_so(tmp_path, capsys):
    """``scenes missing.toml`` said ``scene = '...missing.toml' is outside {axisymmetric, ...}``: a path is a file."""
    missing = str(tmp_path / "missing.toml")
    assert main(["scenes", missing]) == 2
    err = capsys.readouterr().err
    assert err == f"mol-shell: error: FILE = {missing!r} does not exist; allowed: a scene in {{axisymmetric, cone, " \
        "meridian, sphere, spinning-ring, torus, twisted-cylinder, unshearable, vessel} or a run file RUN.nc " \
        "(with --toml)\n"  # what scenes takes (docs/cli.md): a scene file is refused as one, not a run file
    assert main(["scenes", "spheer"]) == 2 and "scene = 'spheer' is outside" in capsys.readouterr().err


def test_a_run_file_whose_scene_this_version_refuses_is_named(tmp_path, capsys):
    """A run made before a scene's check (a torus turning by 2 pi, refused since December 7) could not be written back
    as a scene file, and the refusal did not name the run file: it says the file and the version that wrote it. A
    directory is said as one, not as missing."""
    import math

    import mol_shell
    ds = mol_shell.simulate(mol_shell.Torus(), n=5, times=[0.0, 1e-6], progress=False, stresses=False)
    ds.attrs["alpha2"] = ds.attrs["alpha1"] + 2 * math.pi  # as a run of the earlier version stored it
    ds.attrs["mol_shell_version"] = "0.5.0"  # ... which wrote it (this version's own runs are said otherwise)
    path = tmp_path / "old.nc"
    mol_shell.write_netcdf(ds, path)
    assert main(["scenes", str(path), "--toml"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mol-shell: error: FILE = {str(path)!r}: the run's scene is refused by this version") \
        and "alpha2" in err and len(err.strip().splitlines()) == 1, err
    assert main(["scenes", str(tmp_path)]) == 2 and "is a directory" in capsys.readouterr().err


def test_modes_of_a_file_whose_initial_dilation_is_no_equilibrium_name_the_file_and_key(tmp_path, capsys):
    """examples/torus_gravity.toml starts at dilation = 1.0 (its natural state) under gravity, no equilibrium: modes
    said ``scene = 'torus' is outside a scene whose initial state is an equilibrium (...)``. The value at fault is
    the file's ``[initial] dilation`` (with ``--set dilation=1.0`` the key alone: the command line set it); the fix,
    dilation = auto, and mol-shell run for the motion are said. On n = 11 as test_newcomer's modes of that file."""
    path = Path(__file__).resolve().parents[2] / "examples" / "torus_gravity.toml"
    for sets, head in (([], f"mol-shell: error: {path}: [initial] dilation = 1.0 is outside "),
                       (["--set", "dilation=1.0"], "mol-shell: error: dilation = 1.0 is outside ")):
        assert main(["modes", str(path), *sets, "--n", "11", "-o", str(tmp_path / "m.nc")]) == 2
        err = _error(capsys)
        assert len(err) == 1 and err[0].startswith(head + "auto, or a value whose initial state is an equilibrium"), err
        assert "(residual force " in err[0] and "dilation = auto starts from the static equilibrium" in err[0]
        assert "(mol-shell run) follows the motion" in err[0] and "scene = " not in err[0], err
