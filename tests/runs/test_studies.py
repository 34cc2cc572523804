"""Every script in ``studies/`` runs in its ``--quick`` mode and shows what it is about.

Each study is loaded from its file and its ``main(["--quick", "--out", tmp])`` is called in this
process (the parameter studies run their cases serially in ``--quick``). The expected values
are derived here, independently of the package, from closed forms:

* the membrane radius of the uniformly twisted cylinder. At radius ``r`` (reference radius 1,
  ``z_s = 1``, ``chi_s = gamma``, ``theta = psi = 0``) the Green strains are
  ``E_ss = r^2 gamma^2 / 2``, ``E_pp = (r^2 - 1) / 2``, ``E_sp = r^2 gamma / 2``, and the inextensible
  director leaves no other component; ``W = lambda/2 (tr E)^2 + mu tr(E^2)`` is stationary in
  ``A = r^2`` at ``A = (lambda (1 + gamma^2) + 2 mu) / ((lambda + 2 mu) (1 + gamma^2)^2)``, exact in
  ``gamma``. The shell's strains vary through the thickness by ``O(zeta)`` about a centroidal base
  surface, so the package's ``1 - R`` differs from the membrane's by a relative ``O(h^2)``
  (``h^2 = 3.9e-5`` at the paper's ``h``); we allow ``3 h^2``. The plane-stress law is the same
  with ``lambda* = 2 lambda mu / (lambda + 2 mu)``.
* leap-frog's second order (error ratio 4 per halving of ``dt``, 16 per quartering), spectra of
  single modes (the grid-scale axial wave, the transverse-shear mode and its Kelvin-Voigt
  damping), symmetry (uniform or axisymmetric data stay so) and round-off bounds.

Tolerances are explained where they are used; nothing is copied from a run of the package.
"""

import inspect
import math
from pathlib import Path

import numpy as np
import pytest
import reference_ring as ref
from study_scripts import STUDIES, load_script

import mol_shell

EPS = np.finfo(float).eps
PAPER = mol_shell.TwistedCylinder()
PNG = b"\x89PNG\r\n\x1a\n"


#: study name -> the test below that runs it (filled by :func:`covers` when this module is imported)
COVERED = {}


def covers(name):
    """Declare that the decorated test runs ``studies/<name>.py`` (:func:`test_every_study_has_a_quick_mode`)."""
    def declare(test):
        assert name not in COVERED, (name, COVERED[name])
        COVERED[name] = test.__name__
        return test
    return declare


def load_study(name):
    return load_script(name, "study")


def run_study(name, out, *extra):
    """``studies/<name>.py``'s ``main`` with ``--quick --out out`` (plus ``extra``), in this process."""
    assert name in COVERED, f"declare the test that runs {name} with @covers({name!r})"
    return load_study(name).main(["--quick", "--out", str(out), *extra])


def lame(nu, material="svk", E=PAPER.E):
    lam, mu = ref.lame(E, nu)
    if material == "svk-plane-stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    return lam, mu


def membrane_radius(gamma, nu=PAPER.nu, material="svk"):
    """Radius at which the uniformly twisted membrane is in radial equilibrium (module docstring)."""
    lam, mu = lame(nu, material)
    g2 = gamma**2
    return math.sqrt((lam * (1 + g2) + 2 * mu) / ((lam + 2 * mu) * (1 + g2) ** 2))


def assert_radius(R, gamma, nu=PAPER.nu, material="svk", h=PAPER.h):
    """``1 - R`` against the membrane's, within the ``O(h^2)`` thickness correction (we allow ``3 h^2``)."""
    shift = 1 - membrane_radius(gamma, nu, material)
    assert abs((1 - R) / shift - 1) <= 3 * h**2, (R, gamma, nu, material, h)


def assert_written(*paths):
    for path in paths:
        path = Path(path)
        assert path.stat().st_size > 0, path
        if path.suffix == ".png":
            assert path.read_bytes()[:8] == PNG, path


