"""Uniform equilibria: the radius of the uniformly twisted cylinder, and the stable step of leap-frog."""

from __future__ import annotations

import casadi as ca
import numpy as np

from .errors import ParameterError
from .model.material import Thickness, effective_lame, shell_energy


def equilibrium_radius(scene, tol=1e-14, max_iter=50):
    """Radius ``R`` at which the uniformly twisted cylinder is in radial equilibrium.

    Solves ``dWhat/dr (z_s = 1, r_s = 0, chi_s = gamma, theta = theta_s = psi = psi_s = 0; r = R) = 0``
    by Newton's method on the CasADi graph of ``What`` (the paper's "(R, gamma) is an
    equilibrium state of the material"). For ``gamma = 0`` the root is the natural radius ``a``. A
    pressure ``p`` (its value at ``t = 0``) adds ``-p r^2/(2a)`` per unit reference area (``-p V``, ``V = pi r^2 L``).
    """
    lam, mu = effective_lame(scene.E, scene.nu, scene.material)
    a = getattr(scene, "a", 1.0)
    thickness = Thickness(scene.zeta1_used(), scene.h, scene.n_quad)
    r = ca.SX.sym("r")
    energy = shell_energy((1.0, 0.0, getattr(scene, "gamma", 0.0), 0.0, 0.0, r, 0.0, 0.0), lam, mu, thickness, a)
    # pressure: -p V with V = pi r^2 L, per unit reference area 2 pi a L: -p r^2 / (2a) (follower, at t = 0)
    p0 = getattr(scene, "pressure", 0.0)
    if p0:
        from .model.loads import history

        energy = energy - p0 * history(scene.load_histories()["pressure"], 0.0) * r * r / (2 * a)
    force = ca.gradient(energy, r)
    newton = ca.Function("newton", [r], [force, ca.jacobian(force, r)])
    R = a
    for _ in range(max_iter):
        g, dg = (float(x) for x in newton(R))
        if dg <= 0:
            break
        step = g / dg
        R -= step
        if abs(step) < tol * R:
            return R
    raise ParameterError("gamma", scene.gamma, "twists for which a twisted cylinder has a radial equilibrium")


def spectrum_bounds(jac, y, dissipative=True):
    """``(max |lambda|, max(-Re lambda))`` over the eigenvalues of the Jacobian ``jac(0, y)`` (1/s).

    The first bounds the leap-frog step (``dt max|lambda| < 1`` for the imaginary-axis
    spectrum of an elastic shell); the second is the fastest damping rate, which
    leap-frog's parasitic root turns into growth ``exp(max(-Re lambda) t)``.
    Dense below 2000 states; above, ARPACK's largest-magnitude eigenvalues (relative accuracy
    ~1e-3, enough for a step bound that the energy monitor backs up), whose real
    parts estimate the fastest damping (the most damped modes are the shortest); an
    elastic system (``dissipative=False``) has none.
    """
    J = jac(0, y)
    if J.size1() <= 2000:
        ev = np.linalg.eigvals(np.array(J))
    else:
        import scipy.sparse.linalg  # large grids only: 0.27 s of a process's start otherwise

        sp = J.sparsity()
        mat = scipy.sparse.csc_matrix((np.array(J.nonzeros()).ravel(), sp.row(), sp.colind()), shape=J.shape)
        try:
            # the top of a wave spectrum is clustered: a wide Krylov space and a loose tolerance find
            # max |lambda| to ~1e-3 in 0.1-1 s at n = 2560 (k = 6, tol = 1e-6 took 2.6-11 s)
            ev = scipy.sparse.linalg.eigs(mat, k=4, ncv=min(60, mat.shape[0] - 1), which="LM",
                                          return_eigenvectors=False, tol=1e-4, maxiter=20000)
        except scipy.sparse.linalg.ArpackNoConvergence as exc:  # keep what converged
            ev = exc.eigenvalues
            if len(ev) == 0:
                raise
    damping = float(max(0.0, (-ev.real).max())) if dissipative else 0.0
    return float(np.abs(ev).max()), damping
