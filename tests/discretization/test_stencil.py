"""The vectorised leap-frog stencil (mol_shell.stencil) against the generic driver around the compiled RHS.

Both evaluate the same kernels' instructions in the same order with IEEE arithmetic (no fused multiply-adds),
so the two drivers must give the same states to the last bit, on any thread count, and stop at the same step
when a limit of the model is reached.
"""

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.discretization.compiled import CompiledRHS
from mol_shell.discretization.system import ShellSystem
from mol_shell.scenes import Cone, Sphere, Torus, TwistedCylinder
from mol_shell.runs.simulate import build, resolve
from mol_shell.discretization.stencil import StencilLeapfrog, Unsupported, leapfrog_stepper, sx_statements, unsupported_reason

from test_performance_paths import disturbed, ellipse_points


def both(system, scene, steps, dt, amplitude, threads=1):
    """The pair after ``steps`` steps from a disturbed state, by the generic driver and by the stencil."""
    compiled = CompiledRHS(system.rhs_mapped, system.limits)
    fixed = np.repeat(system.fixed, 2, axis=1).ravel()  # imposed fields and their momenta stay as they are
    y0 = np.where(fixed, system.initial_state(scene), disturbed(system, scene, amplitude))
    start = y0, y0 + dt * compiled.evaluator()(y0, 0.0)
    out = []
    for driver in (compiled, StencilLeapfrog(system, threads=threads)):
        ya, yb = (a.copy() for a in start)
        out.append((driver.leapfrog(ya, yb, steps, dt, dt), ya, yb))
    return out, start


@pytest.mark.parametrize("name", ["paper", "cone", "torus-free", "curved-points"])
def test_stencil_equals_the_generic_driver_to_the_last_bit(name, tmp_path):
    """Uniform and per-cell geometry, node inertias with ``rhoI != 0`` (cone, torus), free and magnet edges."""
    scene = resolve({"paper": TwistedCylinder(), "cone": Cone(gamma=0.05, dilation=1.01),
                     "torus-free": Torus(end1="free", end2="free", dilation=1.01),
                     "curved-points": mol_shell.scenes.MeridianShell(points=ellipse_points(tmp_path / "e.txt"),
                                                                     dilation=1.01)}[name])
    system = ShellSystem(scene, 41)
    assert unsupported_reason(system) is None
    (generic, stencil), start = both(system, scene, 400, 2e-7, 1e-4)
    assert generic[0] == stencil[0] == (400, False)
    assert np.max(np.abs(generic[2] - start[1])) > 1e-6  # the state moved
    np.testing.assert_array_equal(generic[1], stencil[1])
    np.testing.assert_array_equal(generic[2], stencil[2])


def test_stencil_threads_give_identical_states():
    """Blocks of nodes shared among 1 or 2 threads (n = 600: padding, blocks of eight and the threaded regime)."""
    scene = resolve(TwistedCylinder())
    system = ShellSystem(scene, 600)
    (generic, one), start = both(system, scene, 50, 1e-7, 1e-6, threads=1)
    (_, two), _ = both(system, scene, 50, 1e-7, 1e-6, threads=2)
    np.testing.assert_array_equal(one[2], two[2])
    np.testing.assert_array_equal(one[2], generic[2])


def test_stencil_stops_at_the_generic_drivers_step():
    """The fold of tests/test_limits.py (psi0 = 1.5 rad, crossed ~4,900 steps after the start): the stencil
    reports the same step, leaves the same pair, and a chunk that ends on that step says it stopped."""
    scene = resolve(TwistedCylinder(psi0=1.5))
    system, compiled = build(scene, 40)
    stencil = StencilLeapfrog(system, threads=1)
    y0 = system.initial_state(scene)
    f = compiled.evaluator()
    start = y0.copy(), y0 + 1e-6 * np.array(f(y0 + 0.5e-6 * np.array(f(y0))))
    results = []
    for driver in (compiled, stencil):
        ya, yb = (a.copy() for a in start)
        results.append((driver.leapfrog(ya, yb, 8000, 1e-6), ya, yb))
    (taken, stopped), ya, yb = results[1]
    assert stopped and 4000 < taken < 6000
    assert results[0][0] == (taken, True)
    np.testing.assert_array_equal(results[0][2], yb)
    np.testing.assert_array_equal(results[0][1], ya)
    for chunk, expected in ((taken, True), (taken - 1, False)):
        ya, yb = (a.copy() for a in start)
        assert stencil.leapfrog(ya, yb, chunk, 1e-6) == (chunk, expected)


