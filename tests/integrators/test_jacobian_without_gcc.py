"""The ``jacobian`` option without a working gcc: its default follows what can be built (CasADi's virtual machine,
said in one line), a ``compiled`` given is refused naming ``jacobian``, and the SUNDIALS routes' fallback to
scikit-sundae's loop asks whether gcc works, not merely whether it is on PATH."""

import shutil

import numpy as np
import pytest
from fake_gcc import GCC_SAYS, install_failing_gcc

import mol_shell
from mol_shell.cli.main import main
from mol_shell.discretization import sundials_driver
from mol_shell.integrators import INTEGRATORS, sundials_c

try:
    from mol_shell.integrators import buildable
except ImportError:  # each test below fails on its own where the module is missing
    buildable = None

#: a shell of its own (no other test builds its graphs): a run without gcc leaves its right-hand side in CasADi's
#: virtual machine in the process's cache of built systems
SCENE = {"nu": 0.3, "E": 2.345e6}
LINE = ("mol-shell: {name} takes its Jacobian from CasADi's virtual machine (jacobian=vm): the compiled Jacobian "
        "cannot be built ({why})")


@pytest.fixture
def no_gcc(tmp_path, monkeypatch):
    """No gcc on PATH, an empty cache of kernels, the lines said once per process said again."""
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(buildable, "_SAID", set())
    return tmp_path


def _failing_gcc(tmp_path, monkeypatch):
    """A gcc on PATH that exits 1 with a compiler's last lines, and an empty cache of kernels."""
    install_failing_gcc(tmp_path, monkeypatch)
    monkeypatch.setattr(buildable, "_SAID", set())


@pytest.fixture
def failing_gcc(tmp_path, monkeypatch):
    _failing_gcc(tmp_path, monkeypatch)


@pytest.mark.parametrize("integrator", ["scipy-bdf", "sksundae-cvode-bdf"])
def test_without_gcc_the_default_jacobian_is_the_virtual_machines_said_in_one_line(no_gcc, capsys, integrator):
    """scipy-radau, scipy-bdf and the sksundae-* routes refused to run without gcc (their default, compiled, needed
    it: "--option jacobian=vm" had to be given). The default now follows what can be built: the run is the one with
    jacobian = 'vm' given (the same steps and states), the file records vm, and one line says why."""
    scene = mol_shell.TwistedCylinder(**SCENE)
    ds = mol_shell.simulate(scene, integrator, n=6, t_end=2e-4, stresses=False, progress=False)
    said = capsys.readouterr().err.splitlines()
    given = mol_shell.simulate(scene, integrator, n=6, t_end=2e-4, stresses=False, progress=False, jacobian="vm")
    assert said == [LINE.format(name=integrator, why="gcc not found on PATH")]
    assert capsys.readouterr().err == ""  # a value given is used as it is, without a word
    assert ds.attrs["complete"] == 1 and ds.attrs["jacobian"] == given.attrs["jacobian"] == "vm"
    assert ds.attrs["n_steps"] == given.attrs["n_steps"]
    np.testing.assert_array_equal(ds["r"].values, given["r"].values)


def test_without_gcc_a_jacobian_given_as_compiled_is_refused_naming_jacobian(no_gcc, capsys):
    """Given, jacobian = 'compiled' is kept: without gcc it cannot be built, and the line names jacobian (it named gcc
    and "functions ode_jacobian"), exit code 2."""
    sets = [arg for name, value in SCENE.items() for arg in ("--set", f"{name}={value}")]
    code = main(["run", "twisted-cylinder", *sets, "--n", "6", "--t-end", "2e-4", "--integrator", "scipy-radau",
                 "--option", "jacobian=compiled", "--no-stresses", "-o", str(no_gcc / "run.nc")])
    assert code == 2
    assert capsys.readouterr().err.splitlines() == [
        ("mol-shell: error: jacobian = 'compiled' cannot be built: gcc not found on PATH; allowed: 'vm' (CasADi's "
         "virtual machine) where gcc cannot build the Jacobian")]
    assert not (no_gcc / "run.nc").exists()


