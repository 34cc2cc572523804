"""The compiled SUNDIALS loops stop and restart at the kinks of a driven edge's rate (docs/loads.md).

At a kink of the prescribed rate the driven node's acceleration jumps, and with it the driver's power that the
``work`` accumulator integrates. The balance ``E - E(0) - work + dissipated`` of the cases below was 38 to 124 times
``rtol`` with CVODE (BDF and Adams) and 28 times with IDA: the step that ends on a kink took the new segment's rate
there (a history's rate at its corner is the new segment's; the motion itself was right, the ``work`` was 9.5e-6 J
off after the step ending at the kink), and the steps and multistep histories that crossed a kink spanned the jump.
Stopped at each kink (the step ending there evaluated on the old segment) and restarted from it, each saved interval
adds at most about ``rtol`` of the energy exchanged, so a few tens of them stay well under ``20 rtol`` (the bound the
dop853-c tests of tests/model/test_drive_history_balance.py use); measured 0.14 to 7.9 ``rtol``.

The compiled Runge-Kutta pairs had the same corner: their steps landed on the saved times only, so a step spanned
each kink between them, and the one ending on a kink at a saved time took the new segment's rate in its last stage
(``table``: dop853-c 146 ``rtol``, rk45-c 991; ``axial``: rk45-c 23). A step now lands on each kink with its stages
on the old segment, and the next step's first stage (first same as last) is evaluated again on the new one: 0.09 to
1.7 ``rtol``. The peers with a Python loop stop there too: scikit-sundae's solvers with ``tstop`` and a restart
(``sksundae-cvode-bdf`` 227 -> 10, ``sksundae-cvode-adams`` 110 -> 1.1), SciPy's with a new solver from each kink
(``scipy-rk45`` 139 -> 0.75, ``scipy-dop853`` 42 -> 0.53, ``scipy-bdf`` 57 -> 11). CasADi's integrators (one call
for all saved times, crossing the kinks) now make one call per interval between kinks, each ending one ulp short of
its kink and the next starting afresh there (``casadi-cvodes`` 93 -> 7.4 on the table; ``casadi-cvodes-c`` 285 -> 2.9
on the table, 31 -> 1.2 with one kink, 98 -> 0.06 on the ramp).
"""

import numpy as np
import pytest

import mol_shell
from mol_shell.discretization.loading import drive_kinks, history_kinks
from mol_shell.discretization.system import ShellSystem
from mol_shell.integrators import INTEGRATORS
from mol_shell.model.loads import parse_history
from mol_shell.runs.simulate import build, resolve

RTOL = 1e-6

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")

# speed 0.1 m/s falling linearly to -0.1 m/s at 5 ms (a saved time), then held: one kink
AXIAL = mol_shell.Cone(end1="clamped", end2_axial_speed=0.1, end2_axial_speed_history="table 0:1 0.005:-1")
# four kinks between the saved times (every millisecond), one at the end
TABLE = mol_shell.Cone(end1="clamped", end2_axial_speed=0.1,
                       end2_axial_speed_history="table 0:1 0.0013:0.2 0.0021:0.9 0.0037:-1 0.01:-0.5")
# a spin ramped up over 10 ms (a saved time), then held
RAMP = mol_shell.Cone(end1="free", end2_spin=2.0, end2_spin_history="ramp 0.01")
TIMES = {"axial": np.linspace(0.0, 0.01, 11), "table": np.linspace(0.0, 0.01, 11), "ramp": np.arange(21) * 1e-3}
SCENES = {"axial": AXIAL, "table": TABLE, "ramp": RAMP}


def test_the_kinks_are_the_histories_corners_after_the_start():
    assert history_kinks(parse_history("h", "table 0:1 0.005:-1")) == (0.005,)
    assert history_kinks(parse_history("h", "table 0.001:0 0.002:1 0.004:1")) == (0.001, 0.002, 0.004)
    assert history_kinks(parse_history("h", "ramp 0.01")) == (0.01,)
    assert history_kinks(parse_history("h", "step 0")) == ()
    for smooth in ("constant", "sine 50"):
        assert history_kinks(parse_history("h", smooth)) == ()
    both = mol_shell.Cone(end1="free", end2_spin=2.0, end2_spin_history="table 0:0 0.003:1 0.006:0.5",
                          end2_axial_speed=0.1, end2_axial_speed_history="ramp 0.003")
    assert drive_kinks(ShellSystem(both, 5)) == (0.003, 0.006)
    assert drive_kinks(ShellSystem(mol_shell.Cone(end1="clamped", end2_spin=2.0), 5)) == ()


@pytest.mark.parametrize("case, integrator", [
    ("axial", "cvode-bdf"), ("axial", "cvode-adams"), ("ramp", "cvode-bdf"), ("table", "cvode-adams"), ("table", "ida"),
    # the compiled Runge-Kutta pairs: a step lands on each kink
    ("axial", "rk45-c"), ("table", "dop853-c"), ("table", "rk45-c"), ("ramp", "rk45-c"),
    # the peers' Python loops: scikit-sundae stopped and restarted at each kink, SciPy's solvers started anew there
    ("axial", "sksundae-cvode-adams"), ("table", "sksundae-cvode-bdf"), ("ramp", "sksundae-ida"),
    ("axial", "scipy-rk45"), ("table", "scipy-dop853"), ("table", "scipy-bdf"),
    # CasADi's integrators: one call per interval between kinks
    ("table", "casadi-cvodes"), ("axial", "casadi-cvodes-c"), ("table", "casadi-cvodes-c"), ("ramp", "casadi-cvodes-c")])
