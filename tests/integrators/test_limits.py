"""The model's limits stop every integrator at the same time and place.

A shell sheared close to the fold (``psi0 = 1.5`` rad, ``delta = r cos(psi) ~ 0.07`` m at t = 0) keeps
its uniform shear oscillating about 1.5 rad with the fast shear frequency (~5,000 rad/s), so
``cos(psi)`` at a node can touch 0 for a fraction of a millisecond and recover. Leap-frog checks
the limits after every step in C, so it must stop at the same crossing that CVODE's and IDA's root
finders locate, within one of its steps, not at a later chunk boundary (2,000 steps = 2 ms).
"""

import warnings

import numpy as np
import pytest

import mol_shell

SCENE = mol_shell.TwistedCylinder(psi0=1.5)
TIMES = [0.0, 0.002, 0.004, 0.006, 0.008]
DT = 1e-6


@pytest.fixture(scope="module")
def runs():
    with warnings.catch_warnings():  # every run stops early on purpose
        warnings.filterwarnings("ignore", "run incomplete", RuntimeWarning)
        return _runs()


def _runs():
    out = {"leapfrog": mol_shell.simulate(SCENE, "leapfrog", times=TIMES, dt=DT, progress=False)}
    for name in ("cvode-bdf", "ida", "dop853-c"):
        out[name] = mol_shell.simulate(SCENE, name, times=TIMES, rtol=1e-9, atol=1e-12, progress=False)
    return out


def _where(ds):
    return ds.attrs["message"].split(" at t = ")[1].split(", s = ")[1].split(" m")[0]


def test_every_integrator_stops_at_the_first_crossing(runs):
    root = runs["cvode-bdf"]
    assert root.attrs["status"] == "limit", root.attrs["message"]
    t_root = root.attrs["failure_time"]
    assert 0.002 < t_root < 0.006  # between two saved times, away from any chunk boundary of leap-frog
    assert abs(runs["ida"].attrs["failure_time"] - t_root) < 1e-6  # two root finders at rtol 1e-9
    lf = runs["leapfrog"]
    assert lf.attrs["status"] == "limit", lf.attrs["message"]
    # leap-frog stops at the first step past the crossing: within a step of the root, plus its O(dt^2)
    # phase error over ~5,000 steps of a 5,000 rad/s oscillation (~1e-8 s)
    assert 0 <= lf.attrs["failure_time"] - t_root < 2 * DT
    assert _where(lf) == _where(root) == _where(runs["ida"])
    # dop853-c checks the limits in C after every accepted step and locates the crossing inside the step that
    # crossed on its dense output: CVODE's root to the three solvers' agreement at rtol 1e-9, not the step's end (a
    # step is 4e-5 s). That agreement is machine-dependent: CVODE's and IDA's roots 1.7e-9 s apart on an AMD EPYC (the
    # 1e-8 relative, 4.9e-11 s, once asked of dop853-c failed there by 9.2e-10 s), so 1e-5 relative: 4.9e-8 s, 800x
    # below a step
    rk = runs["dop853-c"]
    assert rk.attrs["status"] == "limit", rk.attrs["message"]
    spread = abs(runs["ida"].attrs["failure_time"] - t_root)
    assert abs(rk.attrs["failure_time"] - t_root) < max(1e-5 * t_root, 2 * spread), (rk.attrs["failure_time"], t_root)
    assert _where(rk) == _where(root)


def test_data_before_the_crossing_are_kept_and_finite(runs):
    for name, ds in runs.items():
        assert ds.attrs["complete"] == 0
        assert list(ds.time.values) == [t for t in TIMES if t < ds.attrs["failure_time"]], name
        assert np.all(np.isfinite(ds.psi.values)) and np.abs(ds.psi.values).max() < np.pi / 2


def test_a_limit_at_the_last_step_of_a_chunk_is_reported_as_a_limit():
    """The C loop stops at the first step outside the limits; when that is the chunk's last step the
    step count alone cannot tell, so the driver says so too. The fold above is crossed at step k
    (found by single steps); a chunk of exactly k steps reports (k, stopped), one of k - 1 not."""
    from mol_shell.runs.simulate import build, resolve

    scene = resolve(SCENE)
    system, compiled = build(scene, 40)
    y0 = system.initial_state(scene)
    start = y0.copy(), y0 + DT * np.array(compiled.evaluator()(y0 + 0.5 * DT * np.array(compiled.evaluator()(y0))))
    ya, yb = (a.copy() for a in start)
    k, stopped = 0, False
    while not stopped:
        taken, stopped = compiled.leapfrog(ya, yb, 1, DT)
        assert taken == 1
        k += 1
    assert 4000 < k < 6000  # the crossing of the tests above, ~4.9 ms after the first step
    for chunk, expected in ((k, True), (k - 1, False)):
        ya, yb = (a.copy() for a in start)
        assert compiled.leapfrog(ya, yb, chunk, DT) == (chunk, expected)
