"""Datasets: labels, units, attrs, netCDF round trip; runs that stop keep their data."""

import dataclasses
import math

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import quad

import mol_shell
import reference_ring as ref
from mol_shell.integrators import INTEGRATORS, Leapfrog
from mol_shell.integrators.loop import declared
from mol_shell.runs.simulate import build, resolve


@pytest.fixture(scope="module")
def short_run():
    return mol_shell.simulate("twisted-cylinder", times=[0, 0.001, 0.002], progress=False)


def test_every_variable_has_units_and_long_name(short_run):
    for name, var in {**short_run.data_vars, **short_run.coords}.items():
        assert var.attrs.get("units") or var.dtype.kind in "OSU", name  # labels (CF 6.1) carry no units
        assert var.attrs.get("long_name"), name
    # stresses on cell centres and the faces; the edges' reactions (the magnets hold z) on the two ends
    assert set(short_run.dims) == {"time", "s", "s_cell", "zeta", "end"}
    assert list(short_run.end.values) == ["end1", "end2"] and short_run.reaction_force.dims == ("time", "end")
    for field in ("z", "r", "chi", "theta", "psi"):
        assert short_run[field].dims == ("time", "s")
        assert short_run[field + "_t"].dims == ("time", "s")


def test_attrs_hold_every_scene_parameter(short_run):
    scene = mol_shell.TwistedCylinder()
    for field in dataclasses.fields(scene):
        assert field.name in short_run.attrs
    # R is stored as computed, not as "None"
    assert short_run.attrs["R"] == pytest.approx(resolve(scene).R, rel=1e-15)
    for key in ("integrator", "dt", "n_steps", "n_rhs", "wall_time_s", "mol_shell_version", "rhs_instructions"):
        assert key in short_run.attrs
    assert short_run.attrs["n_steps"] == 2000
    assert short_run.attrs["n_rhs"] == 2001  # one extra evaluation for the midpoint start


def test_netcdf_round_trip_is_identical(short_run, tmp_path):
    path = tmp_path / "run.nc"
    mol_shell.write_netcdf(short_run, path)
    back = mol_shell.read_netcdf(path)
    xr.testing.assert_identical(short_run, back)


EPS = np.finfo(float).eps


def _what(F_of_zeta, lam, mu, zeta1, h):
    """``What = int W_SVK(F) (1 + zeta) dzeta`` by ``scipy.integrate.quad``; returns the value, quad's error
    estimate and ``|E|`` (Frobenius) at mid-thickness."""
    def integrand(zeta):
        F = F_of_zeta(zeta)
        E = 0.5 * (F.T @ F - np.eye(3))
        return (0.5 * lam * np.trace(E) ** 2 + mu * np.sum(E * E)) * (1 + zeta)

    value, error = quad(integrand, zeta1, zeta1 + 2 * h, epsabs=0.0, epsrel=1e-13, limit=100)
    F = F_of_zeta(zeta1 + h)
    return value, error, np.linalg.norm(0.5 * (F.T @ F - np.eye(3)))


def _energy_rtol(n, what, what_error, strain):
    """Relative tolerance of a stored energy ``2 pi L What`` against the Dataset's.

    Both sides form ``E = (F^T F - I)/2`` from ``F`` close to ``I``: an absolute rounding of a few
    ``EPS`` per component, i.e. ``~ 2 x 3 EPS / |E|`` relative in ``W`` (quadratic in ``E``), 10 EPS / |E|
    allowed; plus quad's own error estimate; plus ``n EPS`` for the sum over the cells. The
    cells' strains are the nodal differences: rounded nodes perturb them, but every cell has
    the same stress, so to first order the perturbations add up to the rounding of the end
    values (``z_n - z_0 = L``): no end effect beyond round-off, and the 4-point Gauss rule of the
    package is exact to ``(h/(1 + zeta))^8 ~ 1e-18`` for these rational integrands.
    """
    return 10 * EPS / strain + what_error / what + n * EPS


