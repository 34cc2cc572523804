"""Uniform equilibria: the radius of the uniformly twisted cylinder, and the stable step of leap-frog."""

from __future__ import annotations

import contextlib
import dataclasses
import math

import casadi as ca
import numpy as np
from threadpoolctl import threadpool_limits

from mol_shell._core.constants import DENSE_MAX_STATES
from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Interval
from mol_shell.model.laws import scene_shell_energy
from mol_shell.model.loads import history
from mol_shell.model.material import Thickness

#: dense eigenvalue problems up to this size run on one BLAS thread: at n = 40 (a 200 x 200 product) two
#: OpenBLAS threads gain nothing, and on a machine whose other core is busy (a study's second process, a
#: compiler) their spinning made the spectrum 80 times slower (0.67 s instead of 8 ms a run)
ONE_THREAD_MAX_ROWS = 1000
#: the largest matrix whose eigenvalues :func:`spectrum_bounds` computes densely (a dissipative system's: up to
#: DENSE_MAX_STATES): 0.17 s at 800 rows on one core, 1.0 s at 1,600, where ARPACK took 0.04 s
DENSE_EIG_MAX_ROWS = 800
#: ARPACK's residual tolerance and Krylov space for the largest eigenvalue of a state at rest's ``C D``
#: (:func:`sparse_rest_spectrum`), and the share its Ritz value is raised by: omega_max from its true value to about
#: 5.4e-4 above it (the Ritz value's own error measured within -5.2e-6 .. +3.4e-5)
REST_TOL, REST_NCV, REST_RAISE = 1e-4, 20, 1e-3
#: Newton's iteration for the radius has converged to round-off when its step, below this fraction of R, no longer
#: shrinks
STALLED = 1e-10
#: the most doublings of R (or halvings of R - r_min) in the search for a bracket of the equilibrium radius
MAX_DOUBLINGS = 1100


def blas_threads(rows):
    """One BLAS thread for dense problems of up to :data:`ONE_THREAD_MAX_ROWS` rows, else the library's own."""
    return threadpool_limits(limits=1, user_api="blas") if rows <= ONE_THREAD_MAX_ROWS else contextlib.nullcontext()


def equilibrium_radius(scene, tol=1e-14, max_iter=200):
    """Radius ``R`` at which the uniformly twisted cylinder is in radial equilibrium.

    Solves ``dWhat/dr (z_s = 1, r_s = 0, chi_s = gamma, theta = theta_s = psi = psi_s = 0; r = R) = 0`` on the
    CasADi graph of ``What`` (the paper's "(R, gamma) is an equilibrium state of the material"). For ``gamma = 0``
    the root is the natural radius ``a``. A pressure ``p`` (its value at ``t = 0``) adds ``-p r^2/(2a)`` per unit
    reference area (``-p V``, ``V = pi r^2 L``), so the balance reads ``p = a (dWhat/dr)/r``: the pressure the
    wall holds at ``r`` (for SVK ``h (lambda + 2 mu)(r^2/a^2 - 1)/a`` on a thin wall, rising with ``r``).

    The root of ``G(r) = (dWhat/dr)/r - p/a`` is bracketed first, from ``a`` outwards (doubling ``r``, or halving
    ``r - r_min`` with ``r_min`` where the inner face reaches the axis), then found by Newton's method kept inside
    the bracket (bisection where a step leaves it): Newton from ``a`` alone stopped where the energy's curvature in
    ``r`` turned negative, which a pressure of 2.5e5 Pa does between ``a`` and its root at 1.82 a. No root inside
    the model (an external pressure beyond what the hoop force holds at any radius) is refused naming the
    pressure and that bound.
    """
    a = getattr(scene, "a", 1.0)
    zeta1 = scene.zeta1_used()
    thickness = Thickness(zeta1, scene.h, scene.n_quad)
    r = ca.SX.sym("r")
    energy = scene_shell_energy(scene, (1.0, 0.0, getattr(scene, "gamma", 0.0), 0.0, 0.0, r, 0.0, 0.0), thickness, a)
    # pressure: -p V with V = pi r^2 L, per unit reference area 2 pi a L: -p r^2 / (2a) (follower, at t = 0)
    p0 = getattr(scene, "pressure", 0.0)
    p = p0 * history(scene.load_histories()["pressure"], 0.0) if p0 else 0.0
    held = ca.gradient(energy, r) * a / r  # the pressure the wall holds at r
    balance = ca.Function("balance", [r], [held, ca.jacobian(held, r)])

    def held_at(R):  # the pressure the wall holds at R, and its slope; NaN where the numbers leave double precision
        value, slope = (float(x) for x in balance(R))
        return (value, slope) if math.isfinite(value) and math.isfinite(slope) else (math.nan, math.nan)

    # the inner face on the axis: the search stays inside the model first (a thick wall's held pressure past it is
    # no physics: h = 0.49 of a neo-Hookean wall holds +1.4e8 Pa at r = 0.5, so halving from a stepped over the root
    # at 0.9981 onto one at 0.123); without a pressure it then goes on to the axis, and a root inside the wall's
    # reach (a twist of 1e3 rad/m: R = 5.4e-6 m) is refused, naming what made it, by the caller's check of R
    lo, hi = _bracket(lambda R: held_at(R)[0], p, a, max(-zeta1, 0.0), scene)
    R = a if lo <= a <= hi else 0.5 * (lo + hi)  # from a, an end of the bracket: Newton as before where it goes in
    last = math.inf
    for _ in range(max_iter):
        value, slope = held_at(R)
        value -= p
        if math.isnan(value):
            break
        if value == 0.0:
            return R
        lo, hi = (R, hi) if value < 0 else (lo, R)
        step = value / slope if slope > 0 else math.nan
        # converged, or at round-off: a small step that no longer shrinks (moduli near the smallest normal double
        # leave the force a few digits, and E = 3e-308 ran out of iterations while 2.3e-308 converged)
        if abs(step) < tol * R or STALLED * R > abs(step) >= last:
            return R - step
        new = R - step
        if not lo < new < hi:  # a step out of the bracket: bisect it (geometrically across decades)
            new = math.sqrt(lo * hi) if lo > 0 and hi > 4 * lo else 0.5 * (lo + hi)
        last, R = abs(new - R), new
        if hi - lo <= 4 * math.ulp(hi):  # a bracket a few ulps wide
            return R
    raise ParameterError("gamma", scene.gamma, "twists for which a twisted cylinder has a radial equilibrium")


