"""A comparison says what held an integrator's steps where it was not the tolerance, as a run does
(:mod:`mol_shell.runs.step_limits`), once per integrator; and it records the route each integrator's name ran, as a run
file does. ``compare`` said none of it: a fixed-point ``cvode-adams`` 22 rtol off on a stiff wall came without a word."""

import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.analysis import workprecision as wp
from mol_shell.analysis.workprecision import work_precision
from mol_shell.discretization import sundials_driver
from mol_shell.integrators import sundials_c

STIFF = mol_shell.TwistedCylinder(eta_mu=1e4, eta_lambda=2e4)
THIN = mol_shell.TwistedCylinder(h=1e-6)


@pytest.fixture(autouse=True)
def stand_in_reference(monkeypatch):
    """The comparisons' reference runs (rtol 1e-12) left out: the notes and routes come from the compared runs alone
    (the thin wall's reference does not complete within max_steps), and the errors are not the point here."""

    def reference(system, compiled, y0, times, progress=None):
        info = {"reference": "none", "reference_check": "none", "reference_check_status": "complete",
                "reference_check_message": "", "reference_wall_s": 0.0}
        return np.ones((len(wp.COMPARED), len(times), system.n)), 0.0, info

    monkeypatch.setattr(wp, "reference", reference)


def _compare(scene, sweeps, times):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = work_precision(scene, list(sweeps), n=11, times=times, repeats=1, sweeps=sweeps, log=lambda *a: None)
    return ds, [str(w.message) for w in caught if issubclass(w.category, mol_shell.MolShellWarning)]


def test_a_fixed_point_adams_held_by_a_stiff_wall_is_said_once_for_its_sweep():
    """eta_mu = 1e4, t = 4 ms: cvode-adams takes about 4,300 steps at rtol 1e-4 and 1e-6 alike, 38 % failing to
    converge (error 6.6e-4 and 2.2e-5, 22 rtol); one warning for its two points, in the file too."""
    ds, said = _compare(STIFF, {"cvode-adams": {"rtol": [1e-4, 1e-6]}}, [0.0, 0.002, 0.004])
    notes = [m for m in said if "failed to converge" in m]
    assert len(notes) == 1, said
    assert notes[0].startswith("compare, at rtol = 0.0001 and 1 more of its 2 points: cvode-adams's fixed-point")
    assert 'iteration="newton"' in notes[0] and "cvode-bdf or ida" in notes[0]
    assert ds.attrs["step_warnings"] == notes[0]
    assert ds.route.values.tolist() == ["compiled C"] and ds.route_reason.values.tolist() == [""]


def test_bdf_held_by_an_undamped_director_mode_is_said_naming_max_order_2():
    """h = 1e-6, t = 0.2 ms: the director's undamped rotation holds BDF3-5's steps at 0.65 / omega_max (10,097
    steps at rtol 1e-6); the comparison names max_order = 2."""
    ds, said = _compare(THIN, {"cvode-bdf": {"rtol": [1e-6]}}, [0.0, 1e-4, 2e-4])
    notes = [m for m in said if "held by the stability of BDF orders 3-5" in m]
    assert len(notes) == 1 and notes[0].startswith("compare, at rtol = 1e-06: cvode-bdf took") and (
        "--option max_order=2" in notes[0]), said
    assert ds.attrs["step_warnings"] == notes[0]


def test_a_name_that_ran_scikit_sundaes_loop_is_recorded_with_why(monkeypatch):
    """The compiled SUNDIALS driver unavailable: cvode-bdf runs scikit-sundae's loop, said on stderr; its compare file
    said nothing of it (and a run file said route = scikit-sundae without why). Both now record the reason."""

    def unavailable():
        raise sundials_driver.DriverUnavailable("no driver here")

    monkeypatch.setattr(sundials_driver, "driver", unavailable)
    monkeypatch.setattr(sundials_c, "_REPORTED", set())
    ds, _ = _compare(mol_shell.TwistedCylinder(), {"cvode-bdf": {"rtol": [1e-4]}}, [0.0, 1e-4])
    assert ds.route.values.tolist() == ["scikit-sundae"]
    assert ds.route_reason.values.tolist() == ["the compiled SUNDIALS driver is unavailable (no driver here)"]
    run = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-bdf", n=11, times=[0.0, 1e-4], progress=False,
                             stresses=False)
    assert run.attrs["route"] == "scikit-sundae" and run.attrs["route_reason"] == ds.route_reason.values[0]
