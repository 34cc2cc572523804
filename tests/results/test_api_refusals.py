"""Bad input to the library's functions is a ParameterError naming the parameter, as on the command line: a new
user met raw TypeErrors and ValueErrors from inside numpy, scipy and dataclasses (December 6)."""

import re

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


def test_initial_fields_off_the_values_the_edges_impose_are_refused_by_name():
    """A twisted cylinder's last state given as a sphere's ``initial`` (r = 0.995 m at its poles) was taken: the run
    stopped 29 us later at ``delta <= 0``, far from the cause. A pole's values (r = 0, theta = theta0, psi = 0),
    which the geometry forces, must now hold; other edges take what the state has (a path's clamped edges stay
    where it started, a driven edge where it went), as before."""
    cyl = mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=12, progress=False, stresses=False)
    last = np.stack([cyl[f].isel(time=-1).values for f in ("z", "r", "chi", "theta", "psi")])
    with pytest.raises(mol_shell.ParameterError, match=r"^initial = 'r = 0.99\d* m at s = 0 m' is outside fields with "
                       r"the values the scene's edges impose: r = 0 m there \(end1 is 'pole'\)"):
        mol_shell.simulate(mol_shell.Sphere(), t_end=2e-4, n=12, initial=last, progress=False)
    sphere = mol_shell.simulate(mol_shell.Sphere(), t_end=2e-4, n=12, progress=False, stresses=False)
    state = np.stack([sphere[f].isel(time=-1).values for f in ("z", "r", "chi", "theta", "psi")])
    state[3, -1] += 1e-3  # theta at the top pole
    with pytest.raises(mol_shell.ParameterError, match=r"theta = -1.5698 rad at s = 3.14159 m.*theta = -1.5708 rad there \(end2 is 'pole'"):
        mol_shell.simulate(mol_shell.Sphere(), t_end=2e-4, n=12, initial=state, progress=False)
    driven = mol_shell.TwistedCylinder(end2_axial_speed=0.5)  # its own last state: end2 moved 1e-4 m, taken
    own = mol_shell.simulate(driven, t_end=2e-4, n=12, progress=False, stresses=False)
    state = np.stack([own[f].isel(time=-1).values for f in ("z", "r", "chi", "theta", "psi")])
    assert state[0, -1] > driven.L
    again = mol_shell.simulate(driven, t_end=2e-4, n=12, initial=state, progress=False, stresses=False)
    assert again.attrs["status"] == "complete" and float(again.z.isel(time=0).values[-1]) == state[0, -1]


def test_a_dataset_given_where_it_does_not_belong_is_named_on_one_line():
    """``simulate(ds)``, ``read_netcdf(ds)``, ``load_scene(ds)`` and ``modes(initial=ds)`` printed xarray's repr of
    the Dataset, cut in its middle, inside a two-line message; it is now its kind and sizes."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=False, stresses=False)
    for call in (lambda: mol_shell.simulate(ds, t_end=1e-3), lambda: mol_shell.read_netcdf(ds),
                 lambda: mol_shell.load_scene(ds), lambda: mol_shell.modes(mol_shell.Sphere(), n=8, initial=ds)):
        with pytest.raises(mol_shell.ParameterError) as info:
            call()
        text = str(info.value)
        assert "\n" not in text and "= <xarray.Dataset (time: 11, s: 8, end: 2)> is not" in text, text


@pytest.mark.parametrize("call", ["simulate", "study", "path"])
def test_progress_takes_a_bool_or_none(call):
    """``progress="no"`` showed a bar (any true value did), where ``stresses="yes"`` was refused: both now are."""
    scene = mol_shell.TwistedCylinder()
    calls = {"simulate": lambda p: mol_shell.simulate(scene, t_end=2e-4, n=8, progress=p),
             "study": lambda p: mol_shell.study(scene, {"gamma": [0.05]}, n=8, t_end=2e-4, scheduler="serial",
                                                progress=p),
             "path": lambda p: mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, 10.0, n=8, steps=2, progress=p)}
    with pytest.raises(mol_shell.ParameterError, match=r"^progress = 'no' is not a bool; allowed: True, False, or None"):
        calls[call]("no")


def test_attributes_netcdf_cannot_hold_are_converted_or_refused_by_name(tmp_path):
    """A user's own attributes on a run: ``True`` ended in netCDF4's ``TypeError: illegal data type for attribute
    b'flag' ... got b1``, ``None`` and dicts in TypeErrors. A bool is written as 0/1 and None as "none" (as the
    package writes its own); a dict or a list holding None is refused naming the attribute, nothing written."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=False, stresses=False)
    mine = ds.copy()
    mine.attrs.update(flag=True, note=None, sizes=[1, 2])
    mol_shell.write_netcdf(mine, tmp_path / "a.nc")
    back = mol_shell.read_netcdf(tmp_path / "a.nc")
    assert back.attrs["flag"] == 1 and back.attrs["note"] == "none" and list(back.attrs["sizes"]) == [1, 2]
    assert mine.attrs["flag"] is True  # the caller's Dataset is left as it was
    for where, bad in (("ds.attrs['cfg']", lambda d: d.attrs.update(cfg={"a": 1})),
                       ("ds['r'].attrs['x']", lambda d: d["r"].attrs.update(x=[1, None])),
                       ("ds.attrs['grid']", lambda d: d.attrs.update(grid=np.ones((2, 2)))),  # xarray's ValueError
                       ("ds.attrs['mixed']", lambda d: d.attrs.update(mixed=["a", 1]))):  # was written as strings
        other = ds.copy(deep=True)
        bad(other)
        with pytest.raises(mol_shell.ParameterError, match=rf"^{re.escape(where)} = .* is not a netCDF attribute"):
            mol_shell.write_netcdf(other, tmp_path / "b.nc")
        assert not (tmp_path / "b.nc").exists()
    with pytest.raises(mol_shell.ParameterError, match=r"^scene = \['sphere'\] is outside \{"):
        mol_shell.get_scene(["sphere"])


def test_a_twist_whose_equilibrium_radius_reaches_the_axis_is_refused_naming_the_twist():
    """``TwistedCylinder(gamma=1e3)`` was refused as ``R = 5.4e-06 is outside (0.006296, inf) m``, naming R, which
    the user left to the code; the parameter that made it so is named, with the computed R in the reason."""
    with pytest.raises(mol_shell.ParameterError, match=r"^gamma = 1000.0 is outside values whose equilibrium radius "
                       r"\(R = auto\) keeps the wall off the axis \(R = 5.39\d*e-06 is outside") as info:
        mol_shell.simulate(mol_shell.TwistedCylinder(gamma=1e3), t_end=1e-3, n=8)
    assert info.value.name == "gamma"
    with pytest.raises(mol_shell.ParameterError, match=r"^R = 1e-06 is outside \(0.006296, inf\) m"):
        mol_shell.TwistedCylinder(R=1e-6)  # set by the user: named as before
