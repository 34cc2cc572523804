"""More of what a new user hit in the views: an MP4 of any allowed width, graded walls drawn at their own
thickness, the radius drawn where a vessel is cylindrical, and plot's refusal listing what it reads."""

import stat

import imageio_ffmpeg
import meshio
import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.analysis.workprecision import markdown_table, work_precision
from mol_shell.cli.main import main
from mol_shell.views.fibres import fibres_figure
from mol_shell.views.history import QUADRATURE_LABEL, balance_terms, history_figure, radius_node
from mol_shell.views.workprecision import write_outputs


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """The paper's scene on 6 nodes, two saved times: the smallest run an animation draws."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=[0.0, 2e-6], progress=False, stresses=False)
    path = tmp_path_factory.mktemp("newcomer_views_more") / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return path


# -- an MP4 of every allowed width ---------------------------------------------------------------------------
@pytest.mark.parametrize(("width", "size"), [(201, (202, 180)), (210, (210, 190)), (1024, (1024, 922))])
def test_an_mp4_of_an_odd_frame_size_is_written_with_even_sides(short_run, tmp_path, width, size):
    """H.264 in 4:2:0 colour needs even sides: the frame is the nearest even numbers to the width and to 0.9 of it
    (201 x 180.9 -> 202 x 180; 1024 x 921.6 -> 1024 x 922), where ffmpeg refused 201 x 180 and 1024 x 921."""
    out = tmp_path / "w.mp4"
    assert main(["animate", str(short_run), "--n-phi", "6", "--fibres", "2", "--width", str(width), "-o", str(out)]) == 0
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    reader.close()
    assert tuple(meta["size"]) == size
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == 2


def test_an_encoder_that_fails_is_said_in_one_line_and_leaves_no_file(short_run, tmp_path, monkeypatch, capsys):
    """An ffmpeg that refuses (here a stand-in that says why and exits 1): one line naming -o, exit 2, no file
    written, a previous file left as it was, and no temporary file left beside it."""
    fake = tmp_path / "ffmpeg"
    fake.write_text("#!/bin/sh\ncat > /dev/null\necho '[libx264 @ 0x5555] width not divisible by 2' >&2\nexit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setattr(imageio_ffmpeg, "get_ffmpeg_exe", lambda: str(fake))
    folder = tmp_path / "out"
    folder.mkdir()
    argv = ["animate", str(short_run), "--n-phi", "6", "--fibres", "2", "--width", "200"]
    assert main([*argv, "-o", str(folder / "w.mp4")]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: -o = "), err
    assert "could not be encoded ([libx264] width not divisible by 2)" in err and "200 x 180 pixels" in err, err
    assert list(folder.iterdir()) == []
    (folder / "old.mp4").write_bytes(b"previous")
    assert main([*argv, "-o", str(folder / "old.mp4")]) == 2
    assert (folder / "old.mp4").read_bytes() == b"previous" and len(list(folder.iterdir())) == 1


# -- a graded wall drawn at its own thickness ----------------------------------------------------------------
PROFILE = "0.005 * (1 + 0.25 * s)"


def profile_h(s):
    """The half-thickness of :data:`PROFILE`, written out here: 5 mm at s = 0, growing by a quarter per metre."""
    return 0.005 * (1 + 0.25 * np.asarray(s))


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """A vessel of two hemispheres and a 2 m cylinder (12 nodes) whose wall thickens along the meridian (h from 5 mm
    to 11.4 mm; the nominal h is 6.28 mm), inflated for 0.1 ms."""
    scene = mol_shell.SCENES["vessel"](segments="arc 1 -90, line 2, arc 1 -90", h_profile=PROFILE, pressure=100.0)
    ds = mol_shell.simulate(scene, n=12, times=[0.0, 1e-4], progress=False, stresses=False)
    path = tmp_path_factory.mktemp("graded") / "seg.nc"
    mol_shell.write_netcdf(ds, path)
    return ds, path


def around_poles(values, n, n_phi):
    """Per-point ``values`` of the three surfaces of a closed shell's export, each pole one point there, as grids
    ``(3, n, n_phi, ...)``: each pole's value repeated round its (degenerate) circle."""
    per = values.reshape(3, (n - 2) * n_phi + 2, *values.shape[1:])
    poles = [np.repeat(per[:, end], n_phi, axis=1) for end in (slice(0, 1), slice(-1, None))]
    return np.concatenate([poles[0], per[:, 1:-1], poles[1]], axis=1).reshape(3, n, n_phi, *values.shape[1:])


