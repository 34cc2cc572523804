"""Leap-frog and the loads' time histories (docs/loads.md): what its fixed step cannot resolve is refused up front,
and a drive's kink off the step grid splits the work of the step that holds it.

Leap-frog samples a history once a step: ``sine 999950`` on a pressure at dt = 1e-6 s ran as a 50 Hz load (1.5868e-3
m at the equator against 1.5876e-3 with ``sine 50``; the true amplitude is ~2e-12 m), exit 0. A drive's ``ramp 1e-6``
stopped as a "numerical instability" (exit 3). A kink of a drive's table off the step grid left the work first order,
``dP dt`` with ``dP`` the jump of the driver's power there: 2.4e-5 of the balance at dt = 2e-6 and 1e-6 s alike.
"""

import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError, SceneWarning
from mol_shell.cli.main import main
from mol_shell.model.loads import parse_history

OFF_GRID = mol_shell.Cone(end1="clamped", end2_axial_speed=0.1, end2_axial_speed_history="table 0:1 0.0050007:-1")


def test_a_drive_kink_off_the_step_grid_keeps_the_work_second_order():
    """The kink at 5.0007 ms lies inside a step of either parity at dt = 2e-6 s; the work there is split at it (the
    jump of the driver's power at the kink times the part of the step on its far side). Reference: dop853-c, whose
    steps land on the kink (balance 1e-10). Before: balance 2.4e-5, work 2.4e-5 (relative) off."""
    times = [0.0, 0.006]
    ref = mol_shell.simulate(OFF_GRID, "dop853-c", n=11, times=times, rtol=1e-11, progress=False)
    errors = []
    for dt in (2e-6, 1e-6):
        ds = mol_shell.simulate(OFF_GRID, "leapfrog", n=11, times=times, dt=dt, progress=False)
        assert ds.attrs["energy_balance_error"] < 1e-6
        errors.append(abs(float(ds.work[-1] - ref.work[-1])) / float(ref.work[-1]))
    assert errors[0] < 1e-6 and errors[1] < errors[0] / 2.5, errors  # second order: a fourth per halving


def test_a_sine_faster_than_ten_steps_a_period_is_refused():
    scene = mol_shell.Sphere(R=1.0, pressure=1000.0, pressure_history="sine 999950")
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(scene, "leapfrog", n=11, t_end=1e-5, progress=False)
    assert info.value.name == "pressure_history" and "F <= 1e+05 Hz" in str(info.value)
    assert "dt = 1e-06 s" in str(info.value) and "\n" not in str(info.value)
    ok = mol_shell.Sphere(R=1.0, pressure=1000.0, pressure_history="sine 1e5")  # 10 steps a period: taken
    assert mol_shell.simulate(ok, "leapfrog", n=11, t_end=1e-5, progress=False).attrs["complete"] == 1


@pytest.mark.parametrize("history", ["ramp 1e-6", "ramp 3e-6", "table 0.001:0 0.001000000001:1", "sine 999950"])
def test_a_drive_leap_frog_cannot_resolve_is_refused_in_one_line(history, tmp_path, capsys):
    """Each stopped as a numerical instability (exit 3) at t = 2e-6 s; ``ramp 1e-5`` (10 steps) runs."""
    code = main(["run", "cone", "--set", "end1=clamped", "--set", "end2_spin=2", "--set",
                 f"end2_spin_history={history}", "--n", "11", "--t-end", "2e-5", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    line = [x for x in err.splitlines() if "error" in x]
    assert code == 2 and len(line) == 1 and "end2_spin_history" in line[0] and "dt = 1e-06 s" in line[0], err
    assert "Traceback" not in err


def test_a_ten_step_drive_ramp_runs():
    scene = mol_shell.Cone(end1="clamped", end2_spin=2.0, end2_spin_history="ramp 1e-5")
    ds = mol_shell.simulate(scene, "leapfrog", n=11, t_end=2e-5, progress=False)
    assert ds.attrs["complete"] == 1 and ds.attrs["energy_balance_error"] < 1e-3


def test_the_step_refusal_says_how_short_a_ramp_may_be():
    with pytest.raises(ParameterError) as info:
        parse_history("end2_spin_history", "step 0.001", rate=True)
    assert "at least 10 steps: 1e-05 s at its default dt = 1e-6 s" in str(info.value)


def test_a_load_table_with_close_points_is_warned_and_runs():
    """A load's table is sampled once a step (it aliases if it oscillates faster): said, not refused."""
    scene = mol_shell.Sphere(R=1.0, pressure=1000.0, pressure_history="table 0:0 1e-6:1 2e-6:0")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(scene, "leapfrog", n=11, t_end=1e-5, progress=False)
    assert ds.attrs["complete"] == 1
    assert any(w.category is SceneWarning and "pressure_history" in str(w.message) for w in said)
    assert np.isfinite(ds.attrs["energy_balance_error"])
