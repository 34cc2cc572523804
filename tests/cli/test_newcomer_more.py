"""More of what a new user hit on the command line (and in Python): a template that runs as its header says, options
given twice or abbreviated, output that cannot be written, and refusals that list everything allowed."""

import argparse
import errno
import io
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.args import Once
from mol_shell.cli.main import main, make_parser
from mol_shell.integrators import INTEGRATORS
from mol_shell.results.dataset import read_netcdf
from mol_shell.scenes import SCENES


def one_error(capsys):
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: ") and "Traceback" not in err, err
    return err.strip()


# -- a scene file printed by `scenes NAME --toml` runs with the command its header prints ----------------------
@pytest.mark.parametrize("name", sorted(SCENES))
def test_a_printed_scene_file_runs_with_the_command_of_its_header(name, tmp_path, monkeypatch, capsys):
    assert main(["scenes", name, "--toml"]) == 0
    text = capsys.readouterr().out
    command = re.search(r"mol-shell run THIS\.toml -o out\.nc", text.splitlines()[1]).group(0)
    (tmp_path / "THIS.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(shlex.split(command)[1:]) == 0, capsys.readouterr().err
    assert "wrote out.nc" in capsys.readouterr().out and (tmp_path / "out.nc").stat().st_size > 0


# -- options are spelt in full, and a single-valued option is given once ------------------------------------------
def subcommands():
    parser = make_parser()
    (sub,) = [action for action in parser._actions if isinstance(action, argparse._SubParsersAction)]
    return parser, sub.choices


def test_an_abbreviated_option_is_refused_naming_the_option_it_begins(tmp_path, capsys):
    """``--t-en 0.1`` was taken as ``--t-end`` and silently replaced the ``--t-end 0.001`` given before it."""
    out = tmp_path / "a.nc"
    assert main(["run", "sphere", "--n", "5", "--t-end", "0.001", "--t-en", "0.1", "-o", str(out)]) == 2
    assert one_error(capsys) == ("mol-shell: error: --t-en is not an option of mol-shell run; allowed: options spelt "
                                 "in full, as --t-end")
    assert not out.exists()
    assert main(["scenes", "sphere", "--tom"]) == 2
    assert one_error(capsys).endswith("allowed: options spelt in full, as --toml")
    parser, commands = subcommands()
    assert not parser.allow_abbrev and not any(p.allow_abbrev for p in commands.values())
    # "--" ends the options: nothing after it is an option cut short (it was named as one)
    assert main(["path", "--", "sphere"]) == 2
    assert one_error(capsys) == "mol-shell: error: the following arguments are required: -o/--output"
    # before the command: it said "the following arguments are required: command"
    assert main(["--vers"]) == 2
    assert one_error(capsys) == "mol-shell: error: --vers is not an option of mol-shell; allowed: options spelt in " \
        "full, as --version"


@pytest.mark.parametrize("argv, message", [
    (["run", "sphere", "--n", "10", "--n", "12", "--t-end", "0.001"], "--n = 12 follows --n = 10; allowed: one --n"),
    (["run", "sphere", "--n", "5", "--t-end", "0.001", "--t-end", "0.002"],
     "--t-end = 0.002 follows --t-end = 0.001; allowed: one --t-end"),
    (["run", "sphere", "--n", "5", "--t-end", "0.001", "-o", "b.nc"], "-o = 'b.nc' follows -o = 'a.nc'; allowed: one -o"),
    (["run", "sphere", "--n", "5", "--t-end", "0.001", "--output", "b.nc"],
     "--output = 'b.nc' follows -o = 'a.nc'; allowed: one -o"),
    (["study", "sphere", "--vary", "nu=0.3,0.4", "--integrator", "leapfrog", "--integrator", "ida"],
     "--integrator = 'ida' follows --integrator = 'leapfrog'; allowed: one --integrator"),
    (["path", "sphere", "--param", "pressure=0:1", "--max-steps", "3", "--max-steps", "4"],
     "--max-steps = 4 follows --max-steps = 3; allowed: one --max-steps"),
    (["modes", "sphere", "--count", "2", "--count", "3"], "--count = 3 follows --count = 2; allowed: one --count"),
    (["compare", "sphere", "--repeats", "1", "--repeats", "2"], "--repeats = 2 follows --repeats = 1; allowed: one --repeats"),
])
def test_a_single_valued_option_given_twice_is_refused(argv, message, tmp_path, monkeypatch, capsys):
    """``--n 10 --n 12`` ran on 12 nodes, silently, where ``--set NAME=...`` twice was refused."""
    monkeypatch.chdir(tmp_path)
    assert main([*argv[:2], "-o", "a.nc", *argv[2:]]) == 2
    assert one_error(capsys) == "mol-shell: error: " + message
    assert not list(tmp_path.iterdir())


def test_every_single_valued_option_of_every_command_is_given_once():
    _, commands = subcommands()
    for name, command in commands.items():
        for action in command._actions:
            if action.option_strings and action.nargs != 0 and not isinstance(action, argparse._AppendAction):
                assert isinstance(action, Once), (name, action.option_strings)


def test_repeatable_options_stay_repeatable(tmp_path, capsys):
    """--vary and --set twice each. The varied parameters are initial data (the spin and the starting radius), which
    no kernel depends on: the four cases run on one compiled right-hand side (nu and E varied compiled four)."""
    out = tmp_path / "st.nc"
    assert main(["study", "sphere", "--n", "5", "--t-end", "1e-5", "--workers", "1", "--vary", "omega=0,1",
                 "--vary", "R=1.5,1.51", "--set", "rho=900", "--set", "a=1.5", "-o", str(out)]) == 0, capsys.readouterr()
    ds = read_netcdf(out)
    assert ds.sizes["omega"] == 2 and ds.sizes["R"] == 2 and ds.attrs["rho"] == 900 and ds.attrs["a"] == 1.5


# -- study: --max-steps is an option of a study of paths -----------------------------------------------------------
@pytest.mark.parametrize("option", ["--max-steps", "--steps"])
def test_max_steps_without_path_is_refused_as_t_end_with_path_is(option, tmp_path, capsys):
    """``study ... --max-steps 3`` without ``--path`` ran the study of runs and ignored it."""
    out = tmp_path / "st.nc"
    assert main(["study", "sphere", "--vary", "nu=0.3,0.4", "--t-end", "1e-5", "--n", "5", option, "3",
                 "-o", str(out)]) == 2
    assert one_error(capsys) == (f"mol-shell: error: {option} is an option of a study of paths (--path), not of "
                                 "one of runs")
    assert not list(tmp_path.iterdir())


# -- output that cannot be written -----------------------------------------------------------------------------
class FullStream(io.StringIO):
    """A stream on a full disk."""

    def write(self, text):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


FULL = f"mol-shell: error: cannot write to standard output: [Errno {errno.ENOSPC}] {os.strerror(errno.ENOSPC)}"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("args", [["scenes", "sphere", "--toml"], ["scenes"], ["run", "--help"]])
def test_a_full_standard_output_is_said_in_one_line_not_as_a_bug(args):
    """``mol-shell scenes sphere --toml > /dev/full`` said "internal error: OSError ... (a bug of mol_shell ...)"."""
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "mol_shell", *args], stdout=full, stderr=subprocess.PIPE, text=True,
                              timeout=120, check=False)
    assert (done.returncode, done.stderr) == (2, FULL + "\n")