def test_the_exported_faces_of_a_graded_wall_sit_at_its_own_thickness(graded, tmp_path):
    """Read back by meshio: at every step each face point is h(s) from its base point, h(s) from PROFILE at the
    node (not the nominal h), the base surface halfway between the faces, and the point data zeta is -h(s), +h(s)."""
    ds, path = graded
    out = tmp_path / "seg.pvd"
    n, n_phi = ds.sizes["s"], 6
    assert main(["export", str(path), "--faces", "--n-phi", str(n_phi), "-o", str(out)]) == 0
    h = profile_h(ds["s"].values)[:, None]
    assert h.min() < float(ds.attrs["h"]) < h.max()  # the nominal h would be wrong on both sides
    for k in range(ds.sizes["time"]):
        mesh = meshio.read(tmp_path / f"seg_{k:04d}.vtu")
        base, inner, outer = around_poles(mesh.points, n, n_phi)
        np.testing.assert_allclose(np.linalg.norm(outer - base, axis=-1), np.broadcast_to(h, (n, n_phi)), rtol=1e-9)
        np.testing.assert_allclose(np.linalg.norm(inner - base, axis=-1), np.broadcast_to(h, (n, n_phi)), rtol=1e-9)
        np.testing.assert_allclose((inner + outer) / 2, base, atol=1e-12)
        zeta = around_poles(mesh.point_data["zeta"], n, n_phi)
        np.testing.assert_allclose(zeta, np.stack([0 * h, -h, h]) + np.zeros((3, n, n_phi)), rtol=1e-12)


def test_the_fibre_figure_of_a_graded_wall_draws_the_section_s_own_thickness(graded):
    """At a section of the cylinder (theta0 = 0 there, so the reference fibres are radial) the fibre in panel (a),
    drawn 10x, is 10 x 2 h(s) long and runs from r0 - 10 h(s), h(s) from PROFILE at that node."""
    ds, _ = graded
    i = 5
    s = float(ds["s"].values[i])
    assert np.pi / 2 < s < np.pi / 2 + 2 and float(ds["theta0"].values[i]) == pytest.approx(0.0, abs=1e-12)
    fig = fibres_figure(ds, s=s, count=4, thickness_scale=10.0)
    red = [line for line in fig.axes[0].lines if line.get_color() == "tab:red"]
    assert len(red) == 1
    x, y = red[0].get_data()
    assert np.hypot(np.diff(x), np.diff(y))[0] == pytest.approx(10 * 2 * profile_h(s), rel=1e-9)
    assert x[0] == pytest.approx(float(ds["r0"].values[i]) - 10 * profile_h(s), rel=1e-9)


# -- compare: no speed-up against a baseline that did not complete ------------------------------------------
def test_compare_gives_no_speed_up_against_a_leapfrog_baseline_that_went_unstable(tmp_path):
    """A stiff viscous wall (eta_mu = 1000 Pa s) on 20 nodes: leap-frog at dt = 1e-6 goes unstable, so the table
    (printed, and in the .md) says n/a with a note, not a ratio against the run's time to its blow-up; the dataset
    holds no ratio."""
    scene = mol_shell.SCENES["twisted-cylinder"](eta_mu=1000.0, eta_lambda=2000.0)
    ds = work_precision(scene, ["leapfrog", "cvode-bdf"], n=20, times=[0.0, 0.0025, 0.005], repeats=1,
                        sweeps={"leapfrog": {"dt": (1e-6,)}, "cvode-bdf": {"rtol": (1e-7,)}}, log=lambda *a: None)
    assert list(ds.status.values[:, 0]) == ["unstable", "complete"] and float(ds.error[1, 0]) <= 1e-6
    table = markdown_table(ds)
    row = next(line for line in table.splitlines() if line.startswith("| cvode-bdf |"))
    assert row.endswith("| n/a |") and "x |" not in table
    assert table.splitlines()[-1] == ("Speed-up n/a: the baseline leapfrog 1e-06 did not complete (unstable; its note "
                                      "in the file says why), so no speed-up is measured against it.")
    write_outputs(ds, tmp_path / "wp.nc")
    assert table in (tmp_path / "wp.md").read_text()
    # (the scene's parameters are in attrs: end1_axial_speed is a drive, not a ratio)
    assert not any("speed" in name and "axial_speed" not in name for name in [*ds.variables, *ds.attrs])


