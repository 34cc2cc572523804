"""What a new user hit on 0.5.0, on the command line: each a one-line answer (or quiet success) where there
was a crash, a hang, a silently wrong file or a misaligned listing."""

import dataclasses
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main, make_parser
from mol_shell.model.geometry import PointsMeridian
from mol_shell.results.dataset import read_netcdf
from mol_shell.scenes import UNITS
from mol_shell.scenes.file_writer import scene_toml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SPHERE_FILE = 'scene = "sphere"\n[geometry]\na = 2.0\n[material]\nnu = 0.3\n[run]\nn = 7\nt_end = 2e-6\n'


def mol_shell_command(*args, **options):
    return subprocess.run([sys.executable, "-m", "mol_shell", *args], capture_output=True, text=True, **options)


def one_error(capsys):
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: ") and "Traceback" not in err, err
    return err


@pytest.fixture(scope="module")
def sphere_run(tmp_path_factory):
    """`mol-shell run sphere` with the default R (auto) on 9 nodes."""
    path = tmp_path_factory.mktemp("newcomer") / "s.nc"
    assert main(["run", "sphere", "--n", "9", "--t-end", "1e-5", "-o", str(path)]) == 0
    return path


# -- item 1: plot on a sphere run with R = auto ----------------------------------------------------------------
def test_plot_draws_a_sphere_run_with_the_default_radius(sphere_run, tmp_path, capsys):
    assert main(["plot", str(sphere_run), "-o", str(tmp_path / "s.png")]) == 0
    assert "internal error" not in capsys.readouterr().err and (tmp_path / "s.png").stat().st_size > 10_000


def test_plot_draws_a_file_of_0_5_0_that_stored_none(sphere_run, tmp_path):
    """0.5.0 wrote the string "none" for R, zeta1, end1 and end2: such files are still drawn."""
    ds = read_netcdf(sphere_run)
    ds.attrs.update(R="none", zeta1="none", end1="none", end2="none")
    old = tmp_path / "old.nc"
    mol_shell.write_netcdf(ds, old)
    assert main(["plot", str(old), "-o", str(tmp_path / "old.png")]) == 0


# -- item 4: a scheduler address that is not one ------------------------------------------------------------
@pytest.mark.timeout(60)
def test_a_malformed_scheduler_is_refused_at_once_without_a_traceback(tmp_path):
    start = time.perf_counter()
    done = mol_shell_command("study", "sphere", "--vary", "nu=0.3,0.4", "--t-end", "1e-5", "--n", "5",
                             "--scheduler", "nonsense", "-o", str(tmp_path / "st.nc"), timeout=50)
    elapsed = time.perf_counter() - start
    assert done.returncode == 2 and elapsed < 10, (elapsed, done.stderr)
    assert done.stderr.startswith("mol-shell: error: scheduler = 'nonsense' is not a scheduler address")
    assert len(done.stderr.splitlines()) == 1 and "Traceback" not in done.stderr, done.stderr


