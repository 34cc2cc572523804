"""The ring ODE of section 5 stops at the model's limits as the PDE does (it ran through every one of them:
|psi| to 11.7 rad with delta_min = -0.985, and a start past SVK's turning point, status "complete")."""

import contextlib
import dataclasses
import math

import numpy as np
import pytest

import mol_shell
from mol_shell.runs.ring import simulate_ring

TIMES = np.linspace(0.0, 0.004, 41)


def _ring(**changes):
    stops = changes.pop("stops", True)
    with pytest.warns(RuntimeWarning, match="run incomplete: ") if stops else contextlib.nullcontext():
        return simulate_ring(dataclasses.replace(mol_shell.SpinningRing(), **changes), TIMES)


@pytest.fixture(scope="module")
def tilted():
    """psi0 = 1.5707, 1e-4 rad short of pi/2 (the probe's scene): the ODE and the PDE on 9 nodes."""
    scene = dataclasses.replace(mol_shell.SpinningRing(), psi0=1.5707)
    with pytest.warns(RuntimeWarning, match="run incomplete: "):
        pde = mol_shell.simulate(scene, n=9, times=TIMES, progress=False)
    return _ring(psi0=1.5707), pde


def test_psi_reaching_pi_over_2_stops_the_ode_where_the_pde_stops(tilted):
    ring, pde = tilted
    assert ring.attrs["status"] == pde.attrs["status"] == "limit" and ring.attrs["complete"] == 0
    assert ring.attrs["message"].startswith("|psi| reached pi/2 at t = 0.00284"), ring.attrs["message"]
    assert "reached pi/2" in pde.attrs["message"]
    t_ring, t_pde = ring.attrs["failure_time"], pde.attrs["failure_time"]
    # the leap-frog stops at its first step past the limit: within a step of the event's root (dt = 1e-6 s)
    assert abs(t_pde - t_ring) <= 2 * pde.attrs["dt"], (t_ring, t_pde)
    # the saved times reached are kept, every one inside the limits (|psi| < pi/2, delta = r cos psi > 0)
    assert ring.time.size == pde.time.size == int(t_ring // 1e-4) + 1
    assert float(abs(ring.psi).max()) < math.pi / 2 and float(ring.delta_min.min()) > 0


@pytest.mark.parametrize("R, stops", [(0.5, True), (0.575, True), (0.58, False)])
def test_a_start_past_svks_turning_point_stops_at_t_0(R, stops):
    """At rest, r = R round a natural radius a = 1: the hoop stretch R is past SVK's turning point 1/sqrt(3) = 0.57735
    (to O(h^2) = 1e-5 of the thickness average) for R = 0.5 and 0.575, not for 0.58, which springs back outward."""
    ds = _ring(R=R, omega=0.0, stops=stops)
    if stops:
        assert ds.attrs["status"] == "limit" and ds.time.size == 1 and ds.attrs["failure_time"] == 0.0
        assert ds.attrs["message"].startswith("an in-plane stretch reached 1/sqrt(3) in compression") and \
            " at t = 0 s, " in ds.attrs["message"], ds.attrs["message"]
    else:
        assert ds.attrs["status"] == "complete" and ds.time.size == TIMES.size and float(ds.r.min()) == R


def test_a_law_without_the_turning_point_is_not_stopped_by_it():
    """law_limit = false (and the laws other than SVK) leave the turning point unwatched, as the PDE's runs do."""
    ds = _ring(R=0.5, omega=0.0, law_limit=False, stops=False)
    assert ds.attrs["status"] == "complete" and ds.time.size == TIMES.size


def test_psi_is_said_when_solve_ivp_kept_only_delta_s_root_an_ulp_before_it():
    """|psi| -> pi/2 takes delta = r cos(psi) to 0 at the same instant; solve_ivp keeps only the roots up to the first
    terminal one of a step, so on a machine whose last bits put delta's root first, psi's was never seen and the
    run said delta (this suite on an AMD EPYC): the state at the root decides, as the leap-frog's order does."""
    from types import SimpleNamespace

    from mol_shell.runs.ring import _first_limit

    psi0, t_root = 1.5707, 0.0028452228
    psi_root = math.pi / 2 - 2e-16  # where a root of cos(psi) lands, an ulp or so short of pi/2

    def limits(t, y):  # the ring's order: psi, r, delta (y = [r, psi])
        return np.array([(math.pi / 2) ** 2 - y[1] ** 2, y[0], y[0] * math.cos(y[1])])

    sol = SimpleNamespace(t=np.array([0.0, t_root]), y=np.array([[1.0, 1.0], [psi0, psi_root]]),
                          t_events=[np.array([]), np.array([]), np.array([t_root])],
                          y_events=[np.empty((0, 2)), np.empty((0, 2)), np.array([[1.0, psi_root]])])
    assert _first_limit(sol, limits, TIMES) == (0, t_root)
    # a limit still clear of 0 at the root is not said: delta alone when psi is 1e-6 rad short of pi/2
    sol.y_events[2] = np.array([[1.0, math.pi / 2 - 1e-6]])
    assert _first_limit(sol, limits, TIMES) == (2, t_root)
