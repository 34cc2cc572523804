"""The fast paths against the plain ones: the lean cell kernel against the readable reference kernel, the
threaded (OpenMP) compiled RHS and leap-frog against the serial ones, and the parallel graph's build cache."""

import os

import numpy as np
import pytest

import mol_shell
from mol_shell.discretization.compiled import CompiledRHS, default_threads
from mol_shell.discretization.system import ShellSystem
from mol_shell.scenes import Cone, MeridianShell, Sphere, TwistedCylinder
from mol_shell.runs.simulate import resolve


def ellipse_points(path):
    """An ellipse's quarter (r from 0.4 to 1): curvature changes along it, so ``beta2_0 != 0`` in the cells."""
    phi = np.linspace(0.3, 1.4, 31)
    np.savetxt(path, np.column_stack([np.sin(phi), 0.6 * np.cos(phi)]), header="r z (m)")
    return str(path)


def disturbed(system, scene, amplitude=1e-3):
    y = system.initial_state(scene)
    return y + amplitude * np.sin(1.7 * np.arange(y.size)) * (np.arange(y.size) < system.ny * system.n)


def scenes(tmp_path):
    return {
        "paper": TwistedCylinder(),
        "viscous-loaded": TwistedCylinder(eta_lambda=30.0, eta_mu=20.0, pressure=1e4),
        "axisymmetric": mol_shell.scenes.SCENES["axisymmetric"](),
        "sphere": Sphere(gamma=0.05, R=1.01),
        "cone": Cone(gamma=0.05, dilation=1.01),
        "driven-cylinder": TwistedCylinder(end_omega=2.0, gravity=9.81),
        "curved-points": MeridianShell(points=ellipse_points(tmp_path / "ellipse.txt"), dilation=1.01),
        "viscous-curved": MeridianShell(points=ellipse_points(tmp_path / "ellipse.txt"), dilation=1.01, eta_lambda=30.0,
                                        eta_mu=20.0, n_quad=5),
        "viscous-sphere": Sphere(gamma=0.05, R=1.01, eta_lambda=30.0, eta_mu=20.0, h=0.05),
        "viscous-rubber": Sphere(gamma=0.05, R=1.01, material="neo-hookean", nu=0.3, eta_lambda=30.0, eta_mu=20.0),
        "viscous-incompressible": Sphere(gamma=0.05, R=1.01, material="mooney-rivlin", c01=3e4, eta_mu=20.0),
        "viscous-fibres": TwistedCylinder(fibre_E=5e9, fibre_angle=0.5, eta_lambda=30.0, eta_mu=20.0),
        "viscous-graded": Cone(gamma=0.05, dilation=1.01, eta_lambda=30.0, eta_mu=20.0, h_profile="0.01*(1+0.1*s)"),
    }


@pytest.mark.parametrize("name", ["paper", "viscous-loaded", "axisymmetric", "sphere", "cone", "curved-points",
                                  "driven-cylinder", "viscous-curved", "viscous-sphere", "viscous-rubber",
                                  "viscous-incompressible", "viscous-fibres", "viscous-graded"])
def test_lean_rhs_equals_the_reference_rhs(name, tmp_path):
    """thickness_energy_shared is the same quadrature of the same W as thickness_energy, and the node kernels'
    LDL^T solve the same as CasADi's QR (poles, rhoI != 0 on the cone, driven edges): equal to round-off. The
    viscous forces and their power from the thickness moments and the nodes' trigonometry
    (thickness_dissipation_moments) against the per-point quadrature of D, with every law and a graded wall
    (whose per-point D failed to build on 0.6.0: its thickness points are data); an incompressible law's D (det C = 1
    sets the thickness rate) point by point in both, on the nodes' trigonometry in the lean one."""
    scene = resolve(scenes(tmp_path)[name])
    fast, ref = ShellSystem(scene, 17), ShellSystem(scene, 17, reference=True)
    if "curved" in name:
        assert fast.curved  # the beta2_0 path is exercised
    if fast.law is None:  # a law other than SVK is integrated point by point in both
        assert fast.cell_forces_kernel().n_instructions() < 0.4 * ref.cell_forces_kernel().n_instructions()
    if fast.viscous and not fast.incompressible_viscosity:
        assert (fast.viscous_forces_shared_kernel().n_instructions()
                < 0.4 * ref.viscous_forces_kernel().n_instructions())
    for t in (0.0, 0.003):
        y = disturbed(fast, scene)
        a = np.array(fast.rhs(t, y)).ravel()
        b = np.array(ref.rhs(t, y)).ravel()
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))


