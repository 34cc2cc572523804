"""A SUNDIALS status that scikit-sundae's table of messages lacks (IDA's -60, "tout too close to t0") raised a
``KeyError`` inside scikit-sundae's solver, a traceback for the user; the route ends the run as failed, naming the
status."""

from __future__ import annotations

import numpy as np
from sksundae.ida import IDA

from mol_shell.integrators.sksundae_workarounds import unlisted_status


def _decay(t, y, yp, res):
    res[:] = yp + 0.1 * y


def test_ida_asked_for_a_step_an_ulp_long_fails_with_its_status_not_a_key_error():
    solver = IDA(_decay, rtol=1e-6, atol=1e-9)
    assert solver.init_step(0.009, np.ones(3), -0.1 * np.ones(3)).success
    t = float(np.nextafter(0.009, 1.0))
    res = unlisted_status(solver.step, t, method="onestep", tstop=t)
    assert not res.success and res.status == -60 and "not in scikit-sundae's table" in res.message


def test_other_key_errors_are_not_taken_for_a_status():
    def broken():
        raise KeyError("rtol")
    try:
        unlisted_status(broken)
    except KeyError as exc:
        assert exc.args == ("rtol",)
    else:
        raise AssertionError("a KeyError that is not a SUNDIALS status was swallowed")
