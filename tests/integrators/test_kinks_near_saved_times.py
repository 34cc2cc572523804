"""A drive's kink within round-off of a saved time, of the end, or of another drive's kink is one time with it.

SUNDIALS refuses a first step, after a start or a restart, towards a time closer than ``2 uround max(|t0|, |tout|)``
("tout too close to t0"). The SUNDIALS routes restart at each kink of a drive's history and then stepped towards
the next saved time: a table's point at 0.009 s with the times saved at ``numpy.linspace(0, 0.01, 11)``, whose tenth
is 0.009000000000000001 (one ulp later), ended cvode-bdf and cvode-adams with "SUNDIALS error (status -27)", ida with
-60, sksundae-cvode-* with "The output and initial times are too close to each other. (status -27)" and sksundae-ida
with a ``KeyError: -60``; so did a point one or two ulp before the end, and two drives' kinks one to three ulp apart.
A point one ulp after a saved time completed, with a step more than with the point at the saved time.

Moving a point of a table by an ulp changes the history by round-off, and here only over the 0.3 ms ramp that ends
there (the runs are the same to the last bit before it): the saved states are those of the run with the point at the
saved time (or with the two drives' kinks at one time) to far under the solver's tolerance (measured 8.4e-10 of the
states' scale at most, against ~rtol between runs whose steps differ), with as many steps, and the energy balance
holds as it does there (0.06 to 4.7 ``rtol``: ``E - E(0)`` and ``work`` are 80 J).
"""

import numpy as np
import pytest

import mol_shell

RTOL = 1e-6
TIMES = np.linspace(0.0, 0.002, 11)
SAVED = float(TIMES[9])  # 0.0018000000000000002, one ulp after 0.0018
ROUTES = ["cvode-bdf", "cvode-adams", "ida", "sksundae-cvode-bdf", "sksundae-cvode-adams", "sksundae-ida"]
STATES = ("z", "z_t", "r", "r_t", "chi", "chi_t", "theta", "theta_t", "psi", "psi_t", "work")

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")


def spun(t9, t_end, axial_kink=None):
    """A cone whose driven edge's spin has kinks at ``t9`` (by the tenth saved time) and at ``t_end``, each at the end
    of a ramp 0.3 ms long (where an ulp more or less changes the history); with ``axial_kink``, the edge also driven
    along the axis from 1.5 ms, its speed ramped up to then."""
    axial = {} if axial_kink is None else {"end2_axial_speed": 0.1,
                                           "end2_axial_speed_history": f"table 0:0 0.0015:0 {axial_kink!r}:1"}
    return mol_shell.Cone(end1="clamped", end2_spin=20.0, end2_spin_history=(
        f"table 0:0 0.0005:0.5 0.0015:0.5 {t9!r}:1 0.0019:1 {t_end!r}:0.8"), **axial)


def run(scene, route, times=TIMES):
    # scikit-sundae's loop meets the kinks and the saved times whatever gives it the Jacobian: CasADi's virtual
    # machine's here, where a compiled one is a gcc build (-O1, about 5 s) for each of these histories, used once
    options = {"jacobian": "vm"} if route.startswith("sksundae-") else {}
    ds = mol_shell.simulate(scene, route, n=11, times=times, progress=False, rtol=RTOL, **options)
    states = np.concatenate([ds[v].values.reshape(len(ds.time), -1) for v in STATES], axis=1)
    return ds, states


def assert_one_time(ds, states, ref, ref_states):
    assert ds.attrs["status"] == "complete", ds.attrs["message"]
    assert ds.attrs["n_steps"] == ref.attrs["n_steps"]  # no step between the two times
    assert np.max(np.abs(states - ref_states)) < 0.1 * RTOL * np.abs(ref_states).max()
    assert ds.attrs["energy_balance_error"] < 10 * RTOL


MOVED = {"one ulp before a saved time": (0.0018, 0.002),
         "one ulp after a saved time": (float(np.nextafter(SAVED, 1.0)), 0.002),
         "one ulp before the end": (SAVED, float(np.nextafter(0.002, 0.0)))}


# every position on the compiled routes; the Python loops (slower: scikit-sundae's loop in Python) the one that failed
CASES = [(route, where) for route in ROUTES[:3] for where in MOVED] + \
    [(route, "one ulp before a saved time") for route in ROUTES[3:]]


@pytest.mark.parametrize("route, where", CASES)
def test_a_kink_an_ulp_from_a_saved_time_is_taken_at_it(route, where):
    assert_one_time(*run(spun(*MOVED[where]), route), *run(spun(SAVED, 0.002), route))


@pytest.mark.parametrize("route", ["cvode-bdf", "sksundae-ida", "casadi-cvodes"])
def test_two_drives_kinks_an_ulp_apart_are_one_restart(route):
    times = np.linspace(0.0, 0.002, 8)  # none near the kinks
    assert_one_time(*run(spun(0.0018, 0.002, axial_kink=SAVED), route, times),
                    *run(spun(0.0018, 0.002, axial_kink=0.0018), route, times))


@pytest.mark.parametrize("where", MOVED)
def test_casadis_calls_take_a_kink_an_ulp_from_a_saved_time_at_it(where):
    """CasADi's calls, one per interval between kinks, in a time scaled to the shortest interval (casadi-* since
    December 7): an ulp between a kink and a saved time made that interval an ulp long (CV_TOO_CLOSE, 9 saved times
    of 11), as on the SUNDIALS routes."""
    assert_one_time(*run(spun(*MOVED[where]), "casadi-cvodes"), *run(spun(SAVED, 0.002), "casadi-cvodes"))
