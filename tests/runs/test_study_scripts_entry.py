"""The scripts in ``studies/`` end as ``mol-shell`` commands do, and their summary files are CF-clean.

Bad input is one line naming the option and its range, exit code 2 (an option out of range, a study whose every
case was refused: ``summarize`` says the cases' reasons); a model limit 3; Ctrl-C 130; never a traceback
(:mod:`mol_shell.cli.scripts`). Every summary writer gives each variable a long_name (and units, the numeric ones)
and the file ``Conventions`` and ``history``. Nothing here runs a study: the options are refused before, and the
writers get small synthetic inputs.
"""

import ast
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr
from study_scripts import STUDIES, load_script

import mol_shell
from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.cli.scripts import exit_code
from mol_shell.results.study_store import summarize

ROOT = Path(__file__).resolve().parents[2]


def load(name):
    return load_script(name, "entry")


@pytest.mark.parametrize("path", sorted(STUDIES.glob("*.py")), ids=lambda p: p.stem)
def test_every_study_script_ends_through_run_script(path):
    tree = ast.parse(path.read_text())
    guard = [node for node in tree.body if isinstance(node, ast.If) and "__main__" in ast.unparse(node.test)]
    assert len(guard) == 1 and ast.unparse(guard[0].body[0]) == "run_script(main)", path.name


@pytest.mark.parametrize(("name", "argv", "said"), [
    ("ring_vs_pde", ["--quick", "--n", "0"], "--n = 0 is outside integers >= 3"),
    ("ring_vs_pde", ["--quick", "--t-end", "-1"], "--t-end = -1 is outside (0, inf) s"),
    ("twist_amplitude", ["--gammas", "abc"], "'abc' is not a number"),
    ("twist_amplitude", ["--grids", "40,2"], "--grids = 2 is outside integers >= 3"),
    ("sweeps_nu_h", ["--quick", "--grids", "0"], "--grids = 0 is outside integers >= 3"),
    ("work_precision", ["--repeats", "0"], "--repeats = 0 is outside integers in [1, "),
    ("stability_report", ["--max-n", "-5"], "--max-n = -5 is outside integers >= 40"),
    ("plane_stress", ["--quick", "--dt", "-1"], "--dt = -1 is outside (0, inf) s"),
    ("plane_stress", ["--quick", "--dt", "-1e-6"], "--dt = -1e-6 is outside (0, inf) s"),
    ("implicit_scaling", ["--sizes", "40,x"], "--sizes = 'x' is not an integer"),
    ("implicit_scaling", ["--repeats", "0"], "--repeats = 0 is outside"),
    ("unshearable_vs_free", ["--n", "1"], "--n = 1 is outside integers >= 3"),
    ("ellipticity", ["--out", "/dev/null/x"], "--out = '/dev/null/x' cannot be made a folder"),
])
def test_bad_options_are_one_line_naming_the_option_exit_2(name, argv, said, capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(STUDIES / f"{name}.py")])  # as when the script runs: its name says
    argv = argv if "--out" in argv else [*argv, "--out", str(tmp_path)]
    assert exit_code(load(name).main, argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"{name}.py: error: ") and said in err[0], err


def test_a_script_run_as_a_program_refuses_in_one_line():
    proc = subprocess.run([sys.executable, str(STUDIES / "ring_vs_pde.py"), "--quick", "--n", "0"],
                          capture_output=True, text=True, timeout=60, check=False)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert proc.stderr.strip() == "ring_vs_pde.py: error: --n = 0 is outside integers >= 3"


@pytest.mark.parametrize(("error", "code", "said"), [
    (KeyboardInterrupt(), 130, "study.py: interrupted"),
    (ModelLimitError("r <= 0 at t = 0.1 s", 0.1, "s = 0"), 3, "study.py: stopped: r <= 0 at t = 0.1 s"),
    (ParameterError("nu", 0.7, "(-1, 0.5)"), 2, "study.py: error: nu = 0.7 is outside (-1, 0.5)"),
])
def test_ctrl_c_limits_and_refusals_end_a_script_in_one_line(error, code, said, capsys):
    def main(argv):
        raise error

    assert exit_code(main, [], prog="study.py") == code
    assert capsys.readouterr().err.strip() == said


def refused_study():
    return xr.Dataset({"status": (("gamma",), np.array(["refused", "refused"], dtype=object)),
                       "message": (("gamma",), np.array(["dt = 1.0 is outside (0, 0.00019) s"] * 2, dtype=object))},
                      coords={"gamma": [0.1, 0.2], "time": [0.0, 1e-3]})


def test_summarize_of_a_study_whose_every_case_was_refused_says_why():
    with pytest.raises(ParameterError, match=r"every case of the study was refused \(2 of 2\): dt = 1.0 is outside"):
        summarize(refused_study())


def study_like(name="gamma", values=(0.05, 0.1), n=5):
    """A study's Dataset as summarize reads it, of made-up numbers."""
    rng = np.random.default_rng(0)
    shape = (len(values), 3, n)
    fields = {k: ((name, "time", "s"), rng.normal(size=shape)) for k in ("r", "theta", "psi", "chi")}
    return xr.Dataset({**fields, "energy": ((name, "time"), 1.0 + rng.random(shape[:2])),
                       "R": ((name,), np.ones(len(values))),
                       "status": ((name,), np.array(["complete"] * len(values), dtype=object)),
                       "wall_time_s": ((name,), np.ones(len(values))),
                       "leapfrog_dt_bound_s": ((name,), np.ones(len(values)))},
                      coords={name: list(values), "time": [0.0, 0.1, 0.2], "s": np.linspace(0, 1, n)})