@pytest.mark.slow
@covers("ring_vs_pde")
def test_ring_vs_pde_error_falls_at_order_two_and_the_motion_stays_uniform(tmp_path):
    """Spinning ring (section 5), N = 10, dt = 8, 4, 2 us to 0.04 s against the ring ODE (DOP853, rtol 1e-12).

    Leap-frog's error is ``C dt^2 (1 + O((w dt)^2))``; the fastest motion of the ring is the
    shear oscillation of psi, ``w ~ sqrt(3 mu / rho) / h ~ 5e3`` rad/s, so ``(w dt)^2 <= 1.6e-3``
    at 8 us; the ODE's own error (~1e-12 m) is ~1e-3 of the smallest PDE error (~1e-9 m). So
    ``log2`` of each error ratio is 2 to a few 1e-3: we allow 0.02. Uniform data stay uniform
    by symmetry (translations in s), numerically up to round-off that at worst grows linearly in
    the number of steps: we allow ``100 EPS`` per step.
    """
    out = run_study("ring_vs_pde", tmp_path)
    err = out.discrepancy_r.values
    units = {k: out[f"discrepancy_{k}"].attrs["units"] for k in ("r", "chi", "psi", "r_t", "chi_t", "psi_t")}
    assert units == {"r": "m", "chi": "rad", "psi": "rad", "r_t": "m s-1", "chi_t": "rad s-1", "psi_t": "rad s-1"}
    assert len(err) == 3 and np.all(err > 0)
    np.testing.assert_allclose(np.log2(err[:-1] / err[1:]), 2.0, atol=0.02)
    steps = float(out.time[-1]) / out.dt.values
    assert np.all(out.nonuniformity.values <= 100 * EPS * steps), out.nonuniformity.values
    assert_written(tmp_path / "ring_vs_pde.nc", tmp_path / "ring_vs_pde.png")


@pytest.mark.slow
@covers("paper_figures")
def test_paper_figures_energy_error_is_second_order_and_files_are_written(tmp_path):
    """The paper's run (N = 40) at the paper's dt = 1e-6 s and at 4e-6 s; the figures and netCDF.

    Leap-frog's energy error is ``C dt^2 (1 + O((w_max dt)^2))`` without drift; at dt = 4e-6 s,
    ``w_max dt = 5.3e3 * 4e-6 = 0.021``, so the ratio of the two runs' largest relative energy
    changes is 16 to ~0.1 %: we allow 5 %. The paper's run conserves energy to better than 1e-9
    (the README's claim).
    """
    fine = run_study("paper_figures", tmp_path / "dt1")
    coarse = run_study("paper_figures", tmp_path / "dt4", "--dt", "4e-6")
    for result in (fine, coarse):
        assert result["ds"].attrs["status"] == "complete"
        assert list(result["summaries"]) == [40]  # --quick: no finer grid
    ratio = coarse["energy_drift"] / fine["energy_drift"]
    assert abs(ratio / 16 - 1) <= 0.05, (coarse["energy_drift"], fine["energy_drift"])
    assert 0 < fine["energy_drift"] <= 1e-9
    names = ["paper_figures.nc"] + [f"fig{k}.png" for k in range(4, 9)] + ["paper_psi.png"]
    assert [Path(p).name for p in fine["files"]] == names
    assert_written(*fine["files"])
    back = mol_shell.read_netcdf(fine["files"][0])
    np.testing.assert_array_equal(back.energy.values, fine["ds"].energy.values)
    for t in (0.0, 0.02, 0.07, 0.106, 0.143):  # the paper's times are saved exactly
        assert t in back.time.values


