"""CasADi's plugins (``casadi-cvodes``, ``casadi-cvodes-c``, ``casadi-idas``): short saved intervals, ``max_step`` and
the step budget, and progress.

CasADi 3.8 skips an output interval shorter than about 1e-9 (absolute): ``ca.integrator('F', 'cvodes', {'x': x, 't':
t, 'ode': 1}, 0, linspace(0, 1e-9, 11)[1:])`` returns zeros. A run whose saved times are that close returned the
start (0 steps, ``complete = 1``) or held states; it is now integrated in a scaled time ``tau = t / T`` (``T`` a power
of two at or below the shortest interval), runs with every interval at 1e-6 s or more as before (``T = 1``).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.integrators import INTEGRATORS
from mol_shell.runs.simulate import build, resolve

#: the scene's defaults, E0 and rho0: the twisted cylinder with E and rho scaled moves as the paper's at
#: t' = t sqrt(E rho0 / (E0 rho)) (the equations hold E / rho only; its start is at rest, with no loads)
E0, RHO0 = 1.0e6, 1.0e3


def test_casadi_cvodes_follows_the_scaling_law_at_saved_times_1e_9_s_apart():
    # E = 1e13, rho = 1e-3: time runs sqrt(1e19) = 3.16e9 times faster; 0.02 s of the paper scene is 6.3e-9 s here,
    # saved 6.3e-10 s apart. It returned the start (r max 0.994844 against 0.997359, 0 steps).
    scene = mol_shell.TwistedCylinder()
    assert (scene.E, scene.rho) == (E0, RHO0)
    fast = dataclasses.replace(scene, E=1e13, rho=1e-3)
    factor = math.sqrt(fast.E * RHO0 / (E0 * fast.rho))
    times = np.linspace(0.0, 0.02, 11)
    paper = mol_shell.simulate(scene, "casadi-cvodes", n=11, times=times, progress=False, stresses=False)
    scaled = mol_shell.simulate(fast, "casadi-cvodes", n=11, times=times / factor, progress=False, stresses=False)
    assert paper.attrs["complete"] == scaled.attrs["complete"] == 1
    r0 = float(paper.r.isel(time=0).max())
    assert float(paper.r.isel(time=-1).max()) - r0 > 1e-3  # it moves
    assert np.max(np.abs(scaled.r.values - paper.r.values)) < 1e-5
    # chi's rate scales with 1 / time
    assert np.max(np.abs(scaled.chi_t.values / factor - paper.chi_t.values)) < 1e-5 * np.abs(paper.chi_t).max()


@pytest.mark.parametrize("name", ["casadi-cvodes", "casadi-idas"])
def test_casadi_routes_move_from_rest_at_a_rate_growing_as_t_over_1e_8_s(name):
    # from rest the rates grow as t (a constant acceleration to first order in t: 1e-8 s is 1e-7 of the motion's
    # time scale); they were held (x 1e7: 3.3, 6.6, 6.6, 13.3, 13.3, ...) or 0 (casadi-idas to 1e-9 s)
    for t_end in (1e-8, 1e-9):
        times = np.linspace(0.0, t_end, 11)
        ds = mol_shell.simulate(mol_shell.TwistedCylinder(), name, n=11, times=times, progress=False, stresses=False)
        rate = ds.chi_t.isel(s=-1).values
        assert ds.attrs["complete"] == 1 and abs(rate[-1]) > 0
        np.testing.assert_allclose(rate / rate[-1], times / t_end, rtol=1e-4, atol=1e-6)


@pytest.mark.parametrize("name", ["casadi-cvodes", "casadi-idas"])
def test_casadi_routes_refuse_a_max_step_every_other_route_refuses(name):
    # 1e6 steps of 1e-12 s cannot reach 1e-5 s: refused before anything is built, as by cvode-bdf (it ran, then
    # stopped on CV_TOO_MUCH_WORK); the bound 1e-5 s / (0.99e6 - 1): one more step per saved interval, 1 % for the start
    said = []
    for route in ("cvode-bdf", name):
        with pytest.raises(ParameterError, match=r"^max_step = 1e-12 is outside \[1\.011e-11, inf\) s, or 0 ") as exc:
            mol_shell.simulate("twisted-cylinder", route, n=5, times=[0.0, 1e-5], max_step=1e-12, progress=False)
        said.append(str(exc.value).partition(" (unbounded) ")[0])  # the same range; the hint says how each counts
    assert said[0] == said[1]


def test_casadi_idas_takes_saved_times_1e_11_s_apart_in_a_run_of_ms():
    # integrated in a tau = t / T of the shortest interval (T = 2^-37 s) over the whole 2 ms, IDAS failed its initial
    # condition (IDA_NO_RECOVERY, only t = 0 kept); at 1e-10 s apart it took 1,890 steps with 934 Newton failures
    # against 116. The short interval is now a call of its own in its own tau, the rest in t.
    times = [0.0, 1e-3, 1.00000000001e-3, 2e-3]
    runs = [mol_shell.simulate(mol_shell.TwistedCylinder(), name, n=11, times=times, progress=False, stresses=False)
            for name in ("casadi-idas", "casadi-cvodes")]
    ds, peer = runs
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] < 300
    # its rates agree with CVODES's to the tolerances' order; over 1e-11 s they change by 1e-11 times the
    # acceleration (below 1e-6 of them), the positions by far less than atol = 1e-9
    scale = np.abs(peer.chi_t.values).max()
    assert np.abs(ds.chi_t.values - peer.chi_t.values).max() < 1e-3 * scale
    assert np.abs(ds.chi_t.values[2] - ds.chi_t.values[1]).max() < 1e-6 * scale
    assert np.abs(ds.chi.values[2] - ds.chi.values[1]).max() < 1e-9


def test_casadi_cvodes_takes_the_steps_a_max_step_inside_the_range_needs():
    # one saved interval of 1e-6 s at max_step = 9.5e-12 s needs 105,264 steps: CasADi gave up at 100,000 per interval
    ds = mol_shell.simulate("twisted-cylinder", "casadi-cvodes", n=5, times=[0.0, 1e-6], max_step=9.5e-12,
                            progress=False, stresses=False)
    assert ds.attrs["complete"] == 1
    assert 1e-6 / 9.5e-12 <= ds.attrs["n_steps"] < 1.1 * 1e-6 / 9.5e-12


class _Meter:
    """A progress meter that records what it is told."""

    def __init__(self):
        self.told = []

    def reset(self):
        self.told.append("reset")

    def update(self, n):
        self.told.append(n)


@pytest.mark.parametrize("name", ["casadi-cvodes", "scipy-rk45"])
def test_progress_counts_every_saved_time_a_call_reached_from_after_the_build(name):
    # casadi-cvodes's one call reaches all saved times; progress was told only of the first (t = 0.005 of 0.12 s,
    # 4 %, with 23 min "left" after gcc's 59 s), its clock started before the build
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 5)
    times = np.linspace(0.0, 0.01, 5)
    meter = _Meter()
    traj = INTEGRATORS[name]().integrate(system, compiled, system.initial_state(scene), times, progress=meter)
    assert traj.status == "complete"
    assert meter.told[0] == "reset"
    assert math.isclose(sum(meter.told[1:]), 0.01, rel_tol=1e-12)


def test_casadi_routes_keep_max_steps_without_a_max_step():
    """``max_steps`` bounded CasADi's steps per interval only where ``max_step`` was given: with 20 asked and no
    ``max_step`` a run took 368 steps and said it was complete. The failed call's steps are not known (CasADi zeroes
    its counts), said as -1, not 0."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "casadi-cvodes", n=11, t_end=0.02, max_steps=20,
                            progress=False, stresses=False)
    assert ds.attrs["status"] == "failed" and "max_num_steps = 20 steps" in ds.attrs["message"]
    assert ds.attrs["n_steps"] == -1