def test_leapfrog_runs_on_the_stencil_only_where_it_covers_the_scene():
    covered = build(resolve(TwistedCylinder()), 40)
    assert isinstance(leapfrog_stepper(*covered), StencilLeapfrog)
    for scene, reason in ((Sphere(gamma=0.05, R=1.01), "a pole"),
                          (TwistedCylinder(eta_lambda=30.0), "viscosity"),
                          (TwistedCylinder(pressure=1e4), "loads or driven edges"),
                          (mol_shell.scenes.SCENES["axisymmetric"](), "a scene without all five fields")):
        system, compiled = build(resolve(scene), 40)
        assert unsupported_reason(system) == reason
        assert leapfrog_stepper(system, compiled) is compiled
        with pytest.raises(Unsupported, match=reason):
            StencilLeapfrog(system)


def test_stencil_threads_follow_the_requested_ones():
    system, compiled = build(resolve(TwistedCylinder()), 40)
    compiled.set_threads(2)
    assert leapfrog_stepper(system, compiled).threads == 1  # below PARALLEL_MIN_NODES: one thread
    big, compiled_big = build(resolve(TwistedCylinder()), 600)
    compiled_big.set_threads(2)
    assert leapfrog_stepper(big, compiled_big).threads == 2
    compiled_big.set_threads(1)
    assert leapfrog_stepper(big, compiled_big).threads == 1


def test_emitter_refuses_operations_it_does_not_write():
    x = ca.SX.sym("x")
    with pytest.raises(Unsupported, match="operation"):
        sx_statements(ca.Function("f", [x], [ca.exp(x)]), lambda j, r: "0", ["y"])
    text = sx_statements(ca.Function("g", [x], [ca.vertcat(ca.sin(x) * 0.1, 0)]), lambda j, r: "x0", ["y"])
    assert "0x1.999999999999ap-4" in text  # constants as exact hexadecimal literals
    assert "y1 = 0" in text  # structural zeros of an output


@pytest.mark.parametrize("turning_limit", [True, False])
def test_gcc_vectorises_the_cell_and_the_node_loops(turning_limit, tmp_path):
    """The stencil's speed is its SIMD: gcc's own report on the driver it compiles must name both ``omp simd``
    loops vectorised. The turning-point limit's select (``tr > 0 ? det : -|det|``) once made gcc keep a branch
    (with floating-point traps on), and the paper's leap-frog ran at 1.8x its time: no numerical test saw it."""
    import subprocess

    from mol_shell.discretization.stencil import FLAGS, stencil_source

    system = ShellSystem(resolve(TwistedCylinder(law_limit=turning_limit)), 41)
    assert system.turning_limit == turning_limit
    source = stencil_source(system)[0]
    (tmp_path / "stencil.c").write_text(source)
    report = subprocess.run(["gcc", *FLAGS, "-fopt-info-vec-all", str(tmp_path / "stencil.c"), "-o",
                             str(tmp_path / "stencil.so"), "-lm"], capture_output=True, text=True, check=True).stderr
    lines = source.splitlines()
    pragmas = [k + 1 for k, line in enumerate(lines) if "#pragma omp simd" in line]  # 1-based, as gcc counts
    assert len(pragmas) == 2, pragmas  # the cells' forces, the nodes' updates

    def said(line, what):
        return any(text.startswith(f"{tmp_path / 'stencil.c'}:{line}:") and what in text
                   for text in report.splitlines())

    for pragma in pragmas:  # the loop's own line follows its pragma (gcc names the first line of its body too)
        body = range(pragma + 1, pragma + 4)
        assert any(said(line, "optimized: loop vectorized") for line in body), (pragma, report[-2000:])
        assert not any(said(line, "not vectorized") for line in body), (pragma, report[-2000:])