@pytest.mark.slow
@covers("twist_amplitude")
def test_twist_amplitude_follows_the_small_twist_law(tmp_path):
    """gamma = 0.025, 0.05, 0.1 rad/m on N = 40.

    ``R(gamma)`` is the membrane radius (module docstring). ``max |r - R|`` is even in gamma
    (``chi -> -chi`` is a symmetry), so it is ``a gamma^2 (1 + b gamma^2 + ...)``: the log-log
    slope between successive gammas is 2 plus a departure ``~ 2 b gamma^2`` that shrinks 4x when
    gamma halves. We assert both slopes within 0.1 of 2 (strains are ~gamma <= 0.1 here) and the
    smaller pair's departure at most half the larger pair's (4x expected; 2x allowed).
    """
    out, slopes = run_study("twist_amplitude", tmp_path)
    x = out.sel(grid=40)
    gammas = x.gamma.values
    np.testing.assert_allclose(gammas, [0.025, 0.05, 0.1])
    assert (x.status.values == "complete").all()
    for gamma, R in zip(gammas, x.R.values):
        assert_radius(R, gamma)
    dr = x.dr_max.values
    local = np.diff(np.log(dr)) / np.diff(np.log(gammas))
    assert np.all(np.abs(local - 2) <= 0.1), local
    assert abs(local[0] - 2) <= 0.5 * abs(local[1] - 2), local
    assert abs(slopes[40, "dr_max"] - 2) <= 0.1
    assert_written(*(tmp_path / f for f in ("twist_amplitude.nc", "twist_amplitude_n40.nc", "twist_amplitude.png")))


@pytest.mark.slow
@covers("sweeps_nu_h")
def test_sweeps_radius_change_falls_with_nu_and_the_step_bound_scales_with_h(tmp_path):
    """nu = 0.3, 0.45, 0.499 and h = 1/4, 1/2, 1 x 2 pi 1e-3 m, N = 40.

    nu: ``R`` is the membrane radius; its shift ``1 - R ~ gamma^2 (lambda + 4 mu) / (2 (lambda + 2 mu))``
    falls as ``lambda / mu = 2 nu / (1 - 2 nu)`` grows, and the motion released at the free ends
    moves r by an amount of that order: ``max |r - R|`` falls with nu (the README's trend).
    h: the fastest mode is the transverse-shear mode, ``w^2 = 3 mu / (rho h^2)`` times a factor of
    the prestressed, discrete state that depends on h only through ``(h / ds)^2 <= 4e-3``, so the
    leap-frog bound ``1 / w`` is proportional to h: we allow 1 % on ``bound / h``.
    """
    summaries = run_study("sweeps_nu_h", tmp_path)
    nu = summaries["nu"].sel(grid=40)
    assert (nu.status.values == "complete").all()
    for value, R in zip(nu.nu.values, nu.R.values):
        assert_radius(R, PAPER.gamma, nu=value)
    assert np.all(np.diff(nu.dr_max.values) < 0), nu.dr_max.values
    h = summaries["h"].sel(grid=40)
    assert (h.status.values == "complete").all()
    for value, R in zip(h.h.values, h.R.values):
        assert_radius(R, PAPER.gamma, h=value)
    per_h = h.leapfrog_dt_bound_s.values / h.h.values
    np.testing.assert_allclose(per_h / per_h[-1], 1.0, atol=0.01)
    assert_written(tmp_path / "sweeps_nu_h.nc", tmp_path / "sweep_nu_n40.nc", tmp_path / "sweep_h_n40.nc",
                   tmp_path / "sweeps_nu_h.png")


