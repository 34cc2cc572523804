"""The path and modes figures check what they are given, as the run views do: a wrong response or a Dataset of
another kind ended in xarray's KeyError (``No variable named 'bogus'``, ``'mode'``), a file name in a TypeError."""

import pytest

import mol_shell
from mol_shell.views.modes import plot_modes
from mol_shell.views.path_plot import plot_path


@pytest.fixture(scope="module")
def datasets(tmp_path_factory):
    folder = tmp_path_factory.mktemp("figures")
    path = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, 10.0, n=8, steps=2, progress=False)
    run = mol_shell.simulate(mol_shell.TwistedCylinder(), t_end=2e-4, n=8, progress=False, stresses=False)
    modes = mol_shell.modes(mol_shell.Sphere(), n=8)
    mol_shell.write_netcdf(path, folder / "path.nc")
    mol_shell.write_netcdf(modes, folder / "modes.nc")
    return folder, path, run, modes


def test_wrong_inputs_are_refused_by_name(datasets, tmp_path):
    folder, path, run, _ = datasets
    for call, said in [
        (lambda: plot_path(path, tmp_path / "p.png", response="bogus"), r"^response = 'bogus' is outside \{arclength"),
        (lambda: plot_path(path, tmp_path / "p.png", response="q@1"), r"^response = 'q@1' is outside"),
        (lambda: plot_path(run, tmp_path / "p.png"), r"^ds = '<xarray.Dataset>' is not an equilibrium path"),
        (lambda: plot_modes(run, tmp_path / "m.png"), r"^ds = '<xarray.Dataset>' is a run \(mol-shell run\), not "
                                                      r"natural modes"),
        (lambda: plot_modes(path, tmp_path / "m.png"), r"is an equilibrium path \(mol-shell path\), not natural"),
        (lambda: plot_modes(3, tmp_path / "m.png"), r"^ds = '<int>' is not a Dataset, not natural modes"),
    ]:
        with pytest.raises(mol_shell.ParameterError, match=said):
            call()
    assert not list(tmp_path.iterdir())  # nothing drawn


def test_their_files_are_taken_for_their_datasets(datasets, tmp_path):
    folder, *_ = datasets
    plot_path(folder / "path.nc", tmp_path / "p.png", response="r@1.0")
    plot_modes(str(folder / "modes.nc"), tmp_path / "m.png")
    assert all((tmp_path / name).stat().st_size > 1000 for name in ("p.png", "m.png"))
