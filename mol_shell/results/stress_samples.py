"""The stresses of one sample of the shell, pure functions of its strains (floats, NumPy arrays or CasADi scalars).

The reference geometry of the cells and their two samples, the second Piola-Kirchhoff stress of the default law,
the Gauss rule through the thickness, and the integrals that make the section's resultants and the faces' Cauchy
stresses (:func:`sample_stresses`); :mod:`mol_shell.results.stresses` maps them over a run. The conventions
(signs, samples, faces) are said there.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from mol_shell.discretization.cells import cell_samples as kernel_samples
from mol_shell.model.hyperelastic import incompressible_viscous_stress
from mol_shell.model.kinematics import deformation_gradient
from mol_shell.model.material import green_strain, plane_stress_thickness
from mol_shell.results.tensors import cauchy_stress, det3, matmul, thickness_stretched, transpose


def reference_cells(s, r0=None, z0=None, theta0=None):
    """Reference data of each cell ``[s_i, s_{i+1}]`` by the discrete system's difference formulas.

    ``theta0`` and ``r0`` at the midpoint, ``theta0_s = (theta0_{i+1} - theta0_i)/ds`` and
    ``(beta1_0, beta2_0) = betas(dz0/ds, dr0/ds, 0, r0, theta0)`` (1 and 0 on the cylinder).
    Missing nodal data are the cylinder's: ``r0 = 1``, ``z0 = s``, ``theta0 = 0``.

    Returns
    -------
    dict
        ``ds`` (float) and arrays over cells ``r0, theta0, theta0_s, beta1_0, beta2_0``.
    """
    s = np.asarray(s, dtype=float)
    ds = (s[-1] - s[0]) / (len(s) - 1)
    r0 = np.ones_like(s) if r0 is None else np.asarray(r0, dtype=float)
    z0 = s if z0 is None else np.asarray(z0, dtype=float)
    theta0 = np.zeros_like(s) if theta0 is None else np.asarray(theta0, dtype=float)
    r0m, th_m = (r0[1:] + r0[:-1]) / 2, (theta0[1:] + theta0[:-1]) / 2
    z0_s, r0_s = (z0[1:] - z0[:-1]) / ds, (r0[1:] - r0[:-1]) / ds
    beta1_0 = z0_s * np.cos(th_m) + r0_s * np.sin(th_m)  # kinematics.betas, in NumPy
    beta2_0 = -z0_s * np.sin(th_m) + r0_s * np.cos(th_m)
    th_s = (theta0[1:] - theta0[:-1]) / ds
    return {"ds": ds, "r0": r0m, "theta0": th_m, "theta0_s": th_s, "beta1_0": beta1_0, "beta2_0": beta2_0}


def cell_samples(q, ds):
    """Strains ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)`` of every cell at its two samples.

    ``q`` has shape ``(..., 5, n)`` (fields or their rates); returns ``(..., 8, n - 1, 2)``: the
    kernel's samples (:func:`mol_shell.discretization.cells.cell_samples`) with the differences over
    ``ds``. Linear in ``q``, so the rates of the strains come from the nodal rates the same way.
    """
    q = np.moveaxis(np.asarray(q, dtype=float), -2, 0)
    samples = np.stack([np.stack(np.broadcast_arrays(*sample)) for sample in
                        kernel_samples(q[..., :-1], q[..., 1:])], axis=-1)  # (8, ..., n - 1, 2)
    samples[:5] /= ds
    return np.moveaxis(samples, 0, -3)


def second_piola(E, first, second, plane_stress=False):
    """``S = first tr(E) I + 2 second E`` (7.9; with ``(eta_lambda, eta_mu)`` and ``E_t``: the viscous stress).

    ``plane_stress``: the condensed law of ``material = "svk-plane-stress"`` has ``S22 = 0`` (the
    stress along the director that the condensation eliminated); its other entries are the
    condensed law's. Nested 3x3 tuples in the ``b0`` basis. (An incompressible law's viscous stress is not of this
    form: :func:`~mol_shell.model.hyperelastic.incompressible_viscous_stress`.)
    """
    trace = E[0][0] + E[1][1] + E[2][2]
    S = [[first * trace * (i == j) + 2.0 * second * E[i][j] for j in range(3)] for i in range(3)]
    S[1][1] = S[1][1] * (1 - plane_stress)  # also for a symbolic flag (the compiled kernel's input)
    return tuple(tuple(row) for row in S)


def svk_stretch(E, first, second, plane_stress=False):
    """The thickness stretch of SVK's own kernel: ``1.0`` under the director constraint (``plane_stress`` false),
    else ``sqrt(C_22)`` of :func:`~mol_shell.model.material.plane_stress_thickness` (a symbolic flag: CasADi's
    ``if_else``, exactly 1 when it is 0)."""
    if isinstance(plane_stress, (bool, int, float)) and not plane_stress:
        return 1.0
    stretch = ca.sqrt(plane_stress_thickness(E[0][0], E[2][2], first, second))
    return ca.if_else(plane_stress, stretch, 1.0) if isinstance(plane_stress, ca.SX) else stretch


def thickness_rule(zeta1, h, n_quad):
    """Gauss-Legendre nodes and weights on ``[zeta1, zeta1 + 2h]`` (as :class:`~mol_shell.model.material.Thickness`)."""
    x, w = np.polynomial.legendre.leggauss(n_quad)
    mid = zeta1 + h
    return [mid + h * xk for xk in x], [h * wk for wk in w]


def _director_frame(theta, psi):
    """``k, a3, c1, d, c3`` as components in the ``b`` basis (floats, NumPy arrays or CasADi)."""
    lib = ca if isinstance(theta, (ca.SX, ca.MX, ca.DM)) or isinstance(psi, (ca.SX, ca.MX, ca.DM)) else np
    cs, sn, ct, st = lib.cos(psi), lib.sin(psi), lib.cos(theta), lib.sin(theta)
    return (ct, -st, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, cs, sn), (0.0, -sn, cs)


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def resultants_from_integrals(v1, v2, w1, w2, strains, r0):
    """The table of the module's docstring from ``v1 = int T e1 c``, ``v2 = int zeta T e1 c``,
    ``w1 = int T e3 a``, ``w2 = int zeta T e3 a`` (each ``dzeta``; components in the ``b`` basis)."""
    r, theta, psi = strains[5], strains[6], strains[7]
    k, a3, c1, d, c3 = _director_frame(theta, psi)
    m_s, m_phi = _cross(d, v2), _cross(d, w2)  # r0 m^s and m^phi
    return {
        "axial_force": 2 * math.pi * _dot(v1, k),
        "axial_torque": 2 * math.pi * (r * _dot(v1, a3) + _dot(m_s, k)),
        "membrane_force_meridional": _dot(v1, c1) / r0,
        "membrane_shear_force": _dot(v1, c3) / r0,
        "transverse_shear_force": _dot(v1, d) / r0,
        "membrane_force_hoop": _dot(w1, c3),
        "bending_moment_meridional": _dot(m_s, c3) / r0,
        "twisting_moment": _dot(m_s, c1) / r0,
        "bending_moment_hoop": _dot(m_phi, c1),
    }


def sample_stresses(strains, rates, ref, zeta1, h, n_quad, lam, mu, eta_lambda=0.0, eta_mu=0.0, plane_stress=False,
                    elastic=None, layers=None, incompressible=False, tractions=(0.0, 0.0)):
    """Resultants and face stresses of one sample, elastic and viscous parts (CasADi ``SX`` in, ``SX`` out).

    Parameters
    ----------
    strains : sequence of casadi.SX
        ``(z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi)``.
    rates : sequence of casadi.SX or None
        Their time derivatives; None leaves the viscous part out.
    ref : sequence
        ``(r0, theta0, theta0_s, beta1_0, beta2_0)`` of the cell.
    zeta1, h : float or casadi.SX
        Lower face and half-thickness.
    n_quad : int
        Gauss-Legendre points through the thickness (the run's).
    lam, mu, eta_lambda, eta_mu : float or casadi.SX
        Condensed Lame constants and viscosities (:func:`~mol_shell.model.material.condensed`).
    plane_stress : bool or casadi.SX
        ``S22 = 0`` (:func:`second_piola`), and the face stresses with the wall's thinning (:func:`svk_stretch`).
    elastic : callable, optional
        ``C -> (S, lambda_3)`` in place of SVK's ``S`` (``lam, mu`` unused): another law's stress and thickness
        stretch (:func:`mol_shell.results.law_stresses.energy_stress`); the face stresses then use ``F`` with its
        director column times ``lambda_3``.
    layers : list, optional
        ``[(lower face, upper face, elastic)]`` of a layered wall, from ``zeta1`` to ``zeta1 + 2h``: each layer its
        own ``n_quad`` points and stress (in place of ``elastic``).
    incompressible : bool
        The viscous stress of an incompressible law: ``det C = 1`` sets the thickness rate, ``eta_mu`` alone
        (:func:`~mol_shell.model.hyperelastic.incompressible_viscous_stress`; ``eta_lambda, plane_stress`` unused for
        it); else :func:`second_piola` of ``E_t`` with the condensed pair.
    tractions : pair of float or casadi.SX
        The normal tractions on the faces ``zeta1`` and ``zeta1 + 2h`` (``-p`` on the face a pressure acts on, 0 on
        a free one). Where the face's law holds the director (``svk``; a law or layer with ``thickness =
        "director"``) its thickness stress is the constraint's reaction, not the law's: the face's Cauchy stress
        takes the one that makes its normal stress the traction (:func:`held_thickness_stress`).

    Returns
    -------
    dict
        ``elastic`` (and ``viscous``): dicts of the resultants (see the module's docstring);
        ``sigma_elastic`` (and ``sigma_viscous``): the Cauchy stress at ``zeta1`` and
        ``zeta1 + 2h`` as nested tuples ``[face][i][j]``.
    """
    e = ca.SX.sym("e", 8)
    r0, theta0, theta0_s, beta1_0, beta2_0 = ref
    kinds = ("elastic",) if rates is None else ("elastic", "viscous")

    def stresses(zeta, elastic=elastic):
        F = deformation_gradient(ca.vertsplit(e), zeta, r0, theta0, theta0_s, beta1_0, beta2_0)
        E = green_strain(F)
        if elastic is None:
            out, stretch = {"elastic": second_piola(E, lam, mu, plane_stress)}, svk_stretch(E, lam, mu, plane_stress)
        else:
            S, stretch = elastic(tuple(tuple(2 * E[i][j] + (i == j) for j in range(3)) for i in range(3)))
            out = {"elastic": S}
        if rates is not None:  # E_t = dE/de . e_t
            flat = ca.vertcat(*[E[i][j] for i in range(3) for j in range(3)])
            Et_flat = ca.jtimes(flat, e, ca.vertcat(*rates))
            Et = [[Et_flat[3 * i + j] for j in range(3)] for i in range(3)]
            if incompressible:
                C = tuple(tuple(2 * E[i][j] + (i == j) for j in range(3)) for i in range(3))
                out["viscous"] = incompressible_viscous_stress(C, Et, eta_mu)[0]
            else:
                out["viscous"] = second_piola(Et, eta_lambda, eta_mu, plane_stress)
        return F, out, stretch

    layers = layers or [(zeta1, zeta1 + 2 * h, elastic)]
    points = [(z, w, el) for lo, hi, el in layers for z, w in zip(*thickness_rule(lo, (hi - lo) / 2, n_quad))]
    sums = {kind: [(0.0, 0.0, 0.0)] * 4 for kind in kinds}  # v1, v2, w1, w2
    for zeta, w, el in points:
        F, S, _ = stresses(zeta, el)
        c = w * (r0 + zeta * ca.cos(theta0))
        a = w * (beta1_0 - zeta * theta0_s)
        for kind in kinds:
            T = matmul(F, S[kind])
            t1, t3 = tuple(T[i][0] for i in range(3)), tuple(T[i][2] for i in range(3))
            v1, v2, w1, w2 = sums[kind]
            sums[kind] = [tuple(x + c * y for x, y in zip(v1, t1)), tuple(x + zeta * c * y for x, y in zip(v2, t1)),
                          tuple(x + a * y for x, y in zip(w1, t3)), tuple(x + zeta * a * y for x, y in zip(w2, t3))]
    parts = {kind: resultants_from_integrals(*sums[kind], ca.vertsplit(e), r0) for kind in kinds}
    faces = [stresses(zeta1, layers[0][2]), stresses(zeta1 + 2 * h, layers[-1][2])]
    for (F, S, _), el, traction in zip(faces, (layers[0][2], layers[-1][2]), tractions):
        held = (1 - plane_stress) if el is None else float(getattr(el, "held", False))  # 0: the law gives S_22
        if not (isinstance(held, (int, float)) and held == 0):
            S.update(held_thickness_stress(F, S, traction, held))
    for kind in kinds:  # the director-constrained SVK's (stretch 1.0): F as it is
        parts["sigma_" + kind] = [cauchy_stress(thickness_stretched(F, stretch) if isinstance(stretch, ca.SX) else F,
                                                S[kind]) for F, S, stretch in faces]
    strains = ca.vertcat(*strains)
    return {key: _substitute(value, e, strains) for key, value in parts.items()}


def held_thickness_stress(F, S, traction, held=1.0):
    """``S`` (a dict of nested 3x3 by kind) at a face whose thickness stress is the director constraint's reaction.

    The constraint ``C_22 = 1`` is workless for any ``S_22``: the law's value there (``lambda tr E`` for ``svk``) is
    not the wall's. The face's normal Cauchy stress ``n.sigma.n`` (``n`` the deformed face's normal, along
    ``F^-T e2``) is ``S_22 / (J (C^-1)_22)``, so the traction ``t`` on the face gives
    ``S_22 = t J (C^-1)_22 = t (C_11 C_33 - C_13^2) / J`` for the elastic part and 0 for the viscous one; the
    other entries, and so the in-plane Cauchy stresses (the director is normal to ``c1`` and ``c3``), are kept.
    ``held`` in ``[0, 1]`` blends with the law's value (a symbolic flag: ``1 - plane_stress``).
    """
    C = matmul(transpose(F), F)
    reaction = traction * (C[0][0] * C[2][2] - C[0][2] * C[0][2]) / det3(F)
    out = {}
    for kind, Sk in S.items():
        target = reaction if kind == "elastic" else 0.0
        rows = [list(row) for row in Sk]
        rows[1][1] = rows[1][1] + held * (target - rows[1][1])
        out[kind] = tuple(tuple(row) for row in rows)
    return out


def _substitute(value, e, strains):
    if isinstance(value, dict):
        return {k: _substitute(v, e, strains) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return type(value)(_substitute(v, e, strains) for v in value)
    return ca.substitute(ca.SX(value), e, strains)


__all__ = ["cell_samples", "held_thickness_stress", "reference_cells", "resultants_from_integrals", "sample_stresses",
           "second_piola", "svk_stretch", "thickness_rule"]