@pytest.mark.slow
@covers("plane_stress")
def test_plane_stress_radius_and_locking_against_closed_forms(tmp_path):
    """nu = 0.499, 0.4999 with the paper's law (svk) and with plane stress, N = 40.

    * ``R`` of each law is its membrane radius (``lambda*`` for plane stress).
    * Locking of svk: the fastest mode is the grid-scale axial wave. With ``u = dz`` and
      ``v = R dchi`` (equal lumped inertia ``rho A``) the axial strain of the twisted state varies
      as ``du_s + gamma R dv_s``, so the shortest wave on the ``n - 2`` free nodes has
      ``w = (2 / ds) sin((n - 2) pi / (2 (n - 1))) sqrt((lambda + 2 mu)(1 + gamma^2 R^2) / rho)``;
      neglected: terms of relative size ``mu / (lambda + 2 mu)`` (2e-4 at 0.4999, 2e-3 at 0.499)
      and couplings to the shear mode. We allow 0.5 % at nu = 0.4999 and 1 % at 0.499.
    * Plane stress does not lock: its fastest mode stays the shear mode, ``w ~ sqrt(mu)``, so the
      two nu differ by ``sqrt(mu(0.4999) / mu(0.499))`` (we allow 0.5 %), far below svk's.
    """
    out = run_study("plane_stress", tmp_path)
    n, ds = 40, PAPER.L / 39
    for material in ("svk", "svk-plane-stress"):
        for nu in (0.499, 0.4999):
            assert_radius(float(out.R.sel(material=material, nu=nu)), PAPER.gamma, nu=nu, material=material)
    for nu, tol in ((0.4999, 0.005), (0.499, 0.01)):
        lam, mu = lame(nu)
        R = float(out.R.sel(material="svk", nu=nu))
        wave = (2 / ds) * math.sin((n - 2) * math.pi / (2 * (n - 1))) * math.sqrt(
            (lam + 2 * mu) * (1 + PAPER.gamma**2 * R**2) / PAPER.rho)
        assert abs(float(out.omega_max.sel(material="svk", nu=nu)) / wave - 1) <= tol, (nu, wave)
    ps = out.omega_max.sel(material="svk-plane-stress")
    expected = math.sqrt(lame(0.4999)[1] / lame(0.499)[1])
    assert abs(float(ps.sel(nu=0.4999) / ps.sel(nu=0.499)) / expected - 1) <= 0.005
    assert float(ps.sel(nu=0.4999)) < float(out.omega_max.sel(material="svk", nu=0.4999)) / 3
    assert_written(tmp_path / "plane_stress.nc", tmp_path / "plane_stress.png")


