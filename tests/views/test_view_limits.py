"""The views refuse, in one line with exit code 2, options too large to draw in bounded time and memory, and run
files a hand edit or damage left without saved times or with values that are not finite."""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.views.animate import animate
from mol_shell.views.export import export
from mol_shell.views.fibres import fibres_figure

N_PHI_MAX, MAX_FIBRES = 1024, 360  # export's --n-phi and plot's --fibres


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A small run of the paper's scene (2 saved times), and damaged copies: r all NaN, chi NaN at one node of the
    last time, and no saved times."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=11, t_end=0.001, times=[0.0, 0.001], progress=False,
                            stresses=False)
    folder = tmp_path_factory.mktemp("limits")
    out = {"run": folder / "run.nc", "nan": folder / "nan.nc", "chi": folder / "chi.nc", "empty": folder / "empty.nc"}
    mol_shell.write_netcdf(ds, out["run"])
    mol_shell.write_netcdf(ds.assign(r=ds.r * np.nan), out["nan"])
    chi = ds.chi.values.copy()
    chi[-1, 3] = np.inf
    mol_shell.write_netcdf(ds.assign(chi=(ds.chi.dims, chi, ds.chi.attrs)), out["chi"])
    mol_shell.write_netcdf(ds.isel(time=slice(0, 0)), out["empty"])
    return out


def refused(capsys, argv, *words):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, (argv, code, err)
    for word in words:
        assert word in err, (argv, err)
    return err


@pytest.mark.parametrize(("command", "option", "value", "allowed"), [
    ("export", "--n-phi", N_PHI_MAX + 1, f"integers in [3, {N_PHI_MAX}]"),
    ("export", "--n-phi", 10**9, f"integers in [3, {N_PHI_MAX}]"),
    ("animate", "--n-phi", 1025, "integers in [3, 1024]"),
    ("animate", "--fibres", 361, "integers in [1, 360]"),
    ("animate", "--width", 20000, "integers in [100, 4096]"),
    ("animate", "--width", 100000, "integers in [100, 4096]"),
])
def test_huge_view_options_are_refused_naming_the_option_and_its_range(files, tmp_path, capsys, command, option,
                                                                        value, allowed):
    suffix = "xdmf" if command == "export" else "gif"
    out = tmp_path / f"out.{suffix}"
    refused(capsys, [command, str(files["run"]), option, str(value), "-o", str(out)], f"{option} = {value}", allowed)
    assert not out.exists()


def test_the_fibre_figure_refuses_too_many_fibres(files, tmp_path, capsys):
    for value in (MAX_FIBRES + 1, 10**8):
        refused(capsys, ["plot", str(files["run"]), "--figure", "fibres", "--fibres", str(value), "-o",
                         str(tmp_path / "f.png")], f"--fibres = {value} is outside integers in [1, {MAX_FIBRES}]")
    assert main(["plot", str(files["run"]), "--figure", "fibres", "--fibres", str(MAX_FIBRES), "-o",
                 str(tmp_path / "f.png")]) == 0


def test_the_functions_refuse_the_same_ranges_naming_their_keywords(files, tmp_path):
    ds = mol_shell.read_netcdf(files["run"])
    with pytest.raises(ParameterError, match=r"^n_phi = 1025 is outside integers in \[3, 1024\]$"):
        export(ds, tmp_path / "x.xdmf", n_phi=1025)
    with pytest.raises(ParameterError, match=r"^width = 5000 is outside integers in \[100, 4096\]$"):
        animate(ds, tmp_path / "x.gif", width=5000)
    with pytest.raises(ParameterError, match=r"^fps = 0 is outside \[0.002, 100\] frames per second$"):
        animate(ds, tmp_path / "x.gif", fps=0)
    with pytest.raises(ParameterError, match=r"^fps = 0.001 is outside \[0.002, 100\]"):  # overflowed a GIF's frame
        animate(ds, tmp_path / "x.gif", fps=0.001)
    with pytest.raises(ParameterError, match=r"^count = 361 is outside integers in \[1, 360\]$"):
        fibres_figure(ds, count=361)


def test_the_help_states_the_ranges(capsys):
    for argv, words in ((["export", "--help"], ["azimuthal samples, 3 to 1024"]),
                        (["animate", "--help"], ["3 to 1024", "1 to 360", "100 to 4096"]),
                        (["plot", "--help"], ["1 to 360"])):
        assert main(argv) == 0
        text = " ".join(capsys.readouterr().out.split())
        assert all(word in text for word in words), (argv, text)


@pytest.mark.parametrize("command", ["plot", "animate", "export"])
@pytest.mark.parametrize(("damage", "words"), [
    ("nan", [": r is not finite at t = 0 s, s = 0 m (22 of 22 values)"]),
    ("chi", [": chi is not finite at t = 0.001 s, s = 1.2 m (1 of 22 values)"]),
    ("empty", [" has no saved times"]),
])
def test_damaged_run_files_are_refused_naming_the_file(files, tmp_path, capsys, command, damage, words):
    suffix = {"plot": "png", "animate": "gif", "export": "xdmf"}[command]
    out = tmp_path / f"out.{suffix}"
    refused(capsys, [command, str(files[damage]), "-o", str(out)], f"FILE = '{files[damage]}'", *words)
    assert not out.exists()


@pytest.mark.parametrize("figure", ["fibres", "history"])
def test_every_figure_refuses_a_file_without_saved_times(files, tmp_path, capsys, figure):
    refused(capsys, ["plot", str(files["empty"]), "--figure", figure, "-o", str(tmp_path / "x.png")],
            "has no saved times")


def test_the_refusal_of_at_s_says_which_figures_take_it(files, tmp_path, capsys):
    """The paper's figures 4-8 (an unloaded cylinder) refuse --at-s, in a sentence that reads."""
    err = refused(capsys, ["plot", str(files["run"]), "--at-s", "1", "-o", str(tmp_path / "x.png")],
                  "--at-s is an option of --figure fibres, of --figure history and of the default figure of a shell "
                  "that is not an unloaded cylinder, not of the paper's figures 4-8")
    assert "only; and" not in err


def test_the_slowest_frame_rate_writes_a_gif_and_a_slower_one_is_refused_on_the_command_line(files, tmp_path, capsys):
    """A GIF stores a frame's duration in hundredths of a second (at most 655.35 s): ``--fps 0.001`` overflowed it
    (an internal error); the range's low end, 0.002 (500 s a frame), writes the file."""
    from PIL import Image

    refused(capsys, ["animate", str(files["run"]), "--fps", "0.001", "-o", str(tmp_path / "a.gif")],
            "--fps = 0.001 is outside [0.002, 100]")
    assert main(["animate", str(files["run"]), "--fps", "0.002", "--width", "100", "-o", str(tmp_path / "b.gif")]) == 0
    with Image.open(tmp_path / "b.gif") as gif:
        assert gif.info["duration"] == 500_000