def test_stored_energy_of_the_twisted_cylinder_is_the_closed_form(short_run):
    """The paper's initial state: every cell has ``z_s = 1``, ``chi_s = gamma``, ``r = R``, ``theta = psi = 0``.

    The F table of MODEL_NOTES in the ``b`` basis: ``F = [[1, 0, 0], [0, 1, 0], [a, 0, l3]]`` with
    ``a = (R + zeta) gamma`` (``beta3 + zeta chi_s``) and ``l3 = (R + zeta)/(1 + zeta)``; the cells
    span ``L``, so ``V = 2 pi L What`` with ``What`` integrated by quad through the thickness
    ``[zeta1, zeta1 + 2h]`` (``zeta1`` from ``rhoI = 0`` by brentq). At rest: no kinetic energy,
    and the total is the stored energy.
    """
    scene = mol_shell.TwistedCylinder()
    R, gamma, L = float(short_run.r[0, 0]), scene.gamma, scene.L
    assert np.all(short_run.r[0] == R)  # the uniform initial radius (R as computed)
    lam, mu = ref.lame(scene.E, scene.nu)
    zeta1 = ref.zeta1_centroidal(scene.h)

    def F(zeta):
        return np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [(R + zeta) * gamma, 0.0, (R + zeta) / (1 + zeta)]])

    what, error, strain = _what(F, lam, mu, zeta1, scene.h)
    expected = 2 * math.pi * L * what
    rtol = _energy_rtol(short_run.sizes["s"], what, error, strain)
    assert float(short_run.stored_energy[0]) == pytest.approx(expected, rel=rtol)
    assert float(short_run.kinetic_energy[0]) == 0.0  # p = 0 gives v = M^-1 p = 0 exactly
    assert float(short_run.energy[0]) == pytest.approx(expected, rel=rtol)
    # the tolerance resolves the thickness integral: a thin-shell What (integrand at mid-thickness
    # times 2h) differs by ~h^2 relative
    zm = zeta1 + scene.h
    E = 0.5 * (F(zm).T @ F(zm) - np.eye(3))
    thin = 2 * scene.h * (0.5 * lam * np.trace(E) ** 2 + mu * np.sum(E * E)) * (1 + zm)
    assert abs(thin - what) > 1e3 * rtol * what


