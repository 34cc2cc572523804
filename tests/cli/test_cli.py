"""The command line: named one-line errors with exit code 2, runs that write netCDF, plots."""

import signal
import subprocess
import sys

import numpy as np
import pytest

from mol_shell.cli.args import parse_times_arg
from mol_shell.cli.main import PLOT_FILES, PLOT_WHAT, main
from mol_shell._core.errors import ParameterError, show
from mol_shell.results.dataset import read_netcdf, read_run
from child_process import sigint_default, wait_until_busy
from wrapped_interrupts import WRAPPED

BAD = [
    (["run", "nope", "--t-end", "0.01"], "scene"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "nu=0.5"], "nu"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "nu=-1.2"], "nu"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "h=0"], "h"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "h=0.6"], "h"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "R=-1"], "R"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "psi0=2"], "psi0"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "colour=red"], "parameter"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "gamma=abc"], "gamma"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--n", "2"], "n"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--dt", "1e-3"], "dt"),
    (["run", "twisted-cylinder", "--t-end", "-1"], "--t-end"),
    (["run", "twisted-cylinder"], "t_end"),
    (["run", "twisted-cylinder", "--times", "0:0.01"], "--times"),
    (["run", "twisted-cylinder", "--times", "0.01,0"], "times"),
    (["run", "twisted-cylinder", "--times", "0,0.0000015"], "times"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "euler"], "integrator"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--atol", "0"], "--atol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--atol", "q=1e-9"], "--atol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--atol", "r=-1"], "--atol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "n_quad=1"], "n_quad"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "n_quad=2.5"], "n_quad"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "R=0.005"], "R"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "L=abc"], "L"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--set", "gamma="], "gamma"),
    (["run", "twisted-cylinder", "--times", "0:0.01:0.003"], "--times"),
    (["run", "twisted-cylinder", "--times", "0,,0.002"], "--times"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--rtol", "1"], "--rtol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--rtol", "2"], "--rtol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--integrator", "cvode-bdf", "--rtol", "1e-20"], "--rtol"),
    (["run", "twisted-cylinder", "--t-end", "0.01", "--n", "abc"], "--n"),
    # the memory estimate of 1e306 saved times overflowed, and the refusal blamed --n with a 300-digit count
    (["run", "sphere", "--n", "8", "--times", "0:1e300:1e-6"], "--times"),
]


