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
import textwrap

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
    # dW/dC22 is affine in C22: the fitted step is exact in one step (the fewest it is offered, 2), Newton's in ln C22
    # needed 8 at nu = 0.3 (December 7)
    assert (law.solve, law.steps) == ("fitted", 2)
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
    static radius is 1.65): the run stops at the edge of the law's domain, at a time inside the run and a cell,
    naming the law and why, and keeps its saved times. The first thickness point to get there is the inner one, at
    ``zeta = -0.861 h`` (4 Gauss points), whose stretches ``(R + zeta)/(a + zeta)`` reach 1.4720 when the mid-surface's
    are 1.4679. Until December 7 it stopped at 1.424, where 8 Newton steps on ``ln C22`` no longer reached the root
    (``its 8 Newton steps from C22 = 1 leave dW/dC22 = 1e-06 of the stiffness there``)."""
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
    assert 1.46 < stretch < math.sqrt(1 + 0.7 / 0.6)  # 1.4679 for a uniform dilation; 1.472, where C22 > 0 ends
    assert "its plane-stress condition dW/dC22 = 0 has no root C22 > 0 there" in message, message


def _edge(nu):
    """The equibiaxial stretch where St Venant-Kirchhoff's plane-stress ``C_22 = 1 - 2 nu/(1 - nu) (l^2 - 1)``
    reaches 0: ``l^2 = (1 + nu)/(2 nu)``."""
    return math.sqrt((1 + nu) / (2 * nu))


def _condensed(nu):
    """The user law's condensed energy, as its runs take it (its solve, with NaN where it fails), and its gradient and
    Hessian in ``c = (C11, C33, C13)`` (``C13 = C31 = c[2]``), the in-plane components, the transverse shears 0."""
    from mol_shell.model.hyperelastic import condensed_energy

    law = user_svk(nu)
    c = ca.SX.sym("c", 3)
    C = ((c[0], 0.0, c[2]), (0.0, 1.0, 0.0), (c[2], 0.0, c[1]))
    W = condensed_energy(law.law(), C, law.parameters)
    return ca.Function("w", [c], [W, ca.gradient(W, c), ca.hessian(W, c)[0]])


@pytest.mark.parametrize("nu", [0.3, 0.45])
def test_the_law_of_one_s_own_reaches_the_edge_of_its_domain(nu):
    """The equibiaxial stretch beyond which the user law's energy is NaN (its solve failing) is the closed form's edge,
    1.4720 at ``nu = 0.3`` and 1.2693 at 0.45: until December 7 the 8 (and 12) Newton steps on ``ln C22`` left the
    root unreached from 1.4284 (and 1.2659) on, where ``C22 = 0.11`` (``0.014``): they crawl there, half a unit of
    ``ln C22`` a step."""
    energy = _condensed(nu)

    def finite(stretch):
        return math.isfinite(float(energy([stretch * stretch, stretch * stretch, 0.0])[0]))

    lo, hi = 1.0, 2.0
    assert finite(lo) and not finite(hi)
    for _ in range(50):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if finite(mid) else (lo, mid)
    assert abs(lo - _edge(nu)) <= 1e-6 * _edge(nu), (lo, _edge(nu))


@pytest.mark.parametrize("nu", [0.3, 0.45])
def test_the_law_of_one_s_own_has_svk_plane_stress_s_energy_stresses_and_stiffness_up_to_the_edge(nu):
    """Condensed, ``W = lambda*/2 (E11 + E33)^2 + mu (E11^2 + E33^2 + 2 E13^2)`` with ``lambda* = E nu/(1 - nu^2)``
    (the built-in ``svk-plane-stress``'s pair), so ``S = 2 dW/dC`` is ``lambda* (E11 + E33) I + 2 mu E`` in the plane
    and the Hessian in ``(C11, C33, C13)`` is constant: ``lambda*/4 + mu/2``, ``lambda*/4`` and ``mu``. The user law
    (through its solve and AD, as the runs' forces and Jacobians) gives them to round-off, far from the edge and
    1e-3 from it (``C22`` from 0.82 down to 0.0025 at ``nu = 0.3``); until December 7 its Newton steps left its
    energy NaN there (and at 0.95 of the edge's ``C11`` at ``nu = 0.3``)."""
    lam_star, mu = E * nu / (1 - nu * nu), E / (2 * (1 + nu))
    energy = _condensed(nu)
    edge = _edge(nu)
    hessian = np.array([[lam_star / 4 + mu / 2, lam_star / 4, 0.0], [lam_star / 4, lam_star / 4 + mu / 2, 0.0],
                        [0.0, 0.0, mu]])
    for c11, c33, c13 in [(1.2**2, 1.1**2, 0.1), (1.21, 1.21, 0.0), (0.95 * edge**2, 0.95 * edge**2, 0.05),
                          ((edge - 1e-3) ** 2, (edge - 1e-3) ** 2, 0.0)]:
        e11, e33, e13 = (c11 - 1) / 2, (c33 - 1) / 2, c13 / 2
        assert 1 - 2 * nu / (1 - nu) * (e11 + e33) > 0  # inside the domain
        W, grad, H = (np.array(v, dtype=float) for v in energy([c11, c33, c13]))
        expected = lam_star / 2 * (e11 + e33) ** 2 + mu * (e11**2 + e33**2 + 2 * e13**2)
        assert float(W.squeeze()) == pytest.approx(expected, rel=1e-12, abs=1e-12 * mu)
        stress = [lam_star * (e11 + e33) + 2 * mu * e11, lam_star * (e11 + e33) + 2 * mu * e33, 2 * mu * e13]
        np.testing.assert_allclose([2 * grad[0, 0], 2 * grad[1, 0], grad[2, 0]], stress, rtol=0, atol=1e-12 * E)
        np.testing.assert_allclose(H, hessian, rtol=0, atol=1e-10 * E)


def test_a_static_start_past_the_edge_of_the_law_s_domain_is_a_limit_of_the_law():
    """Under 30 kPa the sphere's equilibrium lies past the law's edge (the built-in law's static radius is 1.65, past
    1.472): there the user law's forces stay finite (its thickness held where the solve stops), and the static
    Newton converged to such a state. The run then started there and stopped at ``t = 0`` (exit 3, ``the energy of
    material ... is not finite at t = 0 s``, nothing said of the static start). The static solve now says that its
    equilibrium lies outside the law's domain, naming the loads, the law, the cell and its stretches: a limit
    (``ModelLimitError``; a study's case ``limit``), no run started."""
    from mol_shell.runs.study import case_result

    law = user_svk(0.3)
    scene = Sphere(h=0.01, material=law, pressure=3e4)
    with pytest.raises(mol_shell.ModelLimitError) as info:
        mol_shell.simulate(scene, "leapfrog", n=12, t_end=1e-4, progress=False, stresses=False)
    message = str(info.value)
    assert message.startswith("the static equilibrium under the loads at t = 0 (pressure = 30000) lies outside the "
                              f"domain of material '{law.name}': its energy is not finite at s = "), message
    assert "(cell centre): nan J in that cell, at the stretches " in message
    assert "its plane-stress condition dW/dC22 = 0 has no root C22 > 0 there" in message
    meridian, hoop = (float(message.split("at the stretches ")[1].split(" ")[k]) for k in (0, 5))
    assert min(meridian, hoop) > 1.46  # past where the inner thickness point reaches the edge (1.4679, above)

    def case():  # a study's case meeting it: recorded as a limit, with the message (it was an "error")
        raise info.value

    _, ds, recorded = case_result(0, case)
    assert ds is None and recorded["status"] == "limit" and recorded["message"] == message


def test_a_static_start_past_the_edge_of_the_law_s_domain_is_exit_3_and_no_file(tmp_path, monkeypatch, capsys):
    """The command line: one line naming the loads, the law (by its import path), the cell and its stretches; exit 3
    (it wrote the run stopped at ``t = 0``: ``mol-shell: run stopped: the energy of material 'svk_laws:law' is not
    finite at t = 0 s, ...; wrote 1 saved time``)."""
    from mol_shell.cli.main import main

    (tmp_path / "svk_laws.py").write_text(textwrap.dedent('''
        import casadi as ca
        import mol_shell

        def svk(C, p):
            lam, mu = p["E"] * p["nu"] / ((1 + p["nu"]) * (1 - 2 * p["nu"])), p["E"] / (2 * (1 + p["nu"]))
            strain = (C - ca.SX.eye(3)) / 2
            return lam / 2 * ca.trace(strain) ** 2 + mu * ca.trace(strain @ strain)

        law = mol_shell.Material("svk-file", svk, {"E": 1e6, "nu": 0.3})
    '''))
    monkeypatch.syspath_prepend(str(tmp_path))
    code = main(["run", "sphere", "--set", "h=0.01", "--set", "material=svk_laws:law", "--set", "pressure=3e4",
                 "--n", "12", "--t-end", "1e-4", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3 and err[-1].startswith("mol-shell: stopped: the static equilibrium under the loads at t = 0 "
                                            "(pressure = 30000) lies outside the domain of material 'svk_laws:law': "
                                            "its energy is not finite at s = "), err
    assert "at the stretches 1.5" in err[-1] and "has no root C22 > 0 there" in err[-1], err
    assert not (tmp_path / "x.nc").exists()
