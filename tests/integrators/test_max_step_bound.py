"""The bound ``simulate`` puts on ``max_step`` from ``max_steps`` counts steps as each route does: per saved interval
for casadi-cvodes and casadi-idas (CasADi's ``max_num_steps``), over the whole run for the others; where no
``max_step`` reaches the saved times within ``max_steps``, ``max_steps`` is what the refusal names."""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError

TIMES = np.linspace(0.0, 2e-3, 201)  # 200 saved intervals of 1e-5 s


@pytest.mark.parametrize("name", ["casadi-cvodes", "casadi-idas"])
def test_a_per_interval_max_steps_bounds_max_step_by_one_interval(name):
    """150 steps per interval of 1e-5 s at max_step = 1e-4 ran (in 63 steps): it was refused as if 150 were the run's
    total ('max_step = 0.0001 is outside 0 (unbounded) at this max_steps'). Each interval's steps of at most max_step,
    one more to land and 1 % of max_steps for the start: max_step >= 1e-5 / (0.99 max_steps - 1)."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), name, n=11, times=TIMES, max_steps=150, max_step=1e-4,
                            progress=False, stresses=False)
    assert ds.attrs["complete"] == 1 and float(ds.time[-1]) == pytest.approx(2e-3)
    low = 1e-5 / (0.99 * 5 - 1)  # 2.5316e-06 s at 5 steps per interval, shown rounded up to 4 digits
    with pytest.raises(ParameterError, match=rf"^max_step = 1e-07 is outside \[{math.ceil(low * 1e9) / 1e9:.4g}, inf\) "
                                             rf"s, or 0 \(unbounded\) \({name} counts max_steps per saved interval"):
        mol_shell.simulate(mol_shell.TwistedCylinder(), name, n=11, times=TIMES, max_steps=5, max_step=1e-7)


def test_max_steps_is_named_where_no_max_step_reaches_the_times():
    """200 saved intervals cannot be crossed in 150 steps whatever max_step: the refusal said 'max_step = 0.0001 is
    outside 0 (unbounded)'. At max_step = 1e-4 s to t = 2e-3 s the least max_steps is the least m with
    0.99 m >= 2e-3 / 1e-4 + 200 = 220: 223 (222 leaves 219.78)."""
    least = math.ceil((2e-3 / 1e-4 + 200) / 0.99)
    assert least == 223
    with pytest.raises(ParameterError, match=rf"^max_steps = 150 is outside integers >= {least} at max_step = 0\.0001 "
                                             r"s \(max_steps = 150 steps of at most max_step"):
        mol_shell.simulate(mol_shell.TwistedCylinder(), "rk45-c", n=11, times=TIMES, max_steps=150, max_step=1e-4)
    with pytest.raises(ParameterError, match=r"^max_step = 0\.0001 is outside \[0\.0001012, inf\) s"):  # 2e-3 / 19.78
        mol_shell.simulate(mol_shell.TwistedCylinder(), "rk45-c", n=11, times=TIMES, max_steps=222, max_step=1e-4)
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "rk45-c", n=11, times=TIMES, max_steps=least, max_step=1e-4,
                            progress=False, stresses=False)
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] <= least
    with pytest.raises(ParameterError, match=r"^max_steps = 1 is outside integers >= 12 at max_step = 1e-06 s "
                                             r"\(casadi-cvodes counts"):  # (1e-5 / 1e-6 + 1) / 0.99 = 11.1
        mol_shell.simulate(mol_shell.TwistedCylinder(), "casadi-cvodes", n=11, times=TIMES, max_steps=1, max_step=1e-6)
