"""``neo-hookean`` (Ciarlet and Geymonat's, plane stress in closed form) near ``nu = 0.5``.

Until December 7 its condensed energy was written with ``lambda/4 - (mu/2 + lambda/4)/det C``, the slope of its
volumetric part at the condensed ``det C``: a difference of two terms of size ``lambda`` for a result of size
``mu``, which left the stresses a round-off of ``1e-16 lambda/mu`` (5e-9 at ``nu = 0.49999999``) and the static
solve stuck above its tolerance (``residual 5.48e-11 of a unit strain's force``: a sphere under 1 Pa refused for
every ``nu`` from 0.49999999 on). The slope is ``-mu/(2 M)`` there (``dW/dC_22 = 0``), computed as such now.

References derived here. As ``lambda/mu -> infinity`` the law tends to the incompressible neo-Hookean
``mu/2 (I1 - 3)``: the condensed ``det C = M (2 mu + lambda)/(2 mu + lambda M) -> 1`` with ``det C - 1`` of order
``mu/lambda``, so the stresses of the two laws (same ``mu``) differ by ``O(mu^2/lambda)``. For the thin sphere
(membrane, wall ``t = 2h``, equibiaxial stretch ``l``; tests/model/test_balloon.py):
``p = 2 mu (t/a)(1/l - 1/l^7)`` incompressible, and the compressible law's
``p = 2 (t/a) [mu (l - 1/l) + lambda/2 (J^2 - 1)/l] / l^2`` with ``J^2 = l^4 (2 mu + lambda)/(2 mu + lambda l^4)``.
With ``e = 1 - 2 nu`` (``2 mu/lambda = e/nu = 2e + O(e^2)``, ``mu = (E/3)(1 + e/3) + O(e^2)``) the second is the
first times ``1 + e c(l)``, ``c = 1/3 - 2 l^-6 (1 - l^-4)/(1 - l^-6)``, so at a given pressure the stretch moves by
``dl = -e c(l) p/p'(l) = -e c(l) l (l^6 - 1)/(7 - l^6)`` to first order in ``e``.
"""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.optimize import brentq

from mol_shell.discretization.system import ShellSystem
from mol_shell.model.hyperelastic import held_energy, thickness_state
from mol_shell.model.laws import LAWS
from mol_shell.model.material import lame
from mol_shell.runs.statics import TOL, newton
from mol_shell.scenes import Sphere

E, H, P, N = 1.0e6, 0.01, 3000.0, 21


def _membrane_stretch():
    """The incompressible balloon's stretch at ``P``: ``2 mu (t/a)(1/l - 1/l^7) = P`` below its maximum."""
    return brentq(lambda l: 2 * E / 3 * 2 * H * (1 / l - l**-7) - P, 1.0, 7 ** (1 / 6), xtol=1e-15)


def _radii(material, **changes):
    """The node radii (from the mean ``z``) of the static equilibrium at ``n = N`` under ``P``, and its residual."""
    scene = Sphere(h=H, E=E, pressure=P, material=material, **changes)
    system = ShellSystem(scene, N)
    y, _, residual = newton(system, system.initial_state(scene))
    z, r = system.unpack(y)[:2]
    return np.hypot(r, z - z.mean()), residual


@pytest.mark.parametrize("nu", [0.4999999, 0.49999999, 0.49999999999])
def test_the_sphere_near_nu_half_has_the_incompressible_balloon_s_equilibrium(nu):
    """Refused for ``nu >= 0.49999999`` (Newton stuck at 5e-11 of a unit strain's force). Now converged to the
    statics' tolerance; the mean radius against the incompressible law's by the membrane's first-order shift
    ``dl`` (relative to it to ``ds^2 = (pi/(N - 1))^2``, the discretisation's order, which moves both laws alike),
    and the incompressible one against the membrane's closed form to ``ds^2`` of the strain."""
    l = _membrane_stretch()
    incompressible, _ = _radii("neo-hookean-incompressible")
    compressible, residual = _radii("neo-hookean", nu=nu)
    assert residual <= TOL
    ds2 = (math.pi / (N - 1)) ** 2
    assert abs(incompressible.mean() - l) <= ds2 * (l - 1)
    e = 1 - 2 * nu
    c = 1 / 3 - 2 * l**-6 * (1 - l**-4) / (1 - l**-6)
    shift = -e * c * l * (l**6 - 1) / (7 - l**6)
    assert shift > 0  # c < 0: the compressible wall is softer
    assert (compressible - incompressible).mean() == pytest.approx(shift, rel=ds2)


def _held_stress(law, C, c, params):
    """``dW/dc`` as the cell kernels take it: the law's thickness values (``C_22`` and what its solve found) held
    while differentiating, then substituted (:meth:`~mol_shell.discretization.cells.CellKernels.cell_forces_shared_kernel`)."""
    values = thickness_state(law, C, params)
    held = [ca.SX.sym(f"v{i}") for i in range(len(values))]
    gradient = ca.gradient(held_energy(law, C, tuple(held), params), c)
    return ca.substitute([gradient], held, list(values))[0]


def test_the_condensed_stresses_near_nu_half_are_the_incompressible_law_s():
    """``dW/dC`` of the condensed law (the five components the shell sets, ``C_22`` and ``det C`` held as the cell
    forces hold them) at ``nu = 0.49999999999`` (``lambda/mu = 5e10``) against the incompressible neo-Hookean's of
    the same ``mu``: equal to ``O(mu/lambda)``, here 1e-9 of the largest; with the slope as a difference of
    ``lambda``-sized terms they were 2e-3 apart at a strain of 1e-4."""
    nu = 0.49999999999
    lam, mu = lame(E, nu)
    c = ca.SX.sym("c", 5)  # C_11, C_33, C_13, C_12, C_23 (C_22 set by the law)
    C = ((c[0], c[3], c[2]), (c[3], 1.0, c[4]), (c[2], c[4], c[1]))
    stress = [ca.Function("stress", [c], [_held_stress(LAWS[name], C, c, params)])
              for name, params in (("neo-hookean", {"lambda": lam, "mu": mu}),
                                   ("neo-hookean-incompressible", {"mu": mu}))]
    for state in ([1.21, 0.81, 0.1, 0.05, -0.02], [1.0001, 1.0002, 0.0, 0.0, 0.0], [2.5, 1.7, -0.3, 0.1, 0.2]):
        got, expected = (np.array(f(state)).ravel() for f in stress)
        assert np.abs(got - expected).max() <= 1e-9 * np.abs(expected).max(), state