def test_standard_output_or_error_that_cannot_be_written_ends_the_command_with_code_2(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdout", FullStream())
    assert main(["scenes", "torus", "--toml"]) == 2
    assert capsys.readouterr().err == FULL + "\n"
    monkeypatch.setattr(sys, "stderr", FullStream())
    assert main(["scenes", "nope"]) == 2  # the refusal cannot be said either: no exception escapes


# -- an integrator that cannot take a scene's loads: every one that can is listed --------------------------------
@pytest.mark.parametrize("argv", [
    ["run", "sphere", "--integrator", "casadi-idas", "--set", "pressure=10", "--n", "10", "--t-end", "0.001"],
    ["compare", "sphere", "--integrators", "leapfrog,casadi-idas", "--set", "pressure=10", "--n", "5", "--t-end", "1e-4"],
])
def test_an_integrator_refusing_loads_lists_every_integrator_that_takes_them(argv, tmp_path, capsys):
    """The list was hand-written: "leapfrog, cvode-bdf, cvode-adams, ida, the scipy peers or casadi-cvodes" left out
    dop853-c, rk45-c, the sksundae-* routes and casadi-cvodes-c, which run a pressurised sphere as well."""
    out = tmp_path / "x.nc"
    assert main([*argv, "-o", str(out)]) == 2
    can = [name for name in INTEGRATORS if name != "casadi-idas"]
    assert one_error(capsys) == ("mol-shell: error: integrator = 'casadi-idas' is outside {" + ", ".join(can) + "} for a "
                                 "scene with loads or driven edges (its semi-explicit DAE form takes no loads)")
    assert {"dop853-c", "rk45-c", "sksundae-ida", "casadi-cvodes-c"} <= set(can) and not out.exists()


# -- atol per field: a name that is not a field -------------------------------------------------------------------
@pytest.mark.parametrize("integrator", ["cvode-bdf", "dop853-c", "sksundae-ida"])
def test_an_atol_naming_no_field_says_which_name_and_the_fields(integrator):
    """``atol={"rr": 1e-9}`` was refused as "is not a number"."""
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(mol_shell.Sphere(), integrator, n=5, t_end=0.001, atol={"r": 1e-9, "rr": 1e-9})
    assert str(info.value) == ("atol = {'r': 1e-09, 'rr': 1e-09} names 'rr', which is not a field; allowed: "
                               "{field: value} with field in {z, r, chi, theta, psi}")
    assert info.value.name == "atol"


# -- what the docs and the help say ------------------------------------------------------------------------------
ROOT = Path(__file__).resolve().parents[2]


def test_the_scene_lists_of_the_readme_and_the_cli_page_name_every_scene():
    """Both left out ``vessel``, which ``mol-shell scenes`` lists."""
    readme = " ".join((ROOT / "README.md").read_text().split())
    listed = readme[readme.index("**Shells of revolution**"):readme.index("**Shells of revolution**") + 700]
    cli = " ".join((ROOT / "docs" / "cli.md").read_text().split())
    scenes = cli[cli.index("* Scenes:"):cli.index("* Integrators:")]
    for name in SCENES:
        assert f"`{name}`" in listed and f"`{name}`" in scenes, name


def test_the_readme_s_peak_torque_is_that_of_the_command_it_names(tmp_path):
    """The peaks were quoted beside a command saving every 11 ms; they are those of 1 ms samples, which it names."""
    readme = " ".join((ROOT / "README.md").read_text().split())
    found = re.search(r"On 1 ms samples \(`(mol-shell run [^`]*)`\) the peak of \|axial torque\| is ([\d,]+) N m "
                      r"\(reversed: -[\d,]+ N m at s = ([\d.]+) m, t = ([\d.]+) s\) and the peak von Mises stress "
                      r"([\d.]+) kPa", readme)
    argv = shlex.split(found.group(1))[1:]
    argv[argv.index("-o") + 1] = str(tmp_path / "paper.nc")
    assert main(argv) == 0
    ds = read_netcdf(tmp_path / "paper.nc")
    torque = ds.axial_torque.values
    k, j = np.unravel_index(np.argmax(np.abs(torque)), torque.shape)
    assert f"{abs(torque[k, j]):,.0f}" == found.group(2) and torque[k, j] < 0
    assert (float(ds.s_cell[j]), float(ds.time[k])) == (float(found.group(3)), float(found.group(4)))
    assert f"{ds.von_mises_stress.values.max() / 1e3:.1f}" == found.group(5)


@pytest.mark.parametrize("command, options", [("run", ("n", "dt", "integrator")), ("study", ("n", "dt")),
                                              ("path", ("n",)), ("modes", ("n",))])
def test_the_help_says_a_scene_file_s_run_table_gives_the_defaults(command, options, capsys):
    """``run --help`` said ``--n`` (default 40) and ``--dt`` (default 1e-6), where a scene file's [run] values win."""
    assert main([command, "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    for option in options:
        assert f"(default: a scene file's [run] {option}, else " in text, (option, text)


def test_the_netcdf_page_names_the_variables_of_a_run_that_hold_nan():
    """docs/netcdf.md said a run never contains NaN; the unshearable DAE's held chi has a NaN reaction torque (and
    stresses past a law's range are NaN too: the page lists them since December 7)."""
    scene = mol_shell.scenes.get_scene("unshearable", end1="chi", omega=0.0)
    ds = mol_shell.simulate(scene, "ida", n=9, t_end=1e-3, progress=False)
    assert [v for v in ds.variables if ds[v].dtype.kind == "f" and np.isnan(ds[v].values).any()] == ["reaction_torque"]
    page = " ".join((ROOT / "docs" / "netcdf.md").read_text().split())
    assert "never contains NaN" not in page and "NaN by design: `reaction_force`, `reaction_torque` where no " \
        "reaction is computed (a held `chi` of the unshearable scene's constrained DAE" in page
