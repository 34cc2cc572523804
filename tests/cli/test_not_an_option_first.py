"""An option a command (or its integrator, its kind of study, its start) does not take is refused as such before its
value is checked, on every command and in a scene file's ``[run]`` table: ``run twisted-cylinder --atol -1`` (leap-frog)
was told atol's range, then with ``--atol 1e-6`` that leap-frog has no atol; ``study ... --path ... --rtol 5`` rtol's
range, not that a study of paths takes no rtol."""

from __future__ import annotations

import pytest
from test_option_ranges_said import _refusal  # one command line, one line of refusal, no file

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.path_inputs import STEPS_MAX
from mol_shell.cli.main import main
from mol_shell.scenes.files import load_scene

LEAPFROG = "is not an option of leapfrog (its options: chunk, dt, restart)"
RUN = ["run", "twisted-cylinder", "--n", "9", "--t-end", "1e-4"]
STUDY = ["study", "twisted-cylinder", "--n", "9", "--t-end", "1e-4", "--vary", "nu=0.3,0.4"]
PATHS = ["study", "twisted-cylinder", "--n", "9", "--vary", "nu=0.3,0.4", "--path", "end1_dz=0:1e-3"]
PATH = ["path", "twisted-cylinder", "--n", "9", "--param", "end1_dz=0:1e-3"]


@pytest.mark.parametrize("command", [RUN, STUDY])
@pytest.mark.parametrize("option,values", [("--atol", ("-1", "1e-6", "bogus=1")), ("--max-step", ("-1", "abc", "1")),
                                           ("--rtol", ("5", "abc", "1e-6"))])
def test_a_tolerance_on_leapfrog_is_not_an_option_whatever_its_value(command, option, values, tmp_path, capsys):
    name = option.lstrip("-").replace("-", "_")
    for value in values:
        assert _refusal([*command, option, value], tmp_path, capsys) == f"{name} {LEAPFROG}", value


@pytest.mark.parametrize("command", [RUN, STUDY])
def test_dt_on_an_adaptive_integrator_is_not_an_option_whatever_its_value(command, tmp_path, capsys):
    for value in ("-1", "0", "1e-6"):
        said = _refusal([*command, "--integrator", "cvode-bdf", "--dt", value], tmp_path, capsys)
        assert said.startswith("dt is not an option of cvode-bdf"), said


@pytest.mark.parametrize("argv,said", [
    ([*RUN, "--integrator", "cvode-bdf", "--atol", "-1"],
     "--atol = -1 is outside [1e-100, inf), or FIELD=VALUE,... with FIELD in {z, r, chi, theta, psi}"),
    ([*RUN, "--integrator", "cvode-bdf", "--max-step", "-1"], "--max-step = -1 is outside [0, inf) s (0: unbounded)"),
    ([*RUN, "--dt", "-1"], "--dt = -1 is outside (0, inf) s"),
    ([*STUDY, "--integrator", "cvode-bdf", "--rtol", "5"], "--rtol = 5 is outside [1e-14, 1)"),
    ([*STUDY, "--dt", "abc"], "--dt = 'abc' is not a number; allowed: (0, inf) s"),
    ([*PATH, "--max-steps", "0"], "--max-steps = 0 is outside integers >= 1"),
    ([*PATHS, "--steps", "0"], f"--steps = 0 is outside integers in [1, {STEPS_MAX}]"),
])
def test_where_the_option_is_taken_its_range_is_said(argv, said, tmp_path, capsys):
    assert _refusal(argv, tmp_path, capsys) == said


@pytest.mark.parametrize("argv,said", [
    ([*PATHS, "--rtol", "5"],
     "--rtol is an option of a study of runs, not of one of paths (--path)"),
    ([*PATHS, "--atol", "-1"],
     "--atol is an option of a study of runs, not of one of paths (--path)"),
    ([*PATHS, "--steps", "-3", "--rtol", "1e-6"],  # a value's range after an option the path study does not take
     "--rtol is an option of a study of runs, not of one of paths (--path)"),
    ([*STUDY, "--max-steps", "0"], "--max-steps is an option of a study of paths (--path), not of one of runs"),
    ([*STUDY, "--steps", "-3"], "--steps is an option of a study of paths (--path), not of one of runs"),
    ([*RUN, "--step", "-1"], "--step is an option with --from PATH.nc only"),
    ([*RUN, "--perturb", "nan"], "--perturb is an option with --from PATH.nc only"),
    (["modes", "sphere", "--n", "9", "--point", "-2"], "--point is an option with --from PATH.nc only"),
    ([*PATH, "--stop", "nan"], "--stop is an option with --from PATH.nc only"),
    ([*PATH, "--step", "-1"], "--step is an option with --from PATH.nc only"),
])
def test_an_option_not_taken_is_said_before_its_range(argv, said, tmp_path, capsys):
    assert _refusal(argv, tmp_path, capsys) == said


