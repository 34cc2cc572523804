"""The static equilibrium a run with ``R`` = auto or ``dilation`` = auto starts from (:mod:`mol_shell.runs.statics`):
sparse Newton, linear memory, the same state as the dense minimum-norm Newton it replaced.

The reference here is that dense Newton, written out in the test (NumPy ``lstsq`` of the dense Jacobian, whose
minimum-norm steps leave a free shell's rigid axial translation where it was): at small ``n`` the sparse Newton,
which holds one ``z`` while it iterates and shifts the result back to the starting mean ``z``, must give the same
state to round-off. At ``n = 4001`` a dense Jacobian of the free coordinates would take ``(5 n)^2 x 8`` bytes =
3.2 GB; the sparse Newton's Python-side peak must stay far below that.
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest

from mol_shell import Cone, MaterialWarning, Sphere
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.statics import newton


def dense_minimum_norm_newton(system, y0, tol=1e-11):
    """Newton with dense minimum-norm least-squares steps (every free field, chi included: the minimum-norm steps
    leave a free shell's spin where it was), halved until the residual falls."""
    y = np.array(y0, dtype=float)
    fixed = system.fixed[:, list(system.active)]
    q = np.array([system.ny * i + j for i in range(system.n) for j, k in enumerate(system.active)
                  if not fixed[i, j]])
    p = q + system.nf
    scale = None
    for _ in range(40):
        f = np.array(system.rhs_newton(0, y)).ravel()[p]
        J = np.array(system.jac(0, y))[np.ix_(p, q)]
        scale = scale or float(np.abs(np.diag(J)).max())
        if np.abs(f).max() <= tol * scale:
            return y
        step = np.linalg.lstsq(J, -f, rcond=None)[0]
        for _ in range(20):
            trial = y.copy()
            trial[q] += step
            if np.abs(np.array(system.rhs_newton(0, trial)).ravel()[p]).max() < np.abs(f).max():
                break
            step /= 2
        y = trial
    raise AssertionError("the dense reference did not converge")


@pytest.mark.parametrize("scene", [
    Sphere(h=0.02, nu=0.3, material="svk-plane-stress", pressure=2000.0),  # free to translate axially
    Cone(end1="clamped", end2="free", gravity=9.81, nu=0.3),  # held by its clamped edge
    Cone(end1="clamped", end2="free", end2_torque=0.05, nu=0.3),  # twisted: chi held as given before
    Sphere(h=0.02, nu=0.3, material="svk-plane-stress", pressure=2000.0, fibre_E=1e6, fibre_angle=0.5),  # a helix
], ids=["closed-sphere-pressure", "clamped-cone-gravity", "clamped-cone-torque", "helical-fibres-sphere-pressure"])
def test_sparse_newton_gives_the_dense_minimum_norm_state(scene):
    system = ShellSystem(scene, 12)
    y0 = system.initial_state(scene)
    y, iterations, residual = newton(system, y0)
    reference = dense_minimum_norm_newton(system, y0)
    fields, expected = system.unpack(y), system.tie(system.unpack(reference))  # a pole's chi: its neighbour's
    assert residual <= 1e-11 and iterations > 0
    assert np.abs(fields - expected).max() <= 1e-9 * np.abs(expected[:2]).max()


def test_static_equilibrium_at_n_4001_in_linear_memory():
    scene = Sphere(h=0.02, nu=0.3, material="svk-plane-stress", pressure=2000.0)
    system = ShellSystem(scene, 4001)
    y0 = system.initial_state(scene)
    tracemalloc.start()
    try:
        y, _, residual = newton(system, y0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert residual <= 1e-11
    assert peak < 0.05 * (5 * system.n) ** 2 * 8  # measured 45 MB; a dense Jacobian alone: 3.2 GB
    z, r = system.unpack(y)[:2]
    z0 = system.unpack(y0)[0]
    assert np.mean(z) == pytest.approx(np.mean(z0), abs=1e-12)  # the rigid translation left where it was
    radius = np.hypot(r, z - np.mean(z))
    # a sphere, inflated: uniform to the discretisation near the poles, O(ds^2 / a^2) = 6e-7
    assert radius.std() <= 1e-7 * radius.mean() and radius.mean() > 1.0


def test_a_cone_twisted_by_an_end_torque_at_rest_has_the_thin_walled_torsion_of_strength_of_materials():
    """Until December 2026 the static Newton held ``chi`` as given: a run with ``R = auto`` under an end torque
    started from the untwisted shell, recorded as "static equilibrium ... residual 1.7e-17" with the torque
    unbalanced, and ``modes`` refused the scene. Now ``chi`` is solved for.

    Reference (thin-walled torsion, derived here): a section of the cone at radius ``r`` carries the torque ``T``
    as a shear flow ``tau t 2 pi r^2`` with ``tau = mu gamma`` and ``gamma = r chi_s`` (the twist per unit length
    of meridian ``s``), so ``chi_s = T / (2 pi mu t r^3)``, ``t = 2h``; along the cone's straight meridian from
    ``r1`` to ``r2`` (length ``L = sqrt(H^2 + (r1 - r2)^2)``) the end turns by
    ``T L / (2 pi mu t (r2 - r1)) (1 / (2 r1^2) - 1 / (2 r2^2))``. The shear is the in-plane one, which the
    director constraint does not stiffen. Corrections: the wall's thickness ``O((h / r)^2)`` = 1e-4 and the
    grid's ``O(ds^2)``: within 0.1 % at n = 41.
    """
    from mol_shell.runs.simulate import simulate

    torque = 0.05
    scene = Cone(end1="clamped", end2="free", end2_torque=torque, nu=0.3)
    ds = simulate(scene, n=41, t_end=2e-4, integrator="cvode-bdf", progress=None)
    mu = scene.E / (2 * (1 + scene.nu))
    r1, r2 = scene.r1, scene.r2
    length = np.hypot(scene.H, r1 - r2)
    expected = torque * length / (2 * np.pi * mu * 2 * scene.h * (r2 - r1)) * (0.5 / r1**2 - 0.5 / r2**2)
    chi = ds.chi.values
    assert chi[0, -1] == pytest.approx(expected, rel=1e-3)
    assert "static equilibrium" in ds.attrs["initial_state"]
    # at rest in equilibrium: the run stays there (a torque left unbalanced turned the end by 1e-7 rad in 1e-4 s)
    assert np.abs(chi - chi[0]).max() <= 1e-6 * abs(expected)


def test_fibres_a_thousand_times_stiffer_than_the_wall_take_full_newton_steps():
    """One helical family of fibres with ``fibre_E = 1e9`` on a wall of ``E = 1e6`` under pressure: the sphere
    twists as it inflates. The full Newton steps converge quadratically (6 iterations), though the residual's
    largest entry grows a hundredfold at the first: halving every step until that entry fell took 30 iterations
    at n = 41, 50 at n = 101 (over the limit of 30: continuation), and refused 1e5 Pa there. The natural
    monotonicity test (the next correction, with this iteration's LU, smaller than this one) accepts them."""
    scene = Sphere(material="svk-plane-stress", nu=0.3, fibre_E=1e9, fibre_angle=0.3, pressure=1e3)
    system = ShellSystem(scene, 41)
    y, iterations, residual = newton(system, system.initial_state(scene))
    assert iterations <= 8 and residual <= 1e-11
    chi = system.unpack(y)[2]
    assert np.ptp(chi) > 0.1  # twisted, by 0.22 rad pole to pole: chi was solved for, not held


def test_a_twist_the_scene_asks_for_is_kept_while_the_rest_comes_to_equilibrium():
    """``gamma`` is initial data (``chi = gamma (s - L/2)``): with the loads' equilibrium (``dilation = auto``)
    solved for, ``chi`` is held as given, not untwisted; without ``gamma`` the clamped cone under pressure stays
    untwisted by symmetry (no torque on it)."""
    from mol_shell.runs.simulate import starting_state

    for gamma in (0.2, 0.0):
        scene = Cone(end1="clamped", end2="free", pressure=500.0, gamma=gamma, nu=0.3)
        system = ShellSystem(scene, 12)
        y, how = starting_state(scene, system, 12)
        assert "static equilibrium" in how
        r, chi = system.unpack(y)[1:3]
        assert np.allclose(chi, gamma * (system.s - system.s[-1] / 2), rtol=0, atol=1e-12)
        assert np.abs(r - system.reference[1]).max() > 1e-6  # the pressure moved the wall


@pytest.mark.parametrize("material, nu", [("svk-plane-stress", 0.3), ("svk", 0.49)])
def test_a_tube_with_free_ends_inflated_starts_at_the_membrane_equilibrium_with_its_lids_axial_push(material, nu):
    """``R = auto`` of the cylinder is the radial equilibrium of its uniform twist at its natural length; under a
    pressure with neither edge holding ``z`` that left the lids' axial push unbalanced, and the tube started
    lengthening. Now the static solve starts from it. Membrane theory of a closed tube (derived here): the
    meridional force ``N_s = p a / 2`` (the lids), the hoop force ``N_phi = p a``, with ``t = 2h``. Plane stress:
    axial strain ``(p a / (E t)) (1/2 - nu)``, hoop strain ``(p a / (E t)) (1 - nu/2)``. The director law (``svk``,
    thickness stretch held at 1): ``N = t S`` with ``S_zz = (lambda + 2 mu) e_z + lambda e_phi`` and
    ``S_phiphi = lambda e_z + (lambda + 2 mu) e_phi``, a 2x2 system (in-plane Poisson ratio ``nu/(1 - nu)`` = 0.96
    at ``nu = 0.49``: the tube shortens). docs/loads.md quotes both. Corrections: the free ends' bending boundary
    layers (length ``~sqrt(a t)`` = 0.1 m of 4 m) and ``p a / E t`` = 1e-3 (nonlinear)."""
    from mol_shell import TwistedCylinder
    from mol_shell.runs.simulate import simulate

    E, a, h, p = 1e6, 1.0, 0.005, 10.0
    t = 2 * h
    scene = TwistedCylinder(gamma=0.0, h=h, E=E, nu=nu, material=material, pressure=p, end1="free", end2="free")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MaterialWarning)  # svk at nu = 0.49: far stiffer than a thin rubber wall
        ds = simulate(scene, n=41, t_end=0.02, integrator="cvode-bdf", progress=None)
    if material == "svk-plane-stress":
        axial, hoop = p * a / (E * t) * (0.5 - nu), p * a / (E * t) * (1 - nu / 2)
    else:
        lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
        axial, hoop = np.linalg.solve([[lam + 2 * mu, lam], [lam, lam + 2 * mu]], [p * a / (2 * t), p * a / t])
        assert axial < 0  # the held thickness: the tube shortens as it inflates
    length = float(ds.z.isel(time=0, s=-1) - ds.z.isel(time=0, s=0))
    assert length / 4.0 - 1 == pytest.approx(axial, rel=0.01)
    assert float(ds.r.isel(time=0, s=20)) / a - 1 == pytest.approx(hoop, rel=0.01)
    assert "static equilibrium" in ds.attrs["initial_state"]
    assert float(ds.kinetic_energy.max()) <= 1e-12 * float(ds.stored_energy[0])  # at rest, and it stays there


def test_a_spin_asked_for_is_kept_on_the_static_equilibrium_under_load():
    """``omega`` with ``R = auto`` under pressure: the static state was returned at rest, the spin dropped
    silently (angular momentum 0). Now it is set spinning at ``omega`` about the axis (chi_t = omega at every
    node) from the equilibrium under the loads."""
    from mol_shell.runs.simulate import simulate

    ds = simulate(Sphere(omega=3.0, pressure=100.0, nu=0.3, material="svk-plane-stress"), n=12, t_end=1e-3,
                  integrator="cvode-bdf", progress=None)
    assert np.allclose(ds.chi_t.values[0], 3.0, rtol=1e-12, atol=0)
    assert float(ds.angular_momentum[0]) > 0 and "then set moving" in ds.attrs["initial_state"]


def test_a_driven_edge_holds_the_rigid_motion_so_no_gauge_is_added():
    """A driven ``z`` (or ``chi``) is no imposed one, but it holds the shell's translation (spin) as well: gauging
    one more node left an equation that could not balance, and the loads were refused (a cone under pressure with
    an edge moving axially; one under an end torque with an edge spun)."""
    from mol_shell.runs.statics import static_equilibrium

    for edges in ({"end1": "free", "end1_axial_speed": 1e-6, "pressure": 100.0},
                  {"end1": "magnet", "end1_spin": 1e-6, "end2_torque": 0.05}):
        scene = Cone(end2="free", nu=0.3, **edges)
        system = ShellSystem(scene, 21)
        y, how = static_equilibrium(scene, 21, system.initial_state(scene))
        assert how.startswith("static equilibrium") and np.all(np.isfinite(y))


def test_a_poles_chi_follows_its_neighbour_in_a_static_state():
    """A pole's ``chi`` is tied to its neighbour's and is not one of Newton's unknowns: once ``chi`` was solved for
    (one helical family of fibres twists an inflated sphere) the pole kept 0 beside a neighbour at 0.064 rad."""
    scene = Sphere(material="svk-plane-stress", nu=0.3, fibre_E=1e8, fibre_angle=0.3, pressure=1e3)
    system = ShellSystem(scene, 21)
    chi = system.unpack(newton(system, system.initial_state(scene))[0])[2]
    assert abs(chi[1]) > 0.05 and chi[0] == chi[1] and chi[-1] == chi[-2]


def test_a_tilt_asked_for_is_kept_with_the_cylinders_radial_equilibrium():
    """``psi0`` is initial data, as ``gamma`` is: a spinning ring under pressure with ``R = auto`` started at
    ``psi = 0`` once its untwisted start went through the static solve, the tilt asked for dropped."""
    from mol_shell.scenes import SpinningRing
    from mol_shell.runs.simulate import simulate

    scene = SpinningRing(R=None, pressure=100.0)
    assert scene.psi0 != 0
    ds = simulate(scene, "cvode-bdf", n=12, t_end=1e-4, progress=False)
    assert np.allclose(ds.psi.values[0], scene.psi0, rtol=0, atol=1e-15)


def test_a_converged_state_is_polished_to_round_off():
    """Newton may stop at its tolerance (1e-11 of a unit strain's force); one more full step from there (quadratic
    convergence, one factorisation) reaches round-off: a run started there stays at rest to round-off, not to the
    tolerance. Without it this inflated, helically reinforced rubber sphere stopped at 6.6e-14."""
    scene = Sphere(pressure=2000.0, material="neo-hookean-incompressible", fibre_E=3e6, fibre_angle=0.6)
    system = ShellSystem(scene, 40)
    y, iterations, residual = newton(system, system.initial_state(scene))
    assert residual <= 10 * np.finfo(float).eps and iterations <= 8, (residual, iterations)
    assert np.ptp(system.unpack(y)[2]) > 0.01  # one helical family: inflated, it twists (chi solved for)


def test_a_static_start_whose_meridian_crosses_itself_is_refused_naming_the_load(tmp_path, capsys):
    """A rubber sphere under -1e4 Pa (far past its buckling pressure) at n = 8: Newton's equilibrium had its poles
    swapped (z = 0.163 at s = 0, -0.163 at s = L), a meridian through itself, run as "R = 0.46 m" with exit 0."""
    from mol_shell.cli.main import main

    code = main(["run", "sphere", "--n", "8", "--set", "material=neo-hookean-incompressible", "--set", "pressure=-1e4",
                 "--t-end", "1e-4", "-o", str(tmp_path / "r.nc")])
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert code == 2 and err == ("mol-shell: error: pressure = -10000.0 is outside values whose equilibrium at t = 0 "
                                 "lies inside the model's limits (the static equilibrium computed at t = 0 is past one: "
                                 "its meridian crosses itself)"), err
    assert not (tmp_path / "r.nc").exists()


def test_no_start_under_a_ramp_is_blamed_on_the_twist_held_not_on_the_load():
    """A twisted sphere (gamma = 1.5) under a pressure ramped from 0 has no static start: the message named
    ``pressure = 1000`` and said the continuation "stopped at 0 of the loads", a load that is 0 at t = 0. The
    twist, held as initial data while the other fields come to rest, is named; a load on at t = 0 still is."""
    import mol_shell

    ramped = mol_shell.Sphere(pressure=1e3, pressure_history="ramp 0.05", gamma=1.5)
    with pytest.raises(mol_shell.ParameterError, match=r"^gamma = 1.5 is outside twists that the shell, its loads 0 "
                       r"at t = 0, holds at a static equilibrium"):
        mol_shell.simulate(ramped, t_end=1e-4, n=8)
    with pytest.raises(mol_shell.ParameterError, match=r"^pressure = -10000000.0 is outside loads under which"):
        mol_shell.simulate(mol_shell.Sphere(pressure=-1e7, gamma=1.5), t_end=1e-4, n=8)


def test_newton_evaluates_the_jacobian_only_where_a_step_uses_it(monkeypatch):
    """Each iteration's Jacobian factorises its step, and the converged iteration's the polishing step
    (:func:`~mol_shell.runs.statics._polished`): ``iterations + 1`` evaluations. At ``max_iter`` it was evaluated once
    more and never used (and so at a non-finite residual): a Newton that fails after ``max_iter = 2`` evaluated it 3
    times, now 2. The states are those of the same iterations (the reference tests above)."""
    from mol_shell.runs import statics

    calls = []
    original = statics.sparse_evaluator

    def counting(f):
        evaluate = original(f)

        def counted(*args):
            calls.append(f.name())
            return evaluate(*args)

        return counted

    monkeypatch.setattr(statics, "sparse_evaluator", counting)
    scene = Sphere(pressure=2000.0, material="neo-hookean-incompressible")
    system = ShellSystem(scene, 12)
    y0 = system.initial_state(scene)
    _, iterations, residual = newton(system, y0)
    assert iterations > 2 and residual <= 1e-11
    assert len(calls) == iterations + 1, calls
    calls.clear()
    with pytest.raises(RuntimeError, match="Newton did not converge"):
        newton(system, y0, max_iter=2)
    assert len(calls) == 2, calls
