"""Small twists travel at the shear speed sqrt(mu/rho); the semi-discrete solution converges at order 2 in s.

Torsion of the natural cylinder (``r = 1``, ``z = s``, ``theta = psi = 0``) in the model:
the table gives ``F31 = (1 + zeta) chi_s`` (``beta3 = r chi_s`` plus ``zeta (psi_s + chi_s)``),
``F33 = 1``, so the stored energy of a small twist is ``mu/2 chi_s^2 int (1 + zeta)^3 dzeta``
and the kinetic energy is ``(rhoA + rhoJ) chi_t^2 / 2 = rho/2 chi_t^2 int (1 + zeta)(1 + zeta^2) dzeta``
(``|r_t|^2 = chi_t^2``, ``|d_t|^2 = chi_t^2``). Since
``int (1 + zeta)^3 = int (1 + zeta)(1 + zeta^2) + 2 int zeta (1 + zeta)``, the two moments are equal
exactly when ``rhoI = rho int zeta (1 + zeta) dzeta = 0``: then ``chi_tt = (mu/rho) chi_ss`` for
every thickness ``h``, the 3-D torsional wave of a hollow cylinder (whose lateral faces are
traction-free under pure torsion). With ``rhoI != 0`` the ``rhoI r_t . d_t`` term would have
to supply the missing ``2 rhoI``. The psi-equation is satisfied by ``psi = 0`` for the same
reason: its flux ``mu chi_s int zeta (1 + zeta)^2`` over its inertia ``rhoJ`` is again ``mu/rho``.
Free ends (``m^s . c1 = 0``, ``n^s . a3 = 0``) make ``chi_s = 0`` there, so the modes are
``chi = eps cos(k pi s / L)`` with ``omega_k = sqrt(mu/rho) k pi / L``.

The discretisation (cell energy with differences, nodal masses with half weights at the
ends) turns this into the Neumann second difference, for which ``cos(k pi s_i / L)`` is an
exact eigenvector (mirror-symmetric ghost node), with the discrete frequency
``omega_k,h = (2 c / ds) sin(k pi ds / (2 L))`` = ``omega_k (1 - (k pi ds / L)^2 / 24 + ...)``.
"""

import math

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import mol_shell
import reference_ring as ref
from mol_shell.discretization.system import ShellSystem
from mol_shell.integrators import Leapfrog

EPS = np.finfo(float).eps
NATURAL = mol_shell.TwistedCylinder(gamma=0.0, R=1.0, omega=0.0, psi0=0.0)
LAM, MU = ref.lame(NATURAL.E, NATURAL.nu)
C_SHEAR = math.sqrt(MU / NATURAL.rho)  # 18.3 m/s


def exact_frequency(k, L=NATURAL.L):
    return C_SHEAR * k * math.pi / L


def discrete_frequency(k, n, L=NATURAL.L):
    ds = L / (n - 1)
    return 2 * C_SHEAR / ds * math.sin(k * math.pi * ds / (2 * L))


def _sparse_jacobian(system, y):
    J = system.jac(0, y)
    sp = J.sparsity()
    return scipy.sparse.csc_matrix((np.array(J.nonzeros()).ravel(), sp.row(), sp.colind()), shape=J.shape)


def torsional_eigenfrequency(system, A, k):
    """Frequency of the eigenpair of ``A`` (the Jacobian at the natural state) whose eigenvector is the k-th torsional mode.

    Shift-invert Arnoldi around ``i omega_k`` returns the nearby eigenpairs; the one whose
    ``chi``-part is closest to ``cos(k pi s/L)`` is picked. Returns the frequency, that
    overlap (1 for the exact mode) and the size of the ``psi``-part relative to the ``chi``-part.
    """
    values, vectors = scipy.sparse.linalg.eigs(A, k=6, sigma=1j * exact_frequency(k))
    fields = vectors.reshape(system.n, 10, -1)
    chi, psi = fields[:, 2, :], fields[:, 4, :]
    mode = np.cos(k * math.pi * system.s / NATURAL.L)
    overlap = np.abs(mode @ chi) / (np.linalg.norm(chi, axis=0) * np.linalg.norm(mode))
    j = int(np.argmax(overlap))
    return abs(values[j].imag), overlap[j], np.linalg.norm(psi[:, j]) / np.linalg.norm(chi[:, j])


