"""Closed-form linear modes of the natural cylinder against the spectrum of the package's exact Jacobian.

The natural cylinder (``r0 = 1``, ``theta0 = 0``, at rest, ``r = 1``, ``z = s``, every other field
zero) is an equilibrium; ``ShellSystem(scene, n).jac(0, y0)`` linearises the semi-discrete system
about it. Everything compared with it below is derived here, from the F table of MODEL_NOTES and
the through-thickness integrals in closed form (``tests/reference_ring.py`` supplies the Lame
constants, the centroidal ``zeta1`` by ``brentq`` and the moments ``rho int zeta^k (1 + zeta)``).

Linear strains (``E = (F^T F - I)/2`` to first order, volume element ``(1 + zeta) dzeta``):

* breathing ``r = 1 + e``: ``F33 = (r + zeta)/(1 + zeta)``, so ``E33 = e/(1 + zeta)``, the only
  component; ``W = (lambda + 2 mu)/2 E33^2`` and ``What = (lambda + 2 mu) e^2/2 ln((1 + zeta2)/(1 + zeta1))``.
  Kinetic energy ``rhoA e_t^2/2`` with ``rhoA = rho 2h (1 + zeta1 + h)``. Hence
  ``omega_b^2 = (lambda + 2 mu) ln(...) / rhoA``, for any base surface ``zeta1``;
* twist and shear (``chi``, ``psi``): ``E13 = [(1 + zeta) chi_s + zeta psi_s]/2``,
  ``E23 = psi/(2 (1 + zeta))``, trace zero, so ``W = mu/2 [(1 + zeta) chi_s + zeta psi_s]^2 +
  mu/2 psi^2/(1 + zeta)^2``; the kinetic energy ``rho/2 int |r_t + zeta d_t|^2 (1 + zeta)`` is
  ``rhoA/2 chi_t^2 + rhoI chi_t (chi_t + psi_t) + rhoJ/2 (chi_t + psi_t)^2``
  (``r_t = chi_t a3``, ``d_t = (chi_t + psi_t) a3``);
* the two groups do not couple: the breathing, axial and bending strains are ``E11, E33, E12``,
  the twist/shear ones ``E13, E23`` with zero trace, and at rest the mass matrix is block diagonal.

Kelvin-Voigt (``S_visc = eta_lambda tr(E_t) I + 2 eta_mu E_t``): the Rayleigh function is the
stored energy's quadratic form with ``(lambda, mu) -> (eta_lambda, eta_mu)`` evaluated on the
rates, so ``C = K(eta)``. On the twist/shear block (trace-free strains) that is ``C = (eta_mu/mu) K``
and ``eta_lambda`` cannot enter; on breathing ``C = (eta_lambda + 2 eta_mu) ln(...)``. A mode with
``K v = omega^2 M v`` and ``C v = 2 a M v`` solves ``M x'' + C x' + K x = 0`` with
``x = v e^{lam t}``, ``lam^2 + 2 a lam + omega^2 = 0``: ``lam = -a +- sqrt(a^2 - omega^2)``, i.e.
``-a +- i sqrt(omega^2 - a^2)`` when underdamped. Plane stress replaces ``lambda`` and ``eta_lambda``
by ``2 lambda mu/(lambda + 2 mu)`` and ``2 eta_lambda eta_mu/(eta_lambda + 2 eta_mu)``.

The discrete system inherits these modes exactly: every cell of a uniform mode has the same
strains (the end nodes carry half a cell's energy, dissipation and mass, and the ``theta``/``z``
forces of the common ``lambda E11 E33`` coupling cancel between neighbouring cells, and are
discarded at the ends where ``z`` and ``theta`` are fixed); the torsional modes
``chi = cos(k pi s/L)`` are exact eigenvectors of the Neumann second difference with half
weights at the ends, ``omega_k,h = (2c/ds) sin(k pi ds/(2L))``, ``c = sqrt(mu/rho)``
(see ``test_waves_convergence.py``).

Two checks per mode: (1) the closed-form eigenpair is an eigenpair of ``J``: the residual
``|J x - lam x|`` is round-off; (2) the nearest computed eigenvalue of ``J`` equals ``lam`` within
its own round-off bound (see :func:`nearest_eigenvalue`). The state layout is node-major
(``y[10 i + k]``: field ``k`` of node ``i``, ``y[10 i + 5 + k]`` its momentum), momenta
``p = 2 pi w dT/dv`` with trapezoid weights ``w`` (``ds/2`` at the ends).
"""

