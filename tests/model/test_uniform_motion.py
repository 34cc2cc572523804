"""Section 5: spatially uniform motions stay uniform and follow an independently derived ring ODE.

Uniform data (``gamma = 0``, ``r = R != 1``, spin ``omega``, shear ``psi0``, ``theta = 0``)
on the free-ended cylinder: the leap-frog solution of the discretised PDE must stay uniform
in ``s`` to round-off and agree with the ODE of :class:`reference_ring.Ring` (Lagrangian
``2 pi [rhoA/2 (r_t^2 + r^2 chi_t^2) + rhoJ/2 (psi_t + chi_t)^2 - What(r, psi)]``, ``What``
from our own NumPy SVK quadrature of the F table, ``zeta1`` from ``rhoI = 0``), solved by
``solve_ivp`` (DOP853, rtol 1e-11). The remaining discrepancy is leap-frog's O(dt^2).
"""

import math

import numpy as np
import pytest

import mol_shell
import reference_ring as ref

EPS = np.finfo(float).eps
SCENE = mol_shell.TwistedCylinder(gamma=0.0, R=1.01, omega=20.0, psi0=0.05)
TIMES = np.linspace(0.0, 0.02, 9)  # every 2.5e-3 s: multiples of both steps
DTS = (4e-6, 2e-6)
COMPARED = ("r", "psi", "chi_t")


@pytest.fixture(scope="module")
def ring():
    model = ref.Ring(SCENE.E, SCENE.nu, SCENE.rho, SCENE.h)
    r, chi, psi, chi_t = model.solve(SCENE.R, SCENE.omega, SCENE.psi0, TIMES, rtol=1e-11)
    return model, {"r": r, "chi": chi, "psi": psi, "chi_t": chi_t}


@pytest.fixture(scope="module")
def runs():
    return {dt: mol_shell.simulate(SCENE, "leapfrog", n=40, times=TIMES, dt=dt, progress=False) for dt in DTS}


def test_reference_ring_forces_are_the_gradient_of_its_energy():
    """The ODE's analytic forces (first Piola contracted with dF/dq) match finite differences of ``What``.

    Five-point stencil with step ``k = 1e-4``: truncation ``k^4/30 |d^5 What|`` (zero in ``r``:
    ``What`` is quartic in ``r``; ``~ (lambda + 2 mu) 2h k^4`` in ``psi``, i.e. ~2e-11 relative)
    plus round-off ``1.5 EPS |What| / k``; both well below 1e-9 relative.
    """
    model = ref.Ring(SCENE.E, SCENE.nu, SCENE.rho, SCENE.h)
    k = 1e-4
    for r, psi in ((1.01, 0.05), (0.97, 0.4)):
        def W(x, y):
            return ref.what((1.0, 0.0, 0.0, 0.0, 0.0, x, 0.0, y), model.lam, model.mu, model.h, model.zeta1)

        f_r, f_psi = ref.ring_forces(r, psi, model.lam, model.mu, model.h, model.zeta1)
        fd_r = (W(r - 2 * k, psi) - 8 * W(r - k, psi) + 8 * W(r + k, psi) - W(r + 2 * k, psi)) / (12 * k)
        fd_psi = (W(r, psi - 2 * k) - 8 * W(r, psi - k) + 8 * W(r, psi + k) - W(r, psi + 2 * k)) / (12 * k)
        assert f_r == pytest.approx(fd_r, rel=1e-9)
        assert f_psi == pytest.approx(fd_psi, rel=1e-9)
    # the ring's inertias: rhoI vanishes for the derived base surface; rhoJ/rhoA ~ h^2/3
    assert abs(model.rho_i) < 1e-6 * model.rho_a * model.h
    assert model.rho_j / model.rho_a == pytest.approx(model.h**2 / 3, rel=1e-3)


