"""The compare's error norm on a field that stays 0: ``compare examples/drum_spin_down.toml`` found the reference
"not converged" (cvode-adams at rtol 1e-11 and 1e-12 apart by 3.9e-3) and every dop853-c point at 2-5e-3. The drum's
motion is uniform, so its meridian angle ``theta`` is 0 in exact arithmetic (the section-5 argument: uniform data,
the magnets' ``theta = 0``, a drag the same on every node) and round-off in the runs; the norm divided ``theta``'s
error by 1e-6 of the largest field's scale (``chi``, 0.88 rad here), so round-off of 1e-14 rad counted as 1e-8.
A field under 1e-6 of the largest in its units is now compared on that one's scale (theta on chi's: never on r's
metres, which would hide a real theta on a large shell)."""

import numpy as np

import mol_shell
from mol_shell.analysis import workprecision as wp
from mol_shell.runs.simulate import build, resolve, starting_state

DRUM = mol_shell.TwistedCylinder(gamma=0.0, R=1.0, omega=20.0, psi0=0.0, drag=50.0)


def test_a_field_that_stays_zero_is_compared_on_the_largest_fields_scale():
    """Synthetic: ``theta`` is 0 in the reference and 1e-14 in the run (round-off), ``r`` and ``chi`` agree; the
    error is 1e-14 over the largest field's scale (``chi``, 4 rad), not over 1e-6 of it (2.5e-9)."""
    ref = np.zeros((3, 2, 5))
    ref[0], ref[2] = 1.0, 4.0  # r (m), chi (rad); theta 0
    run = ref.copy()
    run[1, 1, 2] = 1e-14
    assert abs(wp.relative_error(run, ref) - 1e-14 / 4.0) < 1e-20
    run[0, 1, 2] += 1e-9  # a field of its own scale: relative to itself as before
    assert abs(wp.relative_error(run, ref) - 1e-9) < 1e-15  # 1 + 1e-9 - 1: round-off of 1


def test_the_spinning_drums_runs_at_tight_tolerances_agree_in_the_compares_norm():
    """The drum spinning down in its fluid (n = 12, to 0.05 s, before its breathing dips below the natural radius):
    CVODE-Adams at rtol 1e-11 against 1e-12 (the compare's reference) differ by CVODE's global error, below
    ``100 rtol`` (1e-9; the convention of ``tests/model/test_loads.py``'s drum against the ring ODE). Before, the
    norm said 8.7e-9: ``theta``'s round-off (both runs under 1e-13 rad) over 1e-6 of ``chi``'s 0.88 rad."""
    scene = resolve(DRUM)
    system, compiled = build(scene, 12)
    y0, _ = starting_state(scene, system, 12)
    times = np.linspace(0.0, 0.05, 11)
    fields = {rtol: wp.fields_of(system, wp.run_once(system, compiled, y0, times, "cvode-adams", rtol).y)
              for rtol in (1e-11, 1e-12)}
    assert max(np.abs(f[1]).max() for f in fields.values()) < 1e-13  # theta: round-off of 0
    assert np.abs(fields[1e-12][2]).max() > 0.5  # chi: the spin's angle, the largest field
    assert wp.relative_error(fields[1e-11], fields[1e-12]) < 100 * 1e-11


def test_a_small_angle_is_not_hidden_behind_a_large_radius():
    """A shell of R = 100 m twisting little: theta 1e-4 rad (1e-6 of r's 100 m) and chi 1e-4 rad; theta 50 % off is an
    error of 0.5, not 5e-7 (compared on r's metres, across units, it was)."""
    ref = np.zeros((3, 2, 5))
    ref[0], ref[1], ref[2] = 100.0, 0.9e-4, 1e-4  # r (m), theta, chi (rad)
    run = ref.copy()
    run[1] *= 1.5
    assert abs(wp.relative_error(run, ref) - 0.5) < 1e-12


def test_a_unit_whose_every_field_is_round_off_is_compared_on_the_largest_field():
    """A breathing cylinder without twist or spin: theta (2.6e-15 rad) and chi (0) are round-off, r is 1.05 m. Compared
    on its own unit's largest (theta's round-off), theta's round-off difference counted as an error of 10; on r's
    scale it is round-off, and r's own error (3e-7) is the error."""
    ref = np.zeros((3, 2, 5))
    ref[0], ref[1] = 1.05, 2.6e-15
    run = ref.copy()
    run[0, 1, 2] += 3.15e-7
    run[1, 1, 2] = 2.9e-14
    assert abs(wp.relative_error(run, ref) - 3e-7) < 1e-12
    ref[1] = 0.0  # theta exactly 0 too: not 0/0
    assert abs(wp.relative_error(run, ref) - 3e-7) < 1e-12
