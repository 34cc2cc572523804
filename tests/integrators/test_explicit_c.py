"""``dop853-c`` and ``rk45-c``: SciPy's Runge-Kutta pairs with the step loop in generated C.

The same method with the same step control as SciPy's, so on one saved interval (no step shortened to
land on a saved time) the step sequence must be SciPy's own: an independent route (NumPy in Python
against C) to the same numbers. Their accuracy, and the limits checked after every step, are tested with
the other integrators (tests/test_integrators.py, tests/test_limits.py).
"""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.integrators import INTEGRATORS, explicit
from mol_shell.runs.simulate import build, resolve


@pytest.fixture(scope="module")
def paper():
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    return system, compiled, system.initial_state(scene)


@pytest.mark.parametrize("name, peer", [("dop853-c", "scipy-dop853"), ("rk45-c", "scipy-rk45")])
def test_the_step_sequence_is_scipys(paper, name, peer):
    system, compiled, y0 = paper
    times = [0.0, 0.02]
    ours = INTEGRATORS[name](rtol=1e-6, atol=1e-9).integrate(system, compiled, y0, times)
    theirs = INTEGRATORS[peer](rtol=1e-6, atol=1e-9).integrate(system, compiled, y0, times)
    assert ours.status == theirs.status == "complete"
    assert ours.stats["n_steps"] == theirs.stats["n_steps"] > 50
    assert abs(ours.stats["n_rhs"] - theirs.stats["n_rhs"]) <= 3  # SciPy's starting-step estimate evaluates f once more
    scale = np.abs(theirs.y[-1]).max()
    assert np.max(np.abs(ours.y[-1] - theirs.y[-1])) < 1e-9 * scale  # summation order only


def test_saved_times_are_landed_on_and_steps_counted(paper):
    system, compiled, y0 = paper
    times = np.linspace(0.0, 0.01, 11)
    run = INTEGRATORS["dop853-c"](rtol=1e-7, atol=1e-10).integrate(system, compiled, y0, times)
    assert run.status == "complete" and np.array_equal(run.t, times)
    one = INTEGRATORS["dop853-c"](rtol=1e-7, atol=1e-10).integrate(system, compiled, y0, [0.0, 0.01])
    # landing on ten saved times costs at most one extra step each, and changes the end state within tolerance
    assert one.stats["n_steps"] <= run.stats["n_steps"] <= one.stats["n_steps"] + 10
    assert np.max(np.abs(run.y[-1] - one.y[-1])) < 1e-5 * np.abs(one.y[-1]).max()


def test_max_steps_ends_the_run_as_failed_with_the_data_kept(paper):
    system, compiled, y0 = paper
    run = INTEGRATORS["dop853-c"](rtol=1e-8, max_steps=20, chunk=7).integrate(system, compiled, y0,
                                                                              [0.0, 1e-4, 0.143])
    assert run.status == "failed" and "max_steps = 20" in run.message
    assert run.stats["n_steps"] == 20 and len(run.t) >= 1 and np.all(np.isfinite(run.y))


def test_a_bad_chunk_is_refused():
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ParameterError, match="chunk"):
            INTEGRATORS["dop853-c"](chunk=bad)


@pytest.mark.parametrize("name", ["dop853-c", "rk45-c"])
def test_a_tolerance_the_steps_cannot_meet_is_named_when_the_run_stops(name):
    """``--rtol 1e-14 --atol 1e-20`` stopped with "the motion is too fast for this horizon", as if the motion were to
    blame. The twisted cylinder starts at rest in its equilibrium: at atol = 1e-9 a step covers each saved interval;
    held to atol = 1e-40, entries that are round-off about the equilibrium keep the steps near 1e-13 s and the run
    stops after its first chunk, naming the tolerance (as CVODE's projection names rtol) and what goes on."""
    calm = mol_shell.simulate("twisted-cylinder", name, n=5, t_end=1e-4, rtol=1e-14, atol=1e-9, progress=False,
                              stresses=False)
    assert calm.attrs["complete"] == 1 and calm.attrs["n_steps"] <= 20
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate("twisted-cylinder", name, n=5, t_end=1e-4, rtol=1e-14, atol=1e-40, progress=False,
                                stresses=False)
    message = ds.attrs["message"]
    assert ds.attrs["status"] == "failed" and ds.attrs["n_steps"] == 2000, message  # one chunk
    assert "too fast for this horizon at rtol = 1e-14, atol = 1e-40 (a looser tolerance or a larger max_steps goes on"\
        in message, message


class _UnderflowingDriver:
    """A compiled right-hand side whose Runge-Kutta driver returns -2 (the step fell below 10 ulp(t)) at t = 0.25 s."""

    def runge_kutta(self, state, t_end, rtol, atol, max_step, tableau, max_steps, stats, work=None):
        t, h = state[0], state[3]
        t[0], h[0] = 0.25, 1e-16
        return -2


def test_a_step_below_round_off_names_the_tolerance():
    """The step fell below round-off at t (SciPy's minimum, 10 ulp(t)): said "not finite, or stiff?". Stiffness bounds
    an explicit pair's step by its stability, not by round-off; a tolerance the doubles cannot meet at t shrinks it
    there (or a right-hand side that is not finite), and the message names the tolerance, per field as given."""
    stepper = object.__new__(explicit._RungeKuttaStepper)
    stepper.method = INTEGRATORS["dop853-c"](rtol=1e-14, atol={"r": 1e-30})
    stepper.compiled, stepper.monitor, stepper.t_end = _UnderflowingDriver(), None, 1.0
    stepper.time, stepper.h, stepper.counts = np.zeros(1), np.ones(1), np.zeros(3, dtype=np.int64)
    stepper.y = stepper.f = stepper.atol = stepper.tableau = None
    with pytest.raises(ModelLimitError) as info:
        stepper.advance(1.0)
    assert info.value.status == "failed" and info.value.time == 0.25
    assert str(info.value) == ("dop853-c failed at t = 0.25 s: its step fell below round-off at t (1e-16 s, SciPy's "
                               "minimum): rtol = 1e-14, atol = {z=1e-09,r=1e-30,chi=1e-09,theta=1e-09,psi=1e-09} "
                               "cannot be met there in double precision (a looser tolerance goes on), or the "
                               "right-hand side is not finite near this state")


def test_the_scipy_peers_step_budget_names_the_tolerance_too():
    """The same run on ``scipy-rk45`` (its own step budget, every 1,000 steps) said "too fast for this horizon" without
    the tolerance; it names it now, as the compiled pairs and CVODE do."""
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate("twisted-cylinder", "scipy-rk45", n=5, t_end=1e-4, rtol=2.3e-14, atol=1e-40,
                                progress=False, stresses=False)
    message = ds.attrs["message"]
    assert ds.attrs["status"] == "failed" and ds.attrs["n_steps"] == 1000, message
    assert "too fast for this horizon at rtol = 2.3e-14, atol = 1e-40 (a looser tolerance or a larger max_steps goes "\
        "on; stopped at t = " in message, message