def test_spd_solve_equals_a_dense_solve():
    """LDL^T in a minimum-degree order: dense and structured SPD matrices (decoupled rows, an arrow like the
    shell's mass matrix), against NumPy."""
    import casadi as ca

    from mol_shell.model.linalg import spd_solve

    rng = np.random.default_rng(7)
    for k in (1, 2, 3, 5, 8):
        A = rng.standard_normal((k, k))
        dense = A @ A.T + k * np.eye(k)
        arrow = np.diag(rng.uniform(1, 2, k))
        arrow[0, 1:] = arrow[1:, 0] = 0.3 * rng.uniform(-1, 1, k - 1)  # row 0 couples to all: eliminated last
        for M in (dense, arrow):
            S = ca.SX(ca.DM(M))  # numeric entries: structural zeros where M has zeros
            x = np.array(ca.evalf(spd_solve(S, ca.SX(ca.DM(np.arange(1.0, k + 1)))))).ravel()
            np.testing.assert_allclose(x, np.linalg.solve(M, np.arange(1.0, k + 1)), rtol=1e-12)
    M, b = ca.SX.sym("M", 3, 3), ca.SX.sym("b", 3)  # symbolic and dense: no square root, three reciprocals
    solve = ca.Function("solve", [M, b], [spd_solve(M, b)])
    ops = [solve.instruction_id(k) for k in range(solve.n_instructions())]
    assert ca.OP_SQRT not in ops and ops.count(ca.OP_DIV) <= 3 + 3


def test_thickness_energy_shared_equals_the_reference_pointwise():
    """Every strain non-zero, a curved reference (beta2_0 != 0) and five thickness points."""
    from mol_shell.model.material import Thickness, quadrature_factors, thickness_energy, thickness_energy_shared

    strains = (0.93, 0.21, 0.05, -0.4, 0.07, 1.1, 0.25, 0.12)
    factors = quadrature_factors(Thickness(-0.03, 0.03, 5), r0=0.9, theta0=0.3, theta0_s=0.2, beta1_0=1.01)
    a = thickness_energy(strains, 3e9, 1e9, factors, 0.02)
    b = thickness_energy_shared(strains, 3e9, 1e9, factors, 0.02)
    assert abs(a - b) <= 1e-13 * abs(a)


@pytest.mark.parametrize("name", ["paper", "viscous-loaded", "curved-points"])
def test_parallel_rhs_equals_the_serial_rhs(name, tmp_path):
    """The OpenMP maps compute each cell and node on one thread: the serial result to the last bit."""
    scene = resolve(scenes(tmp_path)[name])
    system = ShellSystem(scene, 64)
    serial = CompiledRHS(system.rhs_mapped, system.limits)
    parallel = CompiledRHS(system.rhs_parallel, system.limits, threads=2)
    assert parallel.parallel and not serial.parallel and serial.threads == 1
    y = disturbed(system, scene)
    a = serial.evaluator()(y, 0.002).copy()
    for k in (1, 2, 3):
        parallel.set_threads(k)
        assert parallel.threads == k
        b = parallel.evaluator()(y, 0.002)
        np.testing.assert_array_equal(a, b)
    # and CasADi's own evaluation of the graph (serial VM) agrees to round-off
    c = np.array(system.rhs_parallel(0.002, y)).ravel()
    assert np.max(np.abs(c - a)) <= 1e-12 * np.max(np.abs(a))


def test_parallel_leapfrog_equals_the_serial_leapfrog():
    scene = resolve(TwistedCylinder())
    system = ShellSystem(scene, 64)
    serial = CompiledRHS(system.rhs_mapped, system.limits)
    parallel = CompiledRHS(system.rhs_parallel, system.limits, threads=2)
    y0 = system.initial_state(scene)
    out = []
    for c in (serial, parallel):
        ya, yb = y0.copy(), y0 + 1e-7 * c.evaluator()(y0, 0.0)
        assert c.leapfrog(ya, yb, 300, 1e-7, 1e-7) == (300, False)
        out.append(yb)
    np.testing.assert_array_equal(out[0], out[1])


