"""``$MOL_SHELL_OPT_LEVEL``: gcc's level for the right-hand sides and stencils, and why the suite may build at -O1.

Without ``-ffast-math`` and with ``-ffp-contract=off``, gcc's levels may reorder loads and stores and vectorise
independent lanes, but never reassociate a floating-point sum or fuse a multiply-add: a kernel built at -O1 computes
the same operations in the same order as at -O3. These tests hold that to the last bit on kernels with every kind of
arithmetic the laws use (square roots, logarithms, powers, trigonometry, the viscous and fibre terms, OpenMP maps, the
vectorised stencil), so the test suite, which builds at -Os to halve gcc's time (tests/conftest.py), tests the
numbers a default (-O3) build gives.
"""

import subprocess
import sys

import numpy as np
import pytest
from test_performance_paths import disturbed

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.discretization import kernel_cache
from mol_shell.discretization.compiled import CFLAGS, CompiledRHS
from mol_shell.discretization.stencil import StencilLeapfrog
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.simulate import resolve
from mol_shell.scenes import Sphere, TwistedCylinder


def test_unset_is_o3_and_each_level_replaces_only_o3(monkeypatch):
    monkeypatch.delenv(kernel_cache.OPT_VARIABLE, raising=False)
    assert kernel_cache.optimised(CFLAGS) == CFLAGS and "-O3" in CFLAGS
    for level in "123s":
        monkeypatch.setenv(kernel_cache.OPT_VARIABLE, f" {level} ")
        flags = kernel_cache.optimised(CFLAGS)
        assert flags[0] == f"-O{level}" and flags[1:] == CFLAGS[1:]
        jacobian_flags = ("-O1", "-fPIC", "-shared")  # flags without -O3 (the Jacobians, the SUNDIALS driver) stay
        assert kernel_cache.optimised(jacobian_flags) == jacobian_flags


@pytest.mark.parametrize("value", ["0", "4", "-O3", "fast", "1.0", "S", "z"])
def test_another_value_is_refused_naming_the_variable(monkeypatch, value):
    monkeypatch.setenv(kernel_cache.OPT_VARIABLE, value)
    with pytest.raises(ParameterError, match=r"MOL_SHELL_OPT_LEVEL = .* is not 1, 2, 3 or s; allowed: 1, 2, 3 or s"):
        kernel_cache.optimised(CFLAGS)