def test_uniform_data_stays_uniform_to_round_off(ring, runs):
    """``max_s - min_s`` of ``r``, ``psi``, ``chi_t`` (and ``chi``) at every saved time is round-off.

    In exact arithmetic the discrete system preserves uniformity (every cell has the same
    strains, the end nodes have half a cell's energy and half a node's mass). Round-off
    enters as relative perturbations ~EPS; the worst amplification is the conversion of
    momenta to rates through the nodal mass matrix, whose condition number is
    ``kappa = rhoA R^2 / rhoJ ~ 3 R^2/h^2 ~ 8e4`` (the initial ``psi_t``, exactly 0, already
    comes out at a few 1e-10 rad/s, node by node). So the spread of a rate is at most
    ``2 EPS kappa X_rate`` with ``X_rate = max|chi_t| + max|psi_t|`` (the rates the mass
    matrix couples), and the spread of a field at most ``2 EPS (max|x| + kappa T max|x_t|)``
    (a perturbed rate acting for the whole run ``T``). These bounds are ~1e-8 .. 1e-11,
    orders of magnitude below the O(dt^2) discrepancy with the ODE (test below), so the
    check separates round-off from any discretisation effect.
    """
    model, _ = ring
    kappa = model.rho_a * SCENE.R**2 / model.rho_j
    T = TIMES[-1]
    for dt, ds in runs.items():
        assert ds.attrs["complete"] == 1
        spread = {k: float((ds[k].max("s") - ds[k].min("s")).max()) for k in ("r", "psi", "chi", "chi_t")}
        x_rate = float(abs(ds.chi_t).max() + abs(ds.psi_t).max())
        assert spread["chi_t"] <= 2 * EPS * kappa * x_rate, (dt, spread)
        for name in ("r", "psi", "chi"):
            bound = 2 * EPS * (float(abs(ds[name]).max()) + kappa * T * float(abs(ds[name + "_t"]).max()))
            assert spread[name] <= bound, (dt, name, spread[name], bound)
        # the motion is not trivial: r breathes, psi swings through zero, the spin changes
        assert float(abs(ds.r - SCENE.R).max()) > 0.01
        assert float(ds.psi.min()) < 0 < float(ds.psi.max())
        assert float(abs(ds.chi_t - SCENE.omega).max()) > 0.5


def test_leapfrog_agrees_with_the_ring_ode_to_order_dt_squared(ring, runs):
    """The discrepancy with the ODE falls 4x when ``dt`` halves, and has the size leap-frog predicts.

    The ODE is solved to rtol 1e-11 (its own error is < 1e-4 of the smallest discrepancy
    below). Leap-frog's error expansion is ``C dt^2 (1 + O((w dt)^2))``; the fastest
    frequency of the ring is the shear swing ``w_psi = sqrt(dWhat_psi,psi / rhoJ) ~ 5e3``
    rad/s, so ``(w dt)^2 <= 4e-4`` and the ratio of discrepancies at ``dt`` and ``dt/2`` is
    ``4 (1 +- 1e-3)``; we allow 4 +- 0.2 (the max over 8 saved times of an oscillating error
    is not exactly the same sample for both steps). Size: leap-frog advances an oscillation
    of frequency ``w`` with frequency ``arcsin(w dt)/dt ~ w (1 + (w dt)^2/6)``, a phase error
    ``w^3 dt^2 T / 6`` after ``T``, i.e. ``psi`` off by about (swing amplitude) x (phase error).
    """
    model, ode = ring
    errors = {dt: {k: float(abs(ds[k] - ode[k][:, None]).max()) for k in COMPARED} for dt, ds in runs.items()}
    for name in COMPARED:
        ratio = errors[DTS[0]][name] / errors[DTS[1]][name]
        assert abs(ratio - 4.0) <= 0.2, (name, ratio, errors)
    # size of the psi discrepancy from the phase-error estimate, with the ring's own frequency
    k = 1e-4
    _, f_plus = ref.ring_forces(SCENE.R, SCENE.psi0 + k, model.lam, model.mu, model.h, model.zeta1)
    _, f_minus = ref.ring_forces(SCENE.R, SCENE.psi0 - k, model.lam, model.mu, model.h, model.zeta1)
    w_psi = math.sqrt((f_plus - f_minus) / (2 * k) / model.rho_j)
    swing = float(abs(runs[DTS[1]].psi_t).max()) / w_psi
    for dt in DTS:
        phase = w_psi**3 * dt**2 * TIMES[-1] / 6
        assert 0.25 * swing * phase < errors[dt]["psi"] < 2 * swing * phase, (dt, errors[dt]["psi"], swing * phase)
    # the ODE's conserved quantity is the PDE's too: total angular momentum = 2 pi L p_chi.
    # Round-off bound as in test_equilibrium_conservation: EPS (n + 2 sqrt(n N)) for n = 40
    # nodes and N = T/dt rounded momentum updates (a random walk), the spin being uniform.
    p_chi = (model.rho_a * SCENE.R**2 + model.rho_j) * SCENE.omega
    n, steps = 40, TIMES[-1] / DTS[1]
    L = runs[DTS[1]].angular_momentum.values
    np.testing.assert_allclose(L, 2 * math.pi * SCENE.L * p_chi, rtol=EPS * (n + 2 * math.sqrt(n * steps)))
