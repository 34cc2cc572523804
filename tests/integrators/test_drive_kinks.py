"""The compiled SUNDIALS loops stop and restart at the kinks of a driven edge's rate (docs/loads.md).

At a kink of the prescribed rate the driven node's acceleration jumps, and with it the driver's power that the
``work`` accumulator integrates. The balance ``E - E(0) - work + dissipated`` of the cases below was 38 to 124 times
``rtol`` with CVODE (BDF and Adams) and 28 times with IDA: the step that ends on a kink took the new segment's rate
there (a history's rate at its corner is the new segment's; the motion itself was right, the ``work`` was 9.5e-6 J
off after the step ending at the kink), and the steps and multistep histories that crossed a kink spanned the jump.
Stopped at each kink (the step ending there evaluated on the old segment) and restarted from it, each saved interval
adds at most about ``rtol`` of the energy exchanged, so a few tens of them stay well under ``20 rtol`` (the bound the
dop853-c tests of tests/model/test_drive_history_balance.py use); measured 0.14 to 7.9 ``rtol``.
"""

import numpy as np
import pytest

import mol_shell
from mol_shell.discretization.loading import drive_kinks, history_kinks
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.loads import parse_history

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


@pytest.mark.parametrize("case, integrator", [("axial", "cvode-bdf"), ("axial", "cvode-adams"), ("ramp", "cvode-bdf"),
                                              ("table", "cvode-adams"), ("table", "ida")])
def test_the_balance_holds_to_about_rtol_across_the_kinks(case, integrator):
    ds = mol_shell.simulate(SCENES[case], integrator, n=21, times=TIMES[case], progress=False, rtol=RTOL)
    assert ds.attrs["status"] == "complete"
    assert ds.attrs["energy_balance_error"] < 20 * RTOL
    # the counts run on across the restarts (SUNDIALS zeroes its own at each): every step evaluates the right-hand
    # side at least once, and each restart takes a fresh Jacobian (a Newton iteration's)
    assert ds.attrs["n_rhs"] >= ds.attrs["n_steps"]
    if integrator != "cvode-adams":
        assert ds.attrs["n_jac"] > len(drive_kinks(ShellSystem(SCENES[case], 5)))