@pytest.mark.slow
@covers("unshearable_vs_free")
def test_unshearable_shell_keeps_its_constraints_while_the_free_shell_twists(tmp_path):
    """N = 21 to 0.02 s; spins 0, 10, 20 rad/s.

    * The constraints are linear and IDA's Newton iteration uses their exact rows, so the
      constrained ``chi_s`` is round-off: differences of ``chi`` (``|chi| <= omega t``) over ``ds``
      carry ``~EPS max|chi| / ds``; we allow 100x that. psi is held by ``psi_tt = 0`` from 0.
    * The constraint forces do no work (``G v = 0``): the energy is conserved to the integrator's
      accuracy (IDA, rtol 1e-8); we allow 100 rtol.
    * The free shell from the same state twists (sections spin at different rates as they
      breathe by different amounts, (4.7)): its ``chi_s`` grows far above that round-off, and
      grows with the spin; without spin both motions are axisymmetric by symmetry
      (``chi -> -chi``, ``psi -> -psi``), so the free shell stays untwisted and the multipliers vanish.
    """
    res = run_study("unshearable_vs_free", tmp_path)
    con, free, spins, free_spins = res["constrained"], res["free"], res["spins"], res["free_spins"]
    grid = float(con.s[1] - con.s[0])
    roundoff = 100 * EPS * float(abs(con.chi).max()) / grid
    assert con.attrs["status"] == "complete" and free.attrs["status"] == "complete"
    assert float(con.chi_s_max.max()) <= roundoff
    assert float(con.psi_max.max()) <= 100 * EPS
    e = con.energy.values
    assert np.abs(e - e[0]).max() / e[0] <= 100 * con.attrs["rtol"]
    assert float(free.chi_s_max[-1]) > 1e6 * roundoff
    assert float(free.chi_s_max[-1]) > float(free.chi_s_max[len(free.time) // 2])  # still growing
    assert list(spins.omega.values) == [0.0, 10.0, 20.0] and (spins.status.values == "complete").all()
    twist = [float(free_spins[w].chi_s_max.max()) for w in (0.0, 10.0, 20.0)]
    assert twist[0] <= 100 * EPS and 0 < twist[1] < twist[2], twist
    lam = [float(abs(spins.lambda_chi.sel(omega=w)).max()) for w in (0.0, 10.0, 20.0)]
    assert 0 < lam[1] < lam[2] and lam[0] <= 1e3 * EPS * lam[2], lam  # zero up to round-off of the spinning scale
    assert_written(tmp_path / "unshearable_constrained.nc", tmp_path / "unshearable_free.nc",
                   tmp_path / "unshearable_omega.nc", tmp_path / "unshearable.png")


@pytest.mark.slow
@covers("work_precision")
def test_work_precision_leapfrog_is_second_order_and_adams_follows_its_tolerance(tmp_path):
    """Leap-frog at dt = 1e-5, 5e-6 s and CVODE-Adams at rtol = 1e-5, 1e-7, paper scene to 0.02 s.

    Leap-frog: error ratio ``4 (1 + O((w_max dt)^2))``, ``w_max dt = 0.053`` at 1e-5 s; we allow 5 %.
    Adams: a tolerance-proportional method; 100x tighter rtol must cut the error by at least 10x
    (exponent >= 0.5). The reference (CVODE-Adams against IDA at rtol 1e-12) must be converged
    below the errors it measures: their difference is at most 5 % of the smallest error (the
    leap-frog errors, used for the ratio, are ~100x larger still).
    """
    ds = run_study("work_precision", tmp_path)
    assert (ds.status.values[ds.status.values != ""] == "complete").all()
    lf = ds.sel(integrator="leapfrog")
    np.testing.assert_allclose(lf.dt.values[:2], [1e-5, 5e-6])
    assert abs(lf.error.values[0] / lf.error.values[1] / 4 - 1) <= 0.05, lf.error.values
    ad = ds.sel(integrator="cvode-adams")
    np.testing.assert_allclose(ad.rtol.values[:2], [1e-5, 1e-7])
    assert ad.error.values[0] / ad.error.values[1] >= 10, ad.error.values
    assert ds.attrs["reference_error"] <= 0.05 * np.nanmin(ds.error.values)
    assert_written(tmp_path / "work_precision.nc", tmp_path / "work_precision.png", tmp_path / "work_precision.md")


@pytest.mark.slow
@covers("stability_report")
def test_stability_report_bound_is_sharp_and_viscosity_damps_the_shear_mode(tmp_path):
    """The paper scene and viscous eta_mu = 100 Pa s (eta_lambda = 200 Pa s), N = 40, 10 ms.

    * Elastic: linear leap-frog is stable iff ``dt max|eig| < 1``; just above, the parasitic mode
      grows by ``exp(sqrt(2 eps))`` per step and is seen within 3,000 steps. Bisection in
      ``[bound/2, 2 bound]`` with 8 geometric halvings resolves ``4^(1/256) - 1 = 0.54 %``; the
      spectrum drifts as the twist unloads by O(gamma^2) ~ 1 %: stable / bound in [0.95, 1.01].
    * Viscous: the fastest mode is the transverse-shear mode, which strains only through ``mu``;
      Kelvin-Voigt adds ``eta_mu / mu`` times its stiffness as damping, so (underdamped) its
      eigenvalues have ``|lambda| = w`` and ``-Re lambda = eta_mu w^2 / (2 mu)`` (we allow 2 % for
      the ``lambda`` share of the mode's strain). Over 10 ms leap-frog's parasitic root would grow
      it by ``exp(41.7) > 1e6``: refused; CVODE-BDF and IDA finish.
    """
    ds = run_study("stability_report", tmp_path)
    paper = ds.sel(case="paper")
    ratio = float(paper.leapfrog_dt_stable / paper.leapfrog_dt_bound)
    assert 0.95 <= ratio <= 1.01, ratio
    for key in ("leapfrog_status", "cvode_bdf_status", "ida_status"):
        assert str(paper[key].values) == "complete"
    viscous = ds.sel(case="viscous eta_mu=100")
    mu = lame(PAPER.nu)[1]
    w = float(viscous.omega_max)
    assert abs(float(viscous.damping_max) / (100.0 * w**2 / (2 * mu)) - 1) <= 0.02
    assert float(viscous.damping_max) * float(viscous.t_end) > math.log(1e6)
    assert str(viscous.leapfrog_status.values).startswith("refused")
    assert str(viscous.cvode_bdf_status.values) == "complete" and str(viscous.ida_status.values) == "complete"
    assert_written(tmp_path / "stability.nc", tmp_path / "stability.md", tmp_path / "stability.png")


@pytest.mark.slow
@covers("implicit_scaling")
def test_implicit_scaling_viscous_steps_do_not_follow_the_grid(tmp_path):
    """Viscous (eta_mu = 1000, eta_lambda = 2000 Pa s, 10 ms) and elastic (2 ms) on n = 40, 80, CVODE-BDF.

    * The explicit bound of the viscous shell is the fast root of the overdamped shear mode:
      with ``w0`` its elastic frequency (the elastic top at n = 40) and ``c = eta_mu w0^2 / mu``,
      ``|lambda| = (c / 2)(1 + sqrt(1 - 4 w0^2 / c^2))`` (we allow 1 %, as above for the ``lambda``
      share); a through-thickness mode, so the same on both grids (1 %), not ~ ds or ds^2.
    * The shell is stiff: BDF takes fewer than a third of the steps an explicit method needs
      (``t_end / bound``), and refining the grid does not double its steps (a step set by a grid
      mode would halve): we allow a growth of 1.5x from n = 40 to 80.
    """
    script = load_study("implicit_scaling")
    script.TIMED_S = 0.0  # timings are not asserted here: one timed run a point, not repeats adding up to 50 ms
    ds = script.main(["--quick", "--repeats", "1", "--out", str(tmp_path)])
    np.testing.assert_array_equal(ds.n.values, [40, 80])
    v = ds.sel(case="viscous", integrator="cvode-bdf")
    w0 = 1.0 / float(ds.dt_bound_s.sel(case="elastic", integrator="cvode-bdf", n=40))
    c = 1000.0 * w0**2 / lame(PAPER.nu)[1]
    fast = 0.5 * c * (1 + math.sqrt(1 - 4 * w0**2 / c**2))
    bound = v.dt_bound_s.values
    assert abs(bound[0] * fast - 1) <= 0.01, bound[0] * fast
    assert abs(bound[1] / bound[0] - 1) <= 0.01
    steps = v.n_steps.values
    t_end = ds.attrs["t_end_viscous"]
    assert np.all(steps < t_end / bound / 3), (steps, t_end / bound)
    assert steps[1] < 1.5 * steps[0], steps
    assert np.all(np.isfinite(ds.wall_time_s.sel(case="elastic").values))
    assert_written(*(tmp_path / f"implicit_scaling.{ext}" for ext in ("nc", "png", "md")))


@covers("ellipticity")
def test_ellipticity_loss_is_the_same_on_every_grid_and_absent_in_plane_stress(tmp_path):
    out = run_study("ellipticity", tmp_path)
    svk = out.where(out.material == "svk", drop=True)
    assert np.all(svk.lost.values == svk.lost.values[0]) and 0.006 < svk.lost.values[0] < 0.008  # 1 % compression
    assert np.all(svk.stretch_min.values < out.attrs["critical_stretch"])
    plane = out.where(out.material == "svk-plane-stress", drop=True)
    assert np.all(np.isnan(plane.lost.values)) and np.all(plane.margin_min.values > 0)
    assert np.all(plane.stretch_min.values < 0.96)  # it did go through the same compression
    assert_written(tmp_path / "ellipticity.nc", tmp_path / "ellipticity.png")


@pytest.mark.parametrize("name", sorted(p.stem for p in STUDIES.glob("*.py")))
def test_every_study_has_a_quick_mode(name, capsys):
    """A new script in studies/ must have ``main(argv=None)`` taking --quick and --out (its ``--help`` lists them),
    and a test above that runs it (declared with ``@covers``)."""
    main = load_study(name).main
    assert inspect.signature(main).parameters["argv"].default is None
    with pytest.raises(SystemExit) as done:
        main(["--help"])
    assert done.value.code == 0
    usage = capsys.readouterr().out
    assert "--quick" in usage and "--out" in usage, usage
    assert name in COVERED, f"studies/{name}.py has no test: add one above, declared with @covers({name!r})"