def test_simulate_threads_option_gives_identical_runs(monkeypatch):
    import importlib

    sim = importlib.import_module("mol_shell.runs.simulate")

    monkeypatch.setattr(importlib.import_module("mol_shell.runs.building"), "PARALLEL_MIN_NODES", 30)
    sim._built.cache_clear()
    try:
        runs = [mol_shell.simulate(TwistedCylinder(), n=31, t_end=2e-4, threads=k, progress=False, stresses=False)
                for k in (1, 2)]
        assert sim.build(resolve(TwistedCylinder()), 31)[1].parallel
    finally:
        sim._built.cache_clear()
    np.testing.assert_array_equal(runs[0].z.values, runs[1].z.values)
    np.testing.assert_array_equal(runs[0].psi.values, runs[1].psi.values)


def test_cache_dir_that_cannot_be_a_writable_directory_is_refused_by_name(monkeypatch, tmp_path):
    """MOL_SHELL_CACHE under /proc, or naming a file, was an internal FileNotFoundError/FileExistsError."""
    from mol_shell._core.errors import ParameterError
    from mol_shell.discretization.compiled import cache_dir

    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "new" / "cache"))
    assert cache_dir() == tmp_path / "new" / "cache" and cache_dir().is_dir()
    (tmp_path / "file").write_text("")
    for bad, problem in (("/proc/nope", "cannot be created"), (str(tmp_path / "file"), "is a file"),
                         ("/proc", "cannot be written")):
        monkeypatch.setenv("MOL_SHELL_CACHE", bad)
        with pytest.raises(ParameterError, match=f"MOL_SHELL_CACHE = '{bad}' {problem}.*a writable directory"):
            cache_dir()


def test_threads_default_and_refusals(monkeypatch):
    from mol_shell._core.errors import ParameterError

    monkeypatch.setenv("MOL_SHELL_THREADS", "3")
    assert default_threads() == 3
    monkeypatch.setenv("MOL_SHELL_THREADS", "zero")
    with pytest.raises(ParameterError, match="MOL_SHELL_THREADS"):
        default_threads()
    monkeypatch.delenv("MOL_SHELL_THREADS")
    assert default_threads() >= 1
    system = ShellSystem(resolve(TwistedCylinder()), 8)
    compiled = CompiledRHS(system.rhs_parallel, system.limits, threads=1)
    for bad in (0, 1.5, True):
        with pytest.raises(ParameterError, match="threads"):
            compiled.set_threads(bad)


@pytest.mark.parametrize("name", ["paper", "viscous-loaded", "sphere"])
def test_spectrum_jacobian_equals_the_exact_jacobian(name, tmp_path):
    """The Jacobian that every run's spectrum and finiteness checks use (built from the mapped kernels' own
    Jacobians) against the flat graph's exact one: the same values to round-off, the same eigenvalue bound."""
    from mol_shell.model.equilibrium import spectrum_bounds

    scene = resolve(scenes(tmp_path)[name])
    system = ShellSystem(scene, 20)
    y = disturbed(system, scene, 1e-4)
    exact, mapped = np.array(system.jac(0.001, y)), np.array(system.spectrum_jac(0.001, y))
    assert np.max(np.abs(mapped - exact)) <= 1e-13 * np.max(np.abs(exact))
    bounds = [spectrum_bounds(j, y, system.viscous) for j in (system.jac, system.spectrum_jac)]
    np.testing.assert_allclose(bounds[0], bounds[1], rtol=1e-10)
    assert system.graph_stats()["jacobian_nnz"] == system.jac.sparsity_out(0).nnz()


def test_rest_spectrum_is_the_spectrum_of_a_block_antidiagonal_matrix():
    """``[[0, C], [D, 0]]`` (positions and rates interleaved as in a state vector) has the eigenvalues
    ``+-sqrt(eig(CD))``: checked on random blocks against the eigenvalues of the whole matrix."""
    from mol_shell.model.equilibrium import rest_spectrum

    rng = np.random.default_rng(7)
    m = 30
    C, D = rng.standard_normal((m, m)), rng.standard_normal((m, m))
    order = np.arange(2 * m).reshape(-1, 2).T.ravel()  # q0 p0 q1 p1 ... as the node-major state
    J = np.zeros((2 * m, 2 * m))
    J[np.ix_(order[:m], order[m:])], J[np.ix_(order[m:], order[:m])] = C, D
    q = np.isin(np.arange(2 * m), order[:m])
    ev = rest_spectrum(J, q)
    full = np.linalg.eigvals(J)
    assert ev.size == full.size
    assert np.max(np.min(np.abs(ev[:, None] - full[None, :]), axis=1)) < 1e-10 * np.abs(full).max()
    assert rest_spectrum(J * 1e160, q) is None  # CD overflows where J does not: J's own eigenvalues are needed
    J[order[0], order[1]] = 1e-300  # a position-position entry: not at rest, no shortcut
    assert rest_spectrum(J, q) is None


