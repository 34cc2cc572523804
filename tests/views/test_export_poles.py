"""3-D export of a closed shell: each pole one point, joined to its neighbouring circle by triangles, so the surface
is closed and no cell has an edge of zero length (its 16 copies of each pole and 32 quads with a zero-length edge
at n = 41, --n-phi 16, were a surface open at the poles); positions still the run's at every saved time."""

import math
import warnings
from collections import Counter
from xml.etree import ElementTree as ET

import meshio
import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main

N_PHI = 6


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """A pressurised sphere on 9 nodes (its ends the poles), 3 saved times (as tests/views/test_view_inputs.py runs it)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(mol_shell.Sphere(pressure=1e4), n=9, times=[0, 1e-4, 2e-4], progress=False)
    path = tmp_path_factory.mktemp("poles") / "sphere.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path


def steps_of(out):
    """``[(points, cells, cell_data)]`` of each saved time, as ParaView sees them (an XDMF's reference + displacement)."""
    if out.suffix == ".pvd":
        meshes = [meshio.read(out.parent / item.get("file")) for item in ET.parse(out).getroot().iter("DataSet")]
        return [(m.points, m.cells, m.cell_data) for m in meshes]
    steps = []
    with meshio.xdmf.TimeSeriesReader(out) as reader:
        reference, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            _, point_data, cell_data = reader.read_data(k)
            steps.append((reference + point_data["displacement"], cells, cell_data))
    return steps


@pytest.mark.parametrize("suffix, faces", [("pvd", False), ("xdmf", True)])
def test_each_pole_is_one_point_and_the_surface_is_closed(sphere, tmp_path, suffix, faces):
    ds, path = sphere
    n, surfaces = ds.sizes["s"], 3 if faces else 1
    out = tmp_path / f"sphere.{suffix}"
    assert main(["export", str(path), "--n-phi", str(N_PHI), "-o", str(out)] + ["--faces"] * faces) == 0
    steps = steps_of(out)
    assert len(steps) == ds.sizes["time"]
    phi = 2 * math.pi * np.arange(N_PHI) / N_PHI
    for k, (points, cells, cell_data) in enumerate(steps):
        # per surface: the n - 2 circles between the poles and the two poles; quads between circles, a fan at each pole
        assert len(points) == surfaces * ((n - 2) * N_PHI + 2) == len(np.unique(points, axis=0))
        assert [(c.type, len(c.data)) for c in cells] == [("quad", surfaces * (n - 3) * N_PHI),
                                                          ("triangle", surfaces * 2 * N_PHI)]
        edges = Counter()
        for block in cells:
            corners = points[block.data]
            assert np.linalg.norm(np.roll(corners, -1, axis=1) - corners, axis=2).min() > 0  # no degenerate cell
            for a in range(block.data.shape[1]):
                edges.update(map(tuple, np.sort(np.stack([block.data[:, a], block.data[:, a - 1]], axis=1), axis=1)))
        assert set(edges.values()) == {2}  # each edge between two cells: closed, without holes or seams
        assert [len(v) for v in cell_data["axial_torque"]] == [len(c.data) for c in cells]
        # the base surface: the pole (0, 0, z), then the circles (r cos(phi + chi), r sin(phi + chi), z), the pole
        r, chi, z = (ds[f].values[k][:, None] for f in ("r", "chi", "z"))
        rings = np.stack([r * np.cos(phi + chi), r * np.sin(phi + chi), z + 0 * phi], axis=-1)[1:-1].reshape(-1, 3)
        base = np.concatenate([[[0.0, 0.0, z[0, 0]]], rings, [[0.0, 0.0, z[-1, 0]]]])
        np.testing.assert_allclose(points[: len(base)], base, rtol=0, atol=4 * np.finfo(float).eps)
