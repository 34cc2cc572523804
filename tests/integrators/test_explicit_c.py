"""``dop853-c`` and ``rk45-c``: SciPy's Runge-Kutta pairs with the step loop in generated C.

The same method with the same step control as SciPy's, so on one saved interval (no step shortened to
land on a saved time) the step sequence must be SciPy's own: an independent route (NumPy in Python
against C) to the same numbers. Their accuracy, and the limits checked after every step, are tested with
the other integrators (tests/test_integrators.py, tests/test_limits.py).
"""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.integrators import INTEGRATORS
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
