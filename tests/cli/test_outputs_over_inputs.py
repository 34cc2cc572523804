"""A command never writes over the file it reads: ``export run.h5 -o run.xdmf`` replaced the run (a netCDF4 file is
HDF5, so users name it ``.h5``) by the export's HDF5 data, exit 0, the run lost. Any file a command would write (its
``-o``, the files beside it: an XDMF's ``.h5``, a PVD's ``_NNNN.vtu``, modes' ``.png``) that is its input (``FILE``,
``--from``, ``--set points``) is refused in one line naming ``-o``, exit 2, before anything is computed; the input
keeps every byte."""

import hashlib
import shutil

import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.views.export import export


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A run (8 nodes, 11 saved times) and an equilibrium path (a sphere, 8 nodes, 2 steps) on disk."""
    folder = tmp_path_factory.mktemp("inputs")
    run = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False)
    mol_shell.write_netcdf(run, folder / "run.nc")
    path = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, -50.0, n=8, max_steps=2, progress=False)
    mol_shell.write_netcdf(path, folder / "path.nc")
    return folder


def digest(path):
    return hashlib.md5(path.read_bytes()).hexdigest()


#: (source file, the input's name, the command after its name, what the refusal says of -o)
CASES = {
    "export .xdmf over its run.h5": ("run.nc", "run.h5", ["export", "{in}", "-o", "{dir}/run.xdmf"],
                                     "would write run.h5 beside it, which is the input file FILE = "),
    "export .pvd over a step's .vtu": ("run.nc", "x_0003.vtu", ["export", "{in}", "-o", "{dir}/x.pvd"],
                                       "would write x_0003.vtu beside it, which is the input file FILE = "),
    "export, the input spelled otherwise": ("run.nc", "run.h5", ["export", "{dir}/sub/../run.h5", "-o",
                                                                 "{dir}/run.xdmf"],
                                            "would write run.h5 beside it, which is the input file FILE = "),
    "plot over its file": ("run.nc", "run.png", ["plot", "{in}", "-o", "{dir}/run.png"], "is the input file FILE = "),
    "animate over its file": ("run.nc", "run.gif", ["animate", "{in}", "--n-phi", "8", "--width", "100", "-o",
                                                    "{dir}/run.gif"], "is the input file FILE = "),
    "run --from over its path": ("path.nc", "p.nc", ["run", "--from", "{in}", "--step", "1", "--n", "8", "--t-end",
                                                     "1e-6", "-o", "{dir}/./p.nc"], "is the input file --from = "),
    "modes --from over its path": ("path.nc", "p.nc", ["modes", "--from", "{in}", "--step", "1", "--count", "1", "-o",
                                                       "{dir}/p.nc"], "is the input file --from = "),
    "modes' figure over its path": ("path.nc", "p.png", ["modes", "--from", "{in}", "--step", "1", "--count", "1",
                                                         "-o", "{dir}/p.nc"],
                                    "would write p.png beside it, which is the input file --from = "),
}


@pytest.mark.parametrize("case", list(CASES))
def test_an_output_that_is_the_input_is_refused_and_the_input_kept(files, tmp_path, capsys, case):
    source, name, argv, words = CASES[case]
    given = tmp_path / name
    shutil.copy(files / source, given)
    (tmp_path / "sub").mkdir()
    before = digest(given)
    code = main([a.format(**{"in": str(given), "dir": str(tmp_path)}) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("mol-shell: error: -o = "), err
    assert words in err[0] and "its data would be lost" in err[0] and "give -o another name" in err[0], err
    assert digest(given) == before  # every byte of the input kept


def test_a_meridian_s_points_file_is_not_overwritten(tmp_path, capsys):
    """``--set points=FILE`` is read too: a run whose -o is that file was refused only as unreadable afterwards."""
    points = tmp_path / "dome.nc"
    points.write_text("1 0\n0.9 0.3\n0.6 0.5\n0 0.6\n")
    code = main(["run", "meridian", "--set", f"points={points}", "--n", "8", "--t-end", "1e-6", "-o", str(points)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "is the input file --set points = " in err[0], err
    assert points.read_text().startswith("1 0\n")


@pytest.mark.parametrize("given", ["pts.nc", "pts.csv"])
def test_a_points_file_a_scene_file_names_is_not_overwritten(tmp_path, capsys, monkeypatch, given):
    """A scene file's ``points = "pts.nc"`` is read (relative to the scene file's folder) as ``--set points`` is,
    but only ``--set points`` counted as an input: ``run scene.toml -o pts.nc`` replaced the meridian by the run.
    Refused naming -o and the scene file's key, every byte kept; ``--set points`` in its place is read instead, and
    the file's points then are not an input."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in").mkdir()
    points = tmp_path / "in" / given
    points.write_text("1 0\n0.9 0.3\n0.6 0.5\n0 0.6\n")
    (tmp_path / "in" / "scene.toml").write_text(f'scene = "meridian"\n[geometry]\npoints = "{given}"\n')
    argv = ["run", "in/scene.toml", "--n", "8", "--t-end", "1e-6", "-o"]
    for output in (f"in/{given}", f"in/../in/{given}", f"./in/{given}"):
        code = main([*argv, output])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and err[0].startswith("mol-shell: error: -o = '"), err
        if given.endswith(".nc"):  # a .csv is no run file either: refused for its suffix first
            assert "is the input file in/scene.toml: [geometry] points = " in err[0], err
        assert points.read_text().startswith("1 0\n")
    if given.endswith(".nc"):
        (tmp_path / "other.nc").write_text("1 0\n0.9 0.3\n0.6 0.5\n0 0.6\n")
        assert main(["run", "in/scene.toml", "--set", "points=other.nc", "--n", "8", "--t-end", "1e-6", "-o",
                     f"in/{given}"]) == 0
        assert points.read_bytes().startswith(b"\x89HDF")  # the run, over a file this run did not read


def test_python_export_refuses_to_write_over_its_run(files, tmp_path):
    """``export(path_or_dataset_read_from_it, ...)``: the same refusal, naming the keyword ``path``."""
    given = tmp_path / "run.h5"
    shutil.copy(files / "run.nc", given)
    before = digest(given)
    for ds in (str(given), mol_shell.read_netcdf(given)):
        with pytest.raises(ParameterError, match="path = .* would write run.h5 beside it, which is the input file ds"):
            export(ds, tmp_path / "run.xdmf", n_phi=3)
    assert digest(given) == before
    assert len(export(str(given), tmp_path / "other.xdmf", n_phi=3)) == 2  # another name: written
