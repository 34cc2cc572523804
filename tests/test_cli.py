"""The command line: named one-line errors with exit code 2, runs that write netCDF, plots."""

import subprocess
import sys

import numpy as np
import pytest

from mol_shell.cli import main, parse_times_arg
from mol_shell.errors import ParameterError
from mol_shell.output import read_netcdf

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
]


@pytest.mark.parametrize("argv,name", BAD)
def test_bad_input_names_the_parameter(argv, name, tmp_path, capsys):
    code = main(argv + ["-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert f"{name} = " in err or f"argument {name}" in err
    assert "outside" in err
    assert not (tmp_path / "x.nc").exists()


def test_per_field_atol_reaches_the_integrator(tmp_path):
    out = tmp_path / "a.nc"
    code = main(["run", "twisted-cylinder", "--t-end", "0.002", "--integrator", "cvode-bdf", "--rtol", "1e-6",
                 "--atol", "r=1e-8,theta=1e-10", "-o", str(out)])
    assert code == 0
    atol = [float(v) for v in read_netcdf(out).attrs["atol"].split(",")]  # stored per field as text
    np.testing.assert_allclose(atol, [1e-9, 1e-8, 1e-9, 1e-10, 1e-9])  # z, r, chi, theta, psi


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


def test_model_limit_writes_data_and_exits_3(tmp_path, capsys):
    nc = tmp_path / "limit.nc"
    code = main(["run", "twisted-cylinder", "--set", "R=3", "--set", "gamma=0", "--times", "0:0.05:0.005", "-o", str(nc)])
    assert code == 3
    assert "r = " in capsys.readouterr().err
    ds = read_netcdf(nc)
    assert ds.attrs["complete"] == 0 and ds.attrs["status"] == "limit"
    assert ds.sizes["time"] >= 2 and np.all(np.isfinite(ds.r.values))