@pytest.mark.slow
def test_torsional_modes_converge_to_the_shear_wave_at_order_two():
    """Eigenvalues of ``system.jac`` on ``n = 20, 40, 80, 160`` for the k = 1 and k = 2 torsional modes.

    * the eigenvector is the torsional mode: overlap with ``cos(k pi s/L)`` is 1, ``psi``-part 0;
    * the frequency equals the discrete prediction ``(2c/ds) sin(k pi ds/(2L))``. Accuracy
      of a computed eigenvalue: the linear Hamiltonian system is normal in the energy inner
      product, so shift-invert Arnoldi gets ``omega`` to ~EPS times the spectral radius
      (~5e3 .. 1e4 1/s here, i.e. ~1e-12 1/s) times a modest scaling factor: 1e-10 relative
      on ``omega ~ 14`` 1/s allows a factor ~1000;
    * the error against ``sqrt(mu/rho) k pi/L`` decays as ``ds^2``: it is ``omega_k x^2/6 (1 - x^2/20 ...)``
      with ``x = k pi ds/(2L) <= 0.17``, so the fitted slope is 2 to within ``x^2/10 < 0.003``; we allow 0.05.
    """
    ns = np.array([20, 40, 80, 160])
    errors = {1: [], 2: []}
    for n in ns:
        system = ShellSystem(NATURAL, int(n))
        A = _sparse_jacobian(system, system.initial_state(NATURAL))
        for k in errors:
            omega, overlap, psi_part = torsional_eigenfrequency(system, A, k)
            assert overlap > 1 - 1e-10 and psi_part < 1e-10, (n, k, overlap, psi_part)
            assert abs(omega - discrete_frequency(k, n)) <= 1e-10 * omega, (n, k, omega, discrete_frequency(k, n))
            errors[k].append(abs(omega - exact_frequency(k)) / exact_frequency(k))
    ds = NATURAL.L / (ns - 1)
    for k in errors:
        slope = np.polyfit(np.log(ds), np.log(errors[k]), 1)[0]
        assert abs(slope - 2.0) <= 0.05, (k, slope, errors[k])
        assert errors[k][-1] < 1e-4  # n = 160: within 0.01 % of the 3-D shear wave


def test_small_twist_period_in_a_nonlinear_leapfrog_run():
    """``chi = 1e-4 cos(pi s/L)`` at rest on n = 40: the period of ``chi(0, t)`` is the discrete prediction.

    Prediction: leap-frog advances a linear oscillation of frequency ``w`` with frequency
    ``arcsin(w dt)/dt``; with ``w = omega_1,h`` (discrete Neumann torsion, n = 40) the period
    is ``T = 2 pi dt / arcsin(w dt)``. Remaining differences: the nonlinear shift, at most
    ``O(twist^2 lambda/mu) ~ (1e-4 pi/4)^2 x 50 ~ 3e-7`` relative; the cubic-spline crossing
    times (samples every 1e-3 s, ``(w Delta)^4 / 384 ~ 1e-10``). We assert 1e-6 (3x the
    first), which is 270x smaller than the gap (2.7e-4) between the discrete and the
    continuum period, so the measurement resolves the discretisation.
    """
    n, eps, dt = 40, 1e-4, 5e-5
    system, compiled = mol_shell.build(NATURAL, n)
    Q = np.zeros((5, n))
    Q[0] = system.s
    Q[1] = 1.0
    Q[2] = eps * np.cos(math.pi * system.s / NATURAL.L)
    y0 = system.pack(Q, np.zeros((5, n)))
    w = discrete_frequency(1, n)
    period = 2 * math.pi * dt / math.asin(w * dt)
    times = np.arange(0.0, 3.2 * period, 1e-3)
    times = np.rint(times / dt) * dt
    traj = Leapfrog(dt=dt).integrate(system, compiled, y0, times)
    assert traj.status == "complete"
    chi0 = system.unpack(traj.y)[:, 2, 0]
    crossings = CubicSpline(traj.t, chi0).roots(extrapolate=False)
    assert len(crossings) >= 6
    half_periods = np.polyfit(np.arange(len(crossings)), crossings, 1)[0]
    measured = 2 * half_periods
    assert abs(measured - period) <= 1e-6 * period, (measured, period)
    continuum = 2 * math.pi / exact_frequency(1)
    assert abs(measured - continuum) > 100 * 1e-6 * continuum
    # a nonlinear run that stayed linear-sized: amplitude preserved, no other field excited
    assert np.abs(chi0).max() <= eps * (1 + 1e-6)
    assert np.abs(system.unpack(traj.y)[:, 4]).max() < 1e-6 * eps


# ---------------------------------------------------------------------------------------
# 6. spatial order of the nonlinear semi-discrete solution
# ---------------------------------------------------------------------------------------
A_Z, A_R, A_CHI = 0.002, 0.005, 0.2  # m, m, rad: a nonlinear-sized twist (the paper's chi spans +-0.2)