import dataclasses
import math
from functools import lru_cache

import numpy as np
import pytest
import scipy.linalg

import mol_shell
import reference_ring as ref
from mol_shell.discretization.system import ShellSystem

EPS = np.finfo(float).eps
NATURAL = mol_shell.TwistedCylinder(gamma=0.0, R=1.0, omega=0.0, psi0=0.0)
H = NATURAL.h
N = 8  # nodes: every mode below is exact on any grid; 8 keeps the SX Jacobian cheap (~0.3-1 s)
R, CHI, PSI = 1, 2, 4  # field indices in the node-major state
MATERIALS = ("svk", "svk-plane-stress")


# ---------------------------------------------------------------------------------------
# closed forms (independent of the package)
# ---------------------------------------------------------------------------------------
@dataclasses.dataclass
class Shell:
    """Material constants and thickness integrals of a scene, in closed form."""

    lam: float
    mu: float
    eta_lambda: float
    eta_mu: float
    rho: float
    zeta1: float
    zeta2: float
    rho_a: float
    rho_i: float
    rho_j: float
    log: float  # int_{zeta1}^{zeta2} dzeta / (1 + zeta) = ln((1 + zeta2)/(1 + zeta1))


def shell_constants(scene):
    lam, mu = ref.lame(scene.E, scene.nu)
    eta_lambda, eta_mu = scene.eta_lambda, scene.eta_mu
    if scene.material == "svk-plane-stress":  # S22 = 0 condensed out of each isotropic law
        lam = 2 * lam * mu / (lam + 2 * mu)
        eta_lambda = 2 * eta_lambda * eta_mu / (eta_lambda + 2 * eta_mu) if eta_lambda + 2 * eta_mu else 0.0
    zeta1 = ref.zeta1_centroidal(scene.h) if scene.zeta1 is None else scene.zeta1
    zeta2 = zeta1 + 2 * scene.h
    rho_a, rho_i, rho_j = ref.inertias(scene.rho, scene.h, zeta1)
    # the task's closed forms of rhoA and rhoJ, as a check on the moments themselves
    assert rho_a == pytest.approx(scene.rho * 2 * scene.h * (1 + zeta1 + scene.h), rel=1e-14)
    assert rho_j == pytest.approx(scene.rho * ((zeta2**3 - zeta1**3) / 3 + (zeta2**4 - zeta1**4) / 4), rel=1e-12)
    # ln((1 + zeta2)/(1 + zeta1)) as log1p(2h/(1 + zeta1)): the ratio is 1.0126, and taking log of
    # its rounded value would lose a factor 1/ln(ratio) ~ 80 in relative accuracy (~1e-14)
    log = math.log1p(2 * scene.h / (1 + zeta1))
    return Shell(lam, mu, eta_lambda, eta_mu, scene.rho, zeta1, zeta2, rho_a, rho_i, rho_j, log)


def damped(omega2, a):
    """Root ``-a + sqrt(a^2 - omega^2)`` of ``lam^2 + 2 a lam + omega^2 = 0`` (upper half plane when underdamped).

    Overdamped, the slow root is written ``-omega^2 / (a + sqrt(a^2 - omega^2))`` (no cancellation).
    """
    if a * a > omega2:
        return complex(-omega2 / (a + math.sqrt(a * a - omega2)))
    return complex(-a, math.sqrt(omega2 - a * a))


def twist_mass(c):
    """Mass matrix per unit area of ``(chi_t, psi_t)`` at rest.

    The Hessian of ``rhoA/2 chi_t^2 + rhoI chi_t (chi_t + psi_t) + rhoJ/2 (chi_t + psi_t)^2``.
    """
    return np.array([[c.rho_a + 2 * c.rho_i + c.rho_j, c.rho_i + c.rho_j], [c.rho_i + c.rho_j, c.rho_j]])


def breathing_eigenvalue(c):
    """``K = (lambda + 2 mu) ln``, ``C = (eta_lambda + 2 eta_mu) ln`` per unit area, mass ``rhoA``."""
    return damped((c.lam + 2 * c.mu) * c.log / c.rho_a, (c.eta_lambda + 2 * c.eta_mu) * c.log / (2 * c.rho_a))


