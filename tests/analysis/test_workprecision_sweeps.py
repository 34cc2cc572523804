"""``work_precision(..., sweeps=...)`` was undocumented and unchecked: a list where the mapping of ``rtol`` belongs
raised an AttributeError ("'list' object has no attribute 'values'"), ``sweeps="x"`` a TypeError, an empty mapping a
StopIteration, an unknown key ran silently as ``rtol``; a leap-frog step past the stability bound that simulate
refuses was run and recorded as a measured instability; a lone integrator name was read letter by letter
(``integrators = 'd' is outside ...``). Each bad form is now one ParameterError naming ``sweeps``; a leap-frog step
past the bound is skipped with simulate's reason (every point skipped: refused)."""

import numpy as np
import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.analysis.workprecision import check_integrators, work_precision
from mol_shell.runs.simulate import simulate

QUIET = {"n": 11, "times": (0.0, 1e-3), "repeats": 1, "log": lambda *a: None}


@pytest.mark.parametrize("sweeps", ["x", [1e-6], {"dop853-c": [1e-6]}, {"dop853-c": {}},
                                    {"dop853-c": {"foo": [1e-6]}}, {"dop853-c": {"rtol": [1e-6], "dt": [1e-6]}},
                                    {"leapfrog": {"rtol": [1e-6]}}, {"euler": {"rtol": [1e-6]}},
                                    {"dop853-c": {"rtol": []}}, {"dop853-c": {"rtol": 1e-6}},
                                    {"dop853-c": {"rtol": "1e-6"}}, {"dop853-c": {"rtol": [1e-6, -1.0]}},
                                    {"leapfrog": {"dt": [0.0]}}, {"dop853-c": {"rtol": ["1e-6"]}},
                                    {"dop853-c": {"rtol": [None]}}, {"dop853-c": {"rtol": [True]}},
                                    {"leapfrog": {"dt": [np.float32(1e-7)]}}])
def test_a_sweep_of_the_wrong_form_is_refused_naming_sweeps_and_the_allowed_form(sweeps):
    with pytest.raises(ParameterError) as err:
        work_precision("twisted-cylinder", ["dop853-c", "leapfrog"], sweeps=sweeps, **QUIET)
    message = str(err.value)
    assert err.value.name.startswith("sweeps") and message.startswith("sweeps")
    assert 'allowed: a mapping {integrator: {"rtol": [values]}}' in message and "\n" not in message


def test_a_lone_integrator_name_is_one_integrator():
    assert check_integrators("dop853-c") == ["dop853-c"]
    with pytest.raises(ParameterError, match=r"^integrators = 'dop853' is outside"):
        check_integrators("dop853")


def test_a_leapfrog_step_past_the_bound_simulate_refuses_is_skipped_with_simulate_s_reason():
    with pytest.raises(ParameterError) as refused:  # simulate's own refusal of dt = 1 ms on this scene
        simulate("twisted-cylinder", "leapfrog", n=11, t_end=1e-3, dt=1e-3)
    assert refused.value.name == "dt"
    ds = work_precision("twisted-cylinder", "leapfrog", sweeps={"leapfrog": {"dt": [1e-3, 1e-4]}}, **QUIET)
    row = ds.sel(integrator="leapfrog")
    assert list(ds.integrator.values) == ["leapfrog"]
    assert list(row.status.values) == ["skipped", "complete"]
    assert str(row.note.values[0]) == f"skipped: {refused.value} (simulate refuses it)"
    assert 0 < float(row.error[1]) < 0.1  # measured: 10 steps at half the bound


def test_a_leapfrog_sweep_all_past_the_bound_is_refused_before_the_reference_runs():
    with pytest.raises(ParameterError, match=r"^sweeps\['leapfrog'\]\['dt'\] = \[0\.001, 0\.0005\] is outside \(0, "
                                             r"[0-9.e-]+\) s \(leap-frog stability bound"):
        work_precision("twisted-cylinder", ["leapfrog"], sweeps={"leapfrog": {"dt": [1e-3, 5e-4]}}, **QUIET)
