"""What a new user hit on 0.5.0, in the views: the XDMF export moves (one mesh, a displacement per step), a
sphere's figure shows its radius and its energy-work balance over time, and the mode figure keeps metres and
radians on their own axes."""

import math
from xml.etree import ElementTree as ET

import h5py
import matplotlib
import meshio
import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.views.history import history_figure
from mol_shell.views.modes import modes_figure
from mol_shell.views.plotting import meridian_figure, shows_history

matplotlib.use("Agg")
N_PHI = 5
EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def twisted(tmp_path_factory):
    """The paper's scene on 8 nodes over 10 us: the twist turns every section (|chi| up to 0.2 rad)."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False)
    path = tmp_path_factory.mktemp("newcomer_views") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path


@pytest.fixture(scope="module")
def inflated():
    """A closed sphere (n = 9: the equator is node 4, s = pi a / 2) under a pressure ramped up over 1 ms."""
    scene = mol_shell.Sphere(pressure=1e3, pressure_history="ramp 0.001")
    return mol_shell.simulate(scene, n=9, times=np.linspace(0, 2e-3, 9), dt=1e-5, progress=False, stresses=False)


def positions(ds, k):
    """``(r cos(phi + chi), r sin(phi + chi), z)`` of the base surface at saved time ``k`` (node-major)."""
    phi = 2 * math.pi * np.arange(N_PHI) / N_PHI
    r, chi, z = (ds[f].values[k][:, None] for f in ("r", "chi", "z"))
    return np.stack([r * np.cos(phi + chi), r * np.sin(phi + chi), z + 0 * phi], axis=-1).reshape(-1, 3)


def reference(ds):
    """The reference cylinder ``(r0 cos phi, r0 sin phi, z0)``."""
    phi = 2 * math.pi * np.arange(N_PHI) / N_PHI
    r0, z0 = ds.r0.values[:, None], ds.z0.values[:, None]
    return np.stack([r0 * np.cos(phi), r0 * np.sin(phi), z0 + 0 * phi], axis=-1).reshape(-1, 3)


# -- item 3: the export moves ------------------------------------------------------------------------------
def test_the_xdmf_series_is_one_mesh_moved_by_its_displacement(twisted, tmp_path):
    """Read back by meshio's TimeSeriesReader as ParaView reads it: the one mesh is the reference shell, and at
    every step mesh + displacement is the rotationally symmetric map of the run's fields at that time."""
    ds, path = twisted
    out = tmp_path / "shell.xdmf"
    assert main(["export", str(path), "--n-phi", str(N_PHI), "-o", str(out)]) == 0
    with meshio.xdmf.TimeSeriesReader(out) as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == ds.sizes["time"] == 11
        np.testing.assert_allclose(points, reference(ds), rtol=0, atol=4 * EPS)
        moved = 0.0
        for k in range(reader.num_steps):
            t, point_data, _ = reader.read_data(k)
            assert t == float(ds.time[k]) and point_data["displacement"].shape == (len(points), 3)
            np.testing.assert_allclose(points + point_data["displacement"], positions(ds, k), rtol=0, atol=4 * EPS)
            moved = max(moved, float(np.abs(point_data["displacement"]).max()))
    assert moved > 0.1  # the twist of 0.2 rad turns the sections by about 0.2 m


def test_the_mesh_is_written_once_and_the_data_are_compressed(twisted, tmp_path):
    """One Topology and one Geometry in the file (each step refers to them), one connectivity array in the HDF5
    file, and (64 azimuths: arrays of 4 kB, compressed) the HDF5 file smaller than its float data alone."""
    ds, path = twisted
    out = tmp_path / "shell.xdmf"
    assert main(["export", str(path), "--n-phi", "64", "-o", str(out)]) == 0
    root = ET.parse(out).getroot()
    assert len(list(root.iter("Topology"))) == 1 and len(list(root.iter("Geometry"))) == 1
    with h5py.File(out.with_suffix(".h5")) as h5:
        arrays = [h5[name] for name in h5]
        connectivity = [a.shape for a in arrays if a.dtype.kind in "iu"]
        raw = sum(a.size * a.dtype.itemsize for a in arrays if a.dtype.kind == "f")
    assert connectivity == [((ds.sizes["s"] - 1) * 64, 4)]
    assert out.with_suffix(".h5").stat().st_size < raw