def amplitudes(ds, n, extras):
    m = summarize(ds)
    for extra in extras:
        m[extra] = xr.DataArray(ds[extra].values, dims=ds[extra].dims)  # without attrs: the writer names them
    return m


def twist_input():
    ds = study_like()
    return [amplitudes(ds, 40, ("R", "status", "wall_time_s")).expand_dims(grid=[40])], 1e-6


def sweeps_input():
    out = {}
    for name, values in (("nu", (0.3, 0.45)), ("h", (0.002, 0.004))):
        ds = study_like(name, values)
        m = amplitudes(ds, 40, ("R", "status", "wall_time_s", "leapfrog_dt_bound_s"))
        m["chi_end"] = xr.DataArray(ds.chi.isel(time=-1, s=0).values, dims=(name,))
        out[name] = m.expand_dims(grid=[40])
    return out, 4e-6


def plane_stress_input():
    module = load("plane_stress")
    keys = ("R", "omega_max", "dt", "r_min", "r_max", "theta_max", "chi_at_end_max", "psi_max")
    nus = (0.499, 0.4999)
    rows = {(m, nu): dict.fromkeys(keys, 1.0) for m in module.MATERIALS for nu in nus}
    finals = {(m, nu): xr.DataArray(np.ones(4), dims="s", coords={"s": np.linspace(0, 1, 4)})
              for m in module.MATERIALS for nu in nus}
    return rows, finals, nus, 1e-5


def ellipticity_input():
    row = {"material": "svk", "n": 21, "status": "complete", "lost": np.nan, "stop": np.nan, "end": 0.02,
           "stretch_min": 0.95, "margin_min": 0.1}
    return [row, {**row, "n": 41}], 0.99


def implicit_scaling_input():
    module = load("implicit_scaling")
    methods, sizes = ["cvode-bdf", "leapfrog"], [40, 80]
    return {k: np.ones((len(module.CASES), len(methods), len(sizes))) for k in module.STATS}, methods, sizes


@pytest.mark.parametrize(("name", "made"), [("twist_amplitude", twist_input), ("sweeps_nu_h", sweeps_input),
                                            ("plane_stress", plane_stress_input), ("ellipticity", ellipticity_input),
                                            ("implicit_scaling", implicit_scaling_input)])
def test_a_studys_summary_file_names_the_units_and_meaning_of_every_variable(name, made, tmp_path):
    path = tmp_path / f"{name}.nc"
    mol_shell.write_netcdf(load(name).summary(*made()), path)
    with netCDF4.Dataset(path) as nc:
        assert nc.Conventions == "CF-1.8" and "created by mol_shell" in nc.history
        for var in nc.variables.values():
            assert "long_name" in var.ncattrs(), var.name
            if var.dtype != str:
                assert "units" in var.ncattrs(), var.name


def test_the_h_sweeps_axis_labels_every_thickness(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    module = load("sweeps_nu_h")
    summaries, _ = sweeps_input()
    summaries = {name: m.rename({f"{k}": k for k in m.data_vars}) for name, m in summaries.items()}
    figures = []
    monkeypatch.setattr(plt, "close", figures.append)
    module._plot(summaries, [40], tmp_path / "sweeps.png")
    fig = figures[0]
    fig.canvas.draw()
    ax = fig.axes[3]  # the h row's first panel
    lo, hi = ax.get_xlim()
    shown = [t.get_text() for t in ax.get_xticklabels() if t.get_text() and lo <= t.get_position()[0] <= hi]
    assert shown == ["0.002", "0.004"], shown
    plt.close(fig)


def test_implicit_scaling_times_a_millisecond_run_until_50_ms_and_gives_the_exponents_spread(monkeypatch):
    module = load("implicit_scaling")
    walls = iter(np.r_[2e-3, np.full(100, 1e-3)])

    def simulate(scene, integrator, **kwargs):
        return xr.Dataset(attrs={"status": "complete", "n_steps": 10, "wall_time_s": float(next(walls)),
                                 "leapfrog_dt_bound_s": 1e-6})

    monkeypatch.setattr(module, "simulate", simulate)  # mol_shell.cli.scripts.simulate: the run, checked
    row = module.measure(module.CASES["viscous"][0], "cvode-bdf", 40, 0.01, repeats=3)
    assert row["n_repeats"] == 49 and row["wall_time_s"] == 1e-3 and row["wall_time_max_s"] == 2e-3
    value, low, high = module.slope_spread(np.array([40, 80]), np.array([1.0, 2.0]), np.array([1.5, 3.0]))
    assert value == pytest.approx(1.0) and low < value < high


def test_a_scripts_warnings_are_one_line_each_once_as_the_command_lines(capsys):
    """The scripts printed a study's warnings in Python's own two-line form (file, line and the source line), once
    per case; they are said as the command line says them: ``SCRIPT: warning: ...``, one line, once."""
    def main(argv):
        for _ in range(3):  # three cases of a study, one warning each
            mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=[0.0, 1e-5], progress=False, stresses=False)

    assert exit_code(main, [], prog="twist_amplitude.py") == 0
    lines = capsys.readouterr().err.splitlines()
    said = [line for line in lines if "warning" in line]
    assert said and all(line.startswith("twist_amplitude.py: warning: ") for line in said), lines
    assert len(said) == len(set(said)) and not any(line.startswith("  ") for line in lines), lines