@pytest.mark.parametrize("zeta1,psi0", [(None, 0.05), ("outer", 0.3)])
def test_kinetic_and_stored_energy_of_a_spinning_shell(zeta1, psi0):
    """Uniform spin ``chi_t = omega`` of the sheared cylinder ``r = R``, ``psi = psi0``, ``gamma = 0``.

    ``r_t = R omega a3`` and ``d_t = omega c3`` (``psi_t = 0``, ``theta = 0``), ``a3 . c3 = cos psi0``, so
    the kinetic energy per unit area is ``(rhoA R^2 + 2 rhoI R cos psi0 + rhoJ) omega^2 / 2``; the
    lumped nodal weights sum to ``L``: ``T = pi L (rhoA R^2 + 2 rhoI R cos psi0 + rhoJ) omega^2``
    (with ``rhoI = 0`` for the centroidal base surface; ``zeta1 = -2h`` checks the ``rhoI`` term).
    Stored: ``F = [[1, 0, 0], [0, cos psi0, -zeta sin psi0/(1 + zeta)],
    [0, sin psi0, (R + zeta cos psi0)/(1 + zeta)]]`` from the table, ``V = 2 pi L What`` as above. Tolerance of ``T``: a sum of ``n`` nodal terms with ~20
    roundings each, including the round trip ``v -> p -> v`` through the nodal mass matrix, whose
    first-order effect on ``T`` is ``v . dp`` (well conditioned): ``(n + 20) EPS``.
    """
    base = mol_shell.TwistedCylinder()
    zeta1 = -2 * base.h if zeta1 == "outer" else None
    R, omega, n = 1.01, 5.0, 20
    scene = mol_shell.TwistedCylinder(gamma=0.0, R=R, omega=omega, psi0=psi0, zeta1=zeta1)
    ds = mol_shell.simulate(scene, n=n, times=[0, 1e-3], progress=False)
    lam, mu = ref.lame(scene.E, scene.nu)
    z1 = ref.zeta1_centroidal(scene.h) if zeta1 is None else zeta1
    rho_a, rho_i, rho_j = ref.inertias(scene.rho, scene.h, z1)
    if zeta1 is None:
        rho_i = 0.0  # brentq's root leaves ~1e-18 of round-off
    T = math.pi * scene.L * (rho_a * R**2 + 2 * rho_i * R * math.cos(psi0) + rho_j) * omega**2
    assert float(ds.kinetic_energy[0]) == pytest.approx(T, rel=(n + 20) * EPS)
    c, s = math.cos(psi0), math.sin(psi0)

    def F(zeta):
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -zeta * s / (1 + zeta)], [0.0, s, (R + zeta * c) / (1 + zeta)]])

    what, error, strain = _what(F, lam, mu, z1, scene.h)
    V = 2 * math.pi * scene.L * what
    rtol = _energy_rtol(n, what, error, strain)
    assert float(ds.stored_energy[0]) == pytest.approx(V, rel=rtol)
    assert float(ds.energy[0]) == pytest.approx(T + V, rel=rtol + (n + 20) * EPS)
    if zeta1 is not None:  # the rhoI term is resolved: it is ~1 % of T here
        assert abs(2 * rho_i * R * c) / (rho_a * R**2 + rho_j) > 1e3 * (n + 20) * EPS


def inside_c_call():
    """What a Ctrl-C raises when it arrives inside a C extension's call (CasADi's wrappers): CPython reports the
    call as having returned with the exception set, a SystemError caused by the KeyboardInterrupt (reproduced by
    signalling a process converting DMs to arrays)."""
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as interrupt:
        raise SystemError("<method 'get' of 'dict' objects> returned a result with an exception set") from interrupt


class _InterruptAfter:
    def __init__(self, calls, inside_c=False):
        self.calls, self.inside_c = calls, inside_c

    def update(self, _):
        self.calls -= 1
        if self.calls == 0:
            if self.inside_c:
                inside_c_call()
            raise KeyboardInterrupt


@pytest.mark.parametrize("inside_c", [False, True])
def test_ctrl_c_keeps_the_saved_times(inside_c):
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    times = np.arange(0, 0.011, 0.001)
    traj = Leapfrog(dt=1e-5, chunk=50).integrate(
        system, compiled, system.initial_state(scene), times, progress=_InterruptAfter(9, inside_c)
    )
    assert traj.status == "interrupted"
    assert len(traj.t) == 5  # 9 chunks of 50 steps of 1e-5 s: saved 0 .. 0.004 s
    assert traj.failure_time == pytest.approx(0.0045)
    assert np.all(np.isfinite(traj.y))


