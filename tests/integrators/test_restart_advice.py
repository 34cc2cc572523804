"""What the leap-frog's refusal on a viscous wall suggests, and what a restart it takes is.

A restart starts the scheme again from its last level, and that level holds what the parasitic root has grown to
since the last start: it is carried on, not started afresh. For the mode ``y' = lambda y`` a start and ``m - 1``
steps multiply it by ``G = c1 z1^m + c2 z2^m`` (:func:`~mol_shell.integrators.leapfrog.restart_gain`), and over many
restarts by ``G`` each. The refusal counted only the growth ``exp(a m dt)`` between two restarts up to 1e6 (twisted
cylinder, eta_mu = 1000 Pa s: "every 0.000166 s or less"), but ``|c2| exp(a m dt) > 1`` there, the run then unstable
(at t = 0.00265 s of 0.01 s); and where that bound was below 100 steps (eta_mu = 1e4 Pa s: "every 1.82e-05 s") the
restart it named was held to 100 steps, unsaid, and the run stopped too.
"""

import math
import re

import numpy as np
import pytest

import mol_shell
from mol_shell import ParameterError
from mol_shell.cli.main import main
from mol_shell.integrators.leapfrog import restart_gain
from mol_shell.results.dataset import read_netcdf


def leapfrog_levels(h, m):
    """The scheme itself on ``y' = (h / dt) y`` from ``y_0 = 1``: a midpoint step, then ``m - 1`` leap-frog steps."""
    ya, yb = 1.0 + 0j, 1.0 + h + 0.5 * h * h
    for _ in range(m - 1):
        ya, yb = yb, ya + 2 * h * yb
    return yb


@pytest.mark.parametrize("h", [-0.083, -0.5 + 0.3j, 0.2j, -1e-3 + 0.9j])
def test_restart_gain_is_what_the_scheme_does_to_a_mode(h):
    for m in (1, 2, 100, 166):
        assert math.isclose(float(restart_gain(h, m)), abs(leapfrog_levels(h, m)), rel_tol=1e-9)
    # a damped real mode at a dt of 0.083 / a: the start leaves c2 = -h^4 / 16 = -3e-6 on the parasitic root, grown
    # by exp(0.083) a step; at 166 steps (exp(13.8) = 1e6: the old bound) the mode grows by 2.9 per restart
    if h == -0.083:
        assert restart_gain(h, 100) < 0.02 and restart_gain(h, 166) > 2


def refused_advice(scene, **kwargs):
    with pytest.raises(ParameterError, match="parasitic root") as info:
        mol_shell.simulate(scene, "leapfrog", progress=False, stresses=False, **kwargs)
    return str(info.value)


def assert_runs_as_cvode_bdf(scene, t_end, **options):
    ds = mol_shell.simulate(scene, "leapfrog", n=11, t_end=t_end, progress=False, stresses=False, **options)
    exact = mol_shell.simulate(scene, "cvode-bdf", n=11, times=ds.time.values, rtol=1e-10, progress=False,
                               stresses=False)
    assert ds.attrs["status"] == "complete" and ds.attrs["n_restarts"] >= 10
    for f in ("r", "theta", "chi", "z", "psi"):
        moved = exact[f].values[-1] - exact[f].values[0]
        assert np.abs(ds[f].values - exact[f].values).max() < 1e-4 * np.abs(moved).max(), f
    return ds


def test_the_restart_a_refusal_suggests_runs():
    scene = mol_shell.TwistedCylinder(eta_mu=1000.0)
    said = refused_advice(scene, n=11, t_end=0.01)
    restart = float(re.search(r"restarts of the leap-frog every (\S+) s or less \(option restart", said).group(1))
    assert restart >= 100 * 1e-6
    ds = assert_runs_as_cvode_bdf(scene, 0.01, restart=restart)
    assert ds.attrs["restart"] == restart
    # one a little longer than where |G| = 1 (158 steps) is refused, carried through the restarts
    assert "carried through the restarts" in refused_advice(scene, n=11, t_end=0.01, restart=1.6e-4)


def test_where_100_steps_are_too_many_it_suggests_a_smaller_dt_with_its_restart():
    scene = mol_shell.TwistedCylinder(eta_mu=1e4, eta_lambda=2e4)
    said = refused_advice(scene, n=11, t_end=1e-3)
    found = re.search(r"dt = (\S+) s, with restarts every (\S+) s or less \(options dt and restart", said)
    dt, restart = float(found.group(1)), float(found.group(2))
    assert dt < 1e-6 and restart >= 100 * dt * (1 - 1e-12)
    assert_runs_as_cvode_bdf(scene, 1e-3, dt=dt, restart=restart)


def test_a_restart_within_100_steps_is_refused_and_the_file_records_the_restart_taken():
    with pytest.raises(ParameterError, match=r"^restart = 1\.8e-05 is outside 0 or inf \(never\), or \[0\.0001, inf\] "
                                             r"s at dt = 1e-06 s \(at least 100 steps"):
        mol_shell.simulate(mol_shell.TwistedCylinder(), "leapfrog", n=11, t_end=0.001, restart=1.8e-5)
    # 123.45 steps of 1e-6 s: 123 are taken, and recorded (1.8e-5 was recorded as asked, with no restart taken)
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "leapfrog", n=11, t_end=0.001, restart=1.2345e-4,
                            progress=False, stresses=False)
    assert ds.attrs["restart"] == 1.23e-4 and ds.attrs["n_restarts"] == 1000 // 123


def test_a_restart_is_checked_against_the_dt_given_with_it(tmp_path):
    # the command line checked --option restart with the default dt (1e-6 s) before --dt 1e-7 s was applied
    out = tmp_path / "x.nc"
    assert main(["run", "twisted-cylinder", "--n", "11", "--t-end", "1e-4", "--dt", "1e-7", "--option",
                 "restart=1.3e-5", "--no-stresses", "-o", str(out)]) == 0
    ds = read_netcdf(out)
    assert ds.attrs["restart"] == 1.3e-5 and ds.attrs["n_restarts"] == 1000 // 130
    assert main(["run", "twisted-cylinder", "--n", "11", "--t-end", "1e-4", "--option", "restart=1.3e-5",
                 "-o", str(out)]) == 2