def test_the_command_line_refuses_it_in_one_line_with_exit_2(tmp_path):
    env = {"MOL_SHELL_OPT_LEVEL": "9", "MOL_SHELL_CACHE": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin"}
    out = subprocess.run([sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--n", "8", "--t-end", "1e-4",
                          "-o", str(tmp_path / "x.nc")], capture_output=True, text=True, env=env, cwd=tmp_path, check=False)
    assert out.returncode == 2, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "MOL_SHELL_OPT_LEVEL = '9'" in lines[0], out.stderr
    assert not (tmp_path / "x.nc").exists()


def _at(monkeypatch, level, make):
    monkeypatch.setenv(kernel_cache.OPT_VARIABLE, level)
    return make()


@pytest.mark.parametrize("scene", [
    TwistedCylinder(),
    Sphere(gamma=0.05, R=1.01, material="neo-hookean", nu=0.3, eta_lambda=30.0, eta_mu=20.0, pressure=1e4,
           fibre_E=5e9, fibre_angle=0.5, gravity=9.81),
], ids=["paper", "viscous-fibre-reinforced-neo-hookean-sphere"])
def test_a_right_hand_side_at_o1_or_os_gives_the_bits_of_o3(monkeypatch, scene):
    scene = resolve(scene)
    system = ShellSystem(scene, 16)  # the paper scene's n = 16 kernel is the whole run's below: built once
    y = disturbed(system, scene)
    out = {}
    for level in ("1", "s", "3"):
        serial = _at(monkeypatch, level, lambda: CompiledRHS(system.rhs_mapped, system.limits))
        out[level + "path"] = serial.path
        out[level] = serial.evaluator()(y, 0.002).copy()
        ya, yb = system.initial_state(scene), y.copy()
        assert serial.leapfrog(ya, yb, 200, 1e-7) == (200, False)
        out[level + "lf"] = yb.copy()
    assert out["1path"] != out["3path"]  # two libraries: the level is part of the cache key
    assert np.all(np.isfinite(out["3"])) and np.max(np.abs(out["3"])) > 0
    for level in ("1", "s"):
        np.testing.assert_array_equal(out[level], out["3"])
        np.testing.assert_array_equal(out[level + "lf"], out["3lf"])


def test_openmp_maps_and_the_stencil_at_os_give_the_bits_of_o3(monkeypatch):
    """The grids of test_performance_paths' parallel RHS (n = 64) and test_stencil's (n = 41): their -Os kernels are
    shared with those tests in the suite's cache."""
    scene = resolve(TwistedCylinder())
    wide, narrow = ShellSystem(scene, 64), ShellSystem(scene, 41)
    y, y41 = disturbed(wide, scene), disturbed(narrow, scene, 1e-4)
    rhs, states = {}, {}
    for level in ("s", "3"):
        parallel = _at(monkeypatch, level, lambda: CompiledRHS(wide.rhs_parallel, wide.limits, threads=2))
        assert parallel.parallel
        rhs[level] = parallel.evaluator()(y, 0.002).copy()
        stencil = _at(monkeypatch, level, lambda: StencilLeapfrog(narrow, threads=1))
        ya, yb = narrow.initial_state(scene), y41.copy()
        assert stencil.leapfrog(ya, yb, 300, 1e-7)[0] == 300
        states[level] = yb.copy()
    assert np.max(np.abs(states["3"] - y41)) > 0  # the state moved
    np.testing.assert_array_equal(rhs["s"], rhs["3"])
    np.testing.assert_array_equal(states["s"], states["3"])


def test_a_whole_run_at_either_level_is_the_same_file_of_numbers(monkeypatch, tmp_path):
    """Through the public API: the paper's scene with the compiled Runge-Kutta pair (its C driver beside the RHS)."""
    runs = {}
    for level in ("s", "3"):
        monkeypatch.setenv(kernel_cache.OPT_VARIABLE, level)
        for integrator in ("dop853-c",):  # the leap-frog's loop: above
            ds = mol_shell.simulate(TwistedCylinder(), times=[0.0, 0.002], n=16, integrator=integrator)
            runs[level, integrator] = ds
    for integrator in ("dop853-c",):
        a, b = runs["s", integrator], runs["3", integrator]
        for name in ("r", "z", "chi", "theta", "psi", "energy", "principal_stress_max"):
            np.testing.assert_array_equal(a[name].values, b[name].values)


def test_a_study_refuses_it_before_any_case_and_writes_nothing(monkeypatch, tmp_path):
    """Each case refused it, after the study had written its file and its .cases folder (exit 2 with two lines)."""
    monkeypatch.setenv(kernel_cache.OPT_VARIABLE, "9")
    with pytest.raises(ParameterError, match="MOL_SHELL_OPT_LEVEL"):
        mol_shell.study("sphere", {"nu": [0.2, 0.3]}, n=8, t_end=1e-5, output=tmp_path / "s.nc", progress=False)
    assert list(tmp_path.iterdir()) == []
    env = {"MOL_SHELL_OPT_LEVEL": "9", "MOL_SHELL_CACHE": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin"}
    out = subprocess.run([sys.executable, "-m", "mol_shell", "study", "sphere", "--vary", "nu=0.2,0.3", "--n", "8",
                          "--t-end", "1e-5", "-o", "s.nc"], capture_output=True, text=True, env=env, cwd=tmp_path, check=False)
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "MOL_SHELL_OPT_LEVEL = '9'" in out.stderr
    assert not (tmp_path / "s.nc").exists() and not (tmp_path / "s.cases").exists()
