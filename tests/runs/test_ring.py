"""Section 5: the PDE started from uniform data stays uniform and follows the reduced ODE."""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.runs.ring import ring_system, simulate_ring

TIMES = np.linspace(0.0, 0.02, 5)
FIELDS = ("r", "chi", "psi", "r_t", "chi_t", "psi_t")


@pytest.fixture(scope="module")
def ring():
    return simulate_ring(mol_shell.SpinningRing(), TIMES)


@pytest.fixture(scope="module")
def pde_runs():
    scene = mol_shell.SpinningRing()
    return {dt: mol_shell.simulate(scene, n=10, times=TIMES, dt=dt, progress=False) for dt in (4e-6, 2e-6)}


def test_the_ode_conserves_energy_and_angular_momentum(ring):
    assert ring.attrs["complete"] == 1
    e = ring.energy.values
    assert np.abs(e - e[0]).max() < 1e-11 * e[0]
    L = ring.angular_momentum.values
    assert L[0] > 1000 and np.abs(L - L[0]).max() < 1e-12 * L[0]
    assert float(abs(ring.r - ring.r[0]).max()) > 0.01 and float(abs(ring.psi - ring.psi[0]).max()) > 0.05  # it moves


def test_pde_stays_uniform_in_s(pde_runs):
    for ds in pde_runs.values():
        for name in ("r", "chi", "psi", "r_t", "chi_t", "psi_t", "z_t", "theta", "theta_t"):
            spread = float(abs(ds[name] - ds[name].isel(s=4)).max())
            assert spread < 1e-11 * max(1.0, float(abs(ds[name]).max())), name


def test_pde_converges_to_the_ode_as_dt_squared(ring, pde_runs):
    """Every node follows the ODE exactly; what is left is leap-frog's O(dt^2) error (the ODE is solved to 1e-12)."""
    errors = {dt: {k: float(abs(ds[k] - ring[k]).max()) for k in FIELDS} for dt, ds in pde_runs.items()}
    for name in FIELDS:
        coarse, fine = errors[4e-6][name], errors[2e-6][name]
        assert 3.6 < coarse / fine < 4.4, (name, coarse, fine)
    assert errors[2e-6]["r"] < 1e-9 and errors[2e-6]["psi"] < 1e-4
    # the totals agree too (same energy, same angular momentum: both are whole-shell quantities)
    np.testing.assert_allclose(pde_runs[2e-6].angular_momentum, ring.angular_momentum, rtol=1e-12)
    np.testing.assert_allclose(pde_runs[2e-6].energy, ring.energy, rtol=1e-6)


def test_broadcast_onto_the_pde_grid():
    ds = simulate_ring(mol_shell.SpinningRing(), [0.0, 0.001], n=10)
    assert ds.r.dims == ("time", "s") and ds.sizes["s"] == 10
    np.testing.assert_allclose(ds.z.isel(time=1), np.linspace(0, 4, 10))


def test_ode_is_a_casadi_function_of_three_fields_and_momenta():
    system = ring_system(mol_shell.SpinningRing())
    assert system.rhs.size1_in(1) == 6 and system.rhs.is_a("SXFunction")
    with pytest.raises(ParameterError, match="gamma"):
        simulate_ring(mol_shell.TwistedCylinder(), [0.0, 0.001])


@pytest.mark.parametrize("kwargs, words", [
    ({"rtol": 0}, r"rtol = 0 is outside \[1e-14, 1\)"),
    ({"rtol": -1}, r"rtol = -1 is outside"),
    ({"atol": float("nan")}, r"atol = nan is outside \[1e-100, inf\)"),
    ({"n": 1}, r"n = 1 is outside None or integers >= 2"),
    ({"method": "foo"}, r"method = 'foo' is outside \{RK45"),
    ({"scene": mol_shell.Sphere()}, r"scene = 'sphere' is not a cylinder scene"),
])
def test_bad_arguments_are_parameter_errors_naming_them(kwargs, words):
    """rtol <= 0 and n = 1 were accepted, method = 'foo' raised SciPy's ValueError, a sphere an AttributeError."""
    scene = kwargs.pop("scene", mol_shell.SpinningRing())
    with pytest.raises(ParameterError, match="^" + words):
        simulate_ring(scene, [0.0, 0.001], **kwargs)