def shear_eigenvalue(c):
    """Uniform ``psi`` with the ``chi`` recoil that keeps the angular momentum zero.

    Stiffness ``mu ln`` on ``psi`` only (``chi`` uniform is a rigid rotation), mass
    :func:`twist_mass`: ``det(K - w^2 M) = 0`` gives ``w^2 = mu ln M_chichi / det M``; with
    ``rhoI = 0`` that is ``mu ln (rhoA + rhoJ) / (rhoA rhoJ)``. Damping ``C = (eta_mu/mu) K``.
    """
    M = twist_mass(c)
    omega2 = c.mu * c.log * M[0, 0] / np.linalg.det(M)
    return damped(omega2, c.eta_mu / c.mu * omega2 / 2)


def torsion_eigenvalue(c, k, n, L):
    """Discrete torsional mode ``k``: ``w_h = (2c/ds) sin(k pi ds/(2L))``, damping ``C = (eta_mu/mu) K``."""
    ds = L / (n - 1)
    omega2 = (2 * math.sqrt(c.mu / c.rho) / ds * math.sin(k * math.pi * ds / (2 * L))) ** 2
    return damped(omega2, c.eta_mu / c.mu * omega2 / 2)


def state_vector(n, fields, momenta):
    """Node-major complex state from per-field nodal shapes ``{index: array}`` and momenta."""
    x = np.zeros((n, 10), complex)
    for k, v in fields.items():
        x[:, k] = v
    for k, v in momenta.items():
        x[:, 5 + k] = v
    return x.ravel()


def weights(n, L):
    ds = L / (n - 1)
    w = np.full(n, ds)
    w[[0, -1]] = ds / 2
    return w


def breathing_mode(c, lam, n, L):
    """``r = 1`` at every node, ``p_r = lam 2 pi w rhoA``."""
    return state_vector(n, {R: np.ones(n)}, {R: lam * 2 * math.pi * weights(n, L) * c.rho_a})


def twist_mode(c, lam, n, L, chi, psi):
    """Nodal ``chi``, ``psi`` shapes, momenta ``lam 2 pi w M (chi, psi)``."""
    M, w = twist_mass(c), 2 * math.pi * weights(n, L)
    p_chi = lam * w * (M[0, 0] * chi + M[0, 1] * psi)
    p_psi = lam * w * (M[1, 0] * chi + M[1, 1] * psi)
    return state_vector(n, {CHI: chi, PSI: psi}, {CHI: p_chi, PSI: p_psi})


def shear_mode(c, lam, n, L):
    """Uniform ``psi = 1`` and ``chi = -M_chipsi/M_chichi`` (zero angular momentum)."""
    M = twist_mass(c)
    return twist_mode(c, lam, n, L, -M[0, 1] / M[0, 0] * np.ones(n), np.ones(n))


def torsion_mode(c, lam, n, L, k):
    s = np.linspace(0.0, L, n)
    return twist_mode(c, lam, n, L, np.cos(k * math.pi * s / L), np.zeros(n))


# ---------------------------------------------------------------------------------------
# the package's Jacobian and the two checks
# ---------------------------------------------------------------------------------------
@lru_cache(maxsize=None)
def jacobian(scene, n=N):
    system = ShellSystem(scene, n)
    y0 = system.initial_state(scene)
    Q = system.unpack(y0)
    assert np.all(Q[1] == 1.0) and not np.any(Q[2:]), "the linearisation point must be the natural state"
    return np.array(system.jac(0, y0))


def check_eigenpair(J, x, lam, kappa=1.0):
    """``|J x - lam x|_inf <= 30 EPS kappa max(|J||x| + |lam||x|)``; returns the ratio residual / bound.

    Round-off on both sides of the comparison: the closed-form pair carries about ten roundings
    (``lam`` from a square root of a quotient of products, ``p = lam 2 pi w rhoA``, ...), each
    ``<= EPS/2`` relative; each entry of ``J`` is a short sum over the 4 Gauss points of the
    thickness and a few terms, and forming ``J x`` adds ``EPS |J||x|`` per row: in all some 30
    ``EPS`` of the row's magnitude ``|J||x| + |lam||x|``. The velocity rows are ``M^-1 p`` per node,
    a solve with the nodal mass matrix whose condition number ``kappa`` (``~ rhoA/rhoJ ~ 8e4`` for
    the twist/shear block, 1 for breathing) amplifies those errors. Measured: residual / bound
    <= 0.11 (breathing, svk), far smaller elsewhere. A model error (a wrong moment, a missing
    or doubled viscous term) leaves a residual of its own relative size (>= 1e-6 for anything
    physical, e.g. the ``h^2`` corrections), far above this bound (<= 1e-9 relative).
    """
    residual = np.abs(J @ x - lam * x).max()
    bound = 30 * EPS * kappa * (np.abs(J) @ np.abs(x) + abs(lam) * np.abs(x)).max()
    assert residual <= bound, (lam, residual, bound)
    return residual / bound