def test_the_pvd_series_carries_the_displacement_too(twisted, tmp_path):
    ds, path = twisted
    out = tmp_path / "shell.pvd"
    assert main(["export", str(path), "--n-phi", str(N_PHI), "-o", str(out)]) == 0
    items = list(ET.parse(out).getroot().iter("DataSet"))
    assert len(items) == ds.sizes["time"]
    for k, item in enumerate(items):
        mesh = meshio.read(out.parent / item.get("file"))
        np.testing.assert_allclose(mesh.points, positions(ds, k), rtol=0, atol=4 * EPS)
        np.testing.assert_allclose(mesh.point_data["displacement"], positions(ds, k) - reference(ds), rtol=0,
                                   atol=4 * EPS)


# -- item 14: a breathing or inflated shell's figures ----------------------------------------------------------
def _axis(fig, title_start):
    found = [ax for ax in fig.axes if ax.get_title().startswith(title_start)]
    assert len(found) == 1, [ax.get_title() for ax in fig.axes]
    return found[0]


def _line(ax, label_start):
    found = [line for line in ax.get_lines() if str(line.get_label()).startswith(label_start)]
    assert len(found) == 1, [line.get_label() for line in ax.get_lines()]
    return found[0]


def test_a_sphere_s_figure_shows_its_equatorial_radius_and_energy_balance_over_time(inflated):
    """The equator of a closed sphere on 9 nodes is node 4 (s = pi a / 2, r0 = a); the balance drawn is
    E - E(0) - W + D from the run's energies, work and dissipation."""
    import matplotlib.pyplot as plt

    ds = inflated
    assert shows_history(ds)
    fig = meridian_figure(ds)
    radius = _line(_axis(fig, "radius at the equator"), "r at s = ")
    np.testing.assert_array_equal(radius.get_xdata(), ds.time.values)
    assert float(ds.s[4]) == pytest.approx(math.pi / 2, rel=1e-12)
    np.testing.assert_array_equal(radius.get_ydata(), ds.r.values[:, 4])
    balance = _axis(fig, "energy-work balance")
    energy, work = ds.energy.values, ds.work.values
    np.testing.assert_allclose(_line(balance, "W,").get_ydata(), work)
    np.testing.assert_allclose(_line(balance, "E - E(0) - W + D").get_ydata(),
                               energy - energy[0] - work + ds.dissipated.values, rtol=0, atol=1e-12 * np.abs(work).max())
    assert np.abs(work).max() > 0 and ds.r.values[-1, 4] > 1.0  # the shell was inflated
    plt.close(fig)
    at = history_figure(ds, s=0.5)  # a chosen s: the node nearest 0.5 m (s_k = k pi / 8: node 1)
    np.testing.assert_array_equal(_line(_axis(at, "radius at the chosen s"), "r at s =").get_ydata(), ds.r.values[:, 1])
    plt.close(at)


def test_the_command_draws_the_history_of_a_pressurised_cylinder_and_the_paper_s_figure_otherwise(tmp_path):
    cylinder = mol_shell.simulate(mol_shell.TwistedCylinder(gamma=0.0, R=1.0), n=6, t_end=1e-5, progress=False,
                                  stresses=False)
    assert not shows_history(cylinder)
    cylinder.attrs["pressure"] = 100.0
    assert shows_history(cylinder)
    path = tmp_path / "c.nc"
    mol_shell.write_netcdf(cylinder, path)
    assert main(["plot", str(path), "--at-s", "1", "-o", str(tmp_path / "c.png")]) == 0
    assert main(["plot", str(path), "--figure", "history", "-o", str(tmp_path / "h.svg")]) == 0
    assert (tmp_path / "c.png").stat().st_size > 10_000 and (tmp_path / "h.svg").stat().st_size > 10_000


def test_the_mode_figure_keeps_angles_and_lengths_on_their_own_axes():
    """Every panel holds lengths (z, r; m) or angles (chi, theta, psi; rad), never both, and says which."""
    import matplotlib.pyplot as plt

    ds = mol_shell.modes(mol_shell.Sphere(), n=9, count=4)
    fig = modes_figure(ds, count=4)
    kinds = set()
    for ax in fig.axes:
        names = {str(line.get_label()).split(" ")[0] for line in ax.get_lines() if not str(line.get_label()).startswith("_")}
        if not names:
            continue
        if names <= {"z", "r"}:  # scaled shapes: no units of their own (tests/views/test_figure_layout.py)
            assert ax.get_ylabel().startswith("shape of z, r"), ax.get_ylabel()
            kinds.add("m")
        else:
            assert names <= {"chi", "theta", "psi"} and ax.get_ylabel().startswith("shape of chi, theta, psi"), (
                names, ax.get_ylabel())
            kinds.add("rad")
    assert kinds == {"m", "rad"}  # the sphere's lowest modes move both
    plt.close(fig)