def test_a_registered_name_is_taken_as_simulate_takes_it(ring):
    """``simulate_ring("spinning-ring", ...)`` refused the scene's own name, which ``simulate`` takes."""
    named = simulate_ring("spinning-ring", TIMES)
    for field in FIELDS:
        np.testing.assert_array_equal(named[field].values, ring[field].values, err_msg=field)
    with pytest.raises(ParameterError, match=r"^scene = 'sphere' is not a cylinder scene of section 5; allowed: "
                       r"mol_shell\.SpinningRing\(\) \(or 'spinning-ring'\)"):
        simulate_ring("sphere", TIMES)
    with pytest.raises(ParameterError, match=r"^scene = 'nope' is outside \{axisymmetric, .*spinning-ring"):
        simulate_ring("nope", TIMES)


@pytest.mark.parametrize("changes, named", [({"end1": "clamped", "end2": "clamped"}, "end1"),
                                            ({"end2": "free"}, "end2"), ({"end1": "pinned"}, "end1"),
                                            ({"h_profile": "0.004+0.002*s"}, "h_profile")])
def test_what_makes_the_motion_depend_on_s_is_refused_by_name(changes, named):
    """Clamped, pinned or free ends and a graded wall bend the shell along s: the ring ODE returned its uniform
    answer as complete, 0.0017-0.026 m in r off the PDE's within 10 ms. (The spinning-ring scene itself refuses
    them now: tests/scenes/test_spinning_ring_uniform.py; the untwisted twisted-cylinder reaches the ring ODE.)"""
    with pytest.raises(mol_shell.ParameterError, match=rf"^{named} = .* for the ring ODE"):
        mol_shell.simulate_ring(mol_shell.TwistedCylinder(gamma=0.0, **changes), times=[0.0, 0.01])


@pytest.mark.parametrize("changes", [{"layers": "0.006 svk; 0.004 svk-plane-stress nu=0.3", "h": 0.005},
                                     {"fibre_E": 1e7, "fibre_angle": 0.5, "fibre_families": 2},
                                     {"material": "neo-hookean-incompressible", "eta_mu": 5.0}])
def test_walls_uniform_along_s_still_run_and_agree_with_the_pde(changes):
    """Layers and balanced helical fibres are the same at every s: the ring ODE holds for them (independent
    route: the PDE on 21 nodes, 4.7e-11 m apart in r over 10 ms). So does an incompressible law's viscosity, whose
    thickness rate follows det C = 1 in both (1.5e-11 m; the plane-stress condensation the ring kept before would be
    6.8e-7 m off)."""
    times = np.linspace(0.0, 0.01, 11)
    scene = mol_shell.SpinningRing(**changes)
    ring = mol_shell.simulate_ring(scene, times=times)
    pde = mol_shell.simulate(scene, n=21, times=times, stresses=False)
    assert float(np.abs(pde.r - ring.r).max()) < 1e-8


def test_the_ring_ode_takes_t_end_as_every_other_run_does():
    """``simulate_ring(SpinningRing(), t_end=0.01)`` was a TypeError (``times`` was required); ``t_end`` alone now
    gives the 11 saved times ``simulate`` gives, and the motion is the one ``times`` gives."""
    from mol_shell.runs.building import parse_times

    by_end = mol_shell.simulate_ring(mol_shell.SpinningRing(), t_end=0.01)
    by_times = mol_shell.simulate_ring(mol_shell.SpinningRing(), parse_times(None, 0.01))
    assert np.array_equal(by_end.time.values, parse_times(None, 0.01))
    assert np.array_equal(by_end.r.values, by_times.r.values)
    with pytest.raises(mol_shell.ParameterError, match="t_end is missing"):
        mol_shell.simulate_ring(mol_shell.SpinningRing())
