"""Any hyperelastic law through the thickness: ``W(C)`` at each Gauss point, with the thickness treatment of the law.

A law (:class:`~mol_shell.model.laws.Law`) is its stored energy ``W(C, parameters)`` per unit reference volume,
``C = F^T F`` the 3-D right Cauchy-Green tensor in the reference basis ``(b0_1, b0_2, b0_3)`` of
:func:`~mol_shell.model.kinematics.deformation_gradient`, whose second direction (index 1 here) is the director,
the thickness direction. The shell's ``F = [(a + zeta b) j1, c2, (c + zeta d) j3]``
(:func:`~mol_shell.model.kinematics.column_polynomials`) gives every component of ``C`` but the thickness one,
``C_22 = |d|^2 = 1`` for the paper's inextensible director; the law's ``thickness`` treatment decides it:

- ``director``: ``C_22 = 1`` (the paper; the transverse shears ``C_12``, ``C_23`` stay kinematic);
- ``plane-stress``: ``C_22 = x`` minimising ``W`` (``dW/dC_22 = 0``, the thickness stress ``S_22 = 2 dW/dC_22``
  vanishes), found by Newton's method in ``u = ln x`` from ``x = 1``, unrolled :data:`NEWTON_STEPS` times in the
  graph (so ``x > 0`` always; a law of one's own may take another count, or fitted third-order steps:
  :func:`condensation_step`); the derivatives of the condensed energy follow by AD through the iterations, which at
  convergence equal those of the implicit function theorem (``dW/dx = 0`` there);
- ``incompressible``: ``det C = 1``. ``det C`` is affine in ``C_22``: ``det C = C_22 (C_11 C_33 - C_13^2) + N``
  with ``N`` the determinant at ``C_22 = 0``, so ``C_22 = (1 - N) / (C_11 C_33 - C_13^2)``, substituted into ``W``
  (the hydrostatic pressure is eliminated by the vanishing thickness stress: the membrane route of rubber). The
  energy is written ``W - p (det C - 1)`` with that pressure ``p`` (:func:`incompressible_pressure`): the same
  value, and stationary in ``C_22``, so the cell forces are taken with ``C_22`` and ``p`` held (no ``dC_22/dC``;
  8-18 % cheaper right-hand sides than differentiating the substitution).

The thickness integral is the same Gauss-Legendre rule as :func:`~mol_shell.model.material.thickness_energy`
(``sum_q vol_q W(C_q)``); the mass per reference area does not change.

Kelvin-Voigt viscosity of an incompressible law (:func:`incompressible_dissipation`): the thickness is kinematic,
``C_22(C)`` as above at every instant, so the thickness strain rate is the time derivative of
``E_22 = (C_22(C) - 1)/2``, not a free variable to be condensed; the Rayleigh function is ``eta_mu E_t : E_t`` with
that ``E_t`` (a bulk viscosity ``eta_lambda`` has nothing to act on under ``det C = 1``).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import casadi as ca
import numpy as np

from mol_shell.model.kinematics import column_polynomials, trigonometry_rates
from mol_shell.model.material import quadrature_factors

#: thickness treatments (:mod:`mol_shell.model.hyperelastic`)
TREATMENTS = ("director", "plane-stress", "incompressible")


@dataclass(frozen=True)
class Law:
    """A hyperelastic law: ``energy(C, params)`` per unit reference volume, ``C`` a nested 3x3 of scalars.

    ``parameters``: the names ``params`` must hold; ``thickness``: one of :data:`TREATMENTS`; ``condense``:
    optionally ``(C, params) -> C_22`` solving the law's plane-stress condition more cheaply than the generic
    Newton iteration on ``dW/dC_22`` (:func:`~mol_shell.model.hyperelastic.plane_stress_thickness`).
    ``held_energy``: optionally ``(C, values, params) -> W`` with ``values = condense(C, params)`` then a tuple,
    ``C_22`` first, then what the solve found on the way (``neo-hookean``: ``det C - 1`` and ``-mu/(2M)``;
    ``neo-hookean-log``: ``ln det C`` and ``det C``; a law of one's own: ``|dW/dC_22|`` left): the energy at
    ``C_22 = values[0]`` written with them, of the same value and the same first derivatives in ``C`` at those values
    as ``energy`` (so it may skip work the solve has done).
    ``unsolved``: optionally ``(C, params) -> why`` for ``C`` of numbers: why the thickness treatment has no solution
    there (``None`` where it has one), said when a run stops where the energy is not finite.
    """

    name: str
    energy: Callable
    parameters: tuple
    thickness: str
    condense: Callable | None = None
    held_energy: Callable | None = None
    unsolved: Callable | None = None

    def __post_init__(self):
        if self.thickness not in TREATMENTS:
            raise ValueError(f"thickness = {self.thickness!r} is outside {{{', '.join(TREATMENTS)}}}")


#: the thickness (director) index of ``C``
THICK = 1
#: Newton steps of the plane-stress condensation (quadratic convergence: the ``(ln J)^2`` neo-Hookean law,
#: 0 <= nu <= 0.49, reaches |dW/dC_22| < 1e-12 mu within 6 steps from x = 1 for in-plane stretches 0.3..3;
#: tests/model/test_laws.py checks the residual; Ciarlet and Geymonat's needs 20 there, and has its closed form)
NEWTON_STEPS = 6


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def cauchy_green(F):
    """``C = F^T F`` (nested 3x3 tuples) of ``F`` given as ``F[k][l]`` (component ``k`` of column ``l``)."""
    return tuple(tuple(sum(F[k][i] * F[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def determinant(C):
    """``det C`` of a nested 3x3."""
    return (C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) - C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0])
            + C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]))


def invariants(C):
    """``(I1, I2, I3)`` of ``C``: ``tr C``, ``(tr(C)^2 - tr(C^2)) / 2``, ``det C``."""
    i1 = C[0][0] + C[1][1] + C[2][2]
    square = sum(C[i][j] * C[j][i] for i in range(3) for j in range(3))
    return i1, 0.5 * (i1 * i1 - square), determinant(C)


def with_thickness(C, x):
    """``C`` with its thickness component ``C_22`` replaced by ``x``."""
    return tuple(tuple(x if i == j == THICK else C[i][j] for j in range(3)) for i in range(3))


def incompressible_thickness(C):
    """``C_22`` such that ``det C = 1`` (closed form: ``det C`` is affine in ``C_22``)."""
    n = determinant(with_thickness(C, 0.0))
    return (1.0 - n) / (C[0][0] * C[2][2] - C[0][2] * C[2][0])


#: the plane-stress solves of :func:`condensation_step`: ``newton`` (every law's until December 7) and ``fitted``
SOLVES = ("newton", "fitted")
#: the fitted step's factor on ``C_22`` (to the power ``1/q``) where its model has no root: the law's minimum is at
#: ``C_22 -> 0``
NO_ROOT_FACTOR = 1e-4


def condensation_equations(energy, C, solve="newton"):
    """``(x, g, f)``: the symbol ``x`` of ``C_22``, ``g = dW/dC_22`` and what :func:`condensation_step` evaluates at
    each iterate, in ``x``: ``[dW/du, d2W/du2]`` (``u = ln x``) for ``newton``, ``[g, g', g'']`` for ``fitted``."""
    x = ca.SX.sym("c22")
    g = ca.gradient(energy(with_thickness(C, x)), x)
    gp = ca.gradient(g, x)
    if solve == "newton":
        return x, g, ca.vertcat(g * x, gp * x * x + g * x)
    return x, g, ca.vertcat(g, gp, ca.gradient(gp, x))


def condensation_step(x, f, u, solve="newton"):
    """``u = ln C_22`` after one step of the plane-stress solve of ``g = dW/dC_22 = 0`` from ``u``, ``f`` from
    :func:`condensation_equations`. Branch-free (``if_else``): the unrolled steps stay one compiled expression.

    - ``newton``: Newton's step on ``dW/du = g x`` (``x = e^u``), ``-r/(1 + r)`` with ``r = g/(g' x)``. It crawls where
      the root is near ``C_22 = 0`` (``g x ~ e^(2u)`` there: half a unit of ``u`` a step), as St Venant-Kirchhoff's
      is next to the edge of its domain: 8 steps reached it only up to an equibiaxial stretch of 1.424 at
      ``nu = 0.3``, where ``C_22 = 0`` is at 1.472.
    - ``fitted``: to the root of ``g ~ A + B x^q`` fitted to ``g, g', g''`` at ``x``, ``ln(1 - q r)/q`` with
      ``q = 1 + x g''/g'``: third order, and exact in one step for a ``g`` affine in ``C_22`` (St Venant-Kirchhoff's,
      up to the edge) or a power of it (a volumetric ``J^-b``). Where that model has no root below (``q r >= 1``,
      ``g > 0``: ``W`` falls all the way to ``C_22 = 0``, as St Venant-Kirchhoff's past its edge) the step multiplies
      ``C_22`` by ``NO_ROOT_FACTOR^(1/q)``, so that the thickness held there is next to the edge's, 0, and the forces
      past the edge (where the energy is NaN) join those inside it. Where the model has no root above, or its step
      goes uphill (along the sign of ``g``: ``W`` not convex there; a NaN fails the test too), Newton's step.
    """
    xu = ca.exp(u)
    if solve == "newton":
        fu = ca.substitute(f, x, xu)
        return u - fu[0] / fu[1]
    g, gp, gpp = ca.vertsplit(ca.substitute(f, x, xu))
    r = g / (gp * xu)
    q = 1 + xu * gpp / gp
    z = q * r
    fitted = ca.if_else(z < 1, ca.log1p(-z), math.log(NO_ROOT_FACTOR)) / q
    taken = ca.logic_and(ca.logic_or(z < 1, g > 0), fitted * g <= 0)
    return u + ca.if_else(taken, fitted, -r / (1 + r))


def plane_stress_thickness(energy, C, steps=NEWTON_STEPS, residual=False, solve="newton"):
    """``C_22`` with ``dW/dC_22 = 0``: ``steps`` of :func:`condensation_step` (``solve``) in ``u = ln C_22`` from
    ``u = 0``.

    ``energy(C)`` is the law with its parameters bound. Returns the last iterate (a CasADi expression of
    ``C``'s other components); :func:`plane_stress_residual` measures how far it is from the root. With
    ``residual``, ``(C_22, |dW/dC_22| there)``: a law of one's own uses it to tell where the solve failed (no root
    ``C_22 > 0``, or one the steps do not reach; :class:`~mol_shell.model.user_laws.Material`).
    """
    x, g, f = condensation_equations(energy, C, solve)
    u = ca.SX(0.0)
    for _ in range(steps):
        u = condensation_step(x, f, u, solve)
    if not residual:
        return ca.exp(u)
    last = ca.exp(u)
    return last, ca.fabs(ca.substitute(g, x, last))


#: the step counts tried for a law of one's own (:func:`plane_stress_steps`), by solve, and the in-plane states
#: ``(C_11, C_33, C_13)`` it must converge at where its condition has a root: equibiaxial stretches 0.6 to 2,
#: uniaxial ones, and a shear. The fitted solve (third order) may take fewer: 2 solve St Venant-Kirchhoff exactly
PLANE_STRESS_STEPS = {"newton": (6, 8, 12, 16, 24, 32), "fitted": (2, 3, 4, 6, 8, 12, 16, 24, 32)}
PLANE_STRESS_STATES = tuple((a * a, a * a, 0.0) for a in (0.6, 0.8, 1.25, 1.6, 2.0)) + (
    (0.49, 1.0, 0.0), (2.25, 1.0, 0.0), (1.0, 1.0, 0.3), (1.44, 0.81, 0.2))
#: states near the natural one (stretches 0.9 and 1.1, a shear of 0.1) where the condition must have a root: a
#: law without one there cannot run in plane stress at all
NATURAL_STATES = ((0.81, 0.81, 0.0), (1.21, 1.21, 0.0), (0.81, 1.0, 0.0), (1.21, 1.0, 0.0), (1.0, 1.0, 0.1))
#: the thickness components ``C_22`` (1e-8 to 1e8, two a decade) at which ``dW/dC_22`` is sampled for a sign change
ROOT_GRID = np.geomspace(1e-8, 1e8, 33)


@dataclass(frozen=True)
class PlaneStressCheck:
    """What :func:`plane_stress_steps` found at the states of :data:`NATURAL_STATES` and :data:`PLANE_STRESS_STATES`
    (each ``(C_11, C_33, C_13)``): ``solve`` and ``steps``, the cheaper of the solves (:data:`SOLVES`) with the fewest
    of its :data:`PLANE_STRESS_STEPS` that converge wherever 32 steps of either do; ``residual``, the largest
    ``|dW/dC_22|`` they leave there (relative to the stiffness); ``rootless``, the states where the condition has no
    root ``C_22 > 0``; ``unreached``, ``(state, residual)`` where it has one that 32 steps of neither reach (the
    smaller residual)."""

    steps: int
    residual: float
    rootless: tuple
    unreached: tuple
    solve: str = "newton"


def has_root(slopes):
    """Whether ``dW/dC_22`` sampled at increasing ``C_22`` (the last axis) changes sign from negative to positive: ``W``
    has a minimum between (a root of the plane-stress condition with ``C_22 > 0``)."""
    slopes = np.asarray(slopes, dtype=float)
    index = np.arange(slopes.shape[-1])
    first = np.where(slopes < 0, index, slopes.shape[-1]).min(axis=-1, keepdims=True)
    return np.any((slopes > 0) & (index > first), axis=-1)


def _solve_table(energy, c, C, solve, states, scale):
    """``(residuals, costs)`` of ``solve`` after each of its :data:`PLANE_STRESS_STEPS`: ``|dW/dC_22| / scale`` at
    the ``states`` ``(counts, states)``, and the operations of the unrolled solve (CasADi instructions) per count."""
    x, g, f = condensation_equations(energy, C, solve)
    u, residuals, costs = ca.SX(0.0), [], []
    counts = PLANE_STRESS_STEPS[solve]
    for k in range(1, counts[-1] + 1):
        u = condensation_step(x, f, u, solve)
        if k in counts:
            residuals.append(ca.substitute(g, x, ca.exp(u)))
            costs.append(ca.Function("solve", [c], [u]).n_instructions())
    table = ca.Function("residuals", [c], [ca.vertcat(*residuals)]).map(len(states))
    with np.errstate(invalid="ignore", over="ignore"):
        found = np.abs(np.array(table(states.T))) / scale
    return np.where(np.isfinite(found), found, np.inf), costs


def plane_stress_steps(energy, scale, tol=1e-9):
    """:class:`PlaneStressCheck` of the law ``energy(C)``: where its plane-stress condition has a root (a sign change
    of ``dW/dC_22`` on :data:`ROOT_GRID`, :func:`has_root`), whether and in how many of :data:`PLANE_STRESS_STEPS`
    each solve of :func:`plane_stress_thickness` reaches it, ``|dW/dC_22| <= tol x scale``, and which of them
    does so in the fewest operations (Newton's where they tie: a law it serves runs as before December 7).

    A volumetric term like Ogden's ``J^-9`` makes Newton from ``C_22 = 1`` crawl (six steps left 1e8 Pa at a stretch
    of 1.3, 16 reach it; 6 fitted steps, at about as many operations); St Venant-Kirchhoff's condition has no root
    beyond an equibiaxial stretch of 1.47 at ``nu = 0.3``, where no count converges and none is asked to (until
    December 7 one was, at every state, and SVK was refused for ``nu >= 0.2``), and Newton's steps crawl next to it
    (the fitted solve takes 2 steps, exact up to the edge)."""
    states = np.array(NATURAL_STATES + PLANE_STRESS_STATES)
    c = ca.SX.sym("c", 3)
    C = ((c[0], 0.0, c[2]), (0.0, 1.0, 0.0), (c[2], 0.0, c[1]))
    x = ca.SX.sym("c22")
    sampled = ca.Function("slopes", [c, x], [ca.gradient(energy(with_thickness(C, x)), x)])
    with np.errstate(invalid="ignore", over="ignore"):
        slopes = np.array(sampled.map(len(states) * len(ROOT_GRID))(np.repeat(states, len(ROOT_GRID), axis=0).T,
                                                                     np.tile(ROOT_GRID, len(states))))
    rooted = has_root(np.nan_to_num(slopes.reshape(len(states), len(ROOT_GRID)), nan=0.0))
    tables = {solve: _solve_table(energy, c, C, solve, states, scale) for solve in SOLVES}
    last = np.minimum(*(found[-1] for found, _ in tables.values()))
    reached = rooted & (last <= tol)
    options = []  # (cost, solve, steps, residual) converging wherever either reaches the root
    for order, (solve, (found, costs)) in enumerate(tables.items()):
        for steps, row, cost in zip(PLANE_STRESS_STEPS[solve], found, costs):
            if np.all(row[reached] <= tol):
                options.append((cost, order, solve, steps, float(row[reached].max(initial=0.0))))
                break
    if options:
        _, _, solve, steps, residual = min(options)
    else:  # neither converges wherever the other does: the one whose 32 steps reach more states
        solve = max(SOLVES, key=lambda s: (int(np.sum(rooted & (tables[s][0][-1] <= tol))), s == "fitted"))
        steps = PLANE_STRESS_STEPS[solve][-1]
        kept = rooted & (tables[solve][0][-1] <= tol)
        residual = float(tables[solve][0][-1][kept].max(initial=0.0))
    return PlaneStressCheck(steps, residual, tuple(tuple(float(v) for v in s) for s in states[~rooted]),
                            tuple((tuple(float(v) for v in s), float(r))
                                  for s, r in zip(states[rooted & ~reached], last[rooted & ~reached])), solve)


def plane_stress_residual(energy, C, x):
    """``dW/dC_22`` at ``C_22 = x`` (twice the thickness stress ``S_22``)."""
    s = ca.SX.sym("c22")
    return ca.substitute(ca.gradient(energy(with_thickness(C, s)), s), s, x)


def thickness_state(law, C, params):
    """The values the law's treatment sets at ``C``: ``(C_22,)`` (``C_22 = 1`` under the director constraint), or
    the tuple of the law's own solve when it has a ``held_energy``.

    Plane stress: the law's own solve (``law.condense``) when it has one, else :func:`plane_stress_thickness`.
    """
    if law.thickness == "director":
        return (C[THICK][THICK],)
    if law.thickness == "incompressible":
        x = incompressible_thickness(C)
        return (x, incompressible_pressure(law, C, x, params))
    if law.thickness == "plane-stress":
        if law.condense is None:
            return (plane_stress_thickness(lambda c: law.energy(c, params), C),)
        values = law.condense(C, params)
        return tuple(values) if law.held_energy is not None else (values,)
    raise ValueError(f"thickness treatment {law.thickness!r} is not director, plane-stress or incompressible")


def thickness_component(law, C, params):
    """``C_22`` as the law's treatment sets it (``1`` under the director constraint)."""
    return thickness_state(law, C, params)[0]


def held_energy(law, C, values, params):
    """``W`` at ``C`` with the values of :func:`thickness_state` given (``C_22 = values[0]``).

    Incompressible: ``W(C_x) - p (det C_x - 1)`` with ``p = values[1]`` (:func:`incompressible_pressure`): the same
    value at ``det C_x = 1``, and, ``x`` and ``p`` held, the first derivatives in ``C`` of ``W`` with ``x(C)``
    substituted (``-p d(det)/dC = dW/dx dx/dC`` there), so a gradient needs no ``dx/dC``.
    """
    if law.held_energy is not None:
        return law.held_energy(C, values, params)
    Cx = with_thickness(C, values[0])
    if law.thickness == "incompressible" and len(values) > 1:
        return law.energy(Cx, params) - values[1] * (determinant(Cx) - 1.0)
    return law.energy(Cx, params)


def incompressible_pressure(law, C, x, params):
    """``p = (dW/dC_22) / (d det C/dC_22)`` at ``C_22 = x``: the multiplier of ``det C = 1`` that makes
    :func:`held_energy` stationary in ``C_22`` (``d det C/dC_22 = C_11 C_33 - C_13^2``, ``det C`` being affine in
    ``C_22``)."""
    s = ca.SX.sym("c22")
    dw = ca.substitute(ca.gradient(law.energy(with_thickness(C, s), params), s), s, x)
    return dw / (C[0][0] * C[2][2] - C[0][2] * C[2][0])


def condensed_energy(law, C, params):
    """``W`` at ``C`` with the thickness component set by the law's treatment (see the module docstring)."""
    if law.thickness == "director":
        return law.energy(C, params)
    return held_energy(law, C, thickness_state(law, C, params), params)


def shell_cauchy_green(a, b, c, d, c2, zeta, j1, j3):
    """``C`` at depth ``zeta`` from :func:`~mol_shell.model.kinematics.column_polynomials` and the column factors.

    ``F = [(a + zeta b) j1, c2, (c + zeta d) j3]`` (``|c2| = 1``); ``C_22 = 1`` here, as the director has it.
    """
    col1 = tuple(x + zeta * y for x, y in zip(a, b))
    col3 = tuple(x + zeta * y for x, y in zip(c, d))
    c11, c33, c13 = _dot(col1, col1) * (j1 * j1), _dot(col3, col3) * (j3 * j3), _dot(col1, col3) * (j1 * j3)
    c12, c23 = _dot(col1, c2) * j1, _dot(c2, col3) * j3
    return ((c11, c12, c13), (c12, 1.0, c23), (c13, c23, c33))


def law_thickness_energy(strains, law, params, factors, beta2_0=0.0, trig=None, thickness_values=None):
    """``sum_q vol_q W(C_q)``: :func:`~mol_shell.model.material.thickness_energy` for any law.

    ``factors``: :func:`~mol_shell.model.material.quadrature_factors` (or a cell's symbolic ones); ``trig``:
    the sample's ``(cos theta, sin theta, cos psi, sin psi)`` if known. ``thickness_values``: the values of
    :func:`thickness_state` at the points (:func:`law_thickness_values`), given instead of solved here.
    """
    a, b, c, d, c2 = column_polynomials(strains, beta2_0, trig)
    total = 0.0
    for q, (zeta, j1, j3, vol) in enumerate(factors):
        C = shell_cauchy_green(a, b, c, d, c2, zeta, j1, j3)
        if thickness_values is None:
            w = condensed_energy(law, C, params)
        else:
            w = held_energy(law, C, thickness_values[q], params)
        total = total + vol * w
    return total


def law_thickness_values(strains, law, params, factors, beta2_0=0.0, trig=None):
    """The values of :func:`thickness_state` (``C_22`` first) that the law's treatment sets at each of
    ``factors``' points."""
    a, b, c, d, c2 = column_polynomials(strains, beta2_0, trig)
    return [thickness_state(law, shell_cauchy_green(a, b, c, d, c2, zeta, j1, j3), params)
            for zeta, j1, j3, _ in factors]


def law_shell_energy(strains, law, params, thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0, beta2_0=0.0):
    """Stored energy per unit reference area for any law: :func:`~mol_shell.model.material.shell_energy`'s
    arguments with ``(law, params)`` in place of the Lame pair."""
    factors = quadrature_factors(thickness, r0, theta0, theta0_s, beta1_0)
    return law_thickness_energy(strains, law, params, factors, beta2_0) / r0


def incompressible_strain(C):
    """The Green strain ``E = (C - I)/2`` (nested 3x3) at ``C`` with ``C_22 = incompressible_thickness(C)``."""
    Cx = with_thickness(C, incompressible_thickness(C))
    return tuple(tuple(0.5 * (Cx[i][j] - (1.0 if i == j else 0.0)) for j in range(3)) for i in range(3))


def incompressible_dissipation(strains, rates, eta_mu, factors, beta2_0=0.0, trig=None):
    """``sum_q vol_q eta_mu E_t : E_t`` with ``E`` of :func:`incompressible_strain`: the Kelvin-Voigt Rayleigh function
    of an incompressible law (``2 D`` its power), exact at finite strain (CasADi ``strains``/``rates``).

    ``C`` at each point is :func:`shell_cauchy_green`'s (as in :func:`law_thickness_energy`), its thickness component
    set by ``det C = 1``; ``E_t`` is ``E``'s derivative along ``rates`` (``ca.jtimes``), so ``E_t,22`` follows the
    in-plane and shear rates (``-2 e`` for an equibiaxial ``e`` at small strain). ``factors``: as in
    :func:`~mol_shell.model.material.thickness_dissipation` (numbers or a cell's symbols); ``trig``: the sample's
    ``(cos theta, sin theta, cos psi, sin psi)`` if known (their rates follow from those of ``theta`` and ``psi``).
    """
    e_sym, r_sym, t_sym = ca.SX.sym("e", 8), ca.SX.sym("edot", 8), ca.SX.sym("trig", 4)
    f_sym = [ca.SX.sym(f"f{i}", 4) for i in range(len(factors))]  # zeta (a graded wall's are symbols), j1, j3, vol
    b_sym = ca.SX.sym("beta2_0")
    b = 0.0 if isinstance(beta2_0, (int, float)) and beta2_0 == 0 else b_sym  # left out when it is 0
    a, bz, c, d, c2 = column_polynomials(ca.vertsplit(e_sym), b, None if trig is None else ca.vertsplit(t_sym))
    inputs, directions = e_sym, r_sym
    if trig is not None:
        inputs = ca.vertcat(e_sym, t_sym)
        directions = ca.vertcat(r_sym, *trigonometry_rates(ca.vertsplit(t_sym), r_sym[6], r_sym[7]))
    total = 0.0
    for f in f_sym:
        E = incompressible_strain(shell_cauchy_green(a, bz, c, d, c2, f[0], f[1], f[2]))
        Et = ca.jtimes(ca.vertcat(*[E[i][j] for i in range(3) for j in range(3)]), inputs, directions)
        total = total + f[3] * (eta_mu * ca.sumsqr(Et))
    fn = ca.Function("incompressible_dissipation", [e_sym, r_sym, t_sym, b_sym, *f_sym], [total])
    values = [ca.vertcat(zeta, j1, j3, vol) for zeta, j1, j3, vol in factors]
    return fn(ca.vertcat(*strains), ca.vertcat(*rates), ca.vertcat(*(trig if trig is not None else [0.0] * 4)),
              beta2_0, *values)


def law_shell_dissipation(strains, rates, eta_mu, thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0,
                          beta2_0=0.0):
    """:func:`incompressible_dissipation` per unit reference area: :func:`~mol_shell.model.material.shell_dissipation`
    of an incompressible law (``eta_mu`` alone)."""
    factors = quadrature_factors(thickness, r0, theta0, theta0_s, beta1_0)
    return incompressible_dissipation(strains, rates, eta_mu, factors, beta2_0) / r0


#: the components of ``C`` and ``E_t`` other than the thickness one, each symmetric pair once
IN_PLANE = ((0, 0), (2, 2), (0, 2), (0, 1), (1, 2))


@functools.lru_cache(maxsize=1)
def _incompressible_viscous():
    """``(c, x, eta_mu) -> S`` of :func:`incompressible_viscous_stress` (``c, x``: :data:`IN_PLANE` of ``C, E_t``)."""
    c, x, eta = ca.SX.sym("c", 5), ca.SX.sym("x", 5), ca.SX.sym("eta_mu")
    where = {k: n for n, k in enumerate(IN_PLANE)}

    def nested(v, thick):
        return [[thick if i == j == THICK else v[where[min(i, j), max(i, j)]] for j in range(3)] for i in range(3)]

    C = nested(ca.vertsplit(c), 1.0)
    x22 = 0.5 * ca.jtimes(incompressible_thickness(C), c, 2.0 * x)  # C_t = 2 E_t, each pair one variable
    Et = nested(ca.vertsplit(x), x22)
    D = eta * sum(Et[i][j] * Et[i][j] for i in range(3) for j in range(3))
    g = ca.gradient(D, x)
    S = ca.vertcat(*[(1.0 if i == j else 0.5) * g[n] for n, (i, j) in enumerate(IN_PLANE)])
    return ca.Function("incompressible_viscous_stress", [c, x, eta], [S, D])


def incompressible_viscous_stress(C, E_t, eta_mu):
    """``(S_v, D)``: the viscous second Piola-Kirchhoff stress of an incompressible law (nested 3x3) and the Rayleigh
    function ``D = eta_mu E_t : E_t`` per unit reference volume at ``C`` for the kinematic rates ``E_t``.

    ``E_t``'s thickness component is not read: it is ``(1/2) dC_22/dt`` with ``C_22`` of
    :func:`incompressible_thickness`, linear in the other rates. ``S_v`` is ``D``'s derivative in the five
    independent rates (:data:`IN_PLANE`; an off-diagonal pair shares it), ``S_v,22 = 0``, so ``S_v : E_t = 2 D``
    (``D`` quadratic); it is ``2 eta_mu (E_t - E_t,22 (C^-1)/(C^-1)_22)`` off the thickness component, at small strain
    ``2 eta_mu (E_t - E_t,22 I)``. ``C``, ``E_t`` nested 3x3 (symmetric) of CasADi expressions or numbers.
    """
    S, D = _incompressible_viscous()(ca.vertcat(*[C[i][j] for i, j in IN_PLANE]),
                                     ca.vertcat(*[E_t[i][j] for i, j in IN_PLANE]), eta_mu)
    where = {k: n for n, k in enumerate(IN_PLANE)}
    return tuple(tuple(0.0 if i == j == THICK else S[where[min(i, j), max(i, j)]] for j in range(3))
                 for i in range(3)), D
