"""Animations and the fibre figure: one frame per saved time, not blank; bad input refused in one line."""

import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.stresses import add_stresses

SMALL = ["--n-phi", "12", "--fibres", "4", "--width", "200"]


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """The paper's scene on 8 nodes over 10 us (11 saved times) with stresses, and the same without."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False)
    folder = tmp_path_factory.mktemp("animate")
    mol_shell.write_netcdf(add_stresses(ds), folder / "run.nc")
    mol_shell.write_netcdf(ds, folder / "bare.nc")
    return folder / "run.nc", folder / "bare.nc"


def not_blank(rgb):
    """A frame with a drawing: many colours, and a good share of saturated (coloured, not grey) pixels."""
    rgb = np.asarray(rgb, dtype=float)
    colours = len(np.unique(rgb.reshape(-1, 3), axis=0))
    saturation = rgb.max(axis=-1) - rgb.min(axis=-1)
    return colours > 20 and (saturation > 60).mean() > 0.02 and rgb.std() > 20


def test_gif_has_one_frame_per_saved_time(run_file, tmp_path):
    out = tmp_path / "shell.gif"
    assert main(["animate", str(run_file[0]), "--field", "von_mises_stress_outer", *SMALL, "-o", str(out)]) == 0
    with Image.open(out) as gif:
        assert gif.n_frames == 11
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    assert all(not_blank(f) for f in frames)
    assert np.any(frames[0] != frames[-1])  # the time in the frame changes


def test_mp4_has_one_frame_per_saved_time(run_file, tmp_path):
    out = tmp_path / "shell.mp4"
    assert main(["animate", str(run_file[0]), "--field", "axial_torque", *SMALL, "-o", str(out)]) == 0
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert frames == 11
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    first = np.frombuffer(next(reader), dtype=np.uint8).reshape(meta["size"][1], meta["size"][0], 3)
    reader.close()
    assert not_blank(first)


def test_bad_input_is_refused_in_one_line(run_file, tmp_path, capsys):
    run, bare = run_file
    (tmp_path / "d.gif").mkdir()
    text = tmp_path / "notes.nc"
    text.write_text("not netCDF")
    cases = [
        ([str(run), "--field", "colour", "-o", str(tmp_path / "a.gif")], "--field = 'colour' is outside {z, z_t"),
        ([str(bare), "--field", "axial_torque", "-o", str(tmp_path / "a.gif")], "this run has no stresses"),
        ([str(text), "-o", str(tmp_path / "a.gif")], "is not a mol_shell run file"),
        ([str(run), "-o", str(tmp_path / "a.avi")], "-o = "),
        ([str(run), "-o", "/proc/no/such/a.gif"], "cannot be written"),
        ([str(run), "-o", str(tmp_path / "d.gif")], "is a directory"),
        ([str(run), "--fps", "0", "-o", str(tmp_path / "a.gif")], "--fps = 0 is outside"),
    ]
    for argv, words in cases:
        code = main(["animate", *argv])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("mol-shell: error: ") and len(err.splitlines()) == 1, (argv, err)
        assert words in err, (argv, err)
    assert not (tmp_path / "a.gif").exists()


def test_fibre_figure_draws_the_fibres_where_the_map_puts_them(tmp_path):
    """Panel (b)'s red fibre (reference azimuth 0) runs from ``p(zeta1)`` to ``p(zeta2)`` projected onto the
    section's plane, ``p = r + M zeta d`` with ``r, d`` from the balance-law module's Cartesian configuration
    (an independent route) and ``M`` the drawn magnification; panel (a)'s is radial from ``1 + M zeta1`` to
    ``1 + M zeta2``. A sheared state (psi0 = 0.3) so that the tilt matters; to round-off."""
    import casadi as ca

    from mol_shell.views.fibres import fibres_figure
    from mol_shell.model.balance import configuration

    ds = mol_shell.simulate(mol_shell.TwistedCylinder(psi0=0.3), n=8, t_end=1e-5, progress=False)
    fig = fibres_figure(ds, time=1e-5, s=0.0, count=8, thickness_scale=10.0)
    zeta1, h = float(ds.attrs["zeta1_used"]), float(ds.attrs["h"])
    q = [float(ds[f].values[-1, 0]) for f in ("z", "r", "chi", "theta", "psi")]
    pos, d, _ = configuration([ca.SX(x) for x in q], ca.SX(0.0))
    expected = np.array([[float(pos[i] + 10 * z * d[i]) for i in (1, 2)] for z in (zeta1, zeta1 + 2 * h)])
    red = [[line for line in ax.get_lines() if line.get_color() == "tab:red"] for ax in fig.axes]
    assert [len(x) for x in red] == [1, 1]
    np.testing.assert_allclose(red[1][0].get_xydata(), expected, rtol=0, atol=4e-16)
    np.testing.assert_allclose(red[0][0].get_xydata(), [[1 + 10 * zeta1, 0], [1 + 10 * (zeta1 + 2 * h), 0]], atol=4e-16)
    assert abs(q[4]) > 0.25 and abs(q[2]) > 0.19  # really sheared and turned
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_fibre_figure_from_the_command_line(run_file, tmp_path, capsys):
    out = tmp_path / "fig1.png"
    assert main(["plot", str(run_file[0]), "--figure", "fibres", "--time", "5e-6", "--at-s", "2", "-o", str(out)]) == 0
    with Image.open(out) as png:
        rgb = np.asarray(png.convert("RGB"), dtype=float)
    dark = (rgb.max(axis=-1) < 80).mean()
    red = ((rgb[..., 0] > 150) & (rgb[..., 1] < 90) & (rgb[..., 2] < 90)).sum()
    shell = (np.abs(rgb - [219, 230, 243]).max(axis=-1) < 8).mean()  # the annulus' fill
    assert dark > 0.01 and red > 20 and shell > 0.05, (dark, red, shell)
    for argv, words in [(["--figure", "fibres", "--time", "1"], "--time = 1 is outside [0, 1e-05] s"),
                        (["--figure", "fibres", "--at-s", "5"], "--at-s = 5 is outside [0, 4] m"),
                        (["--figure", "fibres", "--fibres", "0"], "--fibres = 0 is outside"),
                        (["--time", "0"], "--time is an option of --figure fibres only"),
                        (["--figure", "fibre"], "--figure = 'fibre' is outside {snapshots, fibres, history}")]:
        code = main(["plot", str(run_file[0]), *argv, "-o", str(tmp_path / "x.png")])
        err = capsys.readouterr().err
        assert code == 2 and len(err.splitlines()) == 1 and words in err, (argv, err)


def test_a_stress_of_the_unshearable_scene_colours_its_animation(tmp_path, capsys):
    """Its runs had no stresses (the refusal said "rerun without --no-stresses", a flag never given); they have them
    now, the constraint's torque in axial_torque (tests/results/test_unshearable_stresses.py)."""
    run = tmp_path / "u.nc"
    assert main(["run", "unshearable", "--integrator", "ida", "--n", "8", "--t-end", "1e-4", "-o", str(run)]) == 0
    capsys.readouterr()
    assert main(["animate", str(run), "--field", "von_mises_stress_inner", *SMALL, "-o", str(tmp_path / "u.gif")]) == 0