def _bracket(held_at, p, a, lowest, scene):
    """``(lo, hi)`` with the wall holding less than ``p`` at ``lo`` and more at ``hi``, ``a`` one end: searched
    outwards (doubling ``r``) where ``a`` holds less, inwards (halving ``r - lowest``, ``lowest`` where the inner face
    reaches the axis; then, without a pressure, halving ``r`` towards the axis) where it holds more. Neither
    found: refused, naming the pressure and the most (least) the wall holds where that is why, else (the numbers
    out of double precision first) as a twist without an equilibrium, which the caller diagnoses."""
    value = held_at(a)
    if value == p:
        return a, a
    if math.isnan(value):
        raise ParameterError("gamma", scene.gamma, "twists for which a twisted cylinder has a radial equilibrium")
    outward = value < p
    seen = [(value, a)]
    R = a
    for stage in (lowest, 0.0) if not (outward or p) else (lowest,):  # inwards: the model's radii, then to the axis
        for _ in range(MAX_DOUBLINGS):
            nearer = 2.0 * R if outward else stage + 0.5 * (R - stage)
            if nearer == R or nearer <= stage:
                break
            value = held_at(nearer)
            if math.isnan(value):
                break
            if (value > p) == outward or value == p:
                return (R, nearer) if outward else (nearer, R)
            seen.append((value, nearer))
            R = nearer
    levels_off = outward and len(seen) > 2 and seen[-1][0] - seen[-2][0] <= 1e-9 * abs(seen[-1][0])
    if not p or (outward and not levels_off):  # a push without end out of double precision (the energy overflows)
        raise ParameterError("gamma", scene.gamma, "twists for which a twisted cylinder has a radial equilibrium")
    if outward:  # the hoop force levels off (a rubber balloon's): the most pressure held is the last
        least = seen[-1][0]
    else:  # the least pressure held at any radius, on a fine grid about the least seen (it lies where r - lowest is
        # a few wall thicknesses or less, the inner face near the axis)
        k = min(range(len(seen)), key=lambda i: seen[i][0])
        inner = seen[k + 1][1] if k + 1 < len(seen) else lowest
        outer = seen[max(k - 1, 0)][1]
        grid = [inner + (outer - inner) * i / 400 for i in range(1, 400)]
        least = min([seen[k][0]] + [v for v in map(held_at, grid) if not math.isnan(v)])
    factor = p / scene.pressure  # the pressure history's at t = 0
    bound = least / factor
    allowed = Interval(bound, math.inf, unit="Pa") if (factor > 0) != outward else Interval(-math.inf, bound, unit="Pa")
    held = (f"holds at most {least:.4g} Pa inside (its hoop force levels off as it widens)" if outward else
            f"holds at most {-least:.4g} Pa of external pressure" if least < 0 else f"needs {least:.4g} Pa inside")
    raise ParameterError("pressure", scene.pressure, dataclasses.replace(allowed, shown=f"about {allowed.text()}"),
                         hint=f"at any radius the wall {held} at t = 0: beyond it the cylinder has no radial "
                         "equilibrium")


