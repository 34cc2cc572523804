"""Parameter studies: dims per varied parameter, failing cases recorded, resume, dask cluster, CLI."""

import dataclasses
import importlib
import os

import numpy as np
import pytest
import xarray as xr
from wrapped_interrupts import WRAPPED

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.path_study import path_study
from mol_shell.cli.study import parse_vary
from mol_shell.results.study_dataset import study_case
from mol_shell.runs import scheduling, worker_start
from mol_shell.runs.study import study

study_module = importlib.import_module("mol_shell.runs.study")  # the module, even if mol_shell exports a function study

BASE = mol_shell.TwistedCylinder(gamma=0.0)
SMALL = {"n": 10, "t_end": 0.002}


def test_grid_on_local_processes_with_a_refused_and_a_stopped_case():
    """2 x 3 cases on this machine's cores: nu = 0.5 is refused, R = 3 hits r <= 0 (at nu = 0.49); the others run."""
    base = dataclasses.replace(BASE, law_limit=False)  # R = 3 collapses through SVK's turning point to r = 0
    ds = study(base, {"R": [0.99, 3.0], "nu": [0.3, 0.49, 0.5]}, n=10, t_end=0.01, workers=2)
    # stresses on cells and faces; the magnets' axial force on the two ends
    assert dict(ds.sizes) == {"R": 2, "nu": 3, "time": 11, "s": 10, "s_cell": 9, "zeta": 2, "end": 2}
    assert ds.reaction_force.dims == ("R", "nu", "time", "end")
    assert ds.r.dims == ("R", "nu", "time", "s") and ds.energy.dims == ("R", "nu", "time")
    status = ds.status.values
    assert list(status[:, 2]) == ["refused", "refused"] and "nu = 0.5 is outside" in ds.message.values[0, 2]
    assert list(status[0, :2]) == ["complete", "complete"]
    assert status[1, 1] == "limit" and "r = " in ds.message.values[1, 1]
    assert ds.attrs["n_cases"] == 6 and ds.attrs["n_executed"] == 4
    assert ds.attrs["n_failed"] == int((status != "complete").sum()) >= 3
    # a stopped case keeps what it computed and is NaN afterwards
    r = ds.r.sel(R=3.0, nu=0.49).values
    assert np.isfinite(r[:3]).all() and np.isnan(r[-1]).all()
    assert float(ds.n_steps.sel(R=0.99, nu=0.3)) == 10000 and float(ds.wall_time_s.sel(R=0.99, nu=0.3)) > 0
    pids = {w.split(":")[1] for w in ds.worker.values[:, :2].ravel()}
    assert str(os.getpid()) in pids and len(pids) <= 2  # this process from the back, at most one started worker
    # (whether the worker gets one of these four 0.1 s cases depends on the machine:
    # tests/test_faults.py's 16 cases of 0.25 s check that both take some)
    # a case equals the single run
    one = mol_shell.simulate(mol_shell.TwistedCylinder(gamma=0.0, R=0.99, nu=0.49), n=10, t_end=0.01, progress=False)
    np.testing.assert_array_equal(ds.r.sel(R=0.99, nu=0.49).values, one.r.values)