def nearest_eigenvalue(J, lam):
    """The eigenvalue of ``J`` nearest ``lam`` and its round-off bound ``10 s EPS ||B||_2``.

    ``B`` is ``J`` balanced by a diagonal similarity (same eigenvalues; LAPACK balances too).
    The QR algorithm returns the eigenvalues of ``B + dB`` with ``||dB|| <= p EPS ||B||``
    (``p`` a modest constant; the elementwise rounding of ``J``'s entries is a perturbation of
    the same kind, diagonal scaling preserves it), and a simple eigenvalue moves by at most
    ``s ||dB||`` to first order, ``s = ||y|| ||x|| / |y^H x|`` its condition number, computed
    here from the eigenvector matrix. ``p = 10``. Measured: the bound is 6e-15 .. 2e-10 of
    ``|lam|``, the actual errors 5e-16 .. 5e-13 of ``|lam|`` and at most 0.18 of the bound.
    """
    B, _ = scipy.linalg.matrix_balance(J)
    values, vectors = np.linalg.eig(B)
    vectors = vectors / np.linalg.norm(vectors, axis=0)
    i = int(np.argmin(np.abs(values - lam)))
    s = np.linalg.norm(np.linalg.inv(vectors)[i])
    return values[i], 10 * s * EPS * np.linalg.norm(B, 2)


def check_spectrum(J, lam):
    """The nearest eigenvalue of ``J`` is ``lam`` within its bound; returns (error, bound) relative to ``|lam|``."""
    value, bound = nearest_eigenvalue(J, lam)
    assert abs(value - lam) <= bound, (lam, value, bound)
    return abs(value - lam) / abs(lam), bound / abs(lam)


# ---------------------------------------------------------------------------------------
# a. elastic breathing;  b. uniform shear with the chi recoil
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("zeta1", [None, -2 * H], ids=["centroidal", "outer-face"])
@pytest.mark.parametrize("material", MATERIALS)
def test_breathing_frequency_is_the_closed_form(material, zeta1):
    """``omega_b^2 = (lambda + 2 mu) ln((1 + zeta2)/(1 + zeta1)) / (rho 2h (1 + zeta1 + h))``.

    (About 130.8 rad/s for the paper's svk, 36.3 for plane stress: ``lambda*`` is 50x smaller.)
    The uniform-``r`` vector is an exact eigenvector of the discrete system for any grid and
    base surface; its eigenvalue ``i omega_b`` is in the spectrum of ``J``.
    """
    scene = dataclasses.replace(NATURAL, material=material, zeta1=zeta1)
    c = shell_constants(scene)
    lam = breathing_eigenvalue(c)
    assert lam.real == 0 and lam.imag > 0
    J = jacobian(scene)
    check_eigenpair(J, breathing_mode(c, lam, N, scene.L), lam)
    check_spectrum(J, lam)
    # the check resolves a thin-shell approximation of the moments (ln -> 2h/(1 + zeta1 + h)):
    value, bound = nearest_eigenvalue(J, lam)
    thin = math.sqrt((c.lam + 2 * c.mu) * 2 * H / (1 + c.zeta1 + H) / c.rho_a)
    assert abs(thin - lam.imag) > 1e3 * bound


@pytest.mark.parametrize("zeta1", [None, -2 * H, -H / 2, 0.0], ids=["centroidal", "-2h", "-h/2", "0"])
def test_uniform_shear_frequency_includes_the_chi_recoil(zeta1):
    """Uniform ``psi`` with the recoil ``chi = -(rhoI + rhoJ)/(rhoA + 2 rhoI + rhoJ) psi``.

    ``omega_psi^2 = mu ln (rhoA + rhoJ)/(rhoA rhoJ)`` for the centroidal base surface (about
    5,050 rad/s), ``mu ln (rhoA + 2 rhoI + rhoJ)/(rhoA rhoJ - rhoI^2)`` in general. The recoil
    raises the frequency by the factor ``sqrt(1 + rhoJ/rhoA) - 1 ~ h^2/6 ~ 7e-6``; the
    spectrum check resolves it (asserted: the frequency without it is excluded).
    """
    scene = dataclasses.replace(NATURAL, zeta1=zeta1)
    c = shell_constants(scene)
    lam = shear_eigenvalue(c)
    J = jacobian(scene)
    check_eigenpair(J, shear_mode(c, lam, N, scene.L), lam, kappa=np.linalg.cond(twist_mass(c)))
    check_spectrum(J, lam)
    no_recoil = math.sqrt(c.mu * c.log / c.rho_j)
    _, bound = nearest_eigenvalue(J, lam)
    assert abs(no_recoil - lam.imag) > 100 * bound


