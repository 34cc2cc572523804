"""Panel (c) of ``plot --figure fibres``: the reinforcing fibres (fibre_E > 0) on the shell, seen from the side."""

import numpy as np

import mol_shell
from mol_shell.cli.main import main
from mol_shell.views.fibres import FAMILY_COLOURS, fibres_figure, reinforcing_fibres


def test_helices_on_a_cylinder_and_their_images(tmp_path):
    """On the unit cylinder a fibre at ``alpha`` from the meridian is the helix ``phi = phi_k + s tan(alpha)``: its side
    view ``y = sin(phi)`` (the visible half, ``cos(phi) > 0``); the deformed one is ``r sin(phi + chi)`` at ``z``.
    Two families give two colours; a run without fibres keeps its two panels."""
    scene = mol_shell.TwistedCylinder(fibre_E=1e7, fibre_angle=0.7, fibre_families=2)
    ds = mol_shell.simulate(scene, "leapfrog", n=8, times=[0.0, 2e-3], progress=False)
    (ref, cur), (ref2, _) = reinforcing_fibres(ds, 1, count=4)
    s = np.linspace(0.0, 4.0, 64)
    phi = np.tan(0.7) * s
    expected = np.where(np.cos(phi) >= 0, np.sin(phi), np.nan)
    np.testing.assert_allclose(ref[0][:, 1], expected, atol=1e-12)
    np.testing.assert_allclose(ref2[0][:, 1], np.where(np.cos(phi) >= 0, -np.sin(phi), np.nan), atol=1e-12)
    z, r, chi = (np.interp(s, ds.s.values, ds[f].values[1]) for f in ("z", "r", "chi"))
    np.testing.assert_allclose(cur[0][:, 0], np.where(np.cos(phi + chi) >= 0, z, np.nan), atol=1e-12)
    np.testing.assert_allclose(cur[0][:, 1], np.where(np.cos(phi + chi) >= 0, r * np.sin(phi + chi), np.nan), atol=1e-12)
    fig = fibres_figure(ds)
    colours = {line.get_color() for line in fig.axes[2].get_lines()}
    assert len(fig.axes) == 3 and set(FAMILY_COLOURS) <= colours
    path = tmp_path / "run.nc"
    ds.to_netcdf(path)
    assert main(["plot", str(path), "--figure", "fibres", "-o", str(tmp_path / "f.png")]) == 0
    assert (tmp_path / "f.png").stat().st_size > 10_000
