"""A law of one's own in plane stress whose condition ``dW/dC_22 = 0`` has no root at some stretches.

St Venant-Kirchhoff written as a user ``Material``, ``W = lambda/2 (tr E)^2 + mu E:E``, was refused for every
``nu >= 0.2``: the check asked the unrolled Newton solve to converge at in-plane stretches up to 2, and SVK's
condition has no root there. Derived here: ``S_22 = lambda tr E + 2 mu E_22 = 0`` gives
``E_22 = -lambda/(lambda + 2 mu) (E_11 + E_33)``, so ``C_22 = 1 + 2 E_22 = 1 - 2 nu/(1 - nu) (E_11 + E_33)``
(``lambda/(lambda + 2 mu) = nu/(1 - nu)``), whatever the in-plane shear; it reaches 0 where
``E_11 + E_33 = (1 - nu)/(2 nu)``, an equibiaxial stretch ``l`` with ``l^2 - 1 = (1 - nu)/(2 nu)``: 1.472 at
``nu = 0.3``. Beyond it ``W`` falls as the wall thins to nothing: no root ``C_22 > 0``. The law is taken where
its condition has a root, and a run that gets beyond stops as at the edge of the law's domain, naming the law, the
time and the cell (its energy is NaN there).
"""

import math

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.scenes import Sphere

E = 1e6
TIMES = np.linspace(0.0, 4e-3, 3)


def svk(C, p):
    """St Venant-Kirchhoff from ``E, nu``: ``lambda/2 (tr E)^2 + mu E:E``, ``E = (C - I)/2``."""
    lam, mu = p["E"] * p["nu"] / ((1 + p["nu"]) * (1 - 2 * p["nu"])), p["E"] / (2 * (1 + p["nu"]))
    strain = (C - ca.SX.eye(3)) / 2
    return lam / 2 * ca.trace(strain) ** 2 + mu * ca.trace(strain @ strain)


def user_svk(nu):
    return mol_shell.Material(f"user-svk-{nu}", svk, {"E": E, "nu": nu}, thickness="plane-stress")


@pytest.mark.parametrize("nu", [0.1, 0.2, 0.25, 0.3, 0.45])
def test_svk_of_one_s_own_is_taken_in_plane_stress_for_every_nu(nu):
    """Refused for ``nu >= 0.2`` before (``after 32 steps dW/dC22 is still 0.481 of the stiffness at in-plane
    stretches 0.6 to 2`` at 0.3): the states without a root are those the closed form says, and the solve is asked
    to converge at the others only."""
    from mol_shell.model.hyperelastic import NATURAL_STATES, PLANE_STRESS_STATES, plane_stress_steps

    law = user_svk(nu)
    assert law.steps in (6, 8, 12, 16, 24, 32)
    found = plane_stress_steps(lambda C: law.law().energy(C, law.parameters), law.stiffness)
    expected = {s for s in NATURAL_STATES + PLANE_STRESS_STATES
                if 1 - 2 * nu / (1 - nu) * ((s[0] - 1) / 2 + (s[1] - 1) / 2) <= 0}
    assert set(found.rootless) == expected
    assert (nu >= 0.2) == bool(expected)  # nu = 0.1: a root up to an equibiaxial stretch of 2.35
    assert found.residual <= 1e-9


def test_svk_of_one_s_own_gives_the_built_in_svk_plane_stress_run():
    """A sphere released at ``R = 1.2`` (stretch 1.2, inside the root's range 1.472): the user law's run is the
    built-in ``svk-plane-stress``'s (its closed-form condensed Lame pair) to round-off, every field at every saved
    time; the generic solve converges to round-off there."""
    builtin = mol_shell.simulate(Sphere(h=0.01, nu=0.3, material="svk-plane-stress", R=1.2), "leapfrog", n=8,
                                 times=TIMES, progress=False, stresses=False)
    with pytest.warns(mol_shell.SceneWarning, match="nu = 0.3 is unused"):  # the Material reads its own nu
        own = mol_shell.simulate(Sphere(h=0.01, nu=0.3, material=user_svk(0.3), R=1.2), "leapfrog", n=8,
                                 times=TIMES, progress=False, stresses=False)
    assert own.attrs["status"] == "complete"
    assert float(np.ptp(own.r.values[:, 4])) > 1e-3  # it moved
    for f in ("z", "r", "chi", "theta", "psi", "energy"):
        scale = float(np.abs(builtin[f].values).max()) or 1.0
        np.testing.assert_allclose(own[f].values, builtin[f].values, rtol=0, atol=1e-12 * scale, err_msg=f)


def test_a_start_beyond_the_root_stops_at_t_0_naming_the_law_the_cell_and_why():
    """``R = 1.5``: ``C_22 = 1 - (3/3.5)(1.5^2 - 1) < 0`` at the mid-surface: no root, the energy is NaN, and the run
    stops at ``t = 0`` as a limit of the law, saying so (the built-in law runs on: its closed form has no bound)."""
    law = user_svk(0.3)
    assert 1 - 0.6 / 0.7 * (1.5**2 - 1) < 0
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate(Sphere(h=0.01, material=law, R=1.5), "leapfrog", n=8, t_end=1e-3, progress=False,
                                stresses=False)
    message = ds.attrs["message"]
    assert ds.attrs["status"] == "limit" and ds.sizes["time"] == 1, message
    assert message.startswith(f"the energy of material '{law.name}' is not finite at t = 0 s, s = "), message
    assert "(cell centre)" in message and "at the stretches 1.5 along the meridian and 1.5 round it" in message
    assert "its plane-stress condition dW/dC22 = 0 has no root C22 > 0 there" in message


def test_a_motion_past_where_the_solve_works_stops_there_naming_the_law_and_the_time():
    """Released at ``R = 1.3`` under ``p = 30 kPa`` (more than the wall holds there: it swells; the built-in law's
    static radius is 1.65): the run stops as the stretch nears 1.472, at a time inside the run and a cell, naming
    the law and the solve's failure, and keeps its saved times."""
    law = user_svk(0.3)
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate(Sphere(h=0.01, material=law, R=1.3, pressure=3e4), "leapfrog", n=8, t_end=0.02,
                                times=np.linspace(0, 0.02, 11), progress=False, stresses=False)
    message = ds.attrs["message"]
    assert ds.attrs["status"] == "limit" and ds.sizes["time"] > 1, message
    t = float(message.split("not finite at t = ")[1].split(" s")[0])
    assert 0 < t < 0.02 and ds.time.values[-1] <= t
    assert message.startswith(f"the energy of material '{law.name}' is not finite at t = "), message
    stretch = float(message.split("at the stretches ")[1].split(" ")[0])
    assert 1.3 < stretch < math.sqrt(1 + 0.7 / 0.6)  # where the root C22 > 0 ends, 1.472
    assert "dW/dC22" in message and "plane-stress condition" in message
