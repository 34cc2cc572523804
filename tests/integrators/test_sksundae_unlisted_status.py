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


def test_a_run_whose_step_meets_an_unlisted_status_ends_failed_with_its_counts(monkeypatch):
    """The failed result of :func:`unlisted_status` has no counts (``nfev``): kept as the run's last result, the run's
    statistics then ended in an ``AttributeError``, a traceback. The run ends failed, naming the status, and counts
    the steps that were taken."""
    import mol_shell
    from mol_shell.integrators import sundials

    real, calls = sundials.unlisted_status, [0]

    def sixtieth(call, *args, **kwargs):
        calls[0] += 1
        if calls[0] == 30 and getattr(call, "__name__", "") == "step":
            return unlisted_status(lambda: (_ for _ in ()).throw(KeyError(-60)))
        return real(call, *args, **kwargs)

    monkeypatch.setattr(sundials, "unlisted_status", sixtieth)
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "sksundae-ida", n=6, t_end=0.002, progress=False,
                            stresses=False)
    assert ds.attrs["status"] == "failed" and "(status -60)" in ds.attrs["message"], ds.attrs["message"]
    assert ds.attrs["n_steps"] >= 28 and ds.attrs["n_rhs"] > 0
