"""Where the shell's equations stop being elliptic in s (the Legendre-Hadamard condition of the 1-D shell), against
the 3-D acoustic tensor of the director-constrained SVK law, and what a run reports there.

Closed forms (derived here, not taken from a run). Under the inextensible director (``C_33 = 1``, ``E_33 = 0``) a
uniform state with in-plane stretches ``a`` (meridian) and ``b`` (hoop) has ``S_11 = l (E_11 + E_22) + 2 mu E_11``,
``E_11 = (a^2 - 1)/2``, ``E_22 = (b^2 - 1)/2``, Lame's ``l, mu``. For waves along the meridian the acoustic tensor
``Q_ik = S_11 delta_ik + (F^T m)(F^T m) C_.1.1`` has, for the transverse polarisation ``m = d`` (``F^T d = D``),
``S_11 + mu``, and for the hoop polarisation (``chi``; ``F^T e_phi = b E_2``) ``S_11 + mu b^2``. The shell loses
ellipticity where the smaller reaches 0:
- axial compression of a cylinder (``b = 1``): ``a^2 = 1 - mu / (l/2 + mu)``, both polarisations at once;
- equibiaxial compression of a sphere (``a = b``): the hoop polarisation first, ``a^2 = (l + mu) / (l + 2 mu)``,
  up to a curvature correction of order ``h/a``.
"""

import math
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.checks import resolve

NU = 0.49
L_OVER_MU = 2 * NU / (1 - 2 * NU)  # Lame's l / mu


def crossing(system, equibiaxial):
    """The stretch where the smallest margin of the uniformly stretched reference state reaches 0 (bisection)."""
    lo, hi = 0.5, 1.0
    for _ in range(45):
        mid = (lo + hi) / 2
        Q = system._natural_fields()
        Q[0] *= mid
        if equibiaxial:
            Q[1] *= mid
        if np.nanmin(system.ellipticity_margins(Q)) > 0:
            hi = mid
        else:
            lo = mid
    return hi


def test_natural_state_is_elliptic_for_every_law():
    for params in ({}, {"material": "svk-plane-stress"}, {"material": "neo-hookean"},
                   {"material": "neo-hookean-incompressible", "fibre_E": 2e6, "fibre_angle": 0.5},
                   {"material": "mooney-rivlin", "c10": 1e5, "c01": 2e4}):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = ShellSystem(resolve(mol_shell.Sphere(**params)), 21)
        margins = system.ellipticity_margins(system._natural_fields())
        assert np.all(np.isfinite(margins)), params  # K_0 positive definite in every cell, poles included
        np.testing.assert_allclose(margins, 1.0, atol=1e-9)


@pytest.mark.parametrize("h", [0.02, 0.002])
def test_cylinder_axial_compression_against_the_acoustic_tensor(h):
    system = ShellSystem(resolve(mol_shell.TwistedCylinder(h=h, nu=NU)), 15)
    expected = math.sqrt(1 - 1 / (L_OVER_MU / 2 + 1))  # 0.98020 at nu = 0.49
    assert crossing(system, equibiaxial=False) == pytest.approx(expected, abs=1e-10)


def test_sphere_equibiaxial_compression_converges_to_the_acoustic_tensor_in_h():
    expected = math.sqrt((L_OVER_MU + 1) / (L_OVER_MU + 2))  # 0.99015: the hoop (chi) polarisation first
    errors = {}
    for h in (0.002, 0.0005):
        system = ShellSystem(resolve(mol_shell.Sphere(h=h, nu=NU)), 41)
        errors[h] = crossing(system, equibiaxial=True) - expected
        assert abs(errors[h]) < 0.02 * h  # the curvature's correction, of order h / a (a = 1 m)
    assert errors[0.002] / errors[0.0005] == pytest.approx(4.0, rel=0.1)  # first order in h


