"""SVK's compressive turning point (issue 24, item 6): past an in-plane stretch of 1/sqrt(3) the St Venant-Kirchhoff
stress turns back; a run stops there as a limit of the law, with time and place."""

import math

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.model.material import Thickness, shell_energy, svk_turning_limit, thickness_moments, quadrature_factors
from mol_shell.scenes import Sphere

LIMIT = "an in-plane stretch reached 1/sqrt(3) in compression"


def test_the_limit_is_where_the_stress_turns_back():
    """An axial stretch ``l`` of the unit cylinder (hoop held, plane-stress SVK): the nominal axial force
    ``dW/dz_s`` has its extreme where ``d2W/dz_s^2 = 0``, which is ``l^2 = 1/3`` (``P = (lambda* + 2 mu)(l^3 - l)/2``,
    ``E_33 = 0``); found here from the integrated shell energy by bisection (to the wall's ``(h/a)^2``), and the
    limit function changes sign at the same stretch (to 1e-12: it is that membrane criterion)."""
    thickness = Thickness(-0.005, 0.005, 4)
    x = ca.SX.sym("x")
    W = shell_energy((x, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0), 1.0, 0.5, thickness)
    stiffness = ca.Function("k", [x], [ca.hessian(W, x)[0]])
    moments = thickness_moments(quadrature_factors(thickness))
    g = ca.Function("g", [x], [svk_turning_limit((x, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0), moments)])
    lo, hi = 0.3, 0.9
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if float(stiffness(mid)) < 0 else (lo, mid)
    assert lo == pytest.approx(1 / math.sqrt(3), rel=1e-4)
    assert float(g(1 / math.sqrt(3) + 1e-9)) > 0 > float(g(1 / math.sqrt(3) - 1e-9))


def test_an_imploding_sphere_stops_at_the_law_s_limit():
    """A sphere under a large external pressure (plane-stress SVK, ``h/a = 0.01``, -200 kPa) collapses; the pole's
    cell reaches the stretch first. Leap-frog (its C loop) and CVODE (its root finding) stop at the same time, 9.23
    ms, to 1e-4, and name the limit and the place; the command line ends with exit 3."""
    scene = Sphere(h=0.01, material="svk-plane-stress", nu=0.3, pressure=-2e5, R=1.0)
    times = np.linspace(0, 0.0095, 20)
    runs = [mol_shell.simulate(scene, integrator, n=9, times=times, progress=False)
            for integrator in ("leapfrog", "cvode-bdf")]
    stops = []
    for ds in runs:
        assert ds.attrs["complete"] == 0 and LIMIT in ds.attrs["message"] and "s = 0.19635 m" in ds.attrs["message"]
        stops.append(float(ds.attrs["message"].split(" at t = ")[1].split(" s")[0]))
    assert stops[0] == pytest.approx(stops[1], rel=1e-4) and 0.009 < stops[0] < 0.0095


def test_exit_3_from_the_command_line(tmp_path, capsys):
    code = main(["run", "sphere", "--set", "h=0.01", "--set", "material=svk-plane-stress", "--set", "nu=0.3",
                 "--set", "pressure=-2e5", "--set", "R=1", "--n", "9", "--t-end", "0.0095", "-o", str(tmp_path / "x.nc")])
    assert code == 3
    assert LIMIT in capsys.readouterr().err


def test_both_stretches_past_the_turning_point_read_as_past_it():
    """``det(C_t - I/3)`` alone is positive again when both in-plane stretches are below ``1/sqrt(3)`` (its two
    factors negative): an equibiaxially crushed state (a start there, never reached continuously) read as inside the
    law's range. The limit is negative exactly when some principal stretch is below ``1/sqrt(3)``: checked on a grid
    of axial and hoop stretches of the unit cylinder (``C_t = diag(a^2, b^2)``), and continuous across ``tr = 0``."""
    thickness = Thickness(-0.005, 0.005, 4)
    moments = thickness_moments(quadrature_factors(thickness))
    a, b = ca.SX.sym("a"), ca.SX.sym("b")
    g = ca.Function("g", [a, b], [svk_turning_limit((a, 0.0, 0.0, 0.0, 0.0, b, 0.0, 0.0), moments)])
    edge = 1 / math.sqrt(3)
    for x in np.linspace(0.05, 1.5, 30):
        for y in np.linspace(0.05, 1.5, 30):
            if min(abs(x - edge), abs(y - edge)) < 1e-3:
                continue  # the membrane criterion sits within the wall's (h/a)^2 of the stretch itself
            inside = min(x, y) > edge
            assert (float(g(x, y)) > 0) == inside, (x, y, float(g(x, y)))
    assert float(g(0.5, 0.5)) < 0 and float(g(0.1, 0.1)) < 0


def test_a_computed_starting_state_past_a_limit_is_refused_naming_the_load():
    """A 1 m sphere under -1e9 Pa: Newton's static equilibrium was R = 0.4 mm (thinner than the wall, stretches of
    4e-4), and the run ended complete with exit 0; now refused naming pressure (its continuation cannot stay inside
    the limits). A twisted cylinder at gamma = 1 rad/m: its equilibrium radius R has the tangent metric
    ``[[1 + (R g)^2, R^2 g], [R^2 g, R^2]]`` (axial stretch 1), whose smaller eigenvalue (computed here from R) is
    below 1/3: refused naming gamma, before any step."""
    with pytest.raises(ParameterError) as crushed:
        mol_shell.simulate(Sphere(pressure=-1e9), n=11, t_end=1e-4, progress=False)
    assert crushed.value.name == "pressure" and "inside the model's limits" in str(crushed.value)
    with pytest.raises(ParameterError) as twisted:
        mol_shell.simulate(mol_shell.TwistedCylinder(gamma=1.0), n=11, t_end=1e-4, progress=False)
    message = str(twisted.value)
    assert twisted.value.name == "gamma" and LIMIT in message, message
    R = float(message.split("equilibrium radius R = ")[1].split(" m")[0])
    C = np.array([[1 + R**2, R**2], [R**2, R**2]])
    assert np.linalg.eigvalsh(C)[0] < 1 / 3 < R**2
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(gamma=0.5), n=11, t_end=1e-4, progress=False)
    assert ds.attrs["complete"] == 1  # R = 0.89: every stretch inside
