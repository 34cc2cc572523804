"""3-D export: re-read with meshio, the points are the rotationally symmetric map at every saved time and
the data are the run's; bad input is refused with one line and exit code 2."""

import math
from xml.etree import ElementTree as ET

import casadi as ca
import meshio
import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.model.balance import configuration
from mol_shell.results.stresses import add_stresses

EPS = np.finfo(float).eps
N_PHI = 6


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The paper's scene on 8 nodes over 10 us (11 saved times, twist chi = +-0.2 rad), with stresses."""
    ds = add_stresses(mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False))
    path = tmp_path_factory.mktemp("export") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path


def closed_form(ds, k):
    """``(r cos(phi + chi), r sin(phi + chi), z)`` on the ``s x phi`` grid (node-major), ``phi = 2 pi j / N_PHI``."""
    phi = 2 * math.pi * np.arange(N_PHI) / N_PHI
    r, chi, z = (ds[f].values[k][:, None] for f in ("r", "chi", "z"))
    return np.stack([r * np.cos(phi + chi), r * np.sin(phi + chi), z + 0 * phi], axis=-1).reshape(-1, 3)


def offset_points(ds, k, zeta):
    """``r + zeta d`` from :func:`mol_shell.model.balance.configuration` (CasADi, Cartesian ``(k, i2, i3)``),
    reordered to ``(x, y, z) = (i2, i3, k)``: an independent route to the faces."""
    fields, phi = ca.SX.sym("q", 5), ca.SX.sym("phi")
    pos, d, _ = configuration(ca.vertsplit(fields), phi)
    f = ca.Function("p", [fields, phi], [pos + zeta * d])
    out = []
    for i in range(ds.sizes["s"]):
        q = [float(ds[name].values[k, i]) for name in ("z", "r", "chi", "theta", "psi")]
        for j in range(N_PHI):
            p = np.array(f(q, 2 * math.pi * j / N_PHI)).ravel()
            out.append([p[1], p[2], p[0]])
    return np.array(out)


def read_xdmf(path):
    """Every step of an XDMF time series through meshio's reader: one reference mesh, moved at each step by its
    ``displacement`` (as ParaView's Warp By Vector moves it)."""
    steps = []
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        reference, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            steps.append((t, reference + point_data["displacement"], cells, point_data, cell_data))
    return steps


def read_pvd(path):
    steps = []
    for item in ET.parse(path).getroot().iter("DataSet"):
        mesh = meshio.read(path.parent / item.get("file"))
        steps.append((float(item.get("timestep")), mesh.points, mesh.cells, mesh.point_data, mesh.cell_data))
    return steps


@pytest.mark.parametrize("suffix", ["xdmf", "pvd"])
def test_points_are_the_map_and_data_are_the_run(run, tmp_path, suffix):
    """Positions to round-off (a few EPS of the radius), data exactly (they are copies), one step per saved
    time at that time; the cell data are the run's per-cell values on each quad of the cell."""
    ds, path = run
    out = tmp_path / f"shell.{suffix}"
    assert main(["export", str(path), "--n-phi", str(N_PHI), "-o", str(out)]) == 0
    steps = read_xdmf(out) if suffix == "xdmf" else read_pvd(out)
    assert len(steps) == ds.sizes["time"] == 11
    n = ds.sizes["s"]
    for k, (t, points, cells, point_data, cell_data) in enumerate(steps):
        assert t == float(ds.time[k])
        np.testing.assert_allclose(points, closed_form(ds, k), rtol=0, atol=4 * EPS)
        assert cells[0].type == "quad" and len(cells[0].data) == (n - 1) * N_PHI
        for name in ("z", "r", "chi", "theta", "psi", "chi_t", "r_t"):
            np.testing.assert_array_equal(point_data[name], np.repeat(ds[name].values[k], N_PHI), err_msg=name)
        np.testing.assert_array_equal(point_data["phi"], np.tile(2 * np.pi * np.arange(N_PHI) / N_PHI, n))
        for name in ("axial_torque", "membrane_force_hoop"):
            np.testing.assert_array_equal(cell_data[name][0], np.repeat(ds[name].values[k], N_PHI), err_msg=name)
        np.testing.assert_array_equal(cell_data["von_mises_stress_outer"][0],
                                      np.repeat(ds.von_mises_stress.values[k, :, 1], N_PHI))
        interior = np.repeat((ds.axial_force.values[k, 1:] + ds.axial_force.values[k, :-1]) / 2, N_PHI)
        np.testing.assert_allclose(point_data["axial_force"][N_PHI:-N_PHI], interior, rtol=1e-15)
    assert abs(ds.chi.values).max() > 0.19  # the map really turns the lines