def smooth_state(system):
    """Smooth data compatible with the boundary conditions, at rest.

    ``z = s + A_Z sin(2 pi s/L)`` (z fixed at the ends), ``r = 1 + A_R cos(pi s/L)`` and
    ``chi = A_CHI cos(pi s/L)`` (zero slope at the free ends), ``theta = atan(r_s/z_s)``
    (shear-free: ``beta2 = 0``; vanishes at the ends), ``psi = 0``.
    """
    s, L = system.s, system.scene.L
    z = s + A_Z * np.sin(2 * np.pi * s / L)
    z_s = 1 + A_Z * 2 * np.pi / L * np.cos(2 * np.pi * s / L)
    r = 1 + A_R * np.cos(np.pi * s / L)
    r_s = -A_R * np.pi / L * np.sin(np.pi * s / L)
    Q = np.array([z, r, A_CHI * np.cos(np.pi * s / L), np.arctan2(r_s, z_s), 0 * s])
    return system.pack(Q, system.momenta(Q, np.zeros_like(Q)))


def _solve_smooth(n, t_end, rtol, atol):
    """``smooth_state`` on ``n`` nodes advanced to ``t_end`` by DOP853 on the compiled RHS; fields ``(5, n)``."""
    system, compiled = mol_shell.build(NATURAL, n)
    f = compiled.evaluator()
    sol = solve_ivp(lambda t, y: f(y).copy(), (0.0, t_end), smooth_state(system), method="DOP853",
                    rtol=rtol, atol=atol, t_eval=[t_end])
    assert sol.success, sol.message
    return system.unpack(sol.y[:, -1])


@pytest.mark.slow
def test_nonlinear_solution_converges_at_second_order_in_s():
    """All five fields, ``n = 81, 161, 321, 641`` (nested: ``ds`` halves from 0.05 m), DOP853 at rtol 1e-10 to 0.02 s.

    The cell strains are centred differences, ``r`` and ``theta`` midpoint averages, ``psi``
    sampled at the nodes (trapezoid), the nodal masses trapezoidal: all second order. The half
    cells at the free ends make a first-order local error at one node, which costs
    ``O(ds) x ds`` globally, so the error is ``C ds^2 (1 + D ds^2 + ...)`` and the order measured
    from successive differences at the 81 common nodes, ``log2(e(ds)/e(ds/2))``, is
    ``2 + (3/(4 ln 2)) D ds^2 + ...``: its deviation from 2 is the relative ``O(ds^2)`` correction,
    and it shrinks 4x per halving.

    * ``z, r, chi`` carry the data's own scales (wavelengths ``L`` and ``2L``, and what a
      0.37 m travel of the twist wave makes of them in 0.02 s). A correction ``D ~ k^2/12``
      moves the order by ``~0.09 (k ds)^2``; the band ``|order - 2| <= 0.01`` at ``ds = 0.05``
      admits wave numbers up to ``k ~ 6.7`` 1/m (wavelength ``~L/4``), well above the data's.
    * ``theta`` (``~3e-3`` rad) and ``psi`` (``~4e-6`` rad) are small fields slaved to
      derivatives of the others through the transverse shear and bending, with lengths
      ``h sqrt((lambda + 2 mu)/(3 mu)) = 0.026`` m and ``h/sqrt(3) = 0.004`` m below the grid
      spacing: their error takes more derivatives of the data, and the relative correction is
      larger. Wider bands, ``|order - 2| <= 0.3`` for the first pair and ``<= 0.1`` for the
      second, and the ``O(ds^2)`` signature itself: the deviation must shrink at least 2x per
      halving (4x expected). (Before the nodal ``psi`` rule, ``psi`` did not converge at order 2.)

    Time error: the tolerance is per step; at ``n = 81`` the rtol 1e-10 solution is checked
    against one at rtol 1e-12. An error ``e_t`` in the differences moves a measured order by at
    most ``2 e_t / (ln 2 x finest difference)``; that must stay below a tenth of the field's band
    (measured: ``1e-7`` of it for ``z, r, chi``, 0.26 of it for ``psi``). The finer grids take more,
    stability-limited, steps at the same rtol.
    """
    t_end, ns = 0.02, (81, 161, 321, 641)
    solutions = {n: _solve_smooth(n, t_end, 1e-10, 1e-12) for n in ns}
    common = {n: solutions[n][:, :: (n - 1) // 80] for n in ns}
    tighter = _solve_smooth(81, t_end, 1e-12, 1e-14)
    bands = {"z": (0.01, 0.01), "r": (0.01, 0.01), "chi": (0.01, 0.01), "theta": (0.3, 0.1), "psi": (0.3, 0.1)}
    for k, name in enumerate(("z", "r", "chi", "theta", "psi")):
        diffs = np.array([np.abs(common[a][k] - common[b][k]).max() for a, b in zip(ns, ns[1:])])
        deviation = np.log2(diffs[:-1] / diffs[1:]) - 2.0
        assert np.all(np.abs(deviation) <= bands[name]), (name, deviation + 2, diffs)
        if name in ("theta", "psi"):
            assert abs(deviation[1]) <= abs(deviation[0]) / 2, (name, deviation + 2)
        time_error = np.abs(solutions[81][k] - tighter[k]).max()
        assert 2 * time_error / (math.log(2) * diffs[-1]) <= bands[name][1] / 10, (name, time_error, diffs[-1])
