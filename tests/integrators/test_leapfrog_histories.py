"""Leap-frog and the loads' time histories (docs/loads.md): what its fixed step cannot resolve is refused up front,
and a drive's kink off the step grid splits the work of the step that holds it.

Leap-frog samples a history once a step: ``sine 999950`` on a pressure at dt = 1e-6 s ran as a 50 Hz load (1.5868e-3
m at the equator against 1.5876e-3 with ``sine 50``; the true amplitude is ~2e-12 m), exit 0. A drive's ``ramp 1e-6``
stopped as a "numerical instability" (exit 3). A kink of a drive's table off the step grid left the work first order,
``dP dt`` with ``dP`` the jump of the driver's power there: 2.4e-5 of the balance at dt = 2e-6 and 1e-6 s alike.
"""

import mol_shell

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