# ---------------------------------------------------------------------------------------
# c. Kelvin-Voigt damping in closed form
# ---------------------------------------------------------------------------------------
VISCOSITIES = [(4000.0, 500.0), (1.0e4, 0.0), (0.0, 500.0)]  # eta_lambda != 2 eta_mu; eta_mu = 0; eta_lambda = 0


@pytest.mark.parametrize("eta_lambda,eta_mu", VISCOSITIES)
@pytest.mark.parametrize("material", MATERIALS)
def test_viscous_eigenvalues_are_the_closed_form(material, eta_lambda, eta_mu):
    """Breathing, the torsional modes ``k = 1, 2, 3`` and the (overdamped) shear mode, with damping.

    * breathing: ``lam = -C/(2 rhoA) + i sqrt(K/rhoA - (C/(2 rhoA))^2)``,
      ``C = (eta_lambda + 2 eta_mu) ln``: ``eta_lambda`` enters here (condensed for plane stress,
      where ``eta_mu = 0`` leaves no breathing damping at all);
    * torsion: ``lam = -(eta_mu/(2 mu)) w_h^2 + i sqrt(w_h^2 - (eta_mu w_h^2/(2 mu))^2)``,
      independent of ``eta_lambda`` (``tr E_t = 0``): with ``eta_mu = 0`` undamped;
    * shear (``~5e3`` rad/s): ``eta_mu w^2/(2 mu) > w`` for these viscosities, two real roots; the
      slower one, ``-a + sqrt(a^2 - w^2)``, is checked.

    Asserted besides: a halved ``eta_lambda`` term would move the breathing eigenvalue by far
    more than the tolerance (so the test detects it).
    """
    scene = dataclasses.replace(NATURAL, material=material, eta_lambda=eta_lambda, eta_mu=eta_mu)
    c = shell_constants(scene)
    J = jacobian(scene)
    kappa = np.linalg.cond(twist_mass(c))

    lam = breathing_eigenvalue(c)
    check_eigenpair(J, breathing_mode(c, lam, N, scene.L), lam)
    check_spectrum(J, lam)
    if c.eta_lambda > 0:
        halved = breathing_eigenvalue(dataclasses.replace(c, eta_lambda=c.eta_lambda / 2))
        _, bound = nearest_eigenvalue(J, lam)
        assert abs(halved - lam) > 1e3 * bound
    for k in (1, 2, 3):
        lam = torsion_eigenvalue(c, k, N, scene.L)
        assert (lam.real == 0) == (eta_mu == 0)
        check_eigenpair(J, torsion_mode(c, lam, N, scene.L, k), lam, kappa)
        check_spectrum(J, lam)
    lam = shear_eigenvalue(c)
    if eta_mu > 0:
        assert lam.imag == 0 and lam.real < 0  # overdamped
    check_eigenpair(J, shear_mode(c, lam, N, scene.L), lam, kappa)
    check_spectrum(J, lam)


def test_eta_lambda_does_not_damp_torsion():
    """Same ``eta_mu``, ``eta_lambda`` from 0 to 5e4 Pa s: the torsional eigenvalues do not move.

    Compared computed against computed (no closed form involved) within the sum of their
    round-off bounds; the breathing eigenvalue, by contrast, moves (its decay rate by
    ``eta_lambda ln / (2 rhoA) = 2`` 1/s), so the two scenes do differ. (Both Jacobians are
    the ones of the parametrised test above, cached.)
    """
    scenes = [dataclasses.replace(NATURAL, eta_lambda=eta_lambda, eta_mu=500.0) for eta_lambda in (0.0, 4000.0)]
    Js = [jacobian(scene) for scene in scenes]
    c = shell_constants(scenes[0])
    for k in (1, 2, 3):
        (a, bound_a), (b, bound_b) = (nearest_eigenvalue(J, torsion_eigenvalue(c, k, N, NATURAL.L)) for J in Js)
        assert abs(a - b) <= bound_a + bound_b, (k, a, b)
    (a, bound_a), (b, bound_b) = (nearest_eigenvalue(J, breathing_eigenvalue(c)) for J in Js)
    assert abs(a.real - b.real) > 100 * (bound_a + bound_b)


