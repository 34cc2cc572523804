"""What the views' functions take: a run's Dataset or its file, an output path whose folders are made; a study, an
unknown field or an image type matplotlib cannot write refused by name before anything is drawn or written."""

import warnings

import numpy as np
import pytest
from PIL import Image

import mol_shell
from mol_shell import ParameterError
from mol_shell.cli.main import main
from mol_shell.views.animate import animate, default_field
from mol_shell.views.export import export
from mol_shell.views.fibres import plot_fibres
from mol_shell.views.fields import field
from mol_shell.views.history import plot_history
from mol_shell.views.plotting import plot_meridian, plot_snapshots, snapshot_figure

SMALL = {"n_phi": 6, "fibres": 2, "width": 100}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The paper's scene on 8 nodes over 20 us (3 saved times), as a Dataset and a file; a study of two cases."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, times=[0, 1e-5, 2e-5], progress=False,
                                stresses=False)
        study = mol_shell.study(mol_shell.TwistedCylinder(), {"gamma": [0.05, 0.1]}, n=8, times=[0, 1e-5],
                                scheduler="serial", progress=False)
    path = tmp_path_factory.mktemp("inputs") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path, study


def test_missing_directories_of_the_output_are_created(runs, tmp_path):
    ds = runs[0]
    files = export(ds, tmp_path / "new" / "dir" / "x.xdmf", n_phi=6)
    assert [f.name for f in files] == ["x.xdmf", "x.h5"] and all(f.is_file() for f in files)
    assert animate(ds, tmp_path / "new_dir" / "a.gif", **SMALL) == 3
    with Image.open(tmp_path / "new_dir" / "a.gif") as gif:
        assert gif.format == "GIF" and gif.size == (100, 90)
    plot_snapshots(ds, tmp_path / "figs" / "s.png")
    assert (tmp_path / "figs" / "s.png").stat().st_size > 1000


def test_a_study_is_refused_by_name_and_nothing_is_written(runs, tmp_path):
    study = runs[2]
    calls = {"export": lambda: export(study, tmp_path / "e" / "st.xdmf"),
             "animate": lambda: animate(study, tmp_path / "st.gif", **SMALL),
             "snapshot_figure": lambda: snapshot_figure(study),
             "plot_fibres": lambda: plot_fibres(study, tmp_path / "f.png"),
             "plot_history": lambda: plot_history(study, tmp_path / "h.png")}
    for name, call in calls.items():
        with pytest.raises(ParameterError) as refused:
            call()
        text = str(refused.value)
        assert refused.value.name == "ds" and "\n" not in text, name
        assert text.startswith("ds is a parameter study (mol-shell study) over gamma, not one run; allowed: a run's "
                               "Dataset") and "isel" in text, (name, text)
    assert list(tmp_path.iterdir()) == []  # no e/, no st.xdmf, st.h5
    one = study.isel(gamma=1)  # a case of it is a run
    assert export(one, tmp_path / "one.xdmf", n_phi=6)[0].is_file()


def test_a_run_file_is_taken_for_its_dataset(runs, tmp_path):
    ds, path, _ = runs
    plot_snapshots(str(path), tmp_path / "s.png")
    plot_meridian(path, tmp_path / "m.png")
    plot_history(path, tmp_path / "h.png")
    plot_fibres(str(path), tmp_path / "f.png")
    assert animate(str(path), tmp_path / "a.gif", **SMALL) == ds.sizes["time"]
    assert all((tmp_path / name).stat().st_size > 1000 for name in ("s.png", "m.png", "h.png", "f.png", "a.gif"))
    with pytest.raises(ParameterError, match=r"^ds = '.*missing\.nc' does not exist; allowed: a run's Dataset"):
        plot_snapshots(tmp_path / "missing.nc", tmp_path / "x.png")
    with pytest.raises(ParameterError, match=r"^ds = 3 is not a run's Dataset or a file path; allowed: "):
        animate(3, tmp_path / "x.gif")
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.gif").exists()


def test_an_unknown_field_of_the_snapshots_is_refused_naming_fields(runs, tmp_path):
    with pytest.raises(ParameterError) as refused:
        plot_snapshots(runs[0], tmp_path / "s.png", fields=("rr",))
    assert refused.value.name == "fields"
    assert str(refused.value) == ("fields = ('rr',) names 'rr', not a field the snapshots draw; allowed: one or more "
                                  "of {r, theta, chi}")
    with pytest.raises(ParameterError, match=r"^fields = \(\) is empty; allowed: one or more of \{r, theta, chi\}$"):
        snapshot_figure(runs[0], fields=())
    assert not (tmp_path / "s.png").exists()
    fig = snapshot_figure(runs[0], fields=("chi", "r"))
    assert len([ax for ax in fig.axes if ax.get_visible()]) == 2 * 3


def test_an_image_type_matplotlib_cannot_write_is_refused_before_drawing(runs, tmp_path, monkeypatch):
    drawn = []
    monkeypatch.setattr("mol_shell.views.plotting.snapshot_figure", lambda *a, **k: drawn.append(1))
    with pytest.raises(ParameterError) as refused:
        plot_snapshots(runs[0], tmp_path / "s.xyz")
    text = str(refused.value)
    assert refused.value.name == "path" and text.startswith(f"path = '{tmp_path / 's.xyz'}' ends in .xyz")
    assert all(f".{kind}," in text for kind in ("pdf", "png")) and ".svg" in text
    assert drawn == [] and list(tmp_path.iterdir()) == []


