"""``dop853-c`` and ``rk45-c`` stop where a limit of the model is crossed, inside the step that crossed it.

They reported the end of that step: a twisted cylinder sheared to the fold (``psi0 = 1.5707``) stopped at 4.15e-5 s
where CVODE, IDA and leap-frog find the root of ``delta`` at 3.29e-5 s (26 % late); an SVK sphere under a step of
external pressure at 0.0115152 s where they find SVK's turning point at 0.0111148 s. The crossing is now located on
the step's dense output; CVODE's root finding (BDF, another method and another root search) is the independent value.
"""

import math
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.base import Monitor
from mol_shell.integrators.rk_dense import first_crossing, time_tolerance
from mol_shell.runs.simulate import build, resolve

CASES = {
    "twisted cylinder at the fold": (mol_shell.TwistedCylinder(psi0=1.5707), 0.01),
    "sphere at SVK's turning point": (mol_shell.Sphere(pressure=-1e5, pressure_history="step 0", R=1), 0.05),
}


def _run(scene, name, t_end, rtol, atol):
    with warnings.catch_warnings():  # every run stops early on purpose
        warnings.simplefilter("ignore")
        return mol_shell.simulate(scene, name, n=21, t_end=t_end, rtol=rtol, atol=atol, progress=False,
                                  stresses=False)


@pytest.fixture(scope="module", params=list(CASES))
def root(request):
    scene, t_end = CASES[request.param]
    return scene, t_end, _run(scene, "cvode-bdf", t_end, 1e-10, 1e-13)


def _place(ds):
    return ds.attrs["message"].split(" at t = ")[0], ds.attrs["message"].split(" s, ")[1].split(":")[0]


@pytest.mark.parametrize("name", ["dop853-c", "rk45-c"])
def test_the_limit_is_reported_where_it_was_crossed(root, name):
    scene, t_end, cvode = root
    assert cvode.attrs["status"] == "limit", cvode.attrs["message"]
    ds = _run(scene, name, t_end, 1e-8, 1e-11)
    assert ds.attrs["status"] == "limit", ds.attrs["message"]
    # before: 4.15e-5 s against 3.29e-5 s (26 %), 0.0115152 s against 0.0111148 s (3.6 %)
    assert ds.attrs["failure_time"] == pytest.approx(cvode.attrs["failure_time"], rel=1e-6), ds.attrs["message"]
    what, where = _place(ds)
    assert what == _place(cvode)[0]  # the same limit (the sphere reaches it in every cell at once: places differ)
    if scene.name == "twisted-cylinder":
        assert where == _place(cvode)[1]


@pytest.mark.parametrize("name", ["dop853-c", "rk45-c"])
def test_the_state_left_is_at_the_crossing(name):
    """The stepper is left at the crossing, as CVODE's state at a root: the limit named is 0 there (within what the
    search's tolerance in time moves it), broken by at most that, and the others hold."""
    scene = resolve(CASES["twisted cylinder at the fold"][0])
    system, compiled = build(scene, 21)
    y0 = system.initial_state(scene)
    stepper = INTEGRATORS[name](rtol=1e-8, atol=1e-11).start(system, compiled, y0, [0.0, 0.01], Monitor(system, y0))
    with pytest.raises(mol_shell.ModelLimitError) as caught:
        while True:
            stepper.advance(0.01)
    assert caught.value.time == stepper.t == pytest.approx(3.29e-5, rel=1e-3)
    g0, g = compiled.limits(y0), compiled.limits(stepper.y)
    broken = np.flatnonzero(~(g > 0))  # both samples of one cell (the motion is symmetric in it)
    assert broken.size and all(system.limit_names()[i][1] in str(caught.value) for i in broken)
    assert np.all(-1e-9 * g0[broken] < g[broken]), (g[broken], g0[broken])
    np.testing.assert_array_equal(stepper.f, compiled.evaluator()(stepper.y, stepper.t))


def test_the_search_finds_the_first_of_several_crossings():
    """Two limits crossing within one step (at 0.3 and 0.5 of it) and one that stays: the first, to the tolerance."""
    def g(t):
        return np.array([0.5 - t, math.cos(math.pi * t / 0.6) if t < 1 else -0.2, 1.0 + t])

    t, gt = first_crossing(g, 0.0, 1.0, g(0.0), g(1.0))
    assert 0 <= t - 0.3 <= time_tolerance(1.0) and not gt[1] > 0 and gt[0] > 0
    t, gt = first_crossing(lambda t: np.array([0.5 - t, math.nan if t > 0.7 else 1.0]), 0.0, 1.0,
                           np.array([0.5, 1.0]), np.array([-0.5, math.nan]))
    assert 0 <= t - 0.5 <= time_tolerance(1.0)