def test_a_breathing_sphere_reports_the_loss_where_the_closed_form_says_whatever_the_grid():
    # released 5 % stretched, the sphere breathes through about 5 % compression: past 1 % the default law's
    # equations are no longer elliptic and a finer grid stops sooner (the run's own limit: 1/sqrt(3))
    critical = math.sqrt((L_OVER_MU + 1) / (L_OVER_MU + 2))
    times = np.linspace(0, 0.01, 41)
    lost = []
    for n in (21, 41):
        with pytest.warns(mol_shell.MaterialWarning, match="lost ellipticity by t = "):
            ds = mol_shell.simulate(mol_shell.Sphere(R=1.05), "cvode-bdf", n=n, times=times, stresses=False)
        stretch = (ds.r / ds.r0).isel(s=n // 2).values  # the equator, in the uniform breathing
        first_below = float(ds.time[np.argmax(stretch < critical)])
        assert ds.attrs["ellipticity_lost_time"] == first_below
        assert np.all(ds.ellipticity_margin.values[ds.time.values < first_below] > 0)
        lost.append(ds.attrs["ellipticity_lost_time"])
    assert lost[0] == lost[1]


def test_the_papers_scene_stays_elliptic():
    with warnings.catch_warnings():
        warnings.simplefilter("error", mol_shell.MaterialWarning)
        warnings.filterwarnings("ignore", "material = ", mol_shell.MaterialWarning)  # SVK's locking note
        ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-bdf", n=21, t_end=0.05, stresses=False)
    assert "ellipticity_lost_time" not in ds.attrs
    assert ds.ellipticity_margin.attrs["units"] == "1"
    assert float(ds.ellipticity_margin.min()) > 0.2


def test_a_study_keeps_each_cases_loss_to_itself():
    # one case at rest in its natural state (R = a), one breathing through the loss: the loss is a per-case
    # variable (NaN where there was none), never a study-wide attribute
    times = np.linspace(0, 0.01, 41)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mol_shell.MaterialWarning)
        st = mol_shell.study(mol_shell.Sphere(), {"R": [1.0, 1.05]}, integrator="cvode-bdf", n=21, times=times,
                             scheduler="serial")
    lost = st.ellipticity_lost_time.values
    assert np.isnan(lost[0]) and lost[1] == pytest.approx(0.00675)
    # units from the case that has the number, though the first one does not; a position in metres, not seconds
    assert st.ellipticity_lost_time.attrs["units"] == "s" and st.ellipticity_lost_position.attrs["units"] == "m"
    assert "ellipticity_warning" not in st.attrs and "ellipticity_lost_time" not in st.attrs
    assert np.all(st.ellipticity_margin.values[0] == pytest.approx(1.0))


