"""Equilibria and conservation laws checked against numbers derived independently of the package.

* the natural state at rest is an exact equilibrium of the discrete system (up to the
  round-off of ``z = s`` differences);
* the radius ``R`` of the uniformly twisted cylinder solves radial equilibrium of an
  independent NumPy ``What`` (``tests/reference_ring.py``) and has the small-twist
  asymptotics derived in closed form below;
* leap-frog's energy error is second order in ``dt`` and does not drift; the axial angular
  momentum is conserved to round-off (and equals its closed form);
* ``n_quad = 4`` Gauss points through the thickness are converged.

No expected value is copied from a run; every tolerance is an error estimate, explained
where it is used. ``EPS`` below is the spacing of doubles at 1 (twice the unit round-off),
used as a conservative unit round-off.
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import mol_shell
import reference_ring as ref
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.equilibrium import equilibrium_radius
from mol_shell.model.material import Thickness, centroidal_offset, shell_energy

EPS = np.finfo(float).eps
PAPER = mol_shell.TwistedCylinder()  # gamma = 0.1, default material (section 6)
LAM, MU = ref.lame(PAPER.E, PAPER.nu)
ZETA1 = ref.zeta1_centroidal(PAPER.h)
#: axial force of the whole circumference per unit axial strain, 2 pi (lambda + 2 mu) 2h (N)
FORCE_PER_STRAIN = 2 * math.pi * (LAM + 2 * MU) * 2 * PAPER.h


# ---------------------------------------------------------------------------------------
# 1. the natural state at rest is an exact equilibrium
# ---------------------------------------------------------------------------------------
def _natural_state_rhs(n):
    scene = mol_shell.TwistedCylinder(gamma=0.0, R=1.0, omega=0.0, psi0=0.0)
    if n == 40:  # the size the other tests compile: check the generated C as well as the VM
        system, compiled = mol_shell.build(scene, n)
        y0 = system.initial_state(scene)
        vm = np.array(system.rhs(0, y0)).ravel()
        c = np.array(compiled.function(0, y0)).ravel()
        return system, [vm, c]
    system = ShellSystem(scene, n)
    return system, [np.array(system.rhs(0, system.initial_state(scene))).ravel()]


def test_natural_state_at_rest_is_an_exact_equilibrium():
    """``rhs(y0)`` vanishes up to the round-off of the finite differences of ``z = s``.

    Error estimate: the nodes ``z_i = s_i`` (up to ``L``) carry rounding ``<= EPS L / 2``,
    so the computed axial strain ``(z_{i+1} - z_i)/ds`` is ``1 + O(EPS L/ds)``; with the
    roundings inside ``E = (F^T F - I)/2``, the quadrature sum and ``1/(1 + zeta)`` (a few
    ``EPS`` more) the strain error is ``de <= EPS (2 L/ds + 10)``. A strain error ``de``
    makes an error ``2 pi (lambda + 2 mu) 2h de`` in a cell's axial force (a flux); a
    node's generalised force is the difference of two cell fluxes (``z``, ``chi`` and the
    ``theta_s``, ``psi_s`` parts), hence ``2 x``. Undifferentiated fields (``r``: the hoop
    force) enter each cell through the midpoint with the cell's weight ``ds``, so the
    ``r``-force error is ``ds`` times smaller: ``2 pi (lambda + 2 mu) 2h ds de`` per cell,
    two cells per node. Velocities are ``M^-1 p`` with ``p = 0``: exactly zero.
    """
    for n in (11, 40, 81):
        system, rhs_values = _natural_state_rhs(n)
        ds = system.ds
        strain_error = EPS * (2 * PAPER.L / ds + 10)
        flux_bound = 2 * FORCE_PER_STRAIN * strain_error
        hoop_bound = 2 * FORCE_PER_STRAIN * ds * strain_error
        for rhs in rhs_values:
            node = rhs.reshape(n, 10)  # z, r, chi, theta, psi, then the five momenta' rates
            assert np.all(node[:, :5] == 0.0), "rates of the fields must vanish exactly at rest"
            forces = np.abs(node[:, 5:]).max(axis=0)
            assert forces[0] <= flux_bound, (n, forces[0], flux_bound)  # z
            assert forces[1] <= hoop_bound, (n, forces[1], hoop_bound)  # r
            assert max(forces[2], forces[3], forces[4]) <= flux_bound, (n, forces, flux_bound)
            # and the residual is genuinely round-off: below the force of a 1e-12 axial strain
            assert forces.max() < 1e-12 * FORCE_PER_STRAIN


# ---------------------------------------------------------------------------------------
# 2. the radius of the uniformly twisted cylinder
# ---------------------------------------------------------------------------------------
def _what_twisted(r, gamma):
    """Independent ``What`` of the uniform twist ``z_s = 1, chi_s = gamma``, ``theta = psi = 0`` at radius ``r``."""
    return ref.what((1.0, 0.0, gamma, 0.0, 0.0, r, 0.0, 0.0), LAM, MU, PAPER.h, ZETA1, n_quad=8)


def test_equilibrium_radius_solves_radial_equilibrium_of_an_independent_energy():
    """``dWhat/dr (R) = 0`` for the package's ``R``, with ``What`` from ``reference_ring``.

    With ``theta = psi = 0`` the table's ``F`` is affine in ``r`` (``F31 = gamma (r + zeta)``,
    ``F33 = (r + zeta)/(1 + zeta)``) and ``W_SVK`` is quartic in ``F``, so ``What`` is a quartic
    polynomial in ``r``: the five-point stencils below (first and second derivative) are
    exact for it, and the only error is round-off. Each ``What`` evaluation carries an
    absolute error ``dW <= 10 EPS (lambda + 2 mu) 2h E_max`` (the strains ``E`` come from
    ``(F^T F - I)/2`` with absolute error ~EPS; ``E_max ~ gamma/2``); the stencil turns it
    into ``(18/12) dW / hr`` in ``W'``, and a root error ``(18/12) dW / (hr W'')``.
    """
    gamma = PAPER.gamma
    R = equilibrium_radius(PAPER)
    hr = 1e-3

    def d1(r):
        f = [_what_twisted(r + k * hr, gamma) for k in (-2, -1, 1, 2)]
        return (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * hr)

    def d2(r):
        f = [_what_twisted(r + k * hr, gamma) for k in (-2, -1, 0, 1, 2)]
        return (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * hr**2)

    energy_error = 10 * EPS * (LAM + 2 * MU) * 2 * PAPER.h * gamma / 2
    slope_error = 1.5 * energy_error / hr
    stiffness = d2(R)
    assert stiffness > 0  # a minimum of What in r: a stable radial equilibrium
    assert abs(d1(R)) <= slope_error, (d1(R), slope_error)
    # an independent root (Brent on the reference W') agrees to the round-off estimate
    R_ref = brentq(d1, 0.98, 1.0, xtol=1e-16)
    assert abs(R_ref - R) <= slope_error / stiffness + 4 * EPS, (R_ref, R)
    # the twisted cylinder contracts (R < 1) by about 0.5 gamma^2: see the asymptotic test
    assert 0.99 < R < 1.0


def test_equilibrium_radius_small_twist_asymptotics():
    """``R - 1 = c(h) gamma^2 + O(gamma^4)`` with ``c(h)`` in closed form; ``R(gamma = 0) = 1``.

    Derivation (``theta = psi = 0``, ``z_s = 1``): ``E11 = gamma^2 (r + zeta)^2 / 2``,
    ``E13 = gamma (r + zeta)^2 / (2 (1 + zeta))``, ``E33 = ((r + zeta)^2/(1 + zeta)^2 - 1)/2``.
    At ``r = 1 + e``, to first order in ``e`` and ``gamma^2``,
    ``dW/dr (1 + zeta) = lambda gamma^2 (1 + zeta)^2/2 + (lambda + 2 mu) e/(1 + zeta) + 2 mu gamma^2 (1 + zeta)^2``,
    so ``c(h) = -(lambda/2 + 2 mu) int (1 + zeta)^2 dzeta / ((lambda + 2 mu) int dzeta/(1 + zeta))``,
    exact in ``h`` (thin limit: ``-(lambda + 4 mu) / (2 (lambda + 2 mu))``).

    The package's ``c(gamma) = (R - 1)/gamma^2`` is Richardson-extrapolated from
    ``gamma = 0.05, 0.025``; the remainder is ``O(gamma^4)``, estimated (standard Richardson
    error estimate) as ``|X(0.1, 0.05) - X(0.05, 0.025)| / 15``; we allow twice that.
    """
    a, b = ZETA1, ZETA1 + 2 * PAPER.h
    c_h = -(LAM / 2 + 2 * MU) * ((1 + b) ** 3 - (1 + a) ** 3) / 3 / ((LAM + 2 * MU) * math.log((1 + b) / (1 + a)))
    c = {g: (equilibrium_radius(dataclasses.replace(PAPER, gamma=g)) - 1) / g**2 for g in (0.1, 0.05, 0.025)}
    x12 = (4 * c[0.05] - c[0.1]) / 3
    x23 = (4 * c[0.025] - c[0.05]) / 3
    assert abs(x23 - c_h) <= 2 * abs(x12 - x23) / 15, (x23, c_h, x12)
    # without extrapolation the O(gamma^2) relative correction (~1e-3 at gamma = 0.1) is visible
    assert abs(c[0.1] - c_h) > 10 * abs(x23 - c_h)
    # no twist: the natural radius. Newton starts at 1 where W'(1) is round-off, W'' ~ (lambda + 2 mu) 2h
    assert abs(equilibrium_radius(dataclasses.replace(PAPER, gamma=0.0)) - 1.0) <= 4 * EPS


# ---------------------------------------------------------------------------------------
# 3. energy and angular momentum of leap-frog runs
# ---------------------------------------------------------------------------------------
def _relative_energy_error(ds):
    e = ds.energy.values
    return np.abs(e - e[0]) / e[0]


def test_leapfrog_energy_error_is_second_order_in_dt():
    """Slope of ``max_t |E(t) - E(0)|/E(0)`` against ``dt`` over ``t in [0, 0.01]`` s: 2.

    Leap-frog's energy error is ``C dt^2 (1 + O((w dt)^2))`` for the frequencies ``w``
    present; the stability bound at ``n = 40`` is ``1/w_max ~ 1.9e-4`` s, so at the coarsest
    step ``(w_max dt)^2 <= (4e-5/1.9e-4)^2 ~ 0.045``: the O(dt^4) term changes the error ratio
    of successive steps by at most ~5%, i.e. the slope by ``log2(1.05) ~ 0.07``. The error is
    sampled at the same 51 saved times for every ``dt``; we allow 0.15.
    """
    times = np.linspace(0.0, 0.01, 51)  # every 2e-4 s: a multiple of each dt
    dts = np.array([4e-5, 2e-5, 1e-5])
    errors = np.array(
        [_relative_energy_error(mol_shell.simulate(PAPER, "leapfrog", n=40, times=times, dt=dt, progress=False)).max()
         for dt in dts]
    )
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert abs(slope - 2.0) <= 0.15, (slope, errors)
    assert errors.max() < 1e-5  # and small: the energy is conserved up to the scheme's error


def test_leapfrog_energy_error_does_not_drift():
    """Over 1 s (50 000 steps, two torsional periods) the error stays bounded.

    A secular drift would grow the error linearly, making the max over the second half at
    least twice the max over the first; a bounded oscillating error gives a ratio ~1. We
    assert the ratio is below 1.5 (halfway) and the level stays at the short-run dt^2 level.
    """
    times = np.linspace(0.0, 1.0, 2001)
    err = _relative_energy_error(mol_shell.simulate(PAPER, "leapfrog", n=40, times=times, dt=2e-5, progress=False))
    first, second = err[: len(err) // 2 + 1].max(), err[len(err) // 2 :].max()
    assert second < 1.5 * first, (first, second)
    assert second < 1e-6


def test_angular_momentum_is_conserved_to_round_off_with_spin():
    """Axial angular momentum with spin ``omega = 5`` rad/s, shear ``psi0 = 0.05`` and the paper's twist.

    Closed form at ``t = 0`` (``theta = 0``, ``chi_t = omega``, ``psi_t = 0``, ``rhoI = 0``):
    ``p_chi = 2 pi w (rhoA R^2 chi_t + rhoJ (psi_t + chi_t))``, and the trapezoid weights sum to
    ``L``, so ``L0 = 2 pi L (rhoA R^2 + rhoJ) omega`` with ``rhoA, rhoJ`` from
    ``reference_ring`` (closed-form moments); ``n`` rounded additions: ``10 n EPS``.

    Conservation: ``V`` depends on ``chi`` only through differences, so the chi-forces sum
    to zero; what is left is the rounding of each momentum update, ``<= EPS |p_i|`` per node
    and step, accumulating as a random walk over ``n`` nodes and ``N`` steps:
    ``|dL| <~ EPS max|p_i| sqrt(n N)`` plus ``n EPS |L|`` for the sum. The twist waves move
    spin between nodes by ``~ c gamma = 1.8`` rad/s ``< omega``, so ``max |p_i| <= 2 |L|/n``.
    """
    scene = mol_shell.TwistedCylinder(omega=5.0, psi0=0.05)
    dt, t_end, n = 2e-5, 0.5, 40
    ds = mol_shell.simulate(scene, "leapfrog", n=n, times=np.linspace(0.0, t_end, 101), dt=dt, progress=False)
    L = ds.angular_momentum.values
    rho_a, rho_i, rho_j = ref.inertias(scene.rho, scene.h, ZETA1)
    assert abs(rho_i) < 1e-6 * rho_a * scene.h  # the base surface makes rhoI vanish
    L0 = 2 * math.pi * scene.L * (rho_a * ds.attrs["R"] ** 2 + rho_j) * scene.omega
    assert abs(L[0] - L0) <= 10 * n * EPS * abs(L0), (L[0], L0)
    assert abs(L0) > 1e3  # nonzero: ~1.6e3 kg m^2/s
    steps = t_end / dt
    bound = EPS * abs(L0) * (n + 2 * math.sqrt(n * steps))
    assert np.abs(L - L[0]).max() <= bound, (np.abs(L - L[0]).max(), bound)
    # the shell does spin and twist: the check is not on a trivial motion
    assert float(abs(ds.chi_t - scene.omega).max()) > 0.1


# ---------------------------------------------------------------------------------------
# 7. the thickness quadrature is converged
# ---------------------------------------------------------------------------------------
STRONG = (1.3, 0.2, 0.8, 0.4, 0.2, 0.7, 0.5, 0.6)  # (z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi): far from natural


def _strong_fields(n, L):
    """Nodal fields whose cell strains are those of :data:`STRONG` at the middle of the shell, varying along it."""
    s = np.linspace(0.0, L, n)
    z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi = STRONG
    wave = np.sin(np.pi * s / L)
    Q = np.array([z_s * s, r + r_s * (s - L / 2), chi_s * s, theta + theta_s * (s - L / 2) * wave,
                  psi + psi_s * (s - L / 2)])
    Q[3, [0, -1]] = 0.0  # theta = 0 is imposed at the ends
    V = np.array([0.0 * s, 0.3 * wave, 2.0 + wave, 0.5 * wave, -1.0 * wave])
    return Q, V


def test_thickness_quadrature_with_four_points_is_converged():
    """``n_quad = 4`` vs ``8``: ``What`` and the RHS agree to ``< 1e-10`` relative.

    Error estimate: with ``theta0_s = 0`` the integrand ``W(F(zeta)) (1 + zeta)`` is analytic
    except for the pole of the third column's ``1/(1 + zeta)`` at ``zeta = -1``. In the
    interval's coordinate ``x = (zeta - mid)/h`` the pole sits at ``|x| = (1 + mid)/h ~ 159``,
    so the Bernstein ellipse ``rho = |x| + sqrt(x^2 - 1) ~ 318`` and Gauss's error is
    ``O(rho^(-2 n_quad)) ~ 1e-20`` for ``n_quad = 4``: the difference is round-off.
    Also checks the package's ``What`` (any strains) against the independent reference.
    """
    mid = ZETA1 + PAPER.h
    x = (1 + mid) / PAPER.h
    rho_ellipse = x + math.sqrt(x * x - 1)
    assert rho_ellipse ** (-8) < 1e-18  # the estimate itself

    R = equilibrium_radius(PAPER)
    paper_strains = (1.0, 0.0, PAPER.gamma, 0.0, 0.0, R, 0.0, 0.0)
    zeta1 = centroidal_offset(PAPER.h)
    for strains in (paper_strains, STRONG):
        w4 = shell_energy(strains, LAM, MU, Thickness(zeta1, PAPER.h, 4))
        w8 = shell_energy(strains, LAM, MU, Thickness(zeta1, PAPER.h, 8))
        w_ref = ref.what(strains, LAM, MU, PAPER.h, ZETA1, n_quad=16)
        assert abs(w4 - w8) < 1e-10 * abs(w8), (strains, w4, w8)
        # independent F table and quadrature: agreement to round-off of E = (F^T F - I)/2 (~EPS/|E|)
        assert abs(w4 - w_ref) < 1e-12 * abs(w_ref), (strains, w4, w_ref)

    # the whole right-hand side at the paper's initial state and at a strongly deformed moving state
    n = 11
    systems = {q: ShellSystem(dataclasses.replace(PAPER, n_quad=q), n) for q in (4, 8)}
    sc = dataclasses.replace(PAPER, R=R)
    Q, V = _strong_fields(n, PAPER.L)
    for label in ("paper", "strong"):
        out = {}
        for q, system in systems.items():
            y = system.initial_state(sc) if label == "paper" else system.pack(Q, system.momenta(Q, V))
            out[q] = np.array(system.rhs(0, y)).ravel().reshape(n, 10)
        # generalised forces -dV/dq + dT/dq: What enters here
        scale = np.abs(out[8][:, 5:]).max()
        assert scale > 0
        assert np.abs(out[4][:, 5:] - out[8][:, 5:]).max() <= 1e-10 * scale, label
        # rates M(q)^-1 p: What does not enter; rhoA, rhoJ are integrals of cubics, exact for
        # n_quad >= 2. Both recover V up to round-off amplified by the condition number of the
        # nodal mass matrix (kappa ~ rhoA r^2 / rhoJ ~ 1e5 and more where cos(psi) is small):
        # |dv| <= 10 EPS kappa max|V| (a few roundings per entry of the 5 x 5 solve).
        kappa = max(np.linalg.cond(_nodal_mass(systems[4], Q, i)) for i in range(n))
        rate_bound = 10 * EPS * kappa * np.abs(V).max()
        for q in (4, 8):
            expected = np.zeros((n, 5)) if label == "paper" else (V * ~systems[q].fixed.T).T
            assert np.abs(out[q][:, :5] - expected).max() <= rate_bound, (label, q, rate_bound)


def _nodal_mass(system, Q, i):
    """``M = dp/dv`` (5 x 5) of node ``i`` at fields ``Q``, from the package's momenta of unit rates."""
    cols = []
    for k in range(5):
        unit = np.zeros_like(Q)
        unit[k] = 1.0
        cols.append(np.array(system.momenta(Q, unit))[:, i])
    M = np.stack(cols, axis=1)
    free = ~system.fixed[i]
    return M[np.ix_(free, free)]