def test_the_balance_holds_to_about_rtol_across_the_kinks(case, integrator):
    # scikit-sundae's loop stops at the kinks whatever gives it the Jacobian: on the table its compiled one (the
    # Jacobians test_scikit_sundae_stops_at_the_kinks_as_the_compiled_route_does compiles anyway), on the axial and
    # the ramped drives CasADi's virtual machine's (measured 1.4 and 9e-5 rtol), where a compiled one would be a gcc
    # build of its own (-O1, about 5 s) for this case alone
    options = {"jacobian": "vm"} if integrator.startswith("sksundae-") and case != "table" else {}
    ds = mol_shell.simulate(SCENES[case], integrator, n=21, times=TIMES[case], progress=False, rtol=RTOL, **options)
    assert ds.attrs["status"] == "complete"
    assert ds.attrs["energy_balance_error"] < 20 * RTOL
    # the counts run on across the restarts (SUNDIALS zeroes its own at each, a new SciPy solver starts from 0): every
    # step evaluates the right-hand side at least once, and each restart (at a kink before the end) takes a fresh
    # Jacobian (a Newton iteration's), as does the start
    assert ds.attrs["n_rhs"] >= ds.attrs["n_steps"]
    if integrator in ("cvode-bdf", "ida", "sksundae-cvode-bdf", "sksundae-ida", "scipy-bdf"):
        restarts = [t for t in drive_kinks(ShellSystem(SCENES[case], 5)) if t < TIMES[case][-1]]
        assert ds.attrs["n_jac"] >= 1 + len(restarts)



@pytest.mark.parametrize("name", ["cvode-bdf", "cvode-adams", "ida"])
def test_scikit_sundae_stops_at_the_kinks_as_the_compiled_route_does(name):
    # with the same settings both routes call the same SUNDIALS (tests/integrators/test_sundials_c.py): across the
    # four kinks too they take the same steps, now that the Python loop stops, evaluates and restarts there as well
    scene = resolve(TABLE)
    system, compiled = build(scene, 21)
    y0 = system.initial_state(scene)
    settings = {"rtol": RTOL, "jacobian": "compiled"}
    ours = INTEGRATORS[name](**settings, **({"iteration": "newton"} if name != "ida" else {}))
    theirs = INTEGRATORS["sksundae-" + name](**settings)
    a, b = (m.integrate(system, compiled, y0, TIMES["table"]) for m in (ours, theirs))
    assert a.status == b.status == "complete"
    for key in ("n_steps", "n_rhs", "n_jac"):
        assert a.stats[key] == b.stats[key], key
    assert np.max(np.abs(a.y - b.y)) < 1e-12 * np.abs(b.y).max()


@pytest.mark.parametrize("name", ["casadi-cvodes", "casadi-cvodes-c"])
def test_casadis_integrators_restart_at_each_kink_as_a_fresh_run_from_there(name):
    # the motion after a kink depends on the state there and on the rest of the history only: a run stopped one ulp
    # short of the first kink (0.0013 s) is the first interval's call, to the last bit; a fresh run from the state at
    # that kink on the history shifted by 0.0013 s (three kinks still ahead) is the rest, up to its own tolerances'
    # bookkeeping (casadi-cvodes-c scales its variables by the start's energies): measured 1.9e-11 (casadi-cvodes)
    # and 7.5e-9 (casadi-cvodes-c) of the state's scale. One CasADi call across the kinks was 2.3e-7 and 7.5e-7 off
    # the first interval's run, 3.9e-6 and 5.5e-5 off the fresh one.
    kink = 0.0013
    rest = mol_shell.Cone(end1="clamped", end2_axial_speed=0.1,
                          end2_axial_speed_history="table 0:0.2 0.0008:0.9 0.0024:-1 0.0087:-0.5")
    times = np.array([0.0, 0.001, kink, 0.002, 0.003, 0.004, 0.005])
    method = INTEGRATORS[name](rtol=RTOL)
    scene = resolve(TABLE)
    system, compiled = build(scene, 21)
    whole = method.integrate(system, compiled, system.initial_state(scene), times)
    first = method.integrate(system, compiled, system.initial_state(scene), [0.0, 0.001, np.nextafter(kink, 0.0)])
    scene = resolve(rest)
    system, compiled = build(scene, 21)
    after = method.integrate(system, compiled, whole.y[2], times[2:] - kink)
    assert whole.status == first.status == after.status == "complete"
    assert np.array_equal(whole.y[:3], first.y)
    assert np.max(np.abs(whole.y[2:] - after.y)) < 0.1 * RTOL * np.abs(whole.y).max()