def test_with_ellipticity_limit_a_run_stops_there_on_every_grid_and_integrator():
    # the breathing sphere of the test above, asked to stop: the stop is where the closed form, applied to each cell's
    # membrane stretches in the run without the limit (saved densely), first reaches 0, whatever the grid and the
    # integrator (the breathing is not quite uniform: the first cells to get there are not at the equator)
    times = np.linspace(0, 0.008, 161)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        free = mol_shell.simulate(mol_shell.Sphere(R=1.05), "cvode-bdf", n=21, times=times, stresses=False, rtol=1e-9)
    z, r, z0, r0 = free.z.values, free.r.values, free.z0.values, free.r0.values
    a = np.hypot(np.diff(z), np.diff(r)) / np.hypot(np.diff(z0), np.diff(r0))  # meridional stretch per cell
    b = (r[:, 1:] + r[:, :-1]) / (r0[1:] + r0[:-1])  # hoop stretch per cell
    s11 = L_OVER_MU * (a**2 + b**2 - 2) / 2 + (a**2 - 1)  # S_11 / mu
    margin = np.minimum(s11 + 1, s11 + b**2).min(axis=1)  # transverse and hoop polarisations
    k = int(np.argmax(margin < 0))
    expected = float(np.interp(0.0, margin[[k, k - 1]], times[[k, k - 1]]))  # 6.6 ms
    stops = {}
    for integrator, n in (("cvode-bdf", 21), ("cvode-bdf", 41), ("leapfrog", 21)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = mol_shell.simulate(mol_shell.Sphere(R=1.05, ellipticity_limit=True), integrator, n=n, t_end=0.02,
                                    stresses=False)
        assert ds.attrs["status"] == "limit" and "stopped being elliptic" in ds.attrs["message"]
        stops[integrator, n] = ds.attrs["failure_time"]
    for (integrator, n), t in stops.items():  # the curvature's O(h/a) shift of the stretch is 3e-6 s here
        assert t == pytest.approx(expected, abs=1e-5 if integrator == "leapfrog" else 5e-6), (integrator, n)


@pytest.mark.parametrize("integrator", ["cvode-bdf", "leapfrog"])
def test_with_ellipticity_limit_a_run_that_starts_past_the_loss_stops_at_t_0(integrator):
    """Started already non-elliptic (a rubber sphere released at 0.6 of its radius), a root-finding solver saw no
    crossing and ran to its end with a warning afterwards: the start is checked against the limits at t = 0."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(mol_shell.Sphere(R=0.6, material="neo-hookean-incompressible", ellipticity_limit=True),
                                integrator, n=12, t_end=0.02, stresses=False)
    assert ds.attrs["status"] == "limit" and "stopped being elliptic" in ds.attrs["message"]
    assert ds.attrs["failure_time"] == 0.0 and ds.sizes["time"] == 1  # the start kept


def test_ellipticity_limit_is_a_flag():
    with pytest.raises(ParameterError, match="ellipticity_limit"):
        mol_shell.Sphere(ellipticity_limit="sometimes")
    assert mol_shell.Sphere(ellipticity_limit="true").ellipticity_limit is True


def test_a_rotation_alone_leaves_the_margin_at_one():
    # a very wide cylinder's meridian turned rigidly in its plane (positions and theta together): the hoop strain
    # this leaves is of order L/a = 1e-3, the rotation itself must not count (K_0 is turned with the cell)
    system = ShellSystem(resolve(mol_shell.TwistedCylinder(gamma=0.0, a=1000.0, R=1000.0)), 5)
    Q0 = system._natural_fields()
    d = np.diff(Q0[[0, 1]], axis=1)
    for phi in (0.3, 0.8, 1.5):
        c, s = math.cos(phi), math.sin(phi)
        Q = Q0.copy()
        Q[0] = Q0[0, 0] + np.concatenate([[0], np.cumsum(c * d[0] - s * d[1])])
        Q[1] = Q0[1, 0] + np.concatenate([[0], np.cumsum(s * d[0] + c * d[1])])
        Q[3] = Q0[3] + phi
        np.testing.assert_allclose(system.ellipticity_margins(Q), 1.0, atol=5e-3)


def test_a_law_without_shear_stiffness_is_left_unchecked_and_says_so():
    import casadi as ca

    fluid = mol_shell.Material("fluid-like", energy=lambda C, p: p["k"] * (ca.det(C) - 1) ** 2, parameters={"k": 1e6},
                               thickness="director")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(mol_shell.Sphere(h=0.01, material=fluid), "cvode-bdf", n=11, t_end=0.001,
                                stresses=False)
    assert np.all(np.isnan(ds.ellipticity_margin.values))
    assert "not checked in 10 of 10 cells" in ds.attrs["ellipticity_note"]
    assert "ellipticity_lost_time" not in ds.attrs
    # no RuntimeWarning (All-NaN); the note is said on stderr too, once (no state could be checked)
    said = [str(w.message) for w in caught if not str(w.message).startswith("material = ")]
    assert said == [ds.attrs["ellipticity_note"]], said


def test_a_wall_far_thinner_than_its_radius_is_checked_in_units_of_its_own_stiffnesses():
    """A vessel head of radius 1e10 m (h / R = 6e-13): the natural state's principal symbol spans 1e-27 to 1e25,
    because its entries mix units (membrane ~E h, bending ~E h^3). Tested for positive definiteness as it stands,
    no cell could be checked (and with ``> 0`` as the test, one LAPACK build checked them, another not); scaled by
    its diagonal it is well conditioned (smallest over largest eigenvalue 0.02 in every cell), every cell is checked
    and the natural state's margin is 1, as it must be (the margin is relative to the natural state's symbol)."""
    vessel = mol_shell.scenes.SCENES["vessel"](segments="arc 1e10 -90, line 2, arc 1 -90")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(vessel, n=12, t_end=0.001, progress=False)
    assert ds.attrs["status"] == "complete" and "ellipticity_note" not in ds.attrs
    assert ds.ellipticity_margin.values[0] == pytest.approx(1.0, abs=1e-12)
    assert np.all(ds.ellipticity_margin.values > 0)
    assert not [w for w in caught if "ellipticity" in str(w.message)]
    tiny = mol_shell.simulate(mol_shell.Sphere(a=1e-5, h=1e-7, nu=0.3), "cvode-bdf", n=12, t_end=1e-9,
                             progress=False)
    assert tiny.ellipticity_margin.values[0] == pytest.approx(1.0, abs=1e-12)  # a 10 um sphere: units again


def test_a_law_whose_second_derivatives_underflow_is_left_unchecked_not_a_crash():
    """``neo-hookean`` with ``E = 1e-200`` Pa runs (its forces are finite), but its principal symbol is NaN (the
    Jacobian of its condensation squares ``2 mu + lambda M``, which underflows): ``eigh`` raised LinAlgError after
    the run, an internal error. Every cell is now left unchecked with the note, as a singular symbol is."""
    system = ShellSystem(resolve(mol_shell.Sphere(material="neo-hookean", nu=0.3, E=1e-200)), 8)
    assert not np.any(system._natural_root[1])
    assert np.all(np.isnan(system.ellipticity_margins(system._natural_fields())))
    with pytest.warns(mol_shell.MaterialWarning, match="under- or overflow"):
        ds = mol_shell.simulate(mol_shell.Sphere(material="neo-hookean", nu=0.3, E=1e-200), "leapfrog", n=8,
                                t_end=1e-3, stresses=False, progress=False)
    assert ds.attrs["complete"] == 1 and np.all(np.isnan(ds.ellipticity_margin.values))