def spectrum_bounds(jac, y, dissipative=True, positions=None):
    """``(max |lambda|, max(-Re lambda))`` over the eigenvalues of the Jacobian ``jac(0, y)`` (1/s).

    The first bounds the leap-frog step (``dt max|lambda| < 1`` for the imaginary-axis
    spectrum of an elastic shell); the second is the fastest damping rate, which
    leap-frog's parasitic root turns into growth ``exp(max(-Re lambda) t)``.
    Dense for matrices of up to :data:`DENSE_EIG_MAX_ROWS` rows (a dissipative system's up to DENSE_MAX_STATES:
    ARPACK's largest-magnitude eigenvalues missed its fastest damping by 3x at n = 160, and ARPACK's smallest
    real parts did not converge reliably); above, for a state at rest, :func:`sparse_rest_spectrum` (ARPACK on the
    half-size ``C D``, omega_max up to 5.4e-4 above it), else ARPACK's largest-magnitude eigenvalues (relative accuracy ~1e-3,
    enough for a step bound that the energy monitor backs up; a fixed start vector, so the same every time), whose
    real parts estimate the fastest damping (the most damped modes are the shortest); an elastic system
    (``dissipative=False``) has none. ``positions`` (a mask of the position entries of ``y``, the
    rest being rates or momenta) lets a state at rest use :func:`rest_spectrum`, from a matrix of half the size.
    """
    J = jac(0, y)
    size, ev = J.size1(), None
    sp = J.sparsity()
    rows, starts, values = np.array(sp.row()), np.array(sp.colind()), np.array(J.nonzeros()).ravel()
    dense_max = DENSE_MAX_STATES if dissipative else DENSE_EIG_MAX_ROWS
    if size <= dense_max or (positions is not None and size <= 2 * DENSE_EIG_MAX_ROWS):
        dense = np.zeros(J.shape)  # from the nonzeros: casadi's own conversion took 0.16 s at 1,600 rows
        dense[rows, np.repeat(np.arange(J.size2()), np.diff(starts))] = values
        with blas_threads(size):
            ev = rest_spectrum(dense, positions) if positions is not None else None
            if ev is None and size <= dense_max:
                ev = np.linalg.eigvals(dense)
    if ev is None:
        import scipy.sparse.linalg  # large grids only: 0.27 s of a process's start otherwise

        mat = scipy.sparse.csc_matrix((values, rows, starts), shape=J.shape)
        ev = sparse_rest_spectrum(mat, positions) if positions is not None else None
    if ev is None:
        try:
            # the top of a wave spectrum is clustered: a wide Krylov space and a loose tolerance find
            # max |lambda| to ~1e-3 in 0.1-1 s at n = 2560 (k = 6, tol = 1e-6 took 2.6-11 s)
            ev = scipy.sparse.linalg.eigs(mat, k=4, ncv=min(60, mat.shape[0] - 1), which="LM",
                                          return_eigenvectors=False, tol=1e-4, maxiter=20000,
                                          v0=np.random.default_rng(0).standard_normal(mat.shape[0]))
        except scipy.sparse.linalg.ArpackNoConvergence as exc:  # keep what converged
            ev = exc.eigenvalues
            if len(ev) == 0:
                raise
    damping = float(max(0.0, (-ev.real).max())) if dissipative else 0.0
    return float(np.abs(ev).max()), damping