def test_faces_are_offset_along_the_director_and_quads_face_outwards(run, tmp_path):
    """``--faces``: base, inner and outer surfaces in one mesh; the faces are ``r + zeta d`` at ``zeta1`` and
    ``zeta1 + 2h`` (checked against the balance-law module's Cartesian configuration to round-off). The quad
    ``(p0, p1, p2, p3)`` has ``(p1 - p0) x (p3 - p0)`` pointing away from the axis."""
    ds, path = run
    out = tmp_path / "faces.xdmf"
    assert main(["export", str(path), "--n-phi", str(N_PHI), "--faces", "-o", str(out)]) == 0
    t, points, cells, point_data, _ = read_xdmf(out)[-1]
    k, block = ds.sizes["time"] - 1, ds.sizes["s"] * N_PHI
    zeta1 = float(ds.attrs["zeta1_used"])
    for surface, zeta in enumerate((0.0, zeta1, zeta1 + 2 * float(ds.attrs["h"]))):
        part = points[surface * block : (surface + 1) * block]
        np.testing.assert_allclose(part, offset_points(ds, k, zeta), rtol=0, atol=8 * EPS)
        np.testing.assert_array_equal(point_data["zeta"][surface * block : (surface + 1) * block], zeta)
    quad = points[cells[0].data]
    normal = np.cross(quad[:, 1] - quad[:, 0], quad[:, 3] - quad[:, 0])
    radial = quad.mean(axis=1) * [1, 1, 0]
    assert np.all(np.einsum("ij,ij->i", normal, radial) > 0)


def test_bad_input_is_refused_in_one_line(run, tmp_path, capsys):
    ds, path = run
    text = tmp_path / "notes.nc"
    text.write_text("not netCDF")
    study_like = tmp_path / "other.nc"
    ds[["energy"]].to_netcdf(study_like)
    (tmp_path / "d.xdmf").mkdir()
    cases = [
        ([str(text), "-o", str(tmp_path / "a.xdmf")], "FILE = "),
        ([str(study_like), "-o", str(tmp_path / "a.xdmf")], "is not a mol_shell run file"),
        ([str(tmp_path / "missing.nc"), "-o", str(tmp_path / "a.xdmf")], "does not exist"),
        ([str(path), "-o", str(tmp_path / "a.vtk")], "-o = "),
        ([str(path), "-o", "/proc/no/such/a.xdmf"], "cannot be written"),
        ([str(path), "-o", str(tmp_path / "d.xdmf")], "is a directory"),
        ([str(path), "--n-phi", "2", "-o", str(tmp_path / "a.xdmf")], "--n-phi = 2 is outside"),
    ]
    for argv, words in cases:
        code = main(["export", *argv])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("mol-shell: error: ") and len(err.splitlines()) == 1, (argv, err)
        assert words in err, (argv, err)
    assert not (tmp_path / "a.xdmf").exists() and not (tmp_path / "a.h5").exists()


@pytest.mark.parametrize("suffix", ["xdmf", "pvd"])
def test_an_export_that_fails_on_the_way_leaves_the_previous_one_whole(run, tmp_path, monkeypatch, suffix):
    """The XDMF + HDF5 and PVD + VTU files were written in place: an export that failed (or was interrupted) on the
    way left a new .h5 or some new .vtu beside the old collection, or half of them. Exports are now written into a
    hidden folder and moved into place when whole, the collection last; a failure leaves the previous files as
    they were and nothing else."""
    from mol_shell.views import export as exporting

    ds, _ = run
    target = tmp_path / f"shell.{suffix}"
    exporting.export(ds, target, n_phi=8)
    before = {f.name: f.read_bytes() for f in tmp_path.iterdir()}
    original, calls = meshio.write, [0]

    def failing(*args, **kwargs):  # the PVD writer: a disk full at the second step
        calls[0] += 1
        if calls[0] == 2:
            raise OSError(28, "No space left on device")
        return original(*args, **kwargs)

    def failing_data(self, *args, **kwargs):  # the XDMF writer: the same at its second step
        calls[0] += 1
        if calls[0] == 2:
            raise OSError(28, "No space left on device")
        return original_data(self, *args, **kwargs)

    original_data = meshio.xdmf.TimeSeriesWriter.write_data
    monkeypatch.setattr(meshio, "write", failing)
    monkeypatch.setattr(meshio.xdmf.TimeSeriesWriter, "write_data", failing_data)
    with pytest.raises(OSError, match="No space left"):
        exporting.export(ds, target, n_phi=12)
    assert {f.name: f.read_bytes() for f in tmp_path.iterdir()} == before