def test_a_failing_gcc_gives_the_default_jacobian_and_the_sundials_fallback_the_virtual_machine(failing_gcc):
    """A gcc on PATH that fails: the default jacobian is the VM's (the gcc's last lines the reason), and cvode-bdf's
    and ida's fallback to scikit-sundae's loop took jacobian = 'compiled' because gcc was on PATH, then failed
    building it (one fallback line, then an error)."""
    assert INTEGRATORS["scipy-radau"]().settings()["jacobian"] == "vm"
    assert INTEGRATORS["sksundae-ida"]().jacobian_used() == "vm"
    for name in ("cvode-bdf", "cvode-adams", "ida"):
        assert INTEGRATORS[name]().python_route().jacobian == "vm", name
    assert INTEGRATORS["cvode-bdf"](jacobian="compiled").python_route().jacobian == "compiled"  # given: kept
    assert buildable.resolve_jacobian("x", "compiled") == "compiled"  # a word given


@pytest.mark.skipif(shutil.which("gcc") is None, reason="the right-hand side is built with gcc first")
def test_a_failing_gcc_with_the_right_hand_side_built_runs_cvode_bdf_on_scikit_sundaes_loop(tmp_path, monkeypatch,
                                                                                              capsys):
    """The right-hand side built (kept by this process) and a gcc on PATH that fails since: cvode-bdf said that its
    driver is unavailable, with gcc's lines, then ended in an error building the compiled Jacobian its fallback chose
    (gcc was on PATH). It now runs scikit-sundae's loop with the VM's Jacobian: that one line, and the run is the
    sksundae-cvode-bdf run with jacobian = 'vm' given, step for step. The driver, not in the cache, is not built with a
    gcc that fails the probe build: the probe's failure, with gcc's lines, is the reason."""
    scene = mol_shell.TwistedCylinder(nu=0.3)
    mol_shell.simulate(scene, "rk45-c", n=8, t_end=1e-5, stresses=False, progress=False)  # the RHS, with gcc
    _failing_gcc(tmp_path, monkeypatch)
    monkeypatch.setattr(sundials_c, "_REPORTED", set())
    sundials_driver._load.cache_clear()  # a driver an earlier test loaded
    try:
        ds = mol_shell.simulate(scene, "cvode-bdf", n=8, t_end=1e-4, stresses=False, progress=False)
    finally:
        sundials_driver._load.cache_clear()
    assert capsys.readouterr().err.splitlines() == [
        ("mol-shell: cvode-bdf runs scikit-sundae's Python loop: the compiled SUNDIALS driver is unavailable (gcc "
         f"failed building a probe library (exit status 1): {GCC_SAYS})")]
    given = mol_shell.simulate(scene, "sksundae-cvode-bdf", n=8, t_end=1e-4, stresses=False, progress=False,
                               jacobian="vm")
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] == given.attrs["n_steps"]
    np.testing.assert_array_equal(ds["r"].values, given["r"].values)


@pytest.mark.skipif(shutil.which("gcc") is None, reason="the right-hand side and the driver are built with gcc first")
def test_a_failing_gcc_and_a_loaded_driver_run_ida_on_scikit_sundaes_loop(tmp_path, monkeypatch, capsys):
    """The SUNDIALS driver loaded and the right-hand side built, then a gcc that fails on IDA's residual: the run
    ended in gcc's error (the residual, which only evaluates, refused to run in the VM). It now takes scikit-sundae's
    loop, the reason its one line, and is the sksundae-ida run with jacobian = 'vm', step for step."""
    scene = mol_shell.TwistedCylinder(nu=0.3)
    mol_shell.simulate(scene, "rk45-c", n=8, t_end=1e-5, stresses=False, progress=False)  # the RHS, with gcc
    sundials_driver.driver()  # loaded (built with gcc where it was not cached)
    _failing_gcc(tmp_path, monkeypatch)
    monkeypatch.setattr(sundials_c, "_REPORTED", set())
    ds = mol_shell.simulate(scene, "ida", n=8, t_end=1e-4, stresses=False, progress=False)
    assert capsys.readouterr().err.splitlines() == [
        ("mol-shell: ida runs scikit-sundae's Python loop: the compiled SUNDIALS driver is unavailable (gcc failed "
         f"building functions dae_residual (exit status 1): {GCC_SAYS})")]
    given = mol_shell.simulate(scene, "sksundae-ida", n=8, t_end=1e-4, stresses=False, progress=False, jacobian="vm")
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] == given.attrs["n_steps"]
    np.testing.assert_array_equal(ds["r"].values, given["r"].values)
