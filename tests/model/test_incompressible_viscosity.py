"""Kelvin-Voigt viscosity of the incompressible laws (``det C = 1``): the thickness strain rate is kinematic.

References, derived here and independent of the code under test (``D`` the Rayleigh function, ``2 D`` the power
the Dataset's ``dissipation`` reports, ``E = (C - I)/2``, ``eta_mu E_t : E_t`` per unit reference volume):

- finite equibiaxial stretch ``l`` (in-plane ``C = l^2 I``, ``C_22 = l^-4``): ``E_t = l l_t`` in each in-plane
  direction and ``E_t,22 = (1/2) d(l^-4)/dt = -2 l^-5 l_t``, so ``D = eta_mu (2 l^2 + 4 l^-10) l_t^2``;
- small-amplitude breathing of a sphere of radius ``a``, wall ``2h``, radial velocity ``w_t``: ``l = 1``, ``l_t =
  w_t / a``, so ``2 D = 12 eta_mu (w_t/a)^2`` per unit volume and ``12 eta_mu 4 pi a^2 (2h) w_t^2 / a^2`` in all
  (the same at every depth ``zeta``: the rate ``w_t / (a + zeta)`` times the volume ``4 pi (a + zeta)^2 d zeta``).

``eta_lambda`` acts on nothing under ``det C = 1``. (Before the fix the pair was condensed as for plane stress,
``2 D = 2 eta_mu 2 e^2 + lambda* (2 e)^2``: 1/3 of the above at ``eta_lambda = 0``, 2/3 at ``eta_lambda = 2 eta_mu``.)
"""

import math
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.law_warnings import unused_law_parameters
from mol_shell.runs.simulate import resolve
from mol_shell.scenes import Sphere


def test_a_breathing_sphere_dissipates_the_closed_forms_power_whatever_eta_lambda():
    """The reviewer's sphere (defaults: ``a = 1``, ``h = 2 pi 1e-3``) on 21 nodes, released from ``R = 1.0001``: at
    the largest equatorial ``|r_t|`` the power over ``r_t^2`` is the closed form's 1895 W s^2 m^-2 (the code gave 631
    and 1262). Measured 0.46 % below at n = 21: the error is the grid's, O(ds^2) (1.69, 0.46, 0.13, 0.049 % at n = 11,
    21, 41, 81; the polygonal wall's volume alone is 0.31 % short at n = 21); 1 % allowed. ``eta_lambda`` changes
    nothing, to the last bit."""
    closed = 12 * 1000.0 * 4 * math.pi * 2 * (2 * math.pi * 1e-3)
    values = []
    for eta in (0.0, 2000.0):
        scene = Sphere(R=1.0001, material="neo-hookean-incompressible", eta_mu=1000.0, eta_lambda=eta)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", mol_shell.SceneWarning)
            ds = mol_shell.simulate(scene, "cvode-bdf", n=21, times=np.linspace(0, 0.02, 41), rtol=1e-9,
                                    progress=False, stresses=False)
        r_t = ds.r_t.values[:, 10]
        k = int(np.abs(r_t).argmax())
        values.append(float(ds.dissipation.values[k]) / r_t[k] ** 2)
    assert values[0] == pytest.approx(closed, rel=0.01)
    assert values[1] == values[0]


@pytest.mark.parametrize("stretch", [1.5, 0.8])
@pytest.mark.parametrize("shared", [False, True])
def test_the_cells_dissipation_is_the_finite_stretch_closed_form(stretch, shared):
    """A thin sphere (``h = 1e-3 a``) dilated to ``l a`` and expanding at ``l_t``: every cell is at ``C = l^2 I`` in
    the plane (the reference is the discrete one), so the cells' ``2 D`` sums to ``2 eta_mu (2 l^2 + 4 l^-10) l_t^2``
    times the wall's volume (the cells' own); through the per-point kernel and the shared one (the nodes'
    trigonometry). The remaining error is the wall's, of order ``(h/a)^2``: measured 1.7e-6 (``l = 1.5``) and 4.6e-6
    (``l = 0.8``), 2e-5 allowed (the condensed pair of the code before gave 1.5 % less at ``l = 1.5``, 97 % less at
    ``l = 0.8``). ``eta_lambda`` changes nothing, to the last bit."""
    l, l_t, eta_mu = stretch, 0.7, 1000.0
    powers = []
    for eta_lambda in (0.0, 2000.0):
        scene = resolve(Sphere(h=1e-3, R=l, material="neo-hookean-incompressible", eta_mu=eta_mu,
                               eta_lambda=eta_lambda))
        system = ShellSystem(scene, 9)
        z0, r0, th0 = system.reference
        Q = np.array([l * z0, l * r0, 0 * z0, th0, 0 * z0])
        V = np.array([l_t * z0, l_t * r0, 0 * z0, 0 * z0, 0 * z0])
        if shared:
            kernel, trig = system.viscous_forces_shared_kernel(), system.node_trig_kernel()
            T = np.hstack([np.array(trig(Q[:, i])) for i in range(system.n)])
            geo = np.broadcast_to(system.shared_cell_data, (system.shared_cell_data.shape[0], system.n - 1))
            cells = [kernel(Q[:, i], Q[:, i + 1], V[:, i], V[:, i + 1], T[:, i], T[:, i + 1], geo[:, i])
                     for i in range(system.n - 1)]
        else:
            kernel = system.viscous_forces_kernel()
            cells = [kernel(Q[:, i], Q[:, i + 1], V[:, i], V[:, i + 1], system.cell_data[:, i])
                     for i in range(system.n - 1)]
        powers.append(sum(float(out[2]) for out in cells))
    volume = sum(system.cell_data[3 * q + 2].sum() for q in range(scene.n_quad))
    expected = 2 * eta_mu * (2 * l**2 + 4 * l**-10) * l_t**2 * volume
    assert powers[0] == pytest.approx(expected, rel=2e-5)
    assert powers[1] == powers[0]


@pytest.mark.parametrize("material", ["neo-hookean-incompressible", "mooney-rivlin"])
def test_eta_lambda_on_an_incompressible_law_is_said_unused_once(material):
    """``eta_lambda`` acts on nothing under ``det C = 1``: set on an incompressible law it is a SceneWarning (once)
    and the run's ``scene_warning``, as an unread ``E, nu, c10, c01`` is; not on a compressible law, nor at 0."""
    scene = Sphere(material=material, eta_mu=10.0, eta_lambda=20.0)
    lines = unused_law_parameters(scene)
    assert [line for line in lines if line.startswith("eta_lambda = 20 is unused")] == lines and len(lines) == 1
    assert "det C = 1" in lines[0] and "eta_mu alone" in lines[0]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(scene, n=8, t_end=1e-5, progress=False, stresses=False)
    told = [str(w.message) for w in seen if w.category is mol_shell.SceneWarning]
    assert told == lines and ds.attrs.get("scene_warning", "") == lines[0]
    assert unused_law_parameters(Sphere(material=material, eta_mu=10.0)) == []
    assert unused_law_parameters(Sphere(material="neo-hookean", nu=0.3, eta_mu=10.0, eta_lambda=20.0)) == []
