"""Silent minutes at scale: ida at n = 20,000 spent 69 s before its first line (the graphs 20 s, the DAE's Jacobian
graph 25 s, the spectrum 7 s) under an estimate of 20 s and a threshold of 30 s; 1,001 saved times x 3,000 nodes spent
40 s assembling and writing without a word. The estimate counts the stages, and a start-up or an assembly projected
past LONG_BUILD_S (10 s) is said before the work. Only the estimates run here (no graph is built)."""

import warnings

import numpy as np
import pytest

from mol_shell._core.units import show_seconds
from mol_shell.runs import resources
from mol_shell.runs.resources import LongRunWarning


def _said(*args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        est = resources.check_before_build(*args, **kwargs)
    return est, [str(w.message) for w in caught if issubclass(w.category, LongRunWarning)]


def test_the_start_up_counts_the_daes_jacobian_and_a_minute_is_announced():
    assert resources.LONG_BUILD_S <= 10.0
    est, said = _said(20_000, [0.0, 2e-5], "ida")
    build = (resources.BUILD_S_PER_NODE + resources.JACOBIAN_S_PER_NODE) * 20_000
    assert est.build_seconds == pytest.approx(build) and build > 30.0  # the stages measured: 40 s, not 20
    assert said == [(f"building the graphs, the Jacobian and the spectrum at n = 20,000 takes about "
                     f"{show_seconds(build)} before the first step (the step's stability bound is known only then)")]
    est, said = _said(20_000, [0.0, 2e-5], "leapfrog", dt=1e-6)  # no DAE: the graphs and the spectrum only
    assert est.build_seconds == pytest.approx(resources.BUILD_S_PER_NODE * 20_000)
    assert said and said[0].startswith("building the graphs and the spectrum at n = 20,000 takes about ")
    assert _said(400, [0.0, 1e-3], "ida")[1] == []  # a small run says nothing


def test_the_assembly_of_many_saved_times_is_announced_before_the_run():
    times = np.linspace(0.0, 1e-3, 1001)
    est, said = _said(3000, times, "leapfrog", dt=1e-6)
    output = resources.OUTPUT_S_PER_VALUE * 1001 * 3000
    assert est.output_seconds == pytest.approx(output) and output > resources.LONG_BUILD_S
    assert est.seconds >= output + est.build_seconds  # in the run's projected time too
    assert said == [(f"assembling and writing 1,001 saved times x 3,000 nodes takes about {show_seconds(output)} after "
                     "the last step (fewer saved times make it shorter)")]
    assert _said(3000, times[::100], "leapfrog", dt=1e-6)[1] == []  # 11 saved times: nothing to say
