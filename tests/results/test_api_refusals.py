"""Bad input to the library's functions is a ParameterError naming the parameter, as on the command line: a new
user met raw TypeErrors and ValueErrors from inside numpy, scipy and dataclasses (December 6)."""

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main


def test_add_stresses_and_write_netcdf_name_what_they_take(tmp_path):
    with pytest.raises(mol_shell.ParameterError, match=r"^ds = None is not an xarray.Dataset"):
        mol_shell.add_stresses(None)
    with pytest.raises(mol_shell.ParameterError, match=r"read_netcdf\(PATH\) reads a file"):
        mol_shell.add_stresses(str(tmp_path / "run.nc"))
    ds = mol_shell.simulate(mol_shell.Sphere(), n=8, t_end=1e-4, progress=False, stresses=False)
    with pytest.raises(mol_shell.ParameterError, match=r"^path = 5 is not a file path"):
        mol_shell.write_netcdf(ds, 5)


def test_initial_fields_with_r_at_zero_off_the_axis_are_refused_naming_initial():
    """All zeros put r = 0 at nodes off the axis, where the equations divide by r: modes ended in numpy's "array
    must not contain infs or NaNs", simulate blamed the scene."""
    for call in (lambda: mol_shell.modes(mol_shell.Sphere(), n=12, initial=np.zeros((5, 12))),
                 lambda: mol_shell.simulate(mol_shell.Sphere(), n=12, t_end=1e-4, initial=np.zeros((5, 12)))):
        with pytest.raises(mol_shell.ParameterError, match=r"^initial = 'r = 0 m at s = .* r > 0 at every node off"):
            call()


@pytest.fixture(scope="module")
def path_file(tmp_path_factory):
    ds = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, 50.0, n=8, max_steps=3, progress=False)
    return ds


@pytest.mark.parametrize("scene, why", [(None, "has no scene attribute"),
                                        ("bogus", "names no registered scene in its attribute scene = 'bogus'")])
def test_a_path_file_without_its_scene_is_refused_naming_from(path_file, tmp_path, capsys, scene, why):
    """``run --from`` of a path file whose ``scene`` attribute was deleted ended in an internal KeyError."""
    edited = path_file.copy()
    if scene is None:
        del edited.attrs["scene"]
    else:
        edited.attrs["scene"] = scene
    f = tmp_path / "edited.nc"
    mol_shell.write_netcdf(edited, f)
    assert main(["run", "--from", str(f), "--step", "1", "--t-end", "1e-4", "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"mol-shell: error: --from = '{f}' {why}; allowed: a netCDF file written by mol-shell path", err


def test_numpy_0d_arrays_are_taken_as_the_numbers_they_hold():
    """``np.array(12)`` was refused as ``n = 12 is outside integers >= 3``, ``np.array(1e-3)`` as not a number."""
    ds = mol_shell.simulate(mol_shell.Sphere(), n=np.array(12), t_end=np.array(1e-4), progress=False, stresses=False)
    assert ds.sizes["s"] == 12 and float(ds.time[-1]) == 1e-4
    p = mol_shell.path(mol_shell.Sphere(), "pressure", np.array(0.0), np.array(50.0), n=np.array(8),
                       max_steps=np.array(2), progress=False)
    assert p.sizes["s"] == 8 and float(p.parameter[0]) == 0.0
    assert mol_shell.modes(mol_shell.Sphere(), n=np.array(10), count=np.array(2)).sizes["mode"] == 2