def test_compare_gives_the_speed_up_against_a_baseline_that_completed():
    """The ratio stays where the baseline ran: the paper's scene on 8 nodes, leap-frog at dt = 1e-6 completes."""
    ds = work_precision("twisted-cylinder", ["leapfrog", "cvode-bdf"], n=8, times=[0.0, 1e-4], repeats=1,
                        sweeps={"leapfrog": {"dt": (1e-6,)}, "cvode-bdf": {"rtol": (1e-7,)}}, log=lambda *a: None)
    assert list(ds.status.values[:, 0]) == ["complete", "complete"]
    table = markdown_table(ds, target=1.0)
    base = float(ds.wall_time_s[0, 0])
    for i, name in enumerate(("leapfrog", "cvode-bdf")):
        row = next(line for line in table.splitlines() if line.startswith(f"| {name} |"))
        assert row.endswith(f"| {base / float(ds.wall_time_s[i, 0]):.1f}x |")
    assert "n/a" not in table


# -- units on every variable and coordinate of the files the commands write ------------------------------------
def without_units(path):
    """Names of the numeric variables and coordinates of the netCDF file ``path`` that have no ``units``."""
    with xr.open_dataset(path, decode_times=False) as ds:
        return sorted(name for name, var in ds.variables.items()
                      if var.dtype.kind not in "OSU" and not str(var.attrs.get("units", "")).strip())


def test_every_numeric_variable_and_coordinate_of_the_written_files_has_units(tmp_path):
    """A run with stresses, a modes file, a path file, a path study and a compare file, read back: nothing numeric
    without units (the path's step, point, eigenvalue and the modes' mode had none, and a path's point_kind without
    points was written as numbers; string ones, as field, need none), and the compare file's swept value in rtol
    (1) and dt (s), each true for every row it fills."""
    run = mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=[0.0, 2e-6], progress=False, stresses=True)
    mol_shell.write_netcdf(run, tmp_path / "run.nc")
    mol_shell.write_netcdf(mol_shell.modes("sphere", n=7, count=2), tmp_path / "modes.nc")
    assert main(["path", "sphere", "--param", "pressure=0:1000", "--n", "7", "--max-steps", "3", "-o",
                 str(tmp_path / "path.nc")]) == 0
    assert main(["study", "sphere", "--vary", "h=0.005,0.006", "--path", "pressure=0:1000", "--n", "7", "--max-steps",
                 "3", "-o", str(tmp_path / "path_study.nc")]) == 0
    wp = work_precision("twisted-cylinder", ["leapfrog", "cvode-bdf"], n=6, times=[0.0, 1e-4], repeats=1,
                        sweeps={"leapfrog": {"dt": (1e-5,)}, "cvode-bdf": {"rtol": (1e-6, 1e-7)}}, log=lambda *a: None)
    write_outputs(wp, tmp_path / "wp.nc")
    for name in ("run", "modes", "path", "path_study", "wp"):
        assert without_units(tmp_path / f"{name}.nc") == [], name
    with xr.open_dataset(tmp_path / "path.nc") as path:
        assert all(path[c].attrs["units"] == "1" for c in ("step", "point", "eigenvalue"))
    with xr.open_dataset(tmp_path / "modes.nc") as modes:
        assert modes["mode"].attrs["units"] == "1" and modes["field"].dtype.kind in "OSU"
    with xr.open_dataset(tmp_path / "wp.nc") as wp:
        assert wp["dt"].attrs["units"] == "s" and wp["rtol"].attrs["units"] == "1" and "setting" not in wp
        np.testing.assert_array_equal(wp["dt"].values, [[1e-5, np.nan], [np.nan, np.nan]])
        np.testing.assert_array_equal(wp["rtol"].values, [[np.nan, np.nan], [1e-6, 1e-7]])


# -- the radius drawn at the middle of a vessel's cylinder -----------------------------------------------------
def test_a_vessel_s_radius_is_drawn_at_the_middle_of_its_cylinder():
    """Two hemispheres of radius 1 m and a 2 m cylinder on 21 nodes (ds = (pi + 2) / 20): every node on the cylinder,
    s in [pi/2, pi/2 + 2] m, has the largest r0; the radius is drawn at the node nearest its middle s = pi/2 + 1 m,
    where the pressure widens the wall, not at the first of them (at the head's junction), and the title says which
    s it is."""
    scene = mol_shell.SCENES["vessel"](segments="arc 1 -90, line 2, arc 1 -90", pressure=100.0,
                                       material="svk-plane-stress", nu=0.3)
    ds = mol_shell.simulate(scene, n=21, times=[0.0, 1e-3, 2e-3], progress=False, stresses=False)
    s = ds["s"].values
    node = radius_node(ds)
    assert node == int(np.argmin(np.abs(s - (np.pi / 2 + 1)))) == 10
    on_cylinder = np.flatnonzero((s > np.pi / 2 - 1e-9) & (s < np.pi / 2 + 2 + 1e-9))
    assert on_cylinder[0] != node and on_cylinder[0] == int(np.argmax(ds["r0"].values))  # what was drawn before
    assert float(ds["r"][-1, node]) > float(ds["r0"][node])  # inflated there
    fig = history_figure(ds)
    title = fig.axes[0].get_title()
    assert f"s = {s[node]:.4g} m" in title and "middle of the widest part" in title, title