@pytest.mark.parametrize("argv,name", BAD)
def test_bad_input_names_the_parameter(argv, name, tmp_path, capsys):
    code = main(argv + ["-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert f"{name} = " in err or f"{name} is missing" in err
    assert "outside" in err or "allowed:" in err or "missing: give" in err  # the allowed range is named
    assert "argument" not in err  # argparse's "argument --dt: --dt = ..." named the option twice
    assert not (tmp_path / "x.nc").exists()


def test_per_field_atol_reaches_the_integrator(tmp_path):
    out = tmp_path / "a.nc"
    code = main(["run", "twisted-cylinder", "--t-end", "0.002", "--integrator", "cvode-bdf", "--rtol", "1e-6",
                 "--atol", "r=1e-8,theta=1e-10", "-o", str(out)])
    assert code == 0
    assert read_netcdf(out).attrs["atol"] == "z=1e-09,r=1e-08,chi=1e-09,theta=1e-10,psi=1e-09"  # per field, named


def test_times_ranges_include_the_end():
    np.testing.assert_allclose(parse_times_arg("0:0.1:0.02"), [0, 0.02, 0.04, 0.06, 0.08, 0.1])
    np.testing.assert_allclose(parse_times_arg("0,0.02,0.07"), [0, 0.02, 0.07])
    with pytest.raises(ParameterError):
        parse_times_arg("0:1:-1")


def test_run_and_plot_through_python_m(tmp_path):
    nc, png = tmp_path / "run.nc", tmp_path / "run.png"
    cmd = [sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--times", "0:0.004:0.002", "-o", str(nc)]
    done = subprocess.run(cmd, capture_output=True, text=True, check=True)
    assert "R = 0.99484" in done.stdout
    ds = read_netcdf(nc)
    np.testing.assert_allclose(ds.time.values, [0, 0.002, 0.004])
    assert ds.attrs["n_steps"] == 4000 and ds.attrs["complete"] == 1
    subprocess.run([sys.executable, "-m", "mol_shell", "plot", str(nc), "-o", str(png)], check=True)
    assert png.stat().st_size > 10_000


def test_a_loaded_cylinders_R_is_said_to_be_its_static_starts_mean_radius(tmp_path, capsys):
    """An untwisted cylinder under pressure starts from the static equilibrium found from the radial one, whose
    radius varies along the length (end effects: one edge free); ``R`` (printed and in the file) is that start's
    mean radius, not the radial equilibrium the solve began at (which initial_state names)."""
    out = tmp_path / "c.nc"
    assert main(["run", "twisted-cylinder", "--set", "gamma=0", "--set", "end2=free", "--set", "pressure=10",
                 "--set", "material=svk-plane-stress", "--set", "nu=0.3", "--n", "11", "--t-end", "1e-5",
                 "-o", str(out)]) == 0
    said = capsys.readouterr().out
    ds = read_netcdf(out)
    r0, s = ds.r.isel(time=0).values, ds.s.values
    R = float(ds.attrs["R"])
    assert R == pytest.approx(np.sum((r0[1:] + r0[:-1]) / 2 * np.diff(s)) / (s[-1] - s[0]), rel=1e-14)
    assert r0.min() < R < r0.max() and ds.attrs["R_requested"] == "auto"
    assert f"R = {R:.10g} m (the start's mean radius: the static equilibrium under the loads)" in said, said
    assert "found from the radial equilibrium at r = 1.000" in ds.attrs["initial_state"]


def test_model_limit_writes_data_and_exits_3(tmp_path):
    nc = tmp_path / "limit.nc"
    cmd = [sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--set", "R=3", "--set", "gamma=0",
           "--set", "law_limit=false", "--times", "0:0.05:0.005", "-o", str(nc)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    assert done.returncode == 3
    # only the command's own line (and its one-line warnings): no Python RuntimeWarning with its source line
    lines = [line for line in done.stderr.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert lines[0].startswith("mol-shell: run stopped: r = ") and len(lines) == 1, done.stderr
    ds = read_netcdf(nc)
    assert ds.attrs["complete"] == 0 and ds.attrs["status"] == "limit"
    assert ds.sizes["time"] >= 2 and np.all(np.isfinite(ds.r.values))


# -- error wording --------------------------------------------------------------------------------------
WORDING = [
    (["--set", "L=abc", "--t-end", "0.01"], "L = 'abc' is not a number; allowed: (0, inf) m"),
    (["--set", "n_quad=2.5", "--t-end", "0.01"], "n_quad = 2.5 is not an integer; allowed: integers 2..32"),
    (["--set", "n_quad=1", "--t-end", "0.01"], "n_quad = 1 is outside integers 2..32"),
    ([], "t_end is missing: give t_end in (0, inf) s, or times"),
    (["--dt", "0", "--t-end", "0.01"], "--dt = 0 is outside (0, inf) s"),
    (["--t-end", "abc"], "--t-end = 'abc' is not a number; allowed: (0, inf) s"),
    (["--dt", "inf", "--t-end", "0.01"], "--dt = inf is not a finite number; allowed: (0, inf) s"),
    # an option of a start from a path: said to be one before its value (tests/cli/test_not_an_option_first.py)
    (["--t-end", "0.01", "--perturb", "nan"], "--perturb is an option with --from PATH.nc only"),
    (["--t-end", "0.01", "--rtol", "1e-6"], "rtol is not an option of leapfrog (its options: chunk, dt, restart)"),
    (["--t-end", "0.01", "--atol", "1e-9"], "atol is not an option of leapfrog (its options: chunk, dt, restart)"),
    (["--t-end", "0.01", "--max-step", "1e-3"], "max_step is not an option of leapfrog (its options: chunk, dt, restart)"),
    (["--t-end", "0.01", "--integrator", "cvode-bdf", "--dt", "1e-6"],
     "dt is not an option of cvode-bdf (its options: anderson, atol, constraints, events"),
    (["--t-end", "0.01", "--integrator", "cvode-bdf", "--rtol", "1"], "--rtol = 1 is outside [1e-14, 1)"),
    (["--times", "0:0.01:0.003"], "--times = '0:0.01:0.003' does not end on its grid: (T1 - T0)/DT = 3.333 is not whole"),
    (["--times", "0,,0.002"], "--times = '0,,0.002' has an empty entry"),
    (["--t-end", "0.01", "--set", "R=0.005"], "R = 0.005 is outside (0.006296, inf) m: the inner face r + zeta1"),
]


@pytest.mark.parametrize("extra,message", WORDING)
def test_messages_read_naturally(extra, message, tmp_path, capsys):
    code = main(["run", "twisted-cylinder", *extra, "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: " + message), err
    assert len(err.splitlines()) == 1


def test_times_are_rounded_and_must_end_on_the_grid():
    assert parse_times_arg("0:0.009:0.003").tolist() == [0.0, 0.003, 0.006, 0.009]  # ds.sel(time=0.009) finds it
    assert parse_times_arg("0:0.3:0.1").tolist() == [0.0, 0.1, 0.2, 0.3]
    for bad in ("0:0.01:0.003", "0:0.01", "0,,0.002", ",0.1", "", "0:0:0.1", "0:0.1:0"):
        with pytest.raises(ParameterError, match="--times"):
            parse_times_arg(bad)


def test_version(capsys):
    import mol_shell

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"mol-shell {mol_shell.__version__}"


# -- output paths: checked before anything is computed; missing directories are created ---------------
@pytest.fixture
def no_compute(monkeypatch):
    """Fail the test if a run or a comparison starts."""
    import importlib

    sim = importlib.import_module("mol_shell.runs.simulate")  # the module (mol_shell.simulate is also a function)
    wp = importlib.import_module("mol_shell.analysis.workprecision")

    def boom(*args, **kwargs):
        raise AssertionError("computed before the output path was checked")

    monkeypatch.setattr(sim, "simulate", boom)
    monkeypatch.setattr(importlib.import_module("mol_shell.cli.main"), "simulate", boom)  # the command's own name
    monkeypatch.setattr(importlib.import_module("mol_shell.runs.study"), "simulate", boom)
    monkeypatch.setattr(wp, "reference", boom)


@pytest.mark.parametrize("command", [["run", "twisted-cylinder", "--t-end", "0.01"],
                                     ["compare", "twisted-cylinder", "--integrators", "leapfrog"],
                                     ["study", "twisted-cylinder", "--vary", "gamma=0.1,0.2", "--t-end", "0.01"]])
def test_unwritable_output_is_refused_before_computing(command, tmp_path, capsys, no_compute):
    afile = tmp_path / "afile"
    afile.write_text("x")
    for output, problem in (("", "is empty"), (str(tmp_path), "is a directory"),
                            (str(afile / "x.nc"), "is not a directory")):
        code = main([*command, "-o", output])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("mol-shell: error: -o = ") and problem in err, err
        assert len(err.splitlines()) == 1


def test_missing_directories_are_created_and_removed_after_a_refusal(tmp_path, capsys):
    out = tmp_path / "new" / "deeper" / "x.nc"
    assert main(["run", "nope", "--t-end", "0.01", "-o", str(out)]) == 2  # refused: nothing left behind
    assert not (tmp_path / "new").exists()
    assert main(["run", "twisted-cylinder", "--n", "10", "--t-end", "0.0002", "-o", str(out)]) == 0
    assert out.exists()


# -- plot ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    import mol_shell

    path = tmp_path_factory.mktemp("plot") / "run.nc"
    ds = mol_shell.simulate("axisymmetric", n=10, times=np.linspace(0, 0.001, 11).round(12), progress=False)
    mol_shell.write_netcdf(ds, path)
    return path


def test_plot_refuses_files_that_are_not_runs(run_file, tmp_path, capsys):
    import xarray as xr

    text = tmp_path / "notes.txt"
    text.write_text("not netCDF")
    study_like = tmp_path / "study.nc"
    xr.Dataset({"r": (("gamma", "time", "s"), np.zeros((2, 3, 4)))},
               attrs={"title": "mol_shell parameter study of scene twisted-cylinder"}).to_netcdf(study_like)
    compare_like = tmp_path / "wp.nc"
    xr.Dataset({"error": (("integrator", "level"), np.zeros((2, 3)))},
               attrs={"title": "work-precision of mol_shell integrators"}).to_netcdf(compare_like)
    cases = [(tmp_path / "missing.nc", "does not exist", ""),
             (text, "is not a mol_shell run, path or path-study file", "not a netCDF file"),
             (study_like, "is not a mol_shell run, path or path-study file",
              "it holds a parameter study (mol-shell study)"),
             (compare_like, "is not a mol_shell run, path or path-study file",
              "it holds a work-precision comparison (mol-shell compare)")]
    for path, problem, what in cases:
        code = main(["plot", str(path), "-o", str(tmp_path / "p.png")])
        err = capsys.readouterr().err
        with pytest.raises(ParameterError) as refused:
            read_run(path, allowed=PLOT_FILES, what=PLOT_WHAT)
        # the library's refusal (with what plot reads: run, path and path-study files), naming the file (shortened
        # when the path is long) and what it is
        assert refused.value.name == "FILE" and refused.value.value == str(path)
        assert str(refused.value).startswith(f"FILE = {show(str(path))} {problem}") and what in str(refused.value)
        assert code == 2 and err.splitlines() == [f"mol-shell: error: {refused.value}"], err
    code = main(["plot", str(run_file), "-o", str(tmp_path / "p.xyz")])
    assert code == 2 and "-o = " in capsys.readouterr().err and not (tmp_path / "p.xyz").exists()


def test_plot_shows_every_saved_time_and_only_the_scene_s_parameters(run_file, tmp_path):
    from mol_shell.results.dataset import read_netcdf
    from mol_shell.views.plotting import snapshot_figure, title_of

    png = tmp_path / "new" / "p.png"
    assert main(["plot", str(run_file), "-o", str(png)]) == 0 and png.stat().st_size > 10_000
    ds = read_netcdf(run_file)
    fig = snapshot_figure(ds)
    panels = [ax for ax in fig.axes if ax.get_visible() and ax.lines]
    assert len(panels) == 3 * 11  # r, theta, chi at each of the 11 saved times
    title = fig._suptitle.get_text()
    assert "gamma" not in title and "nan" not in title and "axisymmetric" in title
    assert "shown" in title_of(dict(ds.attrs), 24, 30) and "shown" not in title


# -- compare -----------------------------------------------------------------------------------------
def test_compare_checks_its_input_before_the_references(tmp_path, capsys, no_compute):
    for names in ("", "leapfrog,,ida", "leapfrog,euler", "ida,ida"):
        code = main(["compare", "twisted-cylinder", "--integrators", names, "-o", str(tmp_path / "wp.nc")])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("mol-shell: error: --integrators = ") and len(err.splitlines()) == 1
    from mol_shell.analysis.workprecision import work_precision

    with pytest.raises(ParameterError, match="times"):  # every point would be skipped: refused up front
        work_precision("twisted-cylinder", ["leapfrog"], times=[0, 0.00125], sweeps={"leapfrog": {"dt": (1e-4,)}})


def test_compare_skips_leapfrog_steps_that_miss_the_saved_times(tmp_path):
    from mol_shell.analysis.workprecision import work_precision
    from mol_shell.views.workprecision import write_outputs

    ds = work_precision("twisted-cylinder", ["leapfrog"], n=10, times=[0, 0.00125, 0.0025], repeats=1,
                  sweeps={"leapfrog": {"dt": (1e-4, 5e-5)}}, log=lambda *a: None)
    row = ds.sel(integrator="leapfrog")
    assert list(row.status.values) == ["skipped", "complete"]
    assert np.isnan(float(row.error[0])) and float(row.error[1]) < 0.05
    assert "multiples of dt = 0.0001" in str(row.note.values[0]) and float(row.dt[0]) == 1e-4
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("long_name"), name
        if var.dtype.kind in "iuf":
            assert var.attrs.get("units"), name
    write_outputs(ds, tmp_path / "wp.nc")


# -- casadi-cvodes at a singularity ----------------------------------------------------------------------
def test_casadi_cvodes_fails_cleanly_at_a_singularity(tmp_path, capsys):
    """r -> 0 near t = 7.22 ms: the step collapses; it used to run for minutes (1e7 steps per interval)."""
    import time

    out = tmp_path / "c.nc"
    start = time.perf_counter()
    code = main(["run", "twisted-cylinder", "--integrator", "casadi-cvodes", "--set", "R=3",
                 "--times", "0,0.0072,0.0073", "-o", str(out)])
    assert time.perf_counter() - start < 60
    lines = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert code == 3 and lines[0].startswith("mol-shell: run stopped: casadi-cvodes failed") and len(lines) == 1
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "failed" and ds.attrs["complete"] == 0 and ds.sizes["time"] == 1


@pytest.mark.parametrize("kind", list(WRAPPED))
def test_a_ctrl_c_inside_a_c_call_is_an_interruption_not_an_internal_error(tmp_path, monkeypatch, capsys, kind):
    """A Ctrl-C that arrives while a C extension runs surfaces as a SystemError caused by the KeyboardInterrupt
    (CasADi's wrappers; CPython: "returned a result with an exception set"; seen once at the set-up of a run), as
    ctypes' ArgumentError ("argument 1: KeyboardInterrupt: ", seen as "mol-shell: internal error" with exit 1) or as
    CasADi's RuntimeError: "interrupted", exit 130, not "internal error"."""
    import importlib

    cli_main = importlib.import_module("mol_shell.cli.main")  # the module (the package exports its function main)

    def interrupted_inside_c(*args, **kwargs):
        raise WRAPPED[kind]()

    monkeypatch.setattr(cli_main, "writable_path", interrupted_inside_c)
    code = cli_main.main(["run", "twisted-cylinder", "--t-end", "0.001", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 130 and "interrupted" in err and "internal error" not in err


@pytest.mark.slow
def test_ctrl_c_keeps_the_data_and_exits_130(tmp_path):
    """SIGINT during a leap-frog run (10 s of simulated time: ~40 s of stepping on the 0.5.0 stencil) after the build:
    the saved times reached are written, marked interrupted, and the exit code is 130 (128 + SIGINT)."""
    out = tmp_path / "x.nc"
    proc = subprocess.Popen([sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--t-end", "10",
                             "--times", "0:10:0.01", "-o", str(out)], stderr=subprocess.PIPE, text=True,
                            preexec_fn=sigint_default)
    # past start-up and set-up (2.2 s of its own processor time, measured) and about 2 s into the stepping
    assert wait_until_busy(proc, 4.0), proc.stderr.read()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "interrupted by the user" in err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and ds.attrs["complete"] == 0
    assert ds.sizes["time"] >= 2 and np.isfinite(ds.r.values).all()


def test_summaries_count_in_the_singular_after_one(tmp_path, capsys):
    """"1 steps", "1 cases": a count of one takes the singular."""
    from mol_shell.cli.args import plural

    assert [plural(k, "step") for k in (0, 1, 2)] == ["0 steps", "1 step", "2 steps"]
    assert plural(1, "critical point") == "1 critical point" and plural(3, "case") == "3 cases"
    assert main(["run", "twisted-cylinder", "--n", "5", "--t-end", "1e-6", "-o", str(tmp_path / "one.nc")]) == 0
    out = capsys.readouterr().out
    assert ", 1 step in " in out and "1 steps" not in out
    assert main(["study", "twisted-cylinder", "--vary", "gamma=0.1", "--n", "5", "--t-end", "1e-6", "--workers", "1",
                 "-o", str(tmp_path / "study.nc")]) == 0
    out = capsys.readouterr().out
    assert ": 1 case (1 complete)" in out and "1 cases" not in out


@pytest.mark.parametrize("option, value, why", [("--dt", "-1e-6", "is outside (0, inf) s"),
                                                ("--t-end", "-1e-3", "is outside (0, inf) s"),
                                                ("--t-end", "-inf", "is not a finite number; allowed: (0, inf) s")])
def test_a_negative_number_in_exponent_form_reaches_the_option_s_range(option, value, why, tmp_path, capsys):
    """argparse reads ``-1e-6`` as an option (its pattern of negative numbers takes ``-1`` and ``-.5`` only) and
    refused ``--dt`` for want of a value, naming no range; attached to its option the value gets the range."""
    code = main(["run", "twisted-cylinder", "--n", "11", option, value, "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and err == [f"mol-shell: error: {option} = {value} {why}"], err


def test_compare_interrupted_keeps_the_points_measured_and_exits_130(tmp_path, capsys, monkeypatch):
    """Ctrl-C during `compare` was taken for one point's ending (a NaN in the summary) and the sweep went on to the
    end, exit 0. It stops there now: the points measured kept, the rest `interrupted` (not run), the files written,
    exit 130."""
    import mol_shell.analysis.workprecision as wp
    from mol_shell.cli.main import main
    from mol_shell.results.dataset import read_netcdf

    original, calls = wp.run_once, [0]

    def run_once(*args, **kwargs):  # an interrupt as the integrators keep it: the run's end, status "interrupted"
        calls[0] += 1
        traj = original(*args, **kwargs)
        if calls[0] == 5:  # dop853-c's second point: its warm-up done, its first timed run interrupted
            traj.status = "interrupted"
        return traj

    monkeypatch.setattr(wp, "run_once", run_once)
    monkeypatch.setattr(wp, "SWEEPS", {**wp.SWEEPS, "dop853-c": {"rtol": (1e-4, 1e-6, 1e-8)}})
    out = tmp_path / "wp.nc"
    code = main(["compare", "twisted-cylinder", "--integrators", "dop853-c,rk45-c", "--n", "8", "--t-end", "2e-3",
                 "--repeats", "1", "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 130 and "comparison stopped: interrupted by the user at dop853-c 1e-06" in captured.err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted"
    assert list(ds.status.sel(integrator="dop853-c").values)[:3] == ["complete", "interrupted", "interrupted"]
    assert set(ds.status.sel(integrator="dop853-c").values[3:].tolist()) <= {""}  # no such point in its sweep
    assert set(ds.status.sel(integrator="rk45-c").values.tolist()) <= {"interrupted", ""}
    assert np.isfinite(float(ds.error.sel(integrator="dop853-c").isel(level=0)))
    assert "| rk45-c | interrupted before reached" in captured.out and "Not complete: interrupted" in captured.out


@pytest.mark.parametrize("kind", ["ctypes", "casadi"])
def test_compare_interrupted_inside_a_c_call_between_runs_keeps_the_points_measured(tmp_path, capsys, monkeypatch,
                                                                                     kind):
    """An interrupt that a C call reports as its own error (wrapped_interrupts) as a point's error is measured: the
    comparison stops there as for a KeyboardInterrupt (it was an internal error, exit 1, nothing written)."""
    import mol_shell.analysis.workprecision as wp

    original, calls = wp.relative_error, [0]

    def relative_error(*args):
        calls[0] += 1
        if calls[0] == 3:  # the reference's own check (1), the first point (2), the second point
            raise WRAPPED[kind]()
        return original(*args)

    monkeypatch.setattr(wp, "relative_error", relative_error)
    out = tmp_path / "wp.nc"
    code = main(["compare", "twisted-cylinder", "--integrators", "dop853-c", "--n", "8", "--t-end", "2e-3",
                 "--repeats", "1", "-o", str(out)])
    assert code == 130 and "comparison stopped: interrupted by the user at dop853-c" in capsys.readouterr().err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and list(ds.status.values.ravel()[:2]) == ["complete", "interrupted"]


@pytest.mark.parametrize("call", [1, 2, 3])
def test_compare_interrupted_in_a_reference_or_a_warm_up_run_exits_130(tmp_path, capsys, monkeypatch, call):
    """An interrupt in a reference run (calls 1, 2) was reported as the reference not completing (exit 3); in a
    warm-up run (call 3) it was lost and the sweep went on (exit 0)."""
    import mol_shell.analysis.workprecision as wp
    from mol_shell.cli.main import main

    original, calls = wp.run_once, [0]

    def run_once(*args, **kwargs):
        calls[0] += 1
        traj = original(*args, **kwargs)
        if calls[0] == call:
            traj.status = "interrupted"
        return traj

    monkeypatch.setattr(wp, "run_once", run_once)
    code = main(["compare", "twisted-cylinder", "--integrators", "dop853-c", "--n", "8", "--t-end", "2e-3",
                 "--repeats", "1", "-o", str(tmp_path / "wp.nc")])
    assert code == 130, capsys.readouterr().err


def test_option_sets_any_integrator_option_on_the_command_line(tmp_path, capsys):
    """Options beyond --dt/--rtol/--atol/--max-step (the leap-frog's restart, CVODE's linsolver, jac_every) could be
    set only in a scene file's [run] table or in Python. --option NAME=VALUE sets them, read as the table's TOML
    (a bare word is a string), checked against the option's range, over the file's value."""
    out = tmp_path / "x.nc"
    assert main(["run", "twisted-cylinder", "--n", "12", "--t-end", "0.001", "--integrator", "cvode-bdf",
                 "--option", "linsolver=band", "--option", "jac_every=50", "-o", str(out)]) == 0
    ds = read_netcdf(out)
    assert ds.attrs["linsolver"] == "band" and ds.attrs["jac_every"] == 50
    scene = tmp_path / "s.toml"
    scene.write_text('scene = "twisted-cylinder"\n[material]\neta_mu = 100.0\neta_lambda = 200.0\n'
                     '[run]\nn = 12\nt_end = 0.002\nrestart = 0.5\n')
    assert main(["run", str(scene), "--option", "restart=5e-4", "-o", str(out)]) == 0  # refused at restart = 0.5
    ds = read_netcdf(out)
    assert ds.attrs["restart"] == 5e-4 and ds.attrs["n_restarts"] == 3
    capsys.readouterr()
    for option, said in (("restart=-1", "--option restart = -1 is outside [0, inf] s; 0 or inf: never"),
                         ("rtol=1e-6", "--option = 'rtol=1e-6' sets rtol, which has its own flag; allowed: --rtol in its place"),
                         ("linsolver=band", "--option linsolver is not an option of leapfrog (its options: chunk, dt, restart)"),
                         ("restart", "--option = 'restart' is outside NAME=VALUE")):
        assert main(["run", "twisted-cylinder", "--n", "12", "--t-end", "0.001", "--option", option,
                     "-o", str(out)]) == 2
        err = capsys.readouterr().err.strip()
        assert err == f"mol-shell: error: {said}", err


@pytest.mark.parametrize(("options", "said"), [
    (["--integrator", "cvode-bdf", "--option", "max_order=6"],
     "--option max_order = 6 is outside integers in [1, 5], or None (cvode-bdf is BDF: orders up to 5)"),
    (["--integrator", "cvode-adams", "--option", "jac_every=5"], "--option jac_every = 5 is an option of Newton's"),
])
@pytest.mark.parametrize("command", ["run", "study"])
def test_an_option_the_integrator_refuses_as_set_is_named_with_option_before_the_run(command, options, said,
                                                                                     tmp_path, capsys):
    """A value inside an --option's declared range that its integrator refuses as set (BDF's orders stop at 5,
    jac_every needs Newton's iteration) was said without ``--option`` (as if from Python) and only once the run
    started; now checked with the other options, named as given."""
    vary = ["--vary", "gamma=0.05,0.1"] if command == "study" else []
    assert main([command, "twisted-cylinder", "--n", "8", "--t-end", "0.001", *vary, *options,
                 "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"mol-shell: error: {said}"), err
    assert not (tmp_path / "x.nc").exists()