@pytest.mark.parametrize("name", ["paper", "sphere", "cone", "axisymmetric"])
def test_spectrum_at_rest_equals_the_full_spectrum(name, tmp_path):
    """A shell at rest takes the half-size spectrum (:func:`rest_spectrum`): its largest |eigenvalue| is the full
    Jacobian's to round-off; a moving twisted shell and a loaded one keep the full one."""
    from mol_shell.runs.checks import positions
    from mol_shell.model.equilibrium import rest_spectrum, spectrum_bounds

    scene = resolve(scenes(tmp_path)[name])
    system = ShellSystem(scene, 20)
    y0 = system.initial_state(scene)
    J = np.array(system.spectrum_jac(0, y0))
    ev, full = rest_spectrum(J, positions(system)), np.linalg.eigvals(J)
    assert ev is not None
    np.testing.assert_allclose(np.abs(ev).max(), np.abs(full).max(), rtol=1e-12)
    np.testing.assert_allclose(np.sort(np.abs(ev)), np.sort(np.abs(full)), rtol=0, atol=1e-7 * np.abs(full).max())
    assert spectrum_bounds(system.spectrum_jac, y0, False, positions(system))[0] == np.abs(ev).max()
    assert rest_spectrum(J, positions(system)) is not None
    moving = rest_spectrum(np.array(system.spectrum_jac(0, disturbed(system, scene))), positions(system))
    # moving, the twisting shells' inertia depends on r (angular momentum r^2 chi_t): the rate blocks fill in;
    # the axisymmetric shell's mass matrix is constant, so its blocks stay empty and the shortcut stays exact
    assert (moving is None) == (name != "axisymmetric")
    loaded = ShellSystem(resolve(scenes(tmp_path)["viscous-loaded"]), 20)
    assert positions(loaded) is None


def test_a_run_and_a_study_do_not_import_dask():
    """Datasets are made on xarray's fast path with their indexes made here: the general path's duck-array check
    imports ``dask.array``, its default index ``dask`` (0.4-0.6 s of every process's first run, and of each
    study worker's start). In a fresh interpreter."""
    import subprocess
    import sys

    code = ("import sys, mol_shell\n"
            "ds = mol_shell.simulate('twisted-cylinder', n=10, t_end=0.001)\n"
            "st = mol_shell.study('twisted-cylinder', {'gamma': [0.5, 0.6]}, n=10, t_end=0.001, scheduler='serial')\n"
            "assert 'von_mises_stress' in ds and dict(ds.sizes) == {'time': 11, 's': 10, 's_cell': 9, 'zeta': 2, 'end': 2}\n"
            "assert 'von_mises_stress' in st and st.sizes['gamma'] == 2 and set(st.status.values) == {'complete'}\n"
            "print('dask' in sys.modules or 'dask.array' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split()[-1] == "False"


def test_thread_counts_beyond_the_machine_are_refused_by_name(monkeypatch):
    """MOL_SHELL_THREADS = 100000 (or threads=100000) crashed the process in libgomp (a segmentation fault), 1e20
    was libgomp's out of memory, 2**31 wrapped round a C int, 10,000 ran 500x slower: above 8 threads per logical
    CPU each is refused in one line naming it and the range, before a step; 8 per CPU is taken."""
    from mol_shell._core.errors import ParameterError

    top = 8 * os.cpu_count()
    for text in ("100000", "1000000", "2147483648", "99999999999999999999", str(top + 1)):
        monkeypatch.setenv("MOL_SHELL_THREADS", text)
        with pytest.raises(ParameterError, match=f"^MOL_SHELL_THREADS = '{text}' is outside integers 1 \\.\\. {top} "
                                                 f"\\(8 x this machine's {os.cpu_count()} logical CPUs; "):
            default_threads()
    monkeypatch.setenv("MOL_SHELL_THREADS", str(top))
    assert default_threads() == top
    monkeypatch.delenv("MOL_SHELL_THREADS")
    for bad in (100000, 2**31, top + 1, np.int64(2**40)):  # the build at n = 9 made once (simulate's cache)
        with pytest.raises(ParameterError, match=f"^threads = {int(bad)} is outside integers 1 \\.\\. {top} "):
            mol_shell.simulate(TwistedCylinder(), n=9, t_end=1e-4, threads=bad, progress=False, stresses=False)
