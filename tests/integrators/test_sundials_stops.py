"""How SUNDIALS runs that cannot go on say so: the time of a failure on scikit-sundae's route, and the step budget of
the compiled loops, projected from the last steps rather than the whole run's mean."""

import re
import types
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ModelLimitError
from mol_shell.integrators import INTEGRATORS, sundials
from mol_shell.integrators.base import StepBudget
from mol_shell.model.equilibrium import spectrum_bounds
from mol_shell.runs.building import build
from mol_shell.runs.checks import resolve
from mol_shell.runs.simulate import starting_state

#: what scikit-sundae 1.2.0 handed back as the time of a call SUNDIALS refused at E = 1e300 (its output variable is
#: left uninitialised, so any double can come back: this one is the denormal the run named)
GARBAGE_TIME = 6.92236148e-310


def test_a_refused_call_names_the_last_time_reached_not_scikit_sundaes_unset_time():
    """A one-step call that fails took no step: the solver is still at the time of the last step that succeeded
    (``t_prev``), whatever the result's time says (SUNDIALS does not set it when it refuses the call's input)."""
    run = object.__new__(sundials._Run)
    run.method = INTEGRATORS["sksundae-ida"]()
    res = types.SimpleNamespace(t=GARBAGE_TIME, status=sundials.ILL_INPUT_FLAG, message="One of the function inputs "
                                "is invalid.", y=None)
    for t_prev in (0.0, 0.00125):
        err = run._failure(res, t_prev)
        assert err.time == t_prev and err.status == "failed"
        assert str(err) == (f"sksundae-ida failed at t = {t_prev:.9g} s: {sundials.ILL_INPUT} (status -22)")


def test_sksundae_ida_at_an_extreme_modulus_stops_at_the_start():
    """E = 1e300: SUNDIALS refuses the first step (its starting step is no double); the run stops at t = 0, the only
    time it reached, and says why in the compiled route's words (it said "failed at t = 6.92236148e-310 s: One of the
    function inputs is invalid.")."""
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate(mol_shell.get_scene("twisted-cylinder", E=1e300), "sksundae-ida", n=11, t_end=0.01,
                                progress=False, stresses=False)
    assert ds.attrs["status"] == "failed" and ds.sizes["time"] == 1 and ds.attrs["failure_time"] == 0.0
    assert ds.attrs["message"].startswith("sksundae-ida failed at t = 0 s: SUNDIALS found an input of the step "
                                          "invalid"), ds.attrs["message"]


def test_the_projection_of_chunks_follows_the_last_steps():
    """1,000 steps of 1 ms, then steps of 1e-12 s: projected from the run's mean the end (1,000 s) still looked
    reachable; from the steps since the last projection it needs ~1e15 steps, and the run stops naming them."""
    budget = StepBudget("test", t_end=1000.0, max_steps=10**6, tolerance="rtol = 1e-06, atol = 1e-09")
    budget.project(1000, 1.0)  # a mean step of 1 ms: 1e6 steps in all, within 10 x max_steps
    budget.project(1500, 1.0 + 500e-12)  # fewer than EVERY steps since: no projection yet
    with pytest.raises(ModelLimitError) as info:
        budget.project(2500, 1.0 + 1500e-12)
    needed = 2500 + (1000.0 - 1.0 - 1500e-12) / 1e-12
    assert info.value.status == "failed"
    assert str(info.value) == (f"test would need about {needed:.3g} steps to reach t = 1000 s at the mean step of its "
                               "last 1500 steps (1e-12 s), more than max_steps = 1000000: the motion is too fast for "
                               "this horizon at rtol = 1e-06, atol = 1e-09 (a looser tolerance or a larger max_steps "
                               f"goes on; stopped at t = {1.0 + 1500e-12:.9g} s)")


def test_ida_on_a_wall_too_thin_for_its_horizon_stops_long_before_max_steps():
    """h = 1e-12 m: the director's rotation is the wall's fastest mode, max |eig J| ~ 1/h. IDA reaches ~1 ms in a
    thousand steps; then the mode, once stirred, holds its steps at a fraction of that mode's period (BDF of orders
    3-5 does not damp it at such steps), and it stepped 4e-15 s at a time until max_steps: a million steps, 18 s,
    because the projection from the whole run's mean step never passed 10 x max_steps. Projected from the last steps
    the run stops after one chunk of them, naming their size and the steps it would need."""
    scene = mol_shell.get_scene("twisted-cylinder", h=1e-12)
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate(scene, "ida", n=21, times=[0.0, 0.01], max_steps=100_000, progress=False,
                                stresses=False)
    message = ds.attrs["message"]
    assert ds.attrs["status"] == "failed" and ds.attrs["n_steps"] < 100_000, message
    found = re.search(r"would need about (\S+) steps to reach t = 0.01 s at the mean step of its last \d+ steps "
                      r"\((\S+) s\), more than max_steps = 100000: the motion is too fast for this horizon", message)
    assert found, message
    needed, step = float(found.group(1)), float(found.group(2))
    resolved = resolve(scene)
    system, _ = build(resolved, 21)
    y0, _ = starting_state(resolved, system, 21, asked=scene)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        omega_max = spectrum_bounds(system.jac, y0, system.viscous)[0]
    assert step < 1.0 / omega_max  # a fraction of the fastest mode's period / (2 pi)
    assert needed == pytest.approx(0.01 / step, rel=0.2) and needed > 1e3 * 100_000
    assert np.isfinite(ds.attrs["failure_time"]) and 0 < ds.attrs["failure_time"] < 0.01