@pytest.mark.parametrize(("n", "node"), [(9, 4), (20, 9)])
def test_a_sphere_s_radius_is_still_drawn_at_its_equator_node(n, node):
    """A closed sphere: odd n has its equator at node (n - 1) / 2; even n the two nodes beside it, of equal r0, and
    the first of them, as before."""
    ds = mol_shell.simulate(mol_shell.Sphere(pressure=100.0), n=n, times=[0.0, 1e-4], progress=False, stresses=False)
    assert radius_node(ds) == node
    title = history_figure(ds).axes[0].get_title()
    assert f"s = {float(ds['s'][node]):.4g} m" in title, title


# -- plot's refusal lists what plot reads ------------------------------------------------------------------------
def test_plot_refuses_another_file_listing_run_path_and_path_study_files(short_run, tmp_path, capsys):
    """plot reads runs, paths and studies of paths: its refusal of a modes file or a missing one says so (one line,
    exit 2); animate, which reads runs only, still asks for a run; and plot does read a path file."""
    mol_shell.write_netcdf(mol_shell.modes("sphere", n=7, count=2), tmp_path / "modes.nc")
    listed = "allowed: a netCDF file written by mol-shell run, mol-shell path or mol-shell study --path"
    for name, problem in (("modes.nc", "is not a mol_shell run, path or path-study file"),
                          ("missing.nc", "does not exist")):
        assert main(["plot", str(tmp_path / name), "-o", str(tmp_path / "p.png")]) == 2
        err = capsys.readouterr().err
        assert len(err.splitlines()) == 1 and f"{problem}; {listed}" in err, err
    assert main(["plot", str(tmp_path / "modes.nc"), "-o", str(tmp_path / "p.png")]) == 2
    assert "(it holds natural modes (mol-shell modes))" in capsys.readouterr().err
    assert main(["animate", str(tmp_path / "modes.nc"), "-o", str(tmp_path / "a.gif")]) == 2
    err = capsys.readouterr().err
    assert "is not a mol_shell run file; allowed: a netCDF file written by mol-shell run (" in err, err
    assert main(["path", "sphere", "--param", "pressure=0:1000", "--n", "7", "--max-steps", "2", "-o",
                 str(tmp_path / "path.nc")]) == 0
    assert main(["plot", str(tmp_path / "path.nc"), "-o", str(tmp_path / "path.png")]) == 0
    assert not (tmp_path / "p.png").exists() and (tmp_path / "path.png").stat().st_size > 0


def test_a_viscous_run_without_loads_says_its_balance_is_the_quadratures():
    """Without loads a run carries the dissipated power, not its integral: the figure integrated 11 samples and
    titled the trapezoidal rule's error (0.067 J of 18 J dissipated) as the run's. The rule's error falls as the
    square of the spacing (a tenth of it: a hundredth of the residual), which the run's own error would not."""
    scene = mol_shell.TwistedCylinder(eta_mu=1000.0, eta_lambda=2000.0)
    residuals = []
    for count in (11, 101):
        ds = mol_shell.simulate(scene, "ida", n=20, times=np.linspace(0.0, 0.01, count), stresses=False)
        terms = balance_terms(ds)
        assert QUADRATURE_LABEL in terms and "dissipated" not in ds
        residuals.append(float(np.abs(terms["E - E(0) - W + D (balance)"]).max()))
    assert 70 < residuals[0] / residuals[1] < 130, residuals
    title = history_figure(ds).axes[1].get_title()
    assert "trapezoidal rule on 101 saved times: the balance measures that rule, not the run" in title, title


def test_compare_without_the_baseline_says_why_its_speed_up_column_is_empty():
    """``compare --integrators dop853-c`` left the speed-up column empty with no word: n/a, and why, under the table."""
    ds = work_precision("twisted-cylinder", ["dop853-c"], n=8, times=[0.0, 1e-3], repeats=1,
                        sweeps={"dop853-c": {"rtol": (1e-6, 1e-8)}}, log=lambda *a: None)
    table = markdown_table(ds)
    row = next(line for line in table.splitlines() if line.startswith("| dop853-c |"))
    assert row.endswith("| n/a |"), row
    assert table.splitlines()[-1] == ("Speed-up n/a: the baseline leapfrog was not among the integrators compared "
                                      "(--integrators), so no speed-up is measured against it.")