def test_a_small_spectrum_runs_on_one_blas_thread(monkeypatch):
    """The step bound's dense spectrum at n = 40 is a 200 x 200 problem: on two OpenBLAS threads it gained nothing
    and, with the other core busy (a study's second process), their spinning made it 80 times slower. Every dense
    eigenvalue call of ``spectrum_bounds`` below :data:`ONE_THREAD_MAX_ROWS` rows sees one BLAS thread."""
    from threadpoolctl import threadpool_info

    from mol_shell.model import equilibrium
    from mol_shell.runs.simulate import build, resolve

    scene = resolve(PAPER)
    system, _ = build(scene, 40)
    seen, eigvals = [], np.linalg.eigvals

    def counted(matrix):
        seen.append((matrix.shape[0], {p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"}))
        return eigvals(matrix)

    monkeypatch.setattr(np.linalg, "eigvals", counted)
    omega_max, _ = equilibrium.spectrum_bounds(system.jac, system.initial_state(scene), False)
    assert omega_max > 0 and seen
    assert all(rows <= equilibrium.ONE_THREAD_MAX_ROWS and threads == {1} for rows, threads in seen), seen


def test_a_moving_elastic_spectrum_beyond_the_dense_limit_comes_from_arpack_and_agrees(monkeypatch):
    """A spinning shell has no half-size spectrum (its rate block does not vanish): at n = 160 the step bound's dense
    eigenvalues of the 1,600 x 1,600 Jacobian took 1-2.5 s. Beyond :data:`DENSE_EIG_MAX_ROWS` rows an elastic
    system's bound comes from ARPACK, which agrees with the dense spectrum (computed here independently) to 1e-3
    and gives the same number every time (a fixed start vector)."""
    from mol_shell.model import equilibrium
    from mol_shell.runs.checks import positions
    from mol_shell.runs.simulate import build, resolve

    scene = resolve(dataclasses.replace(PAPER, omega=50.0))
    system, _ = build(scene, 160)
    y0 = system.initial_state(scene)
    seen, eigvals = [], np.linalg.eigvals

    def counted(matrix):
        seen.append(matrix.shape[0])
        return eigvals(matrix)

    monkeypatch.setattr(np.linalg, "eigvals", counted)
    bounds = [equilibrium.spectrum_bounds(system.spectrum_jac, y0, system.viscous, positions(system)) for _ in "ab"]
    monkeypatch.undo()
    assert not system.viscous and all(rows <= equilibrium.DENSE_EIG_MAX_ROWS for rows in seen), seen
    assert bounds[0] == bounds[1] and bounds[0][1] == 0.0
    assert bounds[0][0] == pytest.approx(np.abs(np.linalg.eigvals(np.array(system.spectrum_jac(0, y0)))).max(), rel=1e-3)


@pytest.mark.parametrize("eta", [1.0, 100.0])
def test_a_viscous_spectrum_is_dense_so_its_fastest_damping_is_exact(eta):
    """ARPACK's largest-magnitude eigenvalues of a viscous shell at n = 160 put its fastest damping at 1,279 /s
    where it is 4,177 (eta_mu = 100), and the leap-frog's refusal of a run its parasitic root would blow up did not
    fire. A dissipative system's spectrum is dense up to DENSE_MAX_STATES states: the damping rate is the dense
    one (computed here independently), and the refusal stands."""
    from mol_shell.model import equilibrium
    from mol_shell.runs.checks import positions
    from mol_shell.runs.simulate import build, resolve

    scene = resolve(dataclasses.replace(PAPER, eta_mu=eta, eta_lambda=2 * eta))
    system, _ = build(scene, 160)
    y0 = system.initial_state(scene)
    omega_max, damping = equilibrium.spectrum_bounds(system.spectrum_jac, y0, system.viscous, positions(system))
    ev = np.linalg.eigvals(np.array(system.spectrum_jac(0, y0)))
    assert omega_max == pytest.approx(np.abs(ev).max(), rel=1e-9)
    assert damping == pytest.approx((-ev.real).max(), rel=1e-9) and damping > 0
    if eta == 100.0:
        with pytest.raises(mol_shell.ParameterError, match="its parasitic root grows damped modes"):
            mol_shell.simulate(scene, "leapfrog", n=160, t_end=0.006, progress=False)