# how the Ctrl-C reached the case: plain, inside a CasADi call (SystemError), or wrapped by ctypes (ArgumentError:
# stored as the case's error and reused on every resume, until December 6) or by CasADi (RuntimeError)
@pytest.mark.parametrize("wrapper", [None, "SystemError", "ctypes", "casadi"])
def test_interrupted_study_resumes_and_skips_finished_cases(tmp_path, monkeypatch, wrapper):
    out = tmp_path / "study.nc"
    vary = {"gamma": [0.05, 0.1], "psi0": [0.0, 0.02]}
    calls = []
    real = study_module.run_scene

    def interrupt_third(*args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            if wrapper in WRAPPED:
                raise WRAPPED[wrapper]()
            if wrapper == "SystemError":
                try:
                    raise KeyboardInterrupt
                except KeyboardInterrupt as interrupt:
                    raise SystemError("returned a result with an exception set") from interrupt
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(study_module, "run_scene", interrupt_third)
    with pytest.raises(KeyboardInterrupt):
        study("twisted-cylinder", vary, **SMALL, scheduler="serial", output=out)
    assert len(calls) == 3 and len(list((tmp_path / "study.cases").glob("*.nc"))) == 2 and not out.exists()
    monkeypatch.setattr(study_module, "run_scene", real)
    resumed = study("twisted-cylinder", vary, **SMALL, scheduler="serial", output=out)
    assert (resumed.attrs["n_executed"], resumed.attrs["n_reused"]) == (2, 2)
    assert (resumed.status == "complete").all()
    np.testing.assert_array_equal(resumed.r.values, study("twisted-cylinder", vary, **SMALL, scheduler="serial").r.values)
    again = study("twisted-cylinder", vary, **SMALL, scheduler="serial", output=out)
    assert (again.attrs["n_executed"], again.attrs["n_reused"]) == (0, 4)
    np.testing.assert_array_equal(again.chi.values, resumed.chi.values)
    back = mol_shell.read_netcdf(out)
    np.testing.assert_array_equal(back.chi.values, again.chi.values)
    # a changed setting is a different case: nothing is reused
    other = study("twisted-cylinder", vary, n=10, t_end=0.001, scheduler="serial", output=out)
    assert other.attrs["n_executed"] == 4


@pytest.mark.slow
def test_on_an_explicit_dask_cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        ds = study("spinning-ring", {"omega": [5.0, 10.0], "psi0": [0.0, 0.05]}, **SMALL,
                   scheduler=cluster.scheduler_address)
    assert (ds.status == "complete").all() and ds.attrs["scheduler"].startswith("tcp://")
    assert str(os.getpid()) not in {w.split(":")[1] for w in ds.worker.values.ravel()}
    L = ds.angular_momentum.isel(time=0)
    assert float(L.sel(omega=10.0, psi0=0.0)) == pytest.approx(2 * float(L.sel(omega=5.0, psi0=0.0)), rel=1e-12)


def test_irregular_design_has_a_case_dimension():
    # the third case's twist is initial data: it runs on the second's kernel (nu = 0.45 with it compiled a third)
    ds = study(BASE, [{"nu": 0.3}, {"h": 0.004}, {"gamma": 0.05, "h": 0.004}], **SMALL, scheduler="serial")
    assert ds.r.dims == ("case", "time", "s")
    np.testing.assert_allclose(ds.nu, [0.3, BASE.nu, BASE.nu])
    np.testing.assert_allclose(ds.h, [BASE.h, 0.004, 0.004])
    np.testing.assert_allclose(ds.gamma, [BASE.gamma, BASE.gamma, 0.05])


def test_a_case_that_leaves_an_option_out_runs_with_the_studys_or_the_integrators_value():
    """A list of cases where only some set ``dt`` (or ``rtol``) crashed (``float(None)``) or refused the others
    (``rtol = None is not a number``); the docstring promises the base's value for what a case leaves out."""
    ds = study(BASE, [{"gamma": 0.05}, {"nu": 0.3, "dt": 2e-6}], "leapfrog", n=12, t_end=0.002, scheduler="serial")
    assert list(ds.status.values) == ["complete", "complete"]
    np.testing.assert_allclose(ds.dt, [1e-6, 2e-6])  # leap-frog's default dt, then the case's
    ds = study(BASE, [{"rtol": 1e-7}, {"gamma": 0.05}], "cvode-bdf", n=12, t_end=0.002, scheduler="serial",
               rtol=1e-5)
    assert list(ds.status.values) == ["complete", "complete"]
    np.testing.assert_allclose(ds.rtol, [1e-7, 1e-5])  # the case's, then the study's
    with pytest.raises(ParameterError, match=r"cases that each give max_order"):  # no value of its own to show
        study(BASE, [{"max_order": 3}, {"gamma": 0.05}], "cvode-bdf", n=12, t_end=0.002, scheduler="serial")


def test_the_command_line_varies_integer_and_word_options_of_the_integrator(tmp_path, capsys):
    """``--vary jac_every=20,200`` was read as 20.0 and every case refused ("outside integers >= 0");
    ``--vary linsolver=dense,band`` was "not a number"."""
    from mol_shell.cli.main import main

    code = main(["study", "twisted-cylinder", "--integrator", "cvode-bdf", "--vary", "jac_every=20:200:180",
                 "--vary", "linsolver=dense,band", "--n", "12", "--t-end", "0.002", "--workers", "1", "-o",
                 str(tmp_path / "s.nc")])
    assert code == 0, capsys.readouterr().err
    ds = xr.open_dataset(tmp_path / "s.nc")
    assert ds.jac_every.values.tolist() == [20, 200] and ds.linsolver.values.tolist() == ["dense", "band"]
    assert (ds.status.values == "complete").all()


@pytest.mark.parametrize("scheduler", ["serial", "tcp://127.0.0.1:1"])
def test_workers_with_another_scheduler_is_refused_not_ignored(scheduler):
    """``workers`` counts local processes: with ``scheduler="serial"`` or a cluster it was silently ignored."""
    with pytest.raises(ParameterError, match=r"^workers = 2 applies to local processes \(scheduler None, the "
                                             r"default\), not to scheduler = "):
        study(BASE, {"gamma": [0.05, 0.1]}, **SMALL, scheduler=scheduler, workers=2)
    with pytest.raises(ParameterError, match=r"^workers = 2 applies to local processes \(scheduler None, the "
                                             r"default\), not to scheduler = "):
        path_study("sphere", {"nu": [0.3]}, "pressure", 0, 100, scheduler=scheduler, workers=2)
    if scheduler == "serial":  # one process: workers=1 says the same, and is taken
        assert study(BASE, {"gamma": [0.05]}, **SMALL, scheduler="serial", workers=1).attrs["n_cases"] == 1


def test_auto_and_nan_among_the_values_are_refused_before_any_case(monkeypatch):
    """A list of cases where one leaves ``R`` out runs that one at the base scene's ``R = auto``: refused as ``R=auto``
    among numbers is (the coordinate cannot hold it); NaN is refused by a study of paths too; an edge left to the
    code is the word ``auto`` in its coordinate (it was ``None``, written as an empty string)."""
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    with pytest.raises(ParameterError, match=r"^R = 'auto' cannot be varied.*a case that leaves R out"):
        study(BASE, [{"R": 1.0}, {"gamma": 0.2}], **SMALL, scheduler="serial")
    with pytest.raises(ParameterError, match=r"^nu = nan is outside"):
        path_study("sphere", {"nu": [0.3, float("nan")]}, "pressure", 0, 100, scheduler="serial")
    assert study_module.design(BASE, {"end2": ["auto", "clamped"]})[1] == {"end2": ["auto", "clamped"]}


def test_vary_ranges_include_the_stop():
    vary = parse_vary(["gamma=0.02:0.2:0.02", "nu=0.3,0.45,0.49", "material=svk,svk-plane-stress"])
    assert vary["gamma"] == pytest.approx(np.arange(1, 11) * 0.02) and vary["gamma"][2] == 0.06
    assert vary["nu"] == [0.3, 0.45, 0.49] and vary["material"] == ["svk", "svk-plane-stress"]


def test_vary_lists_may_hold_import_paths():
    """A law of one's own is named by its import path ``module:attr`` on the command line; the colon read as a
    range's (``--vary material = 'svk,my_laws:rubber' is outside START:STOP:STEP``)."""
    assert parse_vary(["material=svk,my_laws:rubber"])["material"] == ["svk", "my_laws:rubber"]
    assert parse_vary(["material=my_laws:rubber"])["material"] == ["my_laws:rubber"]
    with pytest.raises(ParameterError, match="START:STOP:STEP"):  # a range is still a range
        parse_vary(["gamma=0.02:0.2"])


def test_command_line(tmp_path, monkeypatch, capsys):
    from mol_shell.cli.main import main

    out = tmp_path / "u.nc"
    code = main(["study", "unshearable", "--vary", "omega=0,20", "--integrator", "ida", "--n", "8",
                     "--t-end", "0.005", "--scheduler", "serial", "-o", str(out)])
    assert code == 0 and "2 cases (2 complete)" in capsys.readouterr().out
    ds = mol_shell.read_netcdf(out)
    assert ds.lambda_chi.dims == ("omega", "time", "s_cell")
    assert float(abs(ds.lambda_chi.sel(omega=0.0)).max()) == 0.0 < float(abs(ds.lambda_chi.sel(omega=20.0)).max())
    assert float(ds.chi_s_max.max()) < 1e-12 and float(ds.psi_max.max()) == 0.0
    code = main(["study", "twisted-cylinder", "--vary", "colour=1,2", "--t-end", "0.001", "-o", str(tmp_path / "x.nc")])
    assert code == 2 and "vary = 'colour' is outside" in capsys.readouterr().err
    code = main(["study", "twisted-cylinder", "--vary", "nu=0.3,0.6", "--n", "8", "--t-end", "0.001",
                     "--scheduler", "serial", "-o", str(tmp_path / "f.nc")])
    captured = capsys.readouterr()
    assert code == 3 and "1 refused" in captured.out
    # the reason is named on stderr too (it was in the file's message only)
    assert captured.err.strip() == "mol-shell: error: 1 of 2 cases refused: nu = 0.6 is outside (-1, 0.5)"


def test_a_study_whose_every_case_is_refused_exits_2_naming_the_parameter(tmp_path, capsys):
    """Every case out of range is bad input, not a model limit: exit 2 (was 3, with nothing on stderr), one line
    with the count and the first reason; the file keeps every case's message."""
    from mol_shell.cli.main import main

    code = main(["study", "sphere", "--vary", "nu=0.7,0.8", "--n", "8", "--t-end", "0.001", "--scheduler", "serial",
                 "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and err == [("mol-shell: error: 2 of 2 cases refused: nu = 0.7 is outside (-1, 0.5); and "
                                  "nu = 0.8 is outside (-1, 0.5)")], err  # ("1 other reason: the file's message
    # variable" read as if the variable were the reason)
    code = main(["study", "sphere", "--vary", "nu=0.7,0.8,0.9", "--n", "8", "--t-end", "0.001", "--scheduler",
                 "serial", "-o", str(tmp_path / "s3.nc")])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and err == [("mol-shell: error: 3 of 3 cases refused: nu = 0.7 is outside (-1, 0.5); 2 other "
                                  "reasons in the file's variable message")], err
    ds = mol_shell.read_netcdf(tmp_path / "s.nc")
    assert list(ds.message.values) == ["nu = 0.7 is outside (-1, 0.5)", "nu = 0.8 is outside (-1, 0.5)"]


STUDY_BAD = [
    (["--vary", "gamma=0.1,0.2", "--vary", "gamma=0.3"], "--vary = 'gamma=0.3' varies gamma a second time"),
    (["--vary", "gamma=0.1,0.2", "--set", "gamma=0.3"], "--set = 'gamma=0.3' sets gamma, which --vary varies"),
    (["--vary", "gamma=0.1,0.2", "--workers", "0"], f"--workers = 0 is outside integers in [1, {scheduling.most_workers()}]"),
    (["--vary", "gamma=0.1,0.2", "--workers", "-3"], f"--workers = -3 is outside integers in [1, {scheduling.most_workers()}]"),
    (["--vary", "gamma=0.1,0.2", "--workers", "1000"], f"--workers = 1000 is outside integers in [1, {scheduling.most_workers()}]"),
    (["--vary", "gamma=0.1,0.2", "--rtol", "1e-6"], "rtol is not an option of leapfrog (its options: chunk, dt, restart)"),
    (["--vary", "gamma=0.1,0.2", "--integrator", "cvode-bdf", "--dt", "1e-6"], "dt is not an option of cvode-bdf"),
    (["--vary", "rtol=1e-6,1e-7"], "vary = 'rtol' is outside {"),
    (["--vary", "gamma=0.1:0.05:0.01"], "--vary gamma = '0.1:0.05:0.01' is outside START:STOP:STEP"),
    (["--vary", "gamma=0:0.1:0.03"], "--vary gamma = '0:0.1:0.03' does not end on its grid"),
    (["--vary", "gamma=1,,2"], "--vary = 'gamma=1,,2' has an empty entry"),
    (["--vary", "gamma=1,abc"], "gamma = 'abc' is not a number"),
    (["--vary", "gamma=0.1,0.2", "--scheduler", "garbage"], "scheduler = 'garbage' is not a scheduler address"),
    # varying the integrator said "--vary integrator = 'leapfrog' is not a number"
    (["--vary", "integrator=leapfrog,ida"], "vary = 'integrator' is outside {"),
    # NaN ran as a refused case and stood in the coordinate (gamma = abc was refused up front); inf likewise
    (["--vary", "gamma=nan,0.1"], "gamma = nan is outside finite values (rad/m)"),
    (["--vary", "gamma=0.1,inf"], "gamma = inf is outside finite values (rad/m)"),
    (["--vary", "dt=1e-6,nan"], "dt = nan is outside (0, inf) s"),
    # R = auto beside numbers: the coordinate held NaN (None in memory), the radius used was recorded nowhere
    (["--vary", "R=auto,1.0"], "R = 'auto' cannot be varied: a study's coordinate holds numbers; allowed: numbers"),
]


@pytest.mark.parametrize("values", ["h=0.01,0.02", "h=0.01:0.02:0.01"])
def test_a_grid_too_fine_for_one_case_is_blamed_on_n(values, tmp_path, capsys, monkeypatch):
    """It said "vary = '<2 cases>' is outside at most 0 cases", naming what the user had not got wrong (and a range
    gave a bound from the output alone, on 2 saved times)."""
    from mol_shell.cli.main import main

    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    code = main(["study", "sphere", "--vary", values, "--n", "100000000", "--t-end", "0.001", "-o",
                 str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: --n = 100000000 is outside integers 3.."), err
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize("extra,message", STUDY_BAD)
def test_command_line_refuses_bad_studies_up_front(extra, message, tmp_path, capsys, monkeypatch):
    from mol_shell.cli.main import main

    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    code = main(["study", "twisted-cylinder", *extra, "--t-end", "0.001", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: " + message), err
    assert len(err.splitlines()) == 1 and "--times" not in err
    assert not (tmp_path / "s.cases").exists() and not (tmp_path / "s.nc").exists()


@pytest.mark.parametrize("scheduler", [[], ["--scheduler", "serial"]])
def test_an_unusable_kernel_cache_is_refused_once_before_the_cases(scheduler, tmp_path, capsys, monkeypatch):
    """Each case refused it in turn (after about 1 s a case), and the study wrote a file of refused cases."""
    from mol_shell.cli.main import main

    (tmp_path / "a-file").write_text("")
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "a-file"))
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    code = main(["study", "twisted-cylinder", "--vary", "gamma=1e-3,2e-3", *scheduler, "--t-end", "0.001",
                 "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(f"mol-shell: error: MOL_SHELL_CACHE = '{tmp_path / 'a-file'}'"), err
    assert len(err.splitlines()) == 1 and "cases refused" not in err
    assert not (tmp_path / "s.cases").exists() and not (tmp_path / "s.nc").exists()


def test_unreachable_scheduler_is_refused_quickly(monkeypatch):
    import socket
    import time

    pytest.importorskip("distributed")
    from mol_shell._core.errors import ParameterError

    with socket.socket() as sock:  # a port nobody listens on
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    monkeypatch.setattr(scheduling, "SCHEDULER_TIMEOUT", 1.0)
    start = time.perf_counter()
    with pytest.raises(ParameterError, match=rf"^scheduler = 'tcp://127.0.0.1:{port}' does not answer within 1 s"):
        study(BASE, {"gamma": [0.1, 0.2]}, **SMALL, scheduler=f"tcp://127.0.0.1:{port}")
    assert time.perf_counter() - start < 30


def test_local_workers_fork_where_it_is_safe_unless_the_environment_asks_for_a_start_method(monkeypatch):
    """Unset, ``MOL_SHELL_START_METHOD`` leaves the choice to :func:`fork_is_safe` (fork, else spawn); set, it chooses
    how local workers start; ``fork`` is refused with kernels on more than one thread (OpenMP's pool is not safe
    across a fork), a method the platform lacks in one line, both up front."""
    monkeypatch.delenv(worker_start.START_VARIABLE, raising=False)
    monkeypatch.delenv("MOL_SHELL_THREADS", raising=False)
    for safe, method in ((True, "fork"), (False, "spawn")):
        monkeypatch.setattr(worker_start, "fork_is_safe", lambda blas_threads=None, safe=safe: safe)
        assert scheduling.start_method() == worker_start.start_method(0) == method
    monkeypatch.setenv(worker_start.START_VARIABLE, "forkserver")
    assert scheduling.start_method() == "forkserver"
    monkeypatch.setenv(worker_start.START_VARIABLE, "spawn")
    monkeypatch.setattr(worker_start, "fork_is_safe", lambda blas_threads=None: True)
    assert scheduling.start_method() == "spawn"
    monkeypatch.setenv(worker_start.START_VARIABLE, "fork")
    assert scheduling.start_method() == "fork"
    monkeypatch.setenv("MOL_SHELL_THREADS", "2")
    with pytest.raises(ParameterError, match=r"^MOL_SHELL_START_METHOD = 'fork' is outside \{spawn, forkserver\} .*"
                                             r"fork only with MOL_SHELL_THREADS = 1"):
        study(BASE, {"gamma": [0.1, 0.2]}, **SMALL, workers=2)
    monkeypatch.setenv(worker_start.START_VARIABLE, "threads")
    with pytest.raises(ParameterError, match=r"^MOL_SHELL_START_METHOD = 'threads' is outside \{.*spawn.*\} \(the "
                                             r"environment variable"):
        study(BASE, {"gamma": [0.1, 0.2]}, **SMALL, workers=2)
    study(BASE, {"gamma": [0.1]}, **SMALL, scheduler="serial")  # read for local processes only


def test_python_study_refuses_bad_workers_and_options():
    from mol_shell._core.errors import ParameterError

    for workers in (0, -3, 1.5, True, 1000):  # 1000: more processes than cores (30 on 2 ran 4.7x slower than 2)
        with pytest.raises(ParameterError, match="^workers = "):
            study(BASE, {"gamma": [0.1]}, **SMALL, workers=workers)
    with pytest.raises(ParameterError, match=r"^rtol is not an option of leapfrog"):
        study(BASE, {"gamma": [0.1]}, **SMALL, rtol=1e-6)


def test_coordinates_have_units_and_long_names():
    ds = study(BASE, {"gamma": [0.0, 0.05], "material": ["svk", "svk-plane-stress"]}, n=10, t_end=0.0005,
               scheduler="serial")
    assert ds.gamma.attrs == {"long_name": "initial twist chi_s (varied)", "units": "rad m-1"}
    assert ds.material.attrs["long_name"] == "material law (varied)"
    listed = study(BASE, [{"nu": 0.3}, {"h": 0.004}], n=10, t_end=0.0005, scheduler="serial")
    for name in ("nu", "h", "case"):
        assert listed[name].attrs.get("units") and listed[name].attrs.get("long_name"), name
    assert listed.h.attrs["units"] == "m"
    assert "max_damping_rate" in listed.attrs or "max_damping_rate" in listed  # renamed from max_damping_rate_s-1


def test_leapfrog_study_times_follow_simulate():
    """Without saved times a leap-frog study takes simulate's: on the step grid, ``t_end`` a multiple of ``dt``
    (refused otherwise, as simulate refuses it, instead of silently stopping at another time)."""
    with pytest.raises(ParameterError, match="t_end"):
        study(BASE, {"gamma": [0.0, 0.05]}, n=10, t_end=1.05e-5, scheduler="serial")
    ds = study(BASE, {"gamma": [0.0]}, n=10, t_end=1e-5, scheduler="serial")
    assert float(ds.time[-1]) == 1e-5 and ds.sizes["time"] == 11


@pytest.mark.parametrize("vary", [None, 3, "gamma", [1, 2], [{"gamma": 0.1}, "nu"]])
def test_vary_that_is_neither_a_dict_nor_a_list_of_dicts_is_refused_by_name(vary):
    """vary = None raised TypeError: 'NoneType' object is not iterable."""
    with pytest.raises(ParameterError, match="^vary = .* is not a dict or a list of dicts"):
        mol_shell.study("sphere", vary, n=5, t_end=1e-3)


def test_a_varied_leapfrog_step_gets_saved_times_on_every_cases_grid():
    """``vary={"dt": [1e-6, 1.6e-5]}`` with ``t_end`` alone: the saved times were snapped to the base dt's grid,
    and the case at 1.6e-5 s was refused ("times = 0.00012 is outside multiples of dt"), though a run at that dt
    takes the same t_end. They are now on the coarsest step's grid, which the finer one divides."""
    ds = mol_shell.study(mol_shell.TwistedCylinder(), {"dt": [1e-6, 1.6e-5]}, "leapfrog", n=10, t_end=0.0012,
                         scheduler="serial", progress=False)
    assert list(ds.status.values) == ["complete", "complete"]
    steps = ds.time.values / 1.6e-5
    assert np.allclose(steps, np.round(steps), rtol=0, atol=1e-9) and ds.time.values[-1] == 0.0012


def test_a_study_file_carries_a_run_files_cf_attributes():
    """A CF checker found the study's time without standard_name and axis, and no global history: the run's file
    has them (and the comment on the time without an epoch)."""
    ds = mol_shell.study(mol_shell.TwistedCylinder(), {"gamma": [0.05, 0.1]}, "leapfrog", n=8, t_end=1e-5,
                         scheduler="serial", progress=False)
    run = mol_shell.simulate(mol_shell.TwistedCylinder(gamma=0.05), n=8, t_end=1e-5, progress=False)
    assert ds.time.attrs == run.time.attrs
    assert ds.attrs["history"].endswith(f"created by mol_shell {mol_shell.__version__}")
    assert ds.attrs["Conventions"] == "CF-1.8" and ds.attrs["title"].startswith("mol_shell parameter study")


def test_python_outputs_not_ending_in_a_netcdf_suffix_are_refused_before_any_case(tmp_path, monkeypatch):
    """The command line refused ``-o s.txt``; Python's ``study(output="s.txt")`` wrote netCDF under that name (and its
    cases into ``s.cases/``), and ``write_netcdf`` wrote any name."""
    monkeypatch.setattr(study_module, "run_task", None)  # nothing may run
    with pytest.raises(ParameterError, match=r"output = .*s\.txt' ends in \.txt.*allowed: a file ending in one of "
                                             r"\.cdf, \.nc, \.nc4"):
        study("twisted-cylinder", {"gamma": [1.0, 2.0]}, **SMALL, scheduler="serial", output=tmp_path / "s.txt")
    with pytest.raises(ParameterError, match="output = .* has no suffix"):
        path_study("sphere", {"nu": [0.3]}, "pressure", 0, 100, output=tmp_path / "p")
    with pytest.raises(ParameterError, match=r"path = .*d\.png' ends in \.png"):
        mol_shell.write_netcdf(xr.Dataset(), tmp_path / "d.png")
    assert sorted(tmp_path.iterdir()) == []


def test_a_grid_too_large_for_memory_is_refused_in_words_for_runs_and_paths(tmp_path, capsys):
    """Checked as --vary is read, before the saved times or path steps are known: the bound is the smallest case
    (two states); it said "with 2 saved times" of a study of paths, which has none."""
    from mol_shell.cli.main import main

    assert main(["study", "sphere", "--vary", "h=0.001:0.01:1e-9", "--path", "pressure=0:1000",
                 "-o", str(tmp_path / "s.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("mol-shell: error: --vary h = '0.001:0.01:1e-9' is outside at most ") and \
        "cases at n = 40 with at least 2 states each (saved times or path steps)" in err, err


def test_a_varied_dt_that_t_end_is_no_multiple_of_refuses_its_case_not_the_study():
    """``{"dt": [1e-6, 3e-6]}`` with ``t_end = 0.01`` refused the whole study (the saved times were taken on the
    coarsest step's grid, 3e-6 s, of which 0.01 is no multiple), while ``{"dt": [1e-6, 1e-3]}`` refused only its
    second case. The times now come from the coarsest step t_end is a multiple of; a case whose step misses them
    is refused as data, and the study only when no step fits."""
    scene = mol_shell.TwistedCylinder(material="svk-plane-stress")
    ds = mol_shell.study(scene, {"dt": [1e-6, 3e-6]}, t_end=0.01, n=8, scheduler="serial", progress=False)
    assert ds.status.values.tolist() == ["complete", "refused"]
    assert "multiples of dt = 3e-06 s" in str(ds.message.values[1])
    assert float(ds.time.values[-1]) == 0.01
    with pytest.raises(mol_shell.ParameterError, match="multiples of dt"):
        mol_shell.study(scene, {"dt": [3e-6, 7e-6]}, t_end=0.01, n=8, scheduler="serial", progress=False)
    zero = mol_shell.study(scene, {"dt": [0.0, 1e-6]}, t_end=1e-3, n=8, scheduler="serial", progress=False)
    assert zero.status.values.tolist() == ["refused", "complete"]  # not a ZeroDivisionError


def test_a_studys_histories_are_in_the_normal_form_its_cases_store():
    """A varied history kept the string as typed (``'Ramp 0.0010'``) while each case's scene stored its normal form
    (``'ramp 0.001'``): the coordinate and the cases' attrs disagreed, and ``study_case`` refused the normal form."""
    scene = mol_shell.Sphere(pressure=100.0)
    st = mol_shell.study(scene, {"pressure_history": ["Ramp 0.0010", "ramp 0.002"]}, "leapfrog", n=7,
                         times=[0, 1e-4], scheduler="serial", progress=False)
    assert list(st["pressure_history"].values) == ["ramp 0.001", "ramp 0.002"]
    case = study_case(st, pressure_history="ramp 0.001")
    assert case.attrs["pressure_history"] == "ramp 0.001"