def test_overflow_inside_a_chunk_never_reaches_the_file(tmp_path):
    """A step 3x beyond the bound: the fastest mode grows ~5.8x per step, so by the end of the first
    1,000-step chunk an unchecked state has overflowed to inf/NaN. The run stops at the first step
    that leaves the model's limits (checked every step in C) or whose energy grew (checked once a
    chunk, then located by redoing the chunk step by step), and the file holds only finite states."""
    from mol_shell.discretization.compiled import CompiledRHS
    from mol_shell.results.dataset import build_dataset
    from mol_shell.runs.simulate import observe

    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    dt = 3.0 / np.abs(np.linalg.eigvals(np.array(system.jac(0, y0)))).max()
    times = dt * np.arange(0, 20001, 1000)
    unchecked = CompiledRHS(system.rhs_mapped)  # no limits: what a run without checks would have saved
    chunk_end = y0.copy(), y0 + dt * np.array(unchecked.evaluator()(y0))
    assert unchecked.leapfrog(*chunk_end, 1000, dt) == (1000, False)  # no limits to stop it
    assert not np.all(np.isfinite(chunk_end[1]))
    traj = Leapfrog(dt=dt, chunk=2000).integrate(system, compiled, y0, times)
    assert traj.status in ("unstable", "limit"), traj.message
    assert any(word in traj.message for word in ("non-finite", "energy balance", "<= 0", "pi/2")), traj.message
    assert traj.failure_time < 1000 * dt  # within the first chunk: at the first bad step, not at its end
    velocities, totals = observe(system, traj.y)
    ds = build_dataset(system, scene, traj, velocities, totals, {"integrator": "leapfrog", "dt": dt})
    mol_shell.write_netcdf(ds, tmp_path / "blown.nc")
    back = mol_shell.read_netcdf(tmp_path / "blown.nc")
    assert back.attrs["complete"] == 0 and back.attrs["status"] == traj.status
    for name in ("r", "chi", "energy"):
        assert np.all(np.isfinite(back[name].values))


def test_attribute_names_are_plain_and_rates_carry_their_units(short_run):
    """netCDF/CF names: letters, digits, underscores (``max_damping_rate_s-1`` was not); units in ``units_*``."""
    import re

    for key in short_run.attrs:
        assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", key), key
    assert short_run.attrs["max_damping_rate"] == 0.0 and short_run.attrs["units_max_damping_rate"] == "s-1"


def test_write_netcdf_creates_directories_and_names_an_unwritable_path(short_run, tmp_path):
    from mol_shell._core.errors import ParameterError

    mol_shell.write_netcdf(short_run, tmp_path / "a" / "b" / "run.nc")
    assert (tmp_path / "a" / "b" / "run.nc").exists()
    with pytest.raises(ParameterError, match="^path = .* is a directory"):
        mol_shell.write_netcdf(short_run, tmp_path / "a")
    with pytest.raises(ParameterError, match="^path = '' is empty"):
        mol_shell.write_netcdf(short_run, "")


def test_read_and_write_refuse_bad_arguments_by_name(tmp_path):
    """read_netcdf raised FileNotFoundError / OSError, write_netcdf(3, ...) an AttributeError."""
    from mol_shell._core.errors import ParameterError

    garbage = tmp_path / "garbage.nc"
    garbage.write_bytes(bytes(range(256)))
    unreadable = r"cannot be read; allowed: a netCDF file \(not a netCDF file\)"
    for path, words in ((tmp_path / "missing.nc", "does not exist"), (garbage, unreadable),
                        (tmp_path, "is a directory"), (None, "is not a file path")):
        with pytest.raises(ParameterError, match=f"^path = .* {words}"):
            mol_shell.read_netcdf(path)
    with pytest.raises(ParameterError, match="^ds = 3 is not an xarray.Dataset"):
        mol_shell.write_netcdf(3, tmp_path / "w.nc")
    assert not (tmp_path / "w.nc").exists()


def test_a_run_file_records_every_option_of_its_integrator(tmp_path):
    """Options beyond the tolerances (``iteration``, ``jac_every``, ``max_order``, ...) were not in the file, so a run
    could not be repeated from it; each declared option of the integrator is there now, read back from netCDF."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "cvode-adams", n=12, t_end=0.002, iteration="newton",
                            jac_every=7, max_order=4, stresses=False)
    ds.to_netcdf(tmp_path / "o.nc")
    attrs = xr.open_dataset(tmp_path / "o.nc").attrs
    missing = [name for name in declared(INTEGRATORS["cvode-adams"]) if name not in attrs
               and f"{name}_option" not in attrs]
    assert not missing, missing
    assert (attrs["iteration"], int(attrs["jac_every"]), int(attrs["max_order"])) == ("newton", 7, 4)
