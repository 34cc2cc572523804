"""Reactions at held edges: what a support supplies to hold an edge's ``z`` (``reaction_force``) or ``chi``
(``reaction_torque``) without driving it (:mod:`mol_shell.discretization.reactions`).

Checked against two balance laws and a closed form, each derived here:

1. Axial angular momentum. The stored energy does not change under a rigid rotation about the axis, so the
   elastic (and viscous) torques sum to zero over the nodes, and with no loads
   ``dL/dt = R1 + R2`` (the supports' and drivers' torques) exactly in the semi-discrete system, provided ``L``
   includes the momenta conjugate to the held and driven ``chi`` (at a pinned edge the held ``chi`` couples to
   the free ``psi`` through the director's azimuthal velocity, so that momentum is not zero).
2. The membrane state of a pressurised cylinder held in ``z`` at both edges (``theta`` held, ``r`` free: the
   uniform expansion meets these edges exactly, no boundary layer). The pressure acts as if lids closed the
   edges (the scene's convention). With the axial stretch held at 1, plane stress (``svk-plane-stress``) and
   hoop stretch ``lam``: hoop equilibrium of half the tube, ``2 p r = 2 t lam S_pp`` with ``r = lam a``, gives
   ``t S_pp = p a`` exactly (``S`` the second Piola-Kirchhoff stress, ``t = 2h``); ``S_zz = nu S_pp``, and
   the wall's axial force, per reference area ``S_zz`` (axial stretch 1), is ``2 pi a nu p a``; the lid pushes
   the edge out with ``p pi r^2``; ``lam^2 = 1 + 2 E_pp = 1 + 2 (1 - nu^2) p a / (E t)``. So the support at
   ``s = L`` supplies ``R2 = pi a^2 p (2 nu - lam^2)`` along ``k`` and ``R1 = -R2``, up to the through-thickness
   terms of a curved wall, ``O((h/a)^2)``.
3. The statics route (:func:`mol_shell.path`: ``dU/dq`` less the loads at the held node) and a run started at
   rest from that equilibrium (the dynamic route: the edge node's equation of motion) give the same reaction.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson

import mol_shell
from mol_shell import Axisymmetric, path
from mol_shell.analysis.path_start import path_start

T_BALANCE = np.linspace(0.0, 0.04, 801)
RTOL = 1e-10


@pytest.mark.parametrize("end1", ["pinned", "clamped"])
def test_held_and_driven_torques_balance_the_angular_momentum(end1):
    """The paper's twisted cylinder spun at ``omega = 0.5`` rad/s, its first edge held in ``chi`` (pinned: ``psi``
    free; clamped: every field held) and its second driven at ``-sin(2 pi 25 t)`` rad/s, CVODE-BDF at
    ``rtol = 1e-10``, ``n = 21``, 801 saved times to 0.04 s: ``L(t) - L(0) = int (R1 + R2) dt``. Bound as in
    tests/model/test_driven_edges.py: twice the Richardson estimate of the Simpson error plus
    ``10 rtol max|L|``; about 2e-8 N m s against an exchange of 52 N m s. Leaving the held ``chi``'s momentum
    out of ``L`` at the pinned edge breaks the balance by 2e-5 N m s (measured when written): the check sees it."""
    scene = mol_shell.TwistedCylinder(end1=end1, end2_spin=-1.0, end2_spin_history="sine 25", omega=0.5)
    ds = mol_shell.simulate(scene, "cvode-bdf", n=21, times=T_BALANCE, rtol=RTOL, atol=1e-12, progress=False,
                            stresses=False)
    assert ds.attrs["complete"] == 1
    R = ds.reaction_torque.values
    assert np.all(np.isfinite(R)) and np.abs(R[:, 0]).min() > 1e3  # the support holds against kN m
    L_ = ds.angular_momentum.values
    t = ds.time.values
    fine = cumulative_simpson(R.sum(axis=1), x=t, initial=0.0)
    coarse = cumulative_simpson(R.sum(axis=1)[::2], x=t[::2], initial=0.0)
    bound = 2 * float(np.abs(fine[::2] - coarse).max()) / 15 + 10 * RTOL * float(np.abs(L_).max())
    exchange = float(np.abs(L_ - L_[0]).max())
    assert float(np.abs(L_ - L_[0] - fine).max()) <= bound and exchange > 10.0 and bound < 1e-8 * exchange
    # both edges hold z: their axial forces are there, finite
    assert np.all(np.isfinite(ds.reaction_force.values))


def lidded_tube_reaction(a, h, E, nu, p):
    """``R2`` of the module docstring's item 2: ``pi a^2 p (2 nu - lam^2)``, ``lam^2 = 1 + 2 (1 - nu^2) p a / (E t)``."""
    lam2 = 1.0 + 2.0 * (1.0 - nu**2) * p * a / (E * 2.0 * h)
    return math.pi * a**2 * p * (2.0 * nu - lam2)


@pytest.mark.parametrize("h", [0.005, 0.0025])
def test_a_held_edge_of_a_pressurised_tube_carries_the_membrane_force(h):
    """A tube (``a = 1``, ``L = 1``, ``E = 1e6``, ``nu = 0.3``, plane stress) held in ``z`` and ``theta`` at both
    edges, inflated to ``p = 1`` Pa by :func:`mol_shell.path` (hoop strain ~1e-4): its edge reactions are the
    closed form of the module docstring within ``1.5 (h/a)^2`` relative (measured when written: 2.499e-5 at
    ``h = 0.005``, 6.243e-6 at ``h = 0.0025``, i.e. ``(h/a)^2`` to 0.1 %: the curved wall's through-thickness
    terms, second order as derived), equal and opposite; a run started at rest from
    that equilibrium reports the same reactions at its start (1e-9 relative) and keeps them (it stays at rest)."""
    a, E, nu, p = 1.0, 1.0e6, 0.3, 1.0
    scene = Axisymmetric(L=1.0, a=a, R=a, h=h, E=E, nu=nu, material="svk-plane-stress", end1="z,theta",
                         end2="z,theta")
    ds = path(scene, "pressure", 0.0, p, n=41, steps=2, max_steps=10)
    assert ds.attrs["status"] == "complete" and float(ds.parameter[-1]) == pytest.approx(p, rel=1e-12)
    r1, r2 = float(ds.end1_reaction_force[-1]), float(ds.end2_reaction_force[-1])
    closed = lidded_tube_reaction(a, h, E, nu, p)
    assert abs(r2 - closed) <= 1.5 * (h / a) ** 2 * abs(closed)
    assert abs(r1 + r2) <= 1e-9 * abs(r2)
    scene_p, n, fields, _ = path_start(ds, step=len(ds.step) - 1)
    run = mol_shell.simulate(scene_p, "cvode-bdf", n=n, times=np.linspace(0.0, 1e-3, 3), initial=fields,
                             rtol=1e-10, atol=1e-14, progress=False, stresses=False)
    force = run.reaction_force.values
    assert np.abs(force - np.array([r1, r2])).max() <= 1e-9 * abs(r2)
    assert run.reaction_force.attrs["units"] == "N"
