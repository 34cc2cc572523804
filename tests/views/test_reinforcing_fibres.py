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
    assert len(fig.axes) == 3 and set(FAMILY_COLOURS[:2]) <= colours
    path = tmp_path / "run.nc"
    ds.to_netcdf(path)
    assert main(["plot", str(path), "--figure", "fibres", "-o", str(tmp_path / "f.png")]) == 0
    assert (tmp_path / "f.png").stat().st_size > 10_000


def test_on_a_closed_shell_the_section_is_off_the_axis(tmp_path, capsys):
    """A sphere's first node is a pole (r0 = 0): the fibres figure drew two empty panels titled "r = 0 m", exit 0.
    Now the default section is the widest one, and a section asked for at a pole is refused by name."""
    import matplotlib.pyplot as plt

    ds = mol_shell.simulate(mol_shell.Sphere(material="svk-plane-stress", fibre_E=1e6, fibre_angle=0.5), n=10,
                            t_end=1e-4)
    fig = fibres_figure(ds)
    widest = float(ds.s.values[int(np.argmax(ds.r0.values))])
    assert f"the section at s = {widest:.4g} m" in fig._suptitle.get_text()
    plt.close(fig)
    path = tmp_path / "sphere.nc"
    mol_shell.write_netcdf(ds, path)
    assert main(["plot", str(path), "--figure", "fibres", "--at-s", "0", "-o", str(tmp_path / "f.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("mol-shell: error: --at-s = 0.0 is outside [") and "at a pole r = 0" in err


def test_fibres_of_a_layer_are_drawn_and_a_layers_unused_fibre_key_is_said(tmp_path):
    """A layered wall whose fibres live in a layer drew panels (a) and (b) only (the figure read the scene-level
    ``fibre_E``, 0): panel (c) now draws each reinforced layer's families at that layer's angle, labelled; a layer's
    ``fibre_angle`` with no ``fibre_E`` was not said to be unused, as the scene-level one is."""
    import warnings

    import matplotlib.pyplot as plt

    from mol_shell.views.fibres import fibre_sets

    scene = mol_shell.TwistedCylinder(h=0.01, layers="0.012 svk-plane-stress nu=0.3 fibre_angle=0.4; "
                                                     "0.008 svk-plane-stress nu=0.3 fibre_E=5e6 fibre_angle=0.5 "
                                                     "fibre_families=2")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(scene, "leapfrog", n=8, times=[0.0, 2e-3], progress=False)
    said = [str(w.message) for w in caught if issubclass(w.category, mol_shell.MaterialWarning)]
    assert any(m.startswith("layer 1 (0.012 m): fibre_angle = 0.4 is unused") for m in said), said
    assert fibre_sets(ds) == [("layer 2", 0.5, 2)]
    (ref, _), _ = reinforcing_fibres(ds, 1, count=4, angle=0.5, families=2)
    s = np.linspace(0.0, 4.0, 64)
    np.testing.assert_allclose(ref[0][:, 1], np.where(np.cos(np.tan(0.5) * s) >= 0, np.sin(np.tan(0.5) * s), np.nan),
                               atol=1e-12)
    fig = fibres_figure(ds)
    assert len(fig.axes) == 3
    labels = [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    assert labels == ["layer 2: +28.6 deg", "layer 2: -28.6 deg"]
    plt.close(fig)
    assert fibre_sets(ds.assign_attrs(layers="0.02 svk-plane-stress")) == []


def test_twenty_layers_of_two_families_each_get_a_colour():
    """13 or more two-family layers ran out of colours (StopIteration, an internal error): they come round again."""
    import matplotlib.pyplot as plt

    from mol_shell.views.fibres import _fibre_panel

    ds = mol_shell.simulate(mol_shell.TwistedCylinder(fibre_E=1e7, fibre_angle=0.7), "leapfrog", n=8,
                            times=[0.0, 1e-4], progress=False)
    sets = [(f"layer {k}", 0.1 * k, 2) for k in range(1, 21)]
    fig, ax = plt.subplots()
    _fibre_panel(ax, ds, 1, sets)
    assert len(ax.get_legend().get_texts()) == 40
    plt.close(fig)


def test_a_scene_level_fibre_key_unused_by_every_layer_is_said_once():
    """A scene-level ``fibre_angle`` without ``fibre_E`` reaches every layer; it was warned once per layer, the
    same line repeated. A layer of its own keeps its own line."""
    from mol_shell.model.law_warnings import unused_fibres_warnings

    layers = "0.012 neo-hookean-incompressible; 0.008 svk-plane-stress nu=0.3"
    said = unused_fibres_warnings(mol_shell.Sphere(h=0.01, layers=layers, fibre_angle=0.5))
    assert said == [("every layer: fibre_angle = 0.5 is unused: fibre_E = 0 (no fibres); set fibre_E > 0 (Pa) to "
                     "reinforce the wall")]
    own = unused_fibres_warnings(mol_shell.Sphere(h=0.01, layers=layers + " fibre_angle=0.4"))
    assert len(own) == 1 and own[0].startswith("layer 2 (0.008 m): fibre_angle = 0.4 is unused")


def test_a_layer_that_turns_its_fibres_off_is_not_told_the_scene_s_fibre_keys_are_unused():
    """The scene's fibre keys reach every layer; a layer that sets ``fibre_E=0`` itself chose no fibres, and was
    warned that the scene's ``fibre_angle``, ``fibre_families`` were unused there. A key it sets itself is still
    said."""
    from mol_shell.model.law_warnings import unused_fibres_warnings

    scene = mol_shell.Sphere(h=0.01, fibre_E=5e6, fibre_angle=0.7, fibre_families=2,
                             layers="0.012 svk-plane-stress nu=0.3; 0.008 neo-hookean-incompressible fibre_E=0")
    assert unused_fibres_warnings(scene) == []
    own = mol_shell.Sphere(h=0.01, fibre_E=5e6, fibre_angle=0.7,
                           layers="0.012 svk-plane-stress nu=0.3; 0.008 neo-hookean-incompressible fibre_E=0 "
                                  "fibre_angle=0.2")
    assert unused_fibres_warnings(own) == [("layer 2 (0.008 m): fibre_angle = 0.2 is unused: fibre_E = 0 "
                                            "(no fibres); set fibre_E > 0 (Pa) to reinforce the wall")]