def _scene_file(tmp_path, scene, integrator, line):
    path = tmp_path / "f.toml"
    path.write_text(f'scene = "{scene}"\n[run]\nintegrator = "{integrator}"\nt_end = 1e-4\nn = 9\n{line}\n')
    return path


@pytest.mark.parametrize("line", ["atol = -1.0", "atol = 1e-6", "rtol = 5.0", "max_step = -1.0",
                                  "atol = {r = -1.0}"])
def test_a_scene_files_run_option_not_taken_is_said_before_its_range(line, tmp_path, capsys):
    path = _scene_file(tmp_path, "twisted-cylinder", "leapfrog", line)
    name = line.partition(" ")[0]
    said = f"{path}: [run] {name} {LEAPFROG}"
    with pytest.raises(ParameterError) as info:
        load_scene(path, with_run=True)
    assert str(info.value) == said
    if line == "atol = 1e-6":  # the command line checks each value in the file's order first (its --integrator may
        # replace the file's, which takes it), then refuses what the integrator that runs does not take
        assert _refusal(["run", str(path)], tmp_path, capsys) == said
        assert _refusal(["study", str(path), "--vary", "nu=0.3,0.4"], tmp_path, capsys) == said
    else:
        assert " is outside " in _refusal(["run", str(path)], tmp_path, capsys)


def test_the_command_line_checks_a_scene_files_run_values_in_the_files_order_in_one_line(tmp_path, capsys):
    """Values first, in the file's order, one line (a note of a left-out key came before a later value's refusal,
    and a later key's range before an earlier key's); commands that run no integrator check them too."""
    path = _scene_file(tmp_path, "twisted-cylinder", "leapfrog", "dt = 1e-6\nrtol = -1.0")
    said = f"{path}: [run] rtol = -1.0 is outside [1e-14, 1)"
    assert _refusal(["run", str(path), "--integrator", "cvode-bdf"], tmp_path, capsys) == said
    path = _scene_file(tmp_path, "twisted-cylinder", "leapfrog", "rtol = -1.0\ndt = -1.0")
    assert _refusal(["run", str(path)], tmp_path, capsys) == said
    assert _refusal(["modes", str(path), "--n", "9"], tmp_path, capsys) == said


def test_the_unshearable_ida_file_option_not_taken_is_said_before_its_range(tmp_path):
    path = _scene_file(tmp_path, "unshearable", "ida", "jac_reuse = 5000")
    with pytest.raises(ParameterError) as info:
        load_scene(path, with_run=True)
    assert str(info.value) == f"{path}: [run] jac_reuse is not an option of ida (its options: atol, max_step, rtol)"


def test_a_file_option_the_command_lines_integrator_takes_is_checked(tmp_path, capsys):
    # leap-frog's file with a bad atol run on cvode-bdf: the file's atol is cvode-bdf's, and refused by its range
    path = _scene_file(tmp_path, "twisted-cylinder", "leapfrog", "atol = -1.0")
    said = _refusal(["run", str(path), "--integrator", "cvode-bdf"], tmp_path, capsys)
    assert said == f"{path}: [run] atol = -1.0 is outside [1e-100, inf)", said
    path = _scene_file(tmp_path, "twisted-cylinder", "cvode-bdf", "atol = -1.0")
    assert _refusal(["run", str(path)], tmp_path, capsys) == f"{path}: [run] atol = -1.0 is outside [1e-100, inf)"


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("plot") / "run.nc"
    mol_shell.write_netcdf(mol_shell.simulate("twisted-cylinder", n=9, dt=1e-5, times=[0, 1e-5]), path)
    return path


@pytest.mark.parametrize("option,value", [("--fibres", "0"), ("--time", "-1"), ("--thickness-scale", "-1")])
def test_a_figures_option_not_taken_is_said_before_its_range(option, value, run_file, tmp_path, capsys):
    code = main(["plot", str(run_file), option, value, "-o", str(tmp_path / "x.png")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith(f"mol-shell: error: {option} is an option of --figure fibres only"), err
    code = main(["plot", str(run_file), "--figure", "fibres", option, value, "-o", str(tmp_path / "x.png")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith(f"mol-shell: error: {option} = {value} is outside"), err
