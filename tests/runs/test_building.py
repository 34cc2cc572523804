"""Saved times checked before anything is built (mol_shell.runs.building.parse_times)."""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.runs.building import MIN_INTERVAL, parse_times


def test_times_an_integrator_cannot_tell_apart_are_refused():
    """t_end = 1e-300 reached SUNDIALS (CV_ILL_INPUT, exit 3); times 0, 1e-300 ran leap-frog for 0 steps."""
    assert MIN_INTERVAL == pytest.approx(1.49e-154, rel=1e-2)
    with pytest.raises(ParameterError, match=r"^t_end = 1e-300 is outside \[1.5e-153, inf\) s \(its 10 saved intervals"):
        parse_times(None, 1e-300)
    with pytest.raises(ParameterError, match=r"^times = \[0.0, 1e-300\] .* at least 1.4917e-154 s .*1e-300 s apart"):
        parse_times([0, 1e-300])
    with pytest.raises(ParameterError, match="machine epsilons"):
        parse_times([0, 1.0, 1.0 + 1e-14])
    np.testing.assert_array_equal(parse_times([0, 1e-150, 1.0, 1.0 + 1e-12]), [0, 1e-150, 1.0, 1.0 + 1e-12])
    assert parse_times(None, 1e-150)[-1] == 1e-150


def test_times_must_be_one_flat_list():
    """A nested list was flattened and run."""
    with pytest.raises(ParameterError, match=r"^times = \[\[0.0, 0.001\]\] is not a flat list of numbers"):
        mol_shell.simulate("sphere", n=5, times=[[0, 1e-3]])


def test_leapfrog_refuses_saved_times_no_step_apart():
    """1e-12 s after 0 rounds to 0 steps of dt = 1e-6 s and was accepted (the t = 0 state saved again)."""
    step_counts = mol_shell.integrators.INTEGRATORS["leapfrog"](dt=1e-6).step_counts
    assert step_counts(np.array([0.0, 1e-6, 3e-6])).tolist() == [0, 1, 3]
    with pytest.raises(ParameterError, match=r"^times = 1e-12 is outside positive multiples of dt = 1e-06 s, at least one step"):
        step_counts(np.array([0.0, 1e-12]))
    with pytest.raises(ParameterError, match="at least one step"):
        mol_shell.simulate("twisted-cylinder", n=5, times=[0, 1e-6, 1e-6 + 1e-13])


def test_build_refuses_what_it_cannot_build_by_name_before_any_memory_is_taken():
    """``mol_shell.build`` had no guard of its own: ``n = 10**7`` took 5 GB and minutes before a MemoryError (the
    commands refused it at once), ``None`` or a scene's name ended in dataclasses' TypeError."""
    import time

    import pytest

    import mol_shell

    start = time.perf_counter()
    with pytest.raises(mol_shell.ParameterError, match=r"^n = 10000000 is outside integers 3\.\."):
        mol_shell.build(mol_shell.Sphere(R=1.02), n=10**7)
    assert time.perf_counter() - start < 1.0
    with pytest.raises(mol_shell.ParameterError, match="^scene = None is not a scene"):
        mol_shell.build(None)
    with pytest.raises(mol_shell.ParameterError, match=r"^n = 2.5 is outside integers >= 3"):
        mol_shell.build("sphere", n=2.5)
    system, _ = mol_shell.build("sphere", n=12)  # a registered name, as simulate takes
    assert system.n == 12


@pytest.mark.parametrize("t_end", [0.07, 0.143, 3e-5, 1.0 / 3.0])
def test_times_from_t_end_alone_are_the_numbers_a_user_types(t_end):
    """``t_end`` alone gives 11 even times; they came from linspace unrounded (0.014000000000000002 for
    t_end = 0.07), so ``ds.sel(time=0.014)`` of an adaptive integrator's run failed where a leap-frog run's
    (rounded to 12 digits) worked. Each is now k t_end / 10 to 12 significant digits, the last t_end itself."""
    times = parse_times(None, t_end)
    assert times[-1] == t_end and times[0] == 0.0 and len(times) == 11
    for k, t in enumerate(times[1:-1], start=1):
        assert t == float(f"{k * t_end / 10:.12g}"), (k, t)


def test_an_adaptive_run_is_selected_by_the_times_it_printed():
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-bdf", n=8, t_end=0.07, progress=False, stresses=False)
    assert float(ds.sel(time=0.014).time) == 0.014
    assert [f"{t:g}" for t in ds.time.values] == [f"{0.007 * k:g}" for k in range(11)]