# -- item 5: the meridian scene without a file ----------------------------------------------------------------
def test_the_meridian_scene_says_which_meridian_it_runs(tmp_path, capsys):
    out = tmp_path / "m.nc"
    assert main(["run", "meridian", "--n", "9", "--t-end", "1e-5", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if line.startswith("mol-shell: note: ")]
    assert len(notes) == 1 and "built-in dome" in notes[0] and "points = FILE" in notes[0], err
    assert "built-in dome" in read_netcdf(out).attrs["meridian"]
    table = tmp_path / "cap.txt"
    angles = np.linspace(0.0, np.pi / 2, 9)
    np.savetxt(table, np.column_stack([np.cos(angles), np.sin(angles)]))  # a quarter circle: a hemisphere
    assert main(["run", "meridian", "--set", f"points={table}", "--n", "9", "--t-end", "1e-5", "-o", str(out)]) == 0
    assert "note" not in capsys.readouterr().err and str(table) in read_netcdf(out).attrs["meridian"]


def test_the_help_says_so_too(capsys):
    with pytest.raises(SystemExit):
        make_parser().parse_args(["run", "--help"])
    assert "built-in dome" in " ".join(capsys.readouterr().out.split())


# -- item 6: every command that takes a scene takes a scene file ------------------------------------------------
def test_modes_and_study_take_a_scene_file_with_its_run_table(tmp_path, capsys):
    """The file sets a = 2 m and nu = 0.3, and its [run] table n = 7 and t_end = 2 us: modes and study use them."""
    path = tmp_path / "big.toml"
    path.write_text(SPHERE_FILE)
    assert main(["modes", str(path), "--count", "2", "-o", str(tmp_path / "m.nc")]) == 0
    ds = read_netcdf(tmp_path / "m.nc")
    assert ds.attrs["a"] == 2.0 and ds.attrs["nu"] == 0.3 and ds.sizes["s"] == 7
    assert main(["study", str(path), "--vary", "E=1e6,2e6", "--scheduler", "serial", "-o", str(tmp_path / "st.nc")]) == 0
    st = read_netcdf(tmp_path / "st.nc")
    assert st.sizes["s"] == 7 and float(st.time[-1]) == 2e-6 and st.attrs["a"] == 2.0
    capsys.readouterr()  # what the runs printed (a cold kernel cache announces its compilations)
    assert main(["modes", str(tmp_path / "missing.toml"), "-o", str(tmp_path / "m.nc")]) == 2
    assert "missing.toml" in one_error(capsys)


@pytest.mark.parametrize("command", ["compare", "stability"])
def test_compare_and_stability_take_a_scene_file(command, tmp_path, monkeypatch, capsys):
    """The analyses themselves take minutes: what matters here is the scene they are given (the file's, with
    --set on top)."""
    from mol_shell.cli import analysis

    given = []

    def capture(scene, *args, **kwargs):
        given.append(scene)
        raise ParameterError("analysis", "stopped here", "nothing: the test stops it")

    monkeypatch.setattr(analysis, "work_precision", capture)
    monkeypatch.setattr(analysis, "default_cases", capture)
    path = tmp_path / "big.toml"
    path.write_text(SPHERE_FILE)
    assert main([command, str(path), "--set", "E=2e6", "-o", str(tmp_path / "x.nc")]) == 2
    assert "stopped here" in one_error(capsys)
    scene = given[0]
    assert isinstance(scene, mol_shell.Sphere) and scene.a == 2.0 and scene.nu == 0.3 and scene.E == 2e6


# -- item 7: a reader that stops reading -------------------------------------------------------------------------
@pytest.mark.parametrize("args", [["scenes", "sphere"], ["scenes"], ["scenes", "torus", "--toml"]])
def test_output_cut_short_by_its_reader_ends_quietly(args):
    """As ``mol-shell scenes sphere | head -1``: the reader has gone before anything is written."""
    process = subprocess.Popen([sys.executable, "-m", "mol_shell", *args], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE)
    process.stdout.close()
    err = process.stderr.read().decode()
    process.wait(timeout=60)
    process.stderr.close()
    assert err == "" and process.returncode == 141, (process.returncode, err)


# -- item 8: the output's kind ---------------------------------------------------------------------------------
@pytest.mark.parametrize("argv", [
    ["run", "sphere", "--t-end", "1e-5"],
    ["modes", "sphere"],
    ["study", "sphere", "--vary", "nu=0.3,0.4", "--t-end", "1e-5"],
    ["compare", "sphere", "--integrators", "leapfrog"],
    ["stability", "sphere", "--quick"],
    ["path", "sphere", "--param", "pressure=0:1e3"],
])
@pytest.mark.parametrize("suffix", ["png", "xdmf", "txt", ""])
def test_commands_writing_netcdf_refuse_other_file_kinds(argv, suffix, tmp_path, capsys):
    out = tmp_path / (f"x.{suffix}" if suffix else "x")
    start = time.perf_counter()
    assert main([*argv, "-o", str(out)]) == 2
    err = one_error(capsys)
    assert f"-o = '{out}'" in err and ".nc" in err and not out.exists()
    assert time.perf_counter() - start < 5  # refused before anything is computed


@pytest.mark.parametrize("argv,wrong,right", [
    (["export"], "run.nc", ".xdmf"), (["export"], "run.gif", ".pvd"), (["animate"], "run.png", ".gif"),
    (["animate"], "run.nc", ".mp4"), (["plot"], "run.nc", ".png"), (["plot"], "run.xdmf", ".svg"),
])
def test_views_refuse_other_file_kinds(argv, wrong, right, sphere_run, tmp_path, capsys):
    out = tmp_path / wrong
    assert main([*argv, str(sphere_run), "-o", str(out)]) == 2
    err = one_error(capsys)
    assert right in err and not out.exists()


@pytest.mark.skipif(shutil.which("xelatex") is not None, reason="xelatex is installed: pgf is a format here")
def test_plot_refuses_pgf_where_no_tex_system_can_write_it(sphere_run, tmp_path, capsys):
    """matplotlib lists pgf everywhere and fails at the save without xelatex: an internal error before."""
    out = tmp_path / "run.pgf"
    assert main(["plot", str(sphere_run), "-o", str(out)]) == 2
    assert ".png" in one_error(capsys) and not out.exists()


def test_modes_refuses_a_figure_that_is_not_an_image(tmp_path, capsys):
    assert main(["modes", "sphere", "--png", str(tmp_path / "m.nc"), "-o", str(tmp_path / "m.nc")]) == 2
    assert "--png = " in one_error(capsys)


# -- item 9: a malformed points file ------------------------------------------------------------------------------
LONG = "abcdefgh_a_long_word_that_goes_on_and_on_and_on_and_on_and_on_and_on_and_on_and_on_to_its_very_end"
POINTS = {
    "word": (f"# r z\n1.0 0.0\n0.9 0.3\n\n0.7 {LONG}\n0.4 0.55\n0.0 0.6\n", [f"'{LONG}'", "line 5 ('0.7 "]),
    "columns": ("1.0 0.0\n0.9 0.3 0.1\n0.7 0.5\n0.4 0.55\n0.0 0.6\n", ["3 values on line 2 ('0.9 0.3 0.1')"]),
    "negative": ("# c\n1.0 0.0\n0.9 0.3\n-0.7 0.5\n0.4 0.55\n0.0 0.6\n", ["r = -0.7 < 0 on line 4"]),
    "repeated": ("# c\n\n1.0 0.0\n0.9 0.3\n0.9 0.3\n0.4 0.55\n0.0 0.6\n", ["repeats a point: line 4 and line 5"]),
    "axis": ("1.0 0.0\n0.0 0.3\n0.7 0.5\n0.4 0.55\n0.0 0.6\n", ["touches the axis between its ends, on line 2"]),
}


@pytest.mark.parametrize("case", sorted(POINTS))
def test_a_malformed_points_file_is_refused_at_the_line_a_user_counts(case, tmp_path, capsys):
    """Lines counted from 1 as an editor shows them (comments and blank lines included); nothing is cut."""
    text, expected = POINTS[case]
    folder = tmp_path / ("a_folder_with_a_rather_long_name_" * 3)
    folder.mkdir()
    path = folder / "meridian.txt"
    path.write_text(text)
    assert main(["run", "meridian", "--set", f"points={path}", "--t-end", "1e-5", "-o", str(tmp_path / "m.nc")]) == 2
    err = one_error(capsys)
    assert f"points = '{path}'" in err, err  # the whole path
    for words in expected:
        assert words in err, err


def test_a_table_given_in_python_counts_its_rows_from_1():
    table = np.array([[1.0, 0.0], [0.9, 0.3], [-0.7, 0.5], [0.4, 0.55], [0.0, 0.6]])
    with pytest.raises(ParameterError, match=r"r = -0\.7 < 0 on row 3;"):
        PointsMeridian(table)


# -- item 12: the warning on the command line ----------------------------------------------------------------
def test_the_material_warning_is_one_line_and_the_file_keeps_it(tmp_path, capsys):
    out = tmp_path / "s.nc"  # on sphere_run's 9 nodes: the default sphere's kernel is compiled once for the module
    assert main(["run", "sphere", "--n", "9", "--t-end", "1e-5", "-o", str(out)]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if line.startswith("mol-shell: warning: ")]
    assert len(warnings) == 1 and 'choose material = "svk-plane-stress"' in warnings[0]
    assert warnings[0].endswith(read_netcdf(out).attrs["material_warning"])
    assert main(["run", "sphere", "--n", "9", "--t-end", "1e-5", "--set", "material=svk-plane-stress", "-o",
                 str(out)]) == 0
    assert "warning" not in capsys.readouterr().err


# -- item 13: h is the half-thickness ----------------------------------------------------------------------------
def test_h_is_described_as_the_half_thickness_wherever_it_is_set(capsys):
    assert main(["scenes", "sphere"]) == 0
    listed = next(line for line in capsys.readouterr().out.splitlines() if line.split()[:1] == ["h"])
    assert listed.endswith("half-thickness (the wall is 2h thick)")
    assert "half-thickness (the wall is 2h thick)" in next(
        line for line in scene_toml(mol_shell.Sphere).splitlines() if line.startswith("h = "))
    for example in EXAMPLES.glob("*.toml"):
        line = next(line for line in example.read_text().splitlines() if line.startswith("h = "))
        assert "half-thickness" in line and "the wall is 2h thick" in line, example


# -- item 15: the parameter listing --------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(mol_shell.SCENES))
def test_every_parameter_is_described_in_aligned_columns(name, capsys):
    """Below a header, one row per parameter: the name, the default right-aligned under "default", the units and
    the description each starting in the header's column; every description says something (a history names
    the parameter it is the history of)."""
    assert main(["scenes", name]) == 0
    lines = capsys.readouterr().out.splitlines()
    at = next(i for i, line in enumerate(lines) if line.split()[:2] == ["parameter", "default"])
    fields = [f.name for f in dataclasses.fields(mol_shell.SCENES[name])]
    header, rows = lines[at], lines[at + 1 : at + 1 + len(fields)]
    assert [row.split()[0] for row in rows] == fields and lines[at + 1 + len(fields)] == ""
    end = header.index("default") + len("default")
    units_at, text_at = header.index("units"), header.index("what it is")
    for row, field in zip(rows, fields):
        assert row[end - 1] != " " and row[end : end + 2] == "  ", row  # the default ends under the header's end
        assert row[units_at - 1] == " " and row[units_at] != " ", row
        assert row[units_at:text_at].strip() in (UNITS.get(field, "1"), "-"), row  # -: no number (tests/scenes)
        text = row[text_at:]
        assert row[text_at - 1] == " " and text.strip() == text and text, row
        if field.endswith("_history"):
            assert text.startswith(f"time history of {field[: -len('_history')]} "), row


def test_compare_whose_reference_stops_says_where_and_exits_3(monkeypatch, tmp_path, capsys):
    """The reference runs (cvode-adams and ida at rtol 1e-12) that stopped were an internal error (a RuntimeError);
    a ramped drive made IDA stop at t = 0 that way (mended). Here the stop is forced: the command says why in one
    line, names the time, and exits 3."""
    import types

    from mol_shell.analysis import workprecision

    def stopped(system, compiled, y0, times, name, value, progress=None):
        return types.SimpleNamespace(status="limit", message=f"{name} failed at t = 0.5 ms", failure_time=5e-4)

    monkeypatch.setattr(workprecision, "run_once", stopped)
    code = main(["compare", "sphere", "--integrators", "leapfrog", "--n", "8", "--t-end", "1e-3",
                 "-o", str(tmp_path / "c.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3 and len([line for line in err if "mol-shell: stopped" in line]) == 1, err
    assert "did not complete (cvode-adams failed at t = 0.5 ms; ida failed at t = 0.5 ms)" in err[-1]
    assert "internal error" not in " ".join(err)


@pytest.mark.parametrize("argv, output, blocker, kind", [
    (["compare", "sphere", "--integrators", "leapfrog", "--n", "8"], "c.nc", "c.md", "dir"),
    (["stability", "sphere", "--quick"], "st.nc", "st.png", "dir"),
    (["export", "RUN"], "e.xdmf", "e.h5", "dir"),
    (["export", "RUN"], "p.pvd", "p_0001.vtu", "dir"),
    (["study", "sphere", "--vary", "nu=0.3,0.4", "--t-end", "1e-5", "--n", "8"], "s.nc", "s.cases", "file"),
])
def test_a_file_written_beside_the_output_that_cannot_be_is_refused_before_the_work(
        argv, output, blocker, kind, sphere_run, tmp_path, capsys):
    """Only -o itself was checked: a directory where compare's .md, export's .h5 or a .vtu of the series goes, or a
    file where a study keeps its cases, was an internal error after the work (some files already written)."""
    (tmp_path / blocker).mkdir() if kind == "dir" else (tmp_path / blocker).write_text("")
    argv = [str(sphere_run) if a == "RUN" else a for a in argv]
    start = time.perf_counter()
    assert main([*argv, "-o", str(tmp_path / output)]) == 2
    err = one_error(capsys)
    assert str(tmp_path / blocker) in err and not (tmp_path / output).exists()
    assert time.perf_counter() - start < 5


# each on a grid another test runs the same shell on (the refusal does not depend on n), so that no kernel is
# compiled for this test alone: the examples on test_scene_files' 11 nodes (gamma, omega, dilation and R are initial
# data, not part of a kernel), the twisted cylinder on the suite's usual 8 and the sphere on sphere_run's 9
@pytest.mark.parametrize("argv, words", [
    ([str(EXAMPLES / "torus_gravity.toml"), "--n", "11"],
     "dilation = auto starts from the static equilibrium under the loads"),
    ([str(EXAMPLES / "drum_spin_down.toml"), "--n", "11"], "omega = 20.0 is outside 0 for modes (a state at rest)"),
    (["twisted-cylinder", "--n", "8"], "a twist (gamma) is held only by edges imposing chi: end1=clamped, end2=clamped"),
    (["sphere", "--set", "gamma=0.1", "--set", "R=1.0", "--n", "9"],
     "no equilibrium of a shell closed at a pole: gamma = 0"),
])
def test_modes_of_a_state_out_of_equilibrium_says_what_of_the_scene_to_change(argv, words, tmp_path, capsys):
    """Every such refusal ended "e.g. a twisted cylinder needs end1=clamped, end2=clamped", the torus's and the
    spinning drum's too (whose fixes are dilation = auto and omega = 0)."""
    assert main(["modes", *argv, "-o", str(tmp_path / "m.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("mol-shell: error: ") and words in err, err


def test_a_study_whose_case_stops_at_a_limit_says_where_and_when_and_exits_3(tmp_path, capsys):
    """A case crushed by 1e6 Pa stops at SVK's compressive turning point: the study exited 3 saying only the
    counts; now one line gives the first stopped case's message (where and when)."""
    out = tmp_path / "st.nc"
    code = main(["study", "sphere", "--vary", "pressure=0,-1e6", "--set", "R=1.0", "--t-end", "0.05", "--n", "8",
                 "--integrator", "cvode-bdf", "--scheduler", "serial", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 3
    line = next(x for x in err.splitlines() if "stopped short" in x)
    assert line.startswith("mol-shell: 1 of 2 cases stopped short; the first (limit): ") and " at t = " in line


def test_compare_on_the_unshearable_scene_says_which_model_it_compares(tmp_path, capsys):
    """Every integrator of a comparison runs the scene's free shell (ida too), while `run --integrator ida` runs
    its constrained DAE: the file and the output say which model was compared."""
    out = tmp_path / "cu.nc"
    assert main(["compare", "unshearable", "--integrators", "leapfrog", "--n", "8", "--t-end", "1e-3",
                 "--repeats", "1", "-o", str(out)]) == 0
    assert "model: the unshearable scene's free shell" in capsys.readouterr().out
    assert "constrained DAE" in read_netcdf(out).attrs["model"]


def test_a_warning_repeated_by_the_runs_of_one_command_is_said_once(monkeypatch, tmp_path, capsys):
    """A stability report's runs (59 of them for the sphere with --quick) each warned about the same law again.
    Here a command's runs are stood in for by two identical warnings and a third, other one."""
    import importlib
    import warnings

    cli = importlib.import_module("mol_shell.cli.main")  # the module (the package exports its function main)

    def runs(args):
        for text in ("the same law", "the same law", "another"):
            warnings.warn(text, mol_shell.MaterialWarning, stacklevel=1)
        return 0

    monkeypatch.setattr(cli, "cmd_run", runs)
    assert main(["run", "sphere", "--t-end", "1e-5", "-o", str(tmp_path / "s.nc")]) == 0
    err = capsys.readouterr().err
    assert err.count("mol-shell: warning: the same law") == 1 and err.count("mol-shell: warning: another") == 1, err
    assert main(["run", "sphere", "--t-end", "1e-5", "-o", str(tmp_path / "s.nc")]) == 0  # said again by the next
    assert capsys.readouterr().err.count("mol-shell: warning: the same law") == 1