# ---------------------------------------------------------------------------------------
# d. rhoI != 0: the torsional wave is exact for every base surface
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("zeta1,eta_mu", [(-2 * H, 0.0), (-H / 2, 0.0), (0.0, 0.0), (-2 * H, 500.0)],
                         ids=["-2h", "-h/2", "0", "-2h-viscous"])
def test_torsional_modes_are_exact_for_any_base_surface(zeta1, eta_mu):
    """``w_h = (2c/ds) sin(k pi ds/(2L))``, ``c = sqrt(mu/rho)``, whatever ``zeta1``.

    With ``psi = 0`` the chi equation has stiffness ``mu int (1 + zeta)^3`` against inertia
    ``rhoA + 2 rhoI + rhoJ = rho int (1 + zeta)(1 + 2 zeta + zeta^2) = rho int (1 + zeta)^3``, and
    the psi equation flux ``mu chi_s int zeta (1 + zeta)^2`` against ``(rhoI + rhoJ) chi_tt`` with
    ``rhoI + rhoJ = rho int zeta (1 + zeta)^2``: both ratios are ``mu/rho``, so ``psi`` stays 0 and the
    3-D torsional wave of a hollow cylinder is exact. The ``rhoI`` kinetic term supplies
    ``2 rhoI`` and ``rhoI``: with its sign flipped the chi inertia would become
    ``rho int (1 + zeta)^3 - 4 rhoI`` and the frequency change by ``~ 2 |rhoI| / (rho 2h)``, 0.6 % at
    ``zeta1 = -h/2`` and 1.3 % at ``-2h`` and ``0`` (asserted far outside the tolerance; an
    estimate that ignores the psi coupling, enough to show the test resolves it).
    """
    scene = dataclasses.replace(NATURAL, zeta1=zeta1, eta_mu=eta_mu)
    c = shell_constants(scene)
    assert abs(c.rho_i) > 1e-3 * c.rho_a * H  # really off the centroidal placement
    # the two moment identities the exactness rests on, in closed form
    m3 = ((1 + c.zeta2) ** 4 - (1 + c.zeta1) ** 4) / 4  # int (1 + zeta)^3
    m12 = ref._moment(1, c.zeta1, c.zeta2) + ref._moment(2, c.zeta1, c.zeta2)  # int zeta (1 + zeta)^2
    assert c.rho_a + 2 * c.rho_i + c.rho_j == pytest.approx(c.rho * m3, rel=1e-12)
    assert c.rho_i + c.rho_j == pytest.approx(c.rho * m12, rel=1e-12)
    J = jacobian(scene)
    kappa = np.linalg.cond(twist_mass(c))
    for k in (1, 2, 3):
        lam = torsion_eigenvalue(c, k, N, scene.L)
        check_eigenpair(J, torsion_mode(c, lam, N, scene.L, k), lam, kappa)
        check_spectrum(J, lam)
        # a flipped rhoI sign: inertia rho int (1 + zeta)^3 - 4 rhoI
        flipped = lam * math.sqrt(c.rho * m3 / (c.rho * m3 - 4 * c.rho_i))
        _, bound = nearest_eigenvalue(J, lam)
        assert abs(flipped - lam) > 1e3 * bound
    lam = breathing_eigenvalue(c)
    check_eigenpair(J, breathing_mode(c, lam, N, scene.L), lam)
    check_spectrum(J, lam)


def test_the_inverse_mass_matrix_is_inverted_block_by_block():
    """``block_inverse`` inverts a sparse matrix by the connected components of its pattern (a node's coordinates
    for the inverse mass matrix): the exact inverse of a permuted block-diagonal matrix with blocks of several
    sizes. It replaced scipy's column-by-column sparse inverse, quadratic in n (modes at n = 30,000: minutes)."""
    import scipy.sparse

    from mol_shell.analysis.modes import block_inverse

    rng = np.random.default_rng(3)
    blocks = [rng.standard_normal((m, m)) + 4 * np.eye(m) for m in (5, 5, 3, 1, 5, 4, 5)]
    A = scipy.sparse.block_diag(blocks).tocsc()
    order = rng.permutation(A.shape[0])
    A = A[order][:, order].tocsc()
    B = block_inverse(A)
    assert B.nnz == sum(m * m for m in (5, 5, 3, 1, 5, 4, 5))
    np.testing.assert_allclose((A @ B).toarray(), np.eye(A.shape[0]), atol=1e-13)