def test_python_names_keywords_and_the_command_line_its_options(runs, tmp_path, capsys):
    ds, path, _ = runs
    from_python = [(lambda: export(ds, tmp_path / "x.vtu"), "path = ", "ends in .vtu"),
                   (lambda: export(ds, tmp_path / "x.xdmf", n_phi=2), "n_phi = 2 is outside", "[3, 1024]"),
                   (lambda: animate(ds, tmp_path / "a.gif", field="axial_torq"), "field = 'axial_torq' is outside",
                    "{z, z_t, r"),
                   (lambda: plot_fibres(ds, tmp_path / "f.png", time=1.0), "time = 1 is outside", "[0, 2e-05] s"),
                   (lambda: plot_fibres(ds, tmp_path / "f.png", s=9.0), "s = 9 is outside", "[0, 4] m"),
                   (lambda: plot_fibres(ds, tmp_path / "f.png", thickness_scale=-1.0),
                    "thickness_scale = -1.0 is outside", "(0, "),
                   (lambda: plot_history(ds, tmp_path / "h.png", s=9.0), "s = 9 is outside", "[0, 4] m")]
    for call, start, words in from_python:
        with pytest.raises(ParameterError) as refused:
            call()
        assert str(refused.value).startswith(start) and words in str(refused.value), str(refused.value)
        assert "--" not in str(refused.value).split(" is ")[0]
    from_the_command_line = [(["animate", str(path), "--field", "axial_torq", "-o", str(tmp_path / "a.gif")],
                              "--field = 'axial_torq' is outside {z, z_t, r"),
                             (["plot", str(path), "--figure", "fibres", "--time", "1", "-o", str(tmp_path / "f.png")],
                              "--time = 1 is outside [0, 2e-05] s"),
                             (["plot", str(path), "--figure", "history", "--at-s", "9", "-o", str(tmp_path / "h.png")],
                              "--at-s = 9 is outside [0, 4] m")]
    for argv, start in from_the_command_line:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"mol-shell: error: {start}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_the_thickness_scale_is_bounded_by_the_sections_radius(runs, tmp_path, capsys):
    ds, path, _ = runs
    most = float(ds.r0[0]) / (2 * float(ds.attrs["h"]))  # the paper's wall, 2h = 12.6 mm, on a radius of 1 m
    assert 79 < most < 80
    assert main(["plot", str(path), "--figure", "fibres", "--thickness-scale", "1e6", "-o", str(tmp_path / "b.png")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mol-shell: error: --thickness-scale = 1000000.0 is outside (0, {most:.6g}] (the drawn "
                          "wall at most as thick as the section's radius, or true to scale: r0 = ") and len(
                              err.splitlines()) == 1, err
    assert not (tmp_path / "b.png").exists()
    with pytest.raises(ParameterError, match=r"^thickness_scale = 80 is outside \(0, 79\.5"):
        plot_fibres(ds, tmp_path / "b.png", thickness_scale=80)
    plot_fibres(ds, tmp_path / "b.png", thickness_scale=float(f"{most:.6g}"))  # the bound as said is taken
    assert (tmp_path / "b.png").stat().st_size > 1000


def test_a_thick_wall_near_a_pole_is_drawn_true_to_scale_when_asked(tmp_path):
    """Near a pole of a thick wall the section's radius is below the wall's thickness: the bound r0 / wall (0.72
    at the sphere's second node here) refused thickness_scale = 1, the true scale, which the default draws."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(mol_shell.Sphere(h=0.3), n=8, times=[0, 1e-5], progress=False, stresses=False)
    s = float(ds.s.values[1])
    assert float(ds.r0.values[1]) < 2 * 0.3  # thinner section than wall
    plot_fibres(ds, tmp_path / "t.png", s=s, thickness_scale=1.0)
    assert (tmp_path / "t.png").stat().st_size > 1000
    with pytest.raises(ParameterError, match=r"^thickness_scale = 1.5 is outside \(0, 1\]"):
        plot_fibres(ds, tmp_path / "u.png", s=s, thickness_scale=1.5)


def test_the_animation_is_coloured_by_default_by_a_field_that_moves(runs, tmp_path, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sphere = mol_shell.simulate(mol_shell.Sphere(pressure=1e4), n=9, times=[0, 1e-4, 2e-4], progress=False,
                                    stresses=False)
    assert float(np.ptp(sphere.chi.values)) < 1e-12  # a pressurised sphere does not twist: chi coloured nothing
    moved = float(np.abs(sphere.r - sphere.r0).max())
    assert moved > 1e-7
    values, units, label = field(sphere, "r_displacement", "nodes")
    np.testing.assert_array_equal(values, (sphere.r - sphere.r0).values)
    assert units == "m" and label == "radial displacement r - r0 [m]"
    assert default_field(sphere) == ("r_displacement", "coloured by r_displacement (chi does not vary)")
    assert default_field(runs[0]) == ("chi", "coloured by chi")  # the paper's twisting cylinder
    mol_shell.write_netcdf(sphere, tmp_path / "sphere.nc")
    out = tmp_path / "s.gif"
    argv = ["animate", str(tmp_path / "sphere.nc"), "--n-phi", "6", "--fibres", "2", "--width", "100", "-o", str(out)]
    assert main(argv) == 0
    assert capsys.readouterr().out == f"wrote {out}: 3 frames, coloured by r_displacement (chi does not vary)\n"
    assert main([*argv[:-2], "--field", "chi", "-o", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote {out}: 3 frames, coloured by chi\n"  # as asked: said too
    assert main(["animate", "--help"]) == 0
    assert "default: the first of chi, r_displacement, z_displacement, theta, psi that varies" in \
        " ".join(capsys.readouterr().out.split())