def sparse_rest_spectrum(mat, positions):
    """``+-sqrt(mu)`` for the largest ``|mu|`` among the eigenvalues of ``C D`` (:func:`rest_spectrum`'s blocks of
    the sparse ``mat``), ARPACK on a matrix of half the size with a real spectrum; ``None`` when ``mat`` is not of that
    form (its position-position or rate-rate block does not vanish).

    Accuracy: the bound's use is ``dt < 1/omega_max``, the leap-frog's own stability limit (``y_{k+1} = y_{k-1} +
    2 dt f(y_k)`` on ``y' = i omega y`` has roots of modulus 1 only for ``dt omega <= 1``: no margin), refused with
    the bound shown to 4 significant figures and recorded as ``omega_max_rad_s``. So the estimate must not fall below
    the true value. ARPACK's ``tol`` bounds the residual of a Ritz pair, not the eigenvalue's error, and ``C D``
    (similar to a symmetric matrix at rest, its eigenvalues ``-omega**2`` real, but not symmetric itself: Arnoldi,
    not Lanczos) gives no side for the Ritz value: measured at ``tol = 1e-4`` it lay 1.3e-6 .. 5.2e-6 low in
    ``omega_max`` on the twisted cylinder at n = 1,000 .. 3,000 (against shift-invert to 1e-14, in 0.04-0.23 s) and up
    to 3.4e-5 high on curved meridians at n = 21 .. 41 (against dense eigenvalues). The Ritz value is therefore raised
    by :data:`REST_RAISE` (``omega_max`` by 5e-4), ten times the largest error measured: the step bound is that much
    conservative (the old route's was 3e-4 high). ``J``'s own four largest-magnitude
    eigenvalues at tol = 1e-4 took up to 22 s at n = 2,000 (12,700 ARPACK iterations), 3e-4 high at n = 1,000 (5.7 %
    on the cylinder's defaults, in 36 s): the top of ``J``'s spectrum is clustered conjugate pairs on the imaginary
    axis (the top three within 5e-6), ``C D``'s top real eigenvalues at twice the relative gap.
    """
    import scipy.sparse.linalg  # large grids only (as spectrum_bounds)

    q = np.asarray(positions, dtype=bool)
    if mat.shape != (q.size, q.size) or q.sum() * 2 != q.size or q.sum() < 3:
        return None
    if mat[q][:, q].count_nonzero() or mat[~q][:, ~q].count_nonzero():
        return None
    with np.errstate(all="ignore"):
        product = (mat[q][:, ~q] @ mat[~q][:, q]).tocsc()
    if not np.isfinite(product.data).all():  # the squares overflow where J's entries do not: J's own spectrum
        return None
    try:
        mu = scipy.sparse.linalg.eigs(product, k=1, ncv=min(REST_NCV, product.shape[0] - 1), which="LM",
                                      return_eigenvectors=False, tol=REST_TOL, maxiter=20000,
                                      v0=np.random.default_rng(0).standard_normal(product.shape[0]))
    except scipy.sparse.linalg.ArpackNoConvergence as exc:  # keep what converged
        mu = exc.eigenvalues
        if len(mu) == 0:
            return None
    root = np.sqrt(np.asarray(mu, dtype=complex) * (1.0 + REST_RAISE))  # not below the true value (docstring)
    return np.concatenate([root, -root])


def rest_spectrum(J, positions):
    """The eigenvalues of ``J`` when its position-position and rate-rate blocks vanish; else ``None``.

    That is the Jacobian of a mechanical system whose forces do not depend on the rates (elastic, no viscosity
    or drag) at rest (the rate terms of the inertia are quadratic), or in any state if its mass matrix is
    constant (axisymmetric motion). Ordered as positions then rates it reads
    ``[[0, C], [D, 0]]``, whose square is ``diag(CD, DC)``: its eigenvalues are ``+-sqrt(mu)`` over the
    eigenvalues ``mu`` of ``CD``, a matrix of half the size (eight times fewer operations than ``J``'s: 5 ms
    instead of 40 ms at n = 40, where the spectrum was a third of a short run's cost).
    """
    q = np.asarray(positions, dtype=bool)
    if J.shape != (q.size, q.size) or q.sum() * 2 != q.size or q.sum() > DENSE_EIG_MAX_ROWS:
        return None
    if J[np.ix_(q, q)].any() or J[np.ix_(~q, ~q)].any():
        return None
    with np.errstate(all="ignore"):
        product = J[np.ix_(q, ~q)] @ J[np.ix_(~q, q)]
    if not np.isfinite(product).all():  # the squares overflow where J's entries do not: J's own spectrum
        return None
    root = np.sqrt(np.linalg.eigvals(product).astype(complex))
    return np.concatenate([root, -root])
