"""``cvode-bdf``, ``cvode-adams`` and ``ida`` with the loop in compiled C, against scikit-sundae's Python loop.

With the same settings (Newton iterations on the same compiled exact Jacobian) both routes call the same SUNDIALS
build with the same numbers, so they take the same steps: the step counts are equal and the states agree to
round-off. The defaults of the compiled route (difference-quotient Jacobians, fixed-point iterations for Adams)
give other step sequences, held to the tolerance. Their accuracy against the reference, the model's limits and
the constraints are tested with the other integrators (test_integrators, test_limits, test_constraints), whose
tests run these routes under their names unchanged.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis import workprecision as wp
from mol_shell.discretization import sundials_driver as drv
from mol_shell.discretization.compiled import compile_cached
from mol_shell.discretization.sundials_source import SUNDIALS_DRIVER
from mol_shell.integrators import INTEGRATORS, loop, sundials_c
from mol_shell.results.dataset import read_netcdf
from mol_shell.runs.simulate import build, resolve
from child_process import sigint_default, wait_until_busy

TIMES = [0.0, 0.005, 0.01, 0.015, 0.02]


@pytest.fixture(scope="module")
def paper():
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    return system, compiled, system.initial_state(scene)


@pytest.mark.parametrize("name", ["cvode-bdf", "cvode-adams", "ida"])
def test_same_settings_take_the_same_steps_as_scikit_sundae(paper, name):
    system, compiled, y0 = paper
    settings = {"rtol": 1e-7, "atol": 1e-10, "jacobian": "compiled"}
    ours = INTEGRATORS[name](**settings, **({"iteration": "newton"} if name != "ida" else {}))
    theirs = INTEGRATORS["sksundae-" + name](**settings)
    a, b = (m.integrate(system, compiled, y0, TIMES) for m in (ours, theirs))
    assert a.status == b.status == "complete"
    assert a.stats["route"] == "compiled C" and b.stats["route"] == "scikit-sundae"
    for key in ("n_steps", "n_rhs", "n_jac"):
        assert a.stats[key] == b.stats[key], key
    assert np.max(np.abs(a.y - b.y)) < 1e-12 * np.abs(b.y).max()


@pytest.mark.parametrize("name, options", [("cvode-bdf", {}), ("cvode-adams", {}), ("ida", {}),
                                           ("cvode-bdf", {"jacobian": "vm", "linsolver": "dense"}),
                                           ("cvode-adams", {"iteration": "newton", "anderson": 0, "jac_every": 10}),
                                           ("ida", {"linsolver": "lapack-band", "cj_ratio": 0.5, "max_newton": 6})])
def test_defaults_and_options_agree_with_scikit_sundae_to_the_tolerance(paper, name, options):
    system, compiled, y0 = paper
    rtol = 1e-8
    ours = INTEGRATORS[name](rtol=rtol, atol=1e-3 * rtol, **options).integrate(system, compiled, y0, TIMES)
    theirs = INTEGRATORS["sksundae-" + name](rtol=rtol, atol=1e-3 * rtol).integrate(system, compiled, y0, TIMES)
    assert ours.status == "complete", ours.message
    # the package's error measure (largest over r, theta, chi of max |u - v| / max |v|): each within 10 rtol of the
    # reference (test_integrators), so within 20 rtol of each other
    assert wp.relative_error(wp.fields_of(system, ours.y), wp.fields_of(system, theirs.y)) < 20 * rtol


def test_each_route_takes_exactly_its_own_options():
    adams, bdf, ida = (set(loop.declared(INTEGRATORS[n])) for n in ("cvode-adams", "cvode-bdf", "ida"))
    assert {"jac_every", "setup_every", "iteration", "anderson", "max_newton", "linsolver"} <= bdf == adams
    assert "cj_ratio" in ida and not {"jac_every", "iteration"} & ida and "cj_ratio" not in bdf
    assert not {"jac_every", "iteration", "cj_ratio"} & set(loop.declared(INTEGRATORS["sksundae-cvode-bdf"]))
    for name, bad in (("cvode-bdf", {"jac_every": -1}), ("cvode-adams", {"iteration": "picard"}),
                      ("ida", {"cj_ratio": 1.5}), ("cvode-bdf", {"max_newton": 0}),
                      ("cvode-bdf", {"linsolver": "klu"}), ("ida", {"anderson": 2})):
        with pytest.raises((ParameterError, TypeError), match=next(iter(bad))):
            INTEGRATORS[name](**bad)
    with pytest.raises(ParameterError, match="jacobian"):
        INTEGRATORS["cvode-bdf"](jacobian="dq", linsolver="sparse")
    with pytest.raises((TypeError, ParameterError), match="linsolver"):
        INTEGRATORS["dop853-c"](linsolver="band")
    # BDF's orders end at 5 (SUNDIALS' CV_BDF and IDA), Adams' at 12: 6..12 passed the check and the driver
    # failed at its set-up ("could not set up the solver (stage 5)", a RuntimeError)
    for name in ("cvode-bdf", "ida", "sksundae-cvode-bdf", "sksundae-ida"):
        with pytest.raises(ParameterError, match=r"^max_order = 6 is outside integers in \[1, 5\]"):
            INTEGRATORS[name](max_order=6)
    assert INTEGRATORS["cvode-adams"](max_order=12).max_order == 12
    # Newton's options with a fixed-point iteration (cvode-adams' default) were kept in the file and did nothing
    # (and the Newton matrix's Jacobian and linear solver, which it did not use either)
    for name, value in (("jac_every", 200), ("setup_every", 5), ("max_newton", 4), ("newton_coef", 0.2),
                        ("jacobian", "compiled"), ("linsolver", "band")):
        with pytest.raises(ParameterError, match=rf"^{name} = {value!r} is an option of Newton's iteration, which "
                           "cvode-adams runs only with iteration = 'newton'"):
            INTEGRATORS["cvode-adams"](**{name: value})
        assert getattr(INTEGRATORS["cvode-adams"](iteration="newton", **{name: value}), name) == value
        assert getattr(INTEGRATORS["cvode-bdf"](**{name: value}), name) == value



def test_anderson_is_refused_with_newton_by_name_as_newtons_options_are_with_a_fixed_point():
    """Anderson acceleration belongs to CVODE's fixed-point iteration (SUNDIALS' SUNNonlinSol_FixedPoint): with
    Newton's (cvode-bdf's default) ``anderson = 5`` ran and was kept in the file beside iteration = 'newton'."""
    for name, options, how in (("cvode-bdf", {}, "the default"), ("cvode-adams", {"iteration": "newton"}, "as set")):
        with pytest.raises(ParameterError, match=r"^anderson = 5 is an option of the fixed-point iteration, which "
                           rf"{name} runs only with iteration = 'fixed-point' \(its iteration here is 'newton', "
                           rf"{how}\)$") as info:
            INTEGRATORS[name](anderson=5, **options)
        assert info.value.name == "anderson" and "\n" not in str(info.value)
        assert INTEGRATORS[name](anderson=0, **options).anderson == 0  # its default: nothing to refuse
    for name, options in (("cvode-bdf", {"iteration": "fixed-point"}), ("cvode-adams", {})):
        assert INTEGRATORS[name](anderson=5, **options).anderson == 5  # a fixed-point iteration takes it


def test_a_refusal_calls_the_iteration_the_default_only_when_it_is():
    """cvode-bdf's default iteration is Newton's: a fixed-point one asked for was called "the default"."""
    for name, options, how in (("cvode-bdf", {"iteration": "fixed-point"}, "as set"), ("cvode-adams", {}, "the default"),
                               ("cvode-adams", {"iteration": "fixed-point"}, "the default")):
        with pytest.raises(ParameterError, match=rf"\(its iteration here is 'fixed-point', {how}\)$"):
            INTEGRATORS[name](jac_every=10, **options)


@pytest.mark.parametrize("given, used", [({"setup_every": 100, "jac_every": 10}, (10, 10)),
                                         ({"setup_every": 5, "jac_every": 10}, (10, 5)),
                                         ({"setup_every": 0, "jac_every": 10}, (10, 10)),  # SUNDIALS' 20, held at 10
                                         ({"setup_every": 100}, (0, 51)),  # jac_every 0: SUNDIALS' 51
                                         ({"jac_every": 200}, (200, 20)),  # setup_every 0: SUNDIALS' 20
                                         ({}, (0, 0))])  # both SUNDIALS' own (51, 20)
def test_setup_every_is_recorded_as_used_at_most_jac_every(given, used):
    """CVODE evaluates a Jacobian only at a set-up, so a set-up every 100 steps with a Jacobian every 10 sets up
    every 10 (docs/integrators.md: held at most jac_every; 0 stands for SUNDIALS' 51 and 20): the run used 10 and
    its file said setup_every=100. The option holds the count the driver is given, and the file records it."""
    method = INTEGRATORS["cvode-bdf"](**given)
    assert (method.jac_every, method.setup_every) == used
    assert method.newton_settings()[2:4] == used
    assert INTEGRATORS["cvode-bdf"](jac_every=used[0], setup_every=used[1]).newton_settings() == method.newton_settings()


def test_the_file_records_the_setup_every_used(tmp_path):
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-bdf", n=11, times=[0.0, 1e-4], setup_every=100,
                            jac_every=10, progress=False, stresses=False)
    assert (ds.attrs["setup_every"], ds.attrs["jac_every"]) == (10, 10)
    path = tmp_path / "run.nc"
    ds.to_netcdf(path)
    assert read_netcdf(path).attrs["setup_every"] == 10

def test_a_driver_that_cannot_be_had_falls_back_with_one_line(paper, monkeypatch, tmp_path, capsys):
    system, compiled, y0 = paper
    monkeypatch.setattr(drv, "library_folder", lambda: tmp_path)  # no libraries there (the variable's: refused)
    monkeypatch.setattr(sundials_c, "_REPORTED", set())
    with pytest.raises(drv.DriverUnavailable, match="libsundials_core not found"):
        drv.driver()
    runs = [INTEGRATORS[n](rtol=1e-6).integrate(system, compiled, y0, TIMES[:2]) for n in ("cvode-bdf", "ida", "ida")]
    assert all(r.status == "complete" and r.stats["route"] == "scikit-sundae" for r in runs)
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "scikit-sundae's Python loop" in lines[0] and "libsundials_core not found" in lines[0]


def test_gcc_missing_is_said_in_one_line(tmp_path, monkeypatch):
    """No gcc and the driver not in the cache (a cached one is loaded without gcc:
    tests/integrators/test_cached_kernels_without_gcc.py)."""
    monkeypatch.setenv("PATH", "/nonexistent")
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    with pytest.raises(drv.DriverUnavailable, match="^gcc not found on PATH$"):
        drv._load.__wrapped__(str(drv.library_folder()))  # past the in-process cache


_BUILD = "from mol_shell.discretization import sundials_driver as d; d.driver(); print('ok')"


@pytest.mark.slow
def test_two_processes_build_the_driver_once(tmp_path):
    """Two processes that need the driver at once in an empty cache: one compiles, the other waits on the lock."""
    env = dict(os.environ, MOL_SHELL_CACHE=str(tmp_path), PYTHONPATH=str(Path(__file__).parents[2]))
    procs = [subprocess.Popen([sys.executable, "-c", _BUILD], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for _ in range(2)]
    outs = [p.communicate(timeout=120) for p in procs]
    assert [o[0].strip() for o in outs] == ["ok", "ok"], outs
    builds = (tmp_path / "builds.log").read_text().splitlines()
    assert len([b for b in builds if b.startswith("sundials_")]) == 1, builds
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".sundials_") and p.is_dir()]  # no leftovers


def test_a_damaged_cached_driver_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    folder = str(drv.library_folder())
    lib = compile_cached(SUNDIALS_DRIVER, "sundials", drv.FLAGS, link=drv.link_arguments(folder))  # built, not loaded
    lib.write_bytes(b"not a library")
    assert drv._load.__wrapped__(folder).ms_check_index() == 0  # past the in-process cache
    assert len((tmp_path / "builds.log").read_text().splitlines()) == 2


@pytest.mark.slow
def test_ctrl_c_in_the_compiled_loop_keeps_the_data_and_exits_130(tmp_path):
    """SIGINT while cvode-bdf steps in C (n = 40 to 60 s: tens of processor seconds of stepping, far past the wait
    below): the saved times reached are written, marked interrupted, and the exit code is 130; the C loop returns
    within its 0.2 s chunk. n = 40 is the module's ``paper`` fixture's: its right-hand side is in the cache already
    (n = 160 compiled kernels of its own, several seconds of gcc each on a cold cache, for nothing this test reads)."""
    out = tmp_path / "x.nc"
    # the right-hand side and the driver compiled here first (on a cold cache gcc alone can take longer than the wait
    # below on a loaded machine), so that the signal finds the run stepping
    build(resolve(mol_shell.TwistedCylinder()), 40)
    drv.driver()
    proc = subprocess.Popen([sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--integrator", "cvode-bdf",
                             "--n", "40", "--t-end", "60", "--times", "0:60:0.01", "-o", str(out)],
                            stderr=subprocess.PIPE, text=True, preexec_fn=sigint_default)
    # past start-up and set-up (under 3.8 s of its own processor time, measured, the kernels loaded from the cache)
    # and well into the stepping
    assert wait_until_busy(proc, 5.5), proc.stderr.read()
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert time.perf_counter() - sent < 20  # the chunk, then writing the file
    assert "interrupted by the user" in err
    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and ds.attrs["complete"] == 0
    assert ds.sizes["time"] >= 2 and np.isfinite(ds.r.values).all()


def test_the_cost_of_each_part_is_measured(paper):
    """What the benchmark's overhead decomposition reads: a positive cost per call of each part."""
    system, compiled, y0 = paper
    method = INTEGRATORS["cvode-bdf"](rtol=1e-6, jacobian="compiled")
    method.parts(system)
    stepper = method.start(system, compiled, y0, [0.0, 0.002], None)
    while stepper.t < 0.002:
        stepper.advance(0.002)
    costs = stepper.solve.costs(5)
    assert all(0 < v < 0.1 for v in costs.values()), costs
    assert stepper.stats()["n_setups"] >= stepper.stats()["n_jac"] >= 1


@pytest.mark.parametrize("name", ["cvode-bdf", "ida"])
def test_a_limit_stops_at_the_time_and_place_of_scikit_sundaes_route(name):
    """The fold of test_limits (psi0 = 1.5: cos(psi) touches 0 near 4.9 ms): the root found on both routes."""
    scene = mol_shell.TwistedCylinder(psi0=1.5)
    times = [0.0, 0.002, 0.004, 0.006]
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ours, theirs = (mol_shell.simulate(scene, n, times=times, rtol=1e-9, atol=1e-12, progress=False)
                        for n in (name, "sksundae-" + name))
    assert ours.attrs["status"] == theirs.attrs["status"] == "limit"
    assert ours.attrs["failure_time"] == pytest.approx(theirs.attrs["failure_time"], abs=1e-7)
    place = [ds.attrs["message"].split(" at t = ")[1].split(", ")[1].split(":")[0] for ds in (ours, theirs)]
    assert place[0] == place[1] and "root found by" in ours.attrs["message"]


@pytest.mark.parametrize("integrator", ["cvode-bdf", "ida", "sksundae-cvode-adams"])
@pytest.mark.parametrize("atol", [1.0, {"r": 1.0}])
def test_an_atol_of_r_above_the_radius_is_refused_not_a_model_limit(integrator, atol):
    """``--atol 1`` on a shell of radius 0.995 m stopped at t = 3e-9 s as "r reached 0 (to within atol)": the
    SUNDIALS routes watch r -> 0 at r = atol_r. Refused naming atol and the bound (the smallest radius); an atol of
    the other fields that large, or 0.5, runs."""
    import mol_shell

    scene = mol_shell.TwistedCylinder()
    with pytest.raises(ParameterError, match=r"^atol = .* is outside absolute tolerances of r below 0\.9948 m"):
        mol_shell.simulate(scene, integrator, n=8, t_end=1e-4, atol=atol, progress=False)
    ds = mol_shell.simulate(scene, integrator, n=8, t_end=1e-4, atol={"z": 1.0, "r": 0.5}, progress=False)
    assert ds.attrs["complete"] == 1


@pytest.mark.parametrize("integrator", ["cvode-bdf", "dop853-c", "scipy-rk45"])
def test_a_max_step_that_max_steps_cannot_carry_to_t_end_is_refused_up_front(integrator):
    """``--max-step 1e-12`` to 1 ms ran until its step budget said "the motion is too fast for this horizon", exit 3:
    a million steps of 1e-12 s reach 1e-6 s. Refused before the build, naming max_step and its least value
    (1e-3 s / (0.99e6 - 10): one more step per saved interval, 1 % of max_steps for the start)."""
    import mol_shell

    with pytest.raises(ParameterError, match=r"^max_step = 1e-12 is outside \[1\.011e-09, inf\) s, or 0 \(unbounded\)"):
        mol_shell.simulate(mol_shell.TwistedCylinder(), integrator, n=8, t_end=1e-3, max_step=1e-12, progress=False)
