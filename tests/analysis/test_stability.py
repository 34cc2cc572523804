"""Stability: the leap-frog bound predicted from the Jacobian's spectrum matches bisection."""

import dataclasses
import math

import numpy as np
import pytest
from wrapped_interrupts import WRAPPED

import mol_shell
from mol_shell.analysis.stability import Case, default_cases, markdown_table, report, stable_leapfrog_step
from mol_shell.integrators import Leapfrog
from mol_shell.model.equilibrium import spectrum_bounds
from mol_shell.model.material import lame
from mol_shell.runs.simulate import build, resolve


@pytest.mark.parametrize("changes", [{}, {"nu": 0.499}, {"h": 1e-3}])
def test_bisection_finds_the_eigenvalue_bound(changes):
    """Leap-frog on y' = i w y is stable iff |w dt| <= 1: the largest stable step of the
    nonlinear run must sit at 1/max|eig J(y0)| (bisection resolves it to (2)^(1/2^8) ~ 0.3 %;
    the state moves little in 3000 steps, so the spectrum hardly changes)."""
    scene = resolve(dataclasses.replace(mol_shell.TwistedCylinder(), **changes))
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    omega_max, damping = spectrum_bounds(system.jac, y0, system.viscous)
    assert damping == 0.0
    dt, horizon = stable_leapfrog_step(system, compiled, y0, 1.0 / omega_max)
    assert horizon == pytest.approx(1500 / omega_max)  # 3000 steps of bound/2: no damping, no fold
    assert dt == pytest.approx(1.0 / omega_max, rel=0.01)


def test_locking_raises_the_frequency_and_plane_stress_removes_it():
    """nu -> 0.5 with the inextensible director: the axial/hoop stiffness lambda + 2 mu grows
    without bound, and the top of the spectrum is the grid's shortest axial wave,
    (2/ds) sqrt((lambda + 2 mu)/rho) (lumped mass, two-point difference). Condensed (plane
    stress) the membrane stiffness E/(1 - nu^2) stays small, so the top stays the transverse
    shear mode of the director, whose frequency scales as sqrt(mu)."""
    n, tops = 20, {}
    for material in ("svk", "svk-plane-stress"):
        for nu in (0.3, 0.4999):
            scene = resolve(mol_shell.TwistedCylinder(nu=nu, material=material))
            system, _ = build(scene, n)
            tops[material, nu] = spectrum_bounds(system.jac, system.initial_state(scene), False)[0]
    scene = mol_shell.TwistedCylinder(nu=0.4999)
    lam, mu = lame(scene.E, scene.nu)
    axial = 2 / (scene.L / (n - 1)) * np.sqrt((lam + 2 * mu) / scene.rho)
    assert tops["svk", 0.4999] == pytest.approx(axial, rel=0.01)
    mu_ratio = lame(1.0, 0.3)[1] / lame(1.0, 0.4999)[1]
    assert tops["svk-plane-stress", 0.3] / tops["svk-plane-stress", 0.4999] == pytest.approx(np.sqrt(mu_ratio), rel=0.01)


def test_report_table_has_a_row_per_case():
    """The markdown table: a header, its rule and one row per case, each row's cells the report's values."""
    ds = report([Case("paper", mol_shell.TwistedCylinder(), n=12, t_end=0.002)], integrators=(), bisect=False)
    assert str(ds["leapfrog_status"].values[0]) == "complete"
    assert np.isfinite(ds["leapfrog_dt_bound"].values[0])
    header, rule, *rows = [[cell.strip() for cell in line.split("|")[1:-1]] for line in markdown_table(ds).split("\n")]
    assert set(rule) == {"---"} and len(rule) == len(header)
    assert len(rows) == ds.sizes["case"] and all(len(row) == len(header) for row in rows)
    row = dict(zip(header, rows[0]))
    assert row["case"] == "paper" and row["n"] == "12" and row["leapfrog status"] == "complete"
    assert float(row["LF dt bound [s]"]) == pytest.approx(float(ds["leapfrog_dt_bound"].values[0]), rel=5e-3)


@pytest.mark.filterwarnings("ignore:run incomplete:RuntimeWarning")
def test_bisection_judges_the_step_not_a_fold_of_the_shell():
    """At gamma = 3 rad/m the twisted shell itself collapses to a fold (delta -> 0) at ~0.13 s, before
    3000 steps of bound/2 (0.22 s), and leap-frog ends there at any step (N = 20: the energy check trips at
    0.1546 s at bound/10 and bound/30, delta reaches 0 at 0.185 s at bound/100; CVODE-BDF finds the
    root of delta at 0.193 s with rtol 1e-8 and 1e-10: the collapse is sensitive, its time is not the point).
    The bisection cuts its horizon to 0.9 of where the run at bound/10 ends and finds the eigenvalue bound
    as on the paper scene."""
    scene = resolve(dataclasses.replace(mol_shell.TwistedCylinder(), gamma=3.0, law_limit=False))  # to the fold
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    omega_max, _ = spectrum_bounds(system.jac, y0, system.viscous)
    dt, horizon = stable_leapfrog_step(system, compiled, y0, 1.0 / omega_max)
    assert horizon < 0.95 * 1500 / omega_max  # cut
    assert 0.95 <= dt * omega_max <= 1.01
    # saved every tenth of the horizon: with one saved time CVODE's steps grow and the fold (whose time is
    # sensitive to round-off) landed at 0.212 s in 0.2.0 and just after the horizon (0.2155 s) since
    ds = mol_shell.simulate(scene, "cvode-bdf", n=20, times=np.linspace(0.0, 1500 / omega_max, 11), rtol=1e-8,
                            atol=1e-10, progress=False)
    assert ds.attrs["status"] == "limit" and "delta" in ds.attrs["message"]
    assert ds.attrs["failure_time"] < 1500 / omega_max  # the shell folds within the uncut horizon


def test_a_limit_reached_by_an_unstable_step_is_not_a_stable_step():
    """psi0 = 1.55 rad (delta0 = 0.02 m, N = 20): the shell folds at s = 0.32 m after 1.71 ms (runs at
    bound/10 and bound/50 agree to the step). At 2 bound the first step already crosses delta = 0 at the
    other end (s = 3.7 m), before the energy check can see any growth: a run that ends at a limit is
    no evidence of a stable step. Within the horizon before the fold (0.9 x 1.71 ms, ~17 steps of
    2 bound) no step can be judged: the bisection says so (nan) instead of reporting 2 bound."""
    scene = resolve(dataclasses.replace(mol_shell.TwistedCylinder(), psi0=1.55))
    system, compiled = build(scene, 20)
    y0 = system.initial_state(scene)
    omega_max, _ = spectrum_bounds(system.jac, y0, system.viscous)
    bound = 1.0 / omega_max
    big = Leapfrog(dt=2 * bound).integrate(system, compiled, y0, np.array([0.0, 10 * 2 * bound]))
    fine = Leapfrog(dt=bound / 50).integrate(system, compiled, y0, np.array([0.0, 2000 * bound / 50]))  # 40 bounds: ~6 ms
    assert big.status == "limit" and big.failure_time < 0.2 * fine.failure_time
    assert fine.status == "limit" and "s = 0.315789" in fine.message and "s = 0.315789" not in big.message
    dt, horizon = stable_leapfrog_step(system, compiled, y0, bound)
    assert math.isnan(dt)
    assert horizon == pytest.approx(0.9 * fine.failure_time, rel=0.02) and horizon < 100 * 2 * bound


def test_a_loaded_shell_starting_at_rest_reports_its_energy_work_balance_and_every_variable_is_described():
    """A pressure ramped from 0 on a shell at rest: ``E(0) = 0``, and the energy error relative to it read 1e25 to
    1e29 for every integrator. It is the run's energy-work balance error (relative to the energy exchanged), whose
    size is the integrator's accuracy; each variable of the report carries units and a long name."""
    scene = mol_shell.Sphere(pressure=1000.0, pressure_history="ramp 0.001", nu=0.3, material="svk-plane-stress")
    ds = report([Case("ramped", scene, n=12, t_end=0.002)], integrators=("cvode-bdf",), bisect=False)
    for name in ("leapfrog", "cvode_bdf"):
        assert str(ds[f"{name}_status"].values[0]) == "complete"
        assert 0 <= float(ds[f"{name}_energy_error"].values[0]) < 1e-3
    assert all("long_name" in ds[v].attrs for v in ds.variables)
    assert ds["leapfrog_wall_s"].attrs["units"] == "s" and "status" not in ds["cvode_bdf_status"].attrs.get("units", "")


def test_a_run_refused_or_stopped_at_its_start_says_why_and_shows_no_numbers():
    """Leap-frog refused on a stiff viscous case showed a wall time (0.06 s) and ``refused: ...`` cut at 60
    characters; a twist whose start is past SVK's turning point showed ``limit``, 0 steps, an energy error of 0 and
    failed steps -1, with no reason anywhere. Now: ``refused`` or ``limit`` with the run's own one line beside it
    (in the file and under the table), and NaN where nothing was measured."""
    base = mol_shell.TwistedCylinder()
    ds = report([Case("viscous", dataclasses.replace(base, eta_mu=100.0, eta_lambda=200.0)),
                 Case("twist", dataclasses.replace(base, gamma=1.5))], bisect=False)
    assert str(ds.leapfrog_status.values[0]) == "refused" and "integrator = 'leapfrog'" in str(ds.leapfrog_message[0])
    assert np.isnan(ds.leapfrog_wall_s.values[0]) and np.isnan(ds.leapfrog_steps.values[0])
    for name in ("leapfrog", "cvode_bdf", "ida"):
        assert str(ds[f"{name}_status"].values[1]) == "limit"
        assert "at t = 0 s" in str(ds[f"{name}_message"].values[1])
        assert np.isnan(ds[f"{name}_energy_error"].values[1])
    assert np.isnan(ds.cvode_bdf_failures.values[1])  # it was -1
    assert str(ds.cvode_bdf_message.values[0]) == ""  # a complete run says nothing
    table = markdown_table(ds, spectrum=False)
    assert "Runs that did not complete:" in table and "- twist, cvode-bdf: an in-plane stretch" in table


@pytest.mark.filterwarnings("ignore:run incomplete:RuntimeWarning")
def test_a_case_stopped_at_its_start_by_a_law_limit_is_not_called_a_fold():
    """gamma = 1.5 rad/m: the static radius (0.547 m, docs/stability.md) puts the hoop stretch below 1/sqrt(3) = 0.577,
    where SVK's compressive stress turns back, so every run stops at t = 0 and the bisection's horizon is 0. Its
    stable-step cell said "n/a: folds within 100 steps"; it says the runs' own reason now, a limit of the law."""
    ds = report([Case("twist", dataclasses.replace(mol_shell.TwistedCylinder(), gamma=1.5), n=12, t_end=0.002)],
                integrators=())
    assert float(ds.bisection_horizon_s.values[0]) == 0.0 and np.isnan(ds.leapfrog_dt_stable.values[0])
    assert str(ds.leapfrog_status.values[0]) == "limit" and "(a limit of the law) at t = 0 s" in str(
        ds.leapfrog_message.values[0])
    header, _, row = [[cell.strip() for cell in line.split("|")[1:-1]] for line in markdown_table(ds).split("\n")[:3]]
    assert dict(zip(header, row))["LF dt stable (bisection) [s]"] == "n/a: stopped at t = 0 by a limit of the law"
    assert "folds" not in markdown_table(ds)


@pytest.mark.parametrize("kind", ["keyboard", "ctypes", "casadi"])  # ctypes, casadi: the interrupt in a C call
def test_ctrl_c_keeps_the_cases_finished(monkeypatch, tmp_path, capsys, kind):
    """Ctrl-C during `mol-shell stability` exited 130 with nothing written, though cases had printed "done". The
    cases finished are kept (file, table, figure), the message names the case interrupted, exit 130 (also when a C
    call reported the interrupt as its own error: wrapped_interrupts)."""
    from mol_shell.analysis import stability
    from mol_shell.cli.main import main

    real = stability.run_case
    calls = []

    def interrupted_at_the_second(case, **kwargs):
        calls.append(case.label)
        if len(calls) == 2:
            raise WRAPPED[kind]() if kind in WRAPPED else KeyboardInterrupt
        return real(case, **kwargs)

    monkeypatch.setattr(stability, "run_case", interrupted_at_the_second)
    cases = [Case("paper", mol_shell.TwistedCylinder(), n=12, t_end=0.002),
             Case("nu=0.3", mol_shell.TwistedCylinder(nu=0.3), n=12, t_end=0.002),
             Case("h=0.01", mol_shell.TwistedCylinder(h=0.01), n=12, t_end=0.002)]
    monkeypatch.setattr(stability, "default_cases", lambda scene, quick=False: cases)
    monkeypatch.setattr("mol_shell.cli.analysis.default_cases", lambda scene, quick=False: cases)
    out = tmp_path / "st.nc"
    assert main(["stability", "twisted-cylinder", "--no-bisect", "-o", str(out)]) == 130
    err = capsys.readouterr().err
    assert "stability report stopped: interrupted by the user at case 'nu=0.3': the 1 case before it measured, " \
           "2 not run" in err, err
    ds = mol_shell.read_netcdf(out)
    assert list(ds.case.values) == ["paper"] and ds.attrs["status"] == "interrupted"
    assert (tmp_path / "st.md").exists() and (tmp_path / "st.png").exists()


def _by_label(cases, start):
    """The one case whose label starts with ``start``."""
    (case,) = [case for case in cases if case.label.startswith(start)]
    return case


def test_a_thickness_case_scales_a_graded_wall_and_its_spectrum_follows():
    """A graded wall (h_profile = 0.005 (1 + 0.5 s), s in [0, 4] m) in the h cases kept the file's profile: the rows
    h=0.01, 0.001 and 0.0001 were copies of the base row. Now each scales h(s) by h_case / h (0.2 and 0.02 here), and
    the top of the spectrum, the transverse-shear mode of a thin wall (~ 1/h), grows 10-fold from one to the other."""
    base = mol_shell.TwistedCylinder(h=0.005, h_profile="0.005 * (1 + 0.5 * s)", material="svk-plane-stress", nu=0.3)
    cases = default_cases(base, quick=True)
    thin, thinner = _by_label(cases, "h=0.001 "), _by_label(cases, "h=0.0001 ")
    assert thin.label == "h=0.001 (h_profile x 0.2)" and thinner.label == "h=0.0001 (h_profile x 0.02)"
    ds = report([dataclasses.replace(case, n=12, t_end=2e-4) for case in (thin, thinner)], integrators=(), bisect=False)
    top = ds["omega_max"].values
    assert top[1] / top[0] == pytest.approx(10.0, rel=0.05)
    assert _by_label(cases, "h=0.01 ").scene.h_profile == "2 * (0.005 * (1 + 0.5 * s))"
    tabled = default_cases(dataclasses.replace(base, h_profile="table 0:0.005 4:0.015"))
    assert _by_label(tabled, "h=0.001 ").scene.h_profile == "table 0:0.001 4:0.003"


def test_cases_that_do_not_apply_to_a_layered_wall_or_a_law_of_ones_own_say_why():
    """A layered wall (0.012 m + 0.008 m, 2h = 0.02 m) and a law of one's own with material_parameters were refused
    up front: the h=0.001 case could not hold the file's layers, and the plane-stress cases handed svk-plane-stress
    the law's parameters; the nu cases of such walls were copies of the base row. Now the layers scale with h (their
    shares kept), a case that cannot apply is a row saying why (no layer reads the wall's nu; each layer names its
    own law; a law of one's own reads no nu; the law swapped in is the wall's already), a law swap drops the
    parameters of the law swapped out, and a base scene that is not the paper's is not labelled "paper"."""
    layered = mol_shell.Sphere(h=0.01, pressure=500.0, layers="0.012 neo-hookean-incompressible; 0.008 "
                               "svk-plane-stress nu=0.3 fibre_E=5e6 fibre_angle=0.5")
    cases = default_cases(layered, quick=True)
    thin = _by_label(cases, "h=0.001 ")
    assert thin.label == "h=0.001 (layers x 0.1)" and thin.scene.layers.startswith("0.0012 neo-hookean-incompressible; "
                                                                                    "0.0008 svk-plane-stress nu=0.3")
    assert "no layer's law reads the wall's nu" in _by_label(cases, "nu=0.3").skip
    assert "each layer names its own law" in _by_label(cases, "nu=0.499 plane-stress").skip
    rubber = mol_shell.Material("stability-rubber-test", energy=lambda C, p: p["mu"] / 2 * (C[0, 0] + C[1, 1] + C[2, 2]
                                                                                            - 3),
                                parameters={"mu": 3e5}, thickness="incompressible")
    own = default_cases(mol_shell.Sphere(h=0.01, material=rubber, material_parameters="mu=2e5"), quick=True)
    assert "does not read nu" in _by_label(own, "nu=0.3").skip
    plane = default_cases(mol_shell.TwistedCylinder(nu=0.3, material="svk-plane-stress"), quick=True)
    assert plane[0].label == "twisted-cylinder" and default_cases(quick=True)[0].label == "paper"  # not the paper's
    assert "svk-plane-stress already" in _by_label(plane, "nu=0.499 plane-stress").skip  # the row nu=0.499 again
    swapped = _by_label(own, "nu=0.499 plane-stress").scene
    assert swapped.material == "svk-plane-stress" and swapped.material_parameters == ""
    assert _by_label(own, "h=0.001").scene.material_parameters == "mu=200000.0"
    ds = report([Case("sphere", layered, n=8, t_end=2e-4), _by_label(cases, "nu=0.3")], integrators=(), bisect=False)
    assert [str(s) for s in ds.case_status.values] == ["measured", "not applicable"]
    assert str(ds.leapfrog_status.values[1]) == "not applicable" and np.isnan(ds.omega_max.values[1])
    table = markdown_table(ds)
    assert "Cases not measured:\n- nu=0.3, not applicable: no layer's law reads the wall's nu" in table
    assert "< bound/2" not in table  # a case not run has no bisection to report


def test_a_case_without_a_start_is_recorded_and_the_report_written(monkeypatch, tmp_path, capsys):
    """A pressurised sphere twisted by gamma = 1.5 rad/m has no static equilibrium to start from: the stability
    command stopped after 14 cases with exit 2, wrote nothing and blamed the file's pressure. The case is a row
    `not run` with the reason and its name, the report is written (.nc, .md, .png) and the command exits 0, as for a
    run that stops at a limit. The base scene's own error is still the input's (raised: exit 2)."""
    from mol_shell.cli.main import main

    base = mol_shell.Sphere(pressure=1000.0, pressure_history="ramp 0.05", nu=0.3, material="svk-plane-stress")
    cases = [Case("sphere", base, n=12, t_end=2e-4), Case("gamma=1.5", dataclasses.replace(base, gamma=1.5), n=12,
                                                           t_end=2e-4)]
    monkeypatch.setattr("mol_shell.cli.analysis.default_cases", lambda scene, quick=False: cases)
    out = tmp_path / "st.nc"
    assert main(["stability", "sphere", "--no-bisect", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "gamma=1.5                    not run" in printed and "1 case not measured" in printed
    ds = mol_shell.read_netcdf(out)
    assert list(ds.case.values) == ["sphere", "gamma=1.5"] and str(ds.case_status.values[1]) == "not run"
    assert str(ds.cvode_bdf_status.values[0]) == "complete" and str(ds.ida_status.values[1]) == "not run"
    assert "could not start: gamma = 1.5 is outside twists that the shell, its loads 0 at t = 0, holds at a static " \
        "equilibrium" in str(ds.case_note.values[1])
    assert "- gamma=1.5, not run: the case's scene could not start" in (tmp_path / "st.md").read_text()
    assert (tmp_path / "st.png").exists()
    with pytest.raises(mol_shell.ParameterError, match="gamma"):  # the base scene cannot start: the input's error
        report(cases[::-1], integrators=(), bisect=False)


def test_the_quick_option_says_what_it_leaves_out_and_how_long_it_takes(capsys):
    """`--quick` said "grids up to n = 640 only" and a user waited over 3 minutes for a "quick" report: it leaves out
    only the two largest grids, the other 24 cases of the twisted cylinder run as in the full report (measured: 49-56
    s with the kernels cached, 91 s from an empty cache, on two cores). The help names the grids it leaves out, which
    are exactly those the quick set lacks, and the time it takes."""
    from mol_shell.cli.main import main

    assert main(["stability", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    full = {case.n for case in default_cases()}
    quick = {case.n for case in default_cases(quick=True)}
    assert full - quick == {2560, 10240} and len(default_cases(quick=True)) == 24
    assert "leave out the grid cases n = 2560 and 10240" in text and "about 1 min" in text and "8 min" in text


def test_ctrl_c_in_a_bisection_run_stops_the_report_and_is_not_read_as_an_unstable_step(monkeypatch):
    """An interrupted leap-frog run of the bisection (its integrator keeps Ctrl-C as the run's end, status
    ``interrupted``) raises KeyboardInterrupt for the report to stop on; it used to count as an unstable step, the
    bisection went on and the report was written complete, with NaN for the stable step, exit 0."""
    from mol_shell.analysis import stability

    class Interrupted:
        status, failure_time = "interrupted", 1e-3

    monkeypatch.setattr(stability.Leapfrog, "integrate", lambda self, *args, **kwargs: Interrupted())
    with pytest.raises(KeyboardInterrupt):
        stability.stable_leapfrog_step(None, None, None, 1e-4)


def test_a_scene_files_run_table_is_said_to_be_unused(monkeypatch, tmp_path, capsys):
    """`mol-shell stability FILE.toml` took the file's scene and dropped its [run] table (n = 12, t_end) without a
    word, though `run`, `modes` and `path` take their defaults from it: the report's cases set their own grids,
    times and integrators. It now says so in a note, once the report is written."""
    from mol_shell.cli.main import main

    scene_file = tmp_path / "s.toml"
    scene_file.write_text('scene = "twisted-cylinder"\n[run]\nn = 12\nt_end = 0.001\n')
    seen = []

    def cases(scene, quick=False):
        seen.append(scene)
        return [Case("paper", scene, n=8, t_end=1e-4)]

    monkeypatch.setattr("mol_shell.cli.analysis.default_cases", cases)
    assert main(["stability", str(scene_file), "--no-bisect", "-o", str(tmp_path / "st.nc")]) == 0
    err = capsys.readouterr().err
    assert seen == [mol_shell.TwistedCylinder()]  # the file's scene is the base
    assert f"mol-shell: note: the stability report runs its own cases (each with its own n, times and integrators); " \
        f"{scene_file}'s [run] table (n, t_end) is not used" in err, err
    assert main(["stability", "twisted-cylinder", "--no-bisect", "-o", str(tmp_path / "st2.nc")]) == 0
    assert "[run] table" not in capsys.readouterr().err  # a scene by name has no [run] table to leave out


def test_a_shell_that_stays_at_rest_has_no_energy_error(monkeypatch, tmp_path):
    """`mol-shell stability sphere` (the unloaded sphere at its natural state, which never moves) reported energy
    errors of about 250 for every integrator: E(0) is round-off (1e-26 J), and so is every change of it. Such a row
    has no energy error now (NaN, an empty cell); a shell that moves (the paper's) keeps its measured one."""
    from mol_shell.cli.main import main

    cases = [Case("sphere at rest", mol_shell.Sphere(), n=8, t_end=1e-3),
             Case("paper", mol_shell.TwistedCylinder(), n=8, t_end=1e-3)]
    monkeypatch.setattr("mol_shell.cli.analysis.default_cases", lambda scene, quick=False: cases)
    assert main(["stability", "sphere", "--no-bisect", "-o", str(tmp_path / "st.nc")]) == 0
    ds = mol_shell.read_netcdf(tmp_path / "st.nc")
    for name in ("leapfrog", "cvode_bdf", "ida"):
        errors = ds[f"{name}_energy_error"].values
        assert np.isnan(errors[0]) and 0 <= errors[1] < 1e-3, (name, errors)


def test_a_horizon_cut_by_damping_judges_no_step():
    """The viscous sphere (eta_mu = 100 Pa s, R = 1.001 a) damps its fastest modes at ``d`` = 3.8e3 s-1, so the
    horizon is cut to ln(1e6) / d, about 9 steps of 2 bound. Leap-frog ``y_(k+1) = y_(k-1) + 2 dt f`` grows by
    ``|x| = w dt + sqrt((w dt)^2 - 1)`` = 3.73 per step at ``w dt = 2``: in 9 steps a run ends complete whether
    stable or not, and 2 bound (3.94e-4 s) was reported as the stable step. Below 100 steps of 2 bound the
    bisection judges nothing, whatever cut the horizon: NaN, and the table says why."""
    ds = report([Case("viscous", mol_shell.Sphere(eta_mu=100.0, eta_lambda=200.0, R=1.001))], integrators=())
    bound, damping = float(ds.leapfrog_dt_bound.values[0]), float(ds.damping_max.values[0])
    assert float(ds.bisection_horizon_s.values[0]) == pytest.approx(math.log(1e6) / damping)
    assert math.log(1e6) / damping < 100 * 2 * bound  # the premise: fewer than 100 steps of 2 bound
    assert np.isnan(ds.leapfrog_dt_stable.values[0])
    note = str(ds.leapfrog_dt_note.values[0])
    assert note.startswith("n/a: damped 1e6-fold in ") and note.endswith("steps of 2 bound (< 100)"), note
    header, _, row = [[cell.strip() for cell in line.split("|")[1:-1]] for line in markdown_table(ds).split("\n")[:3]]
    assert dict(zip(header, row))["LF dt stable (bisection) [s]"] == note


def test_a_bracket_whose_top_never_fails_measures_no_step(monkeypatch):
    """Leap-frog is unstable past ``w dt = 1``: where a run at 2 bound reaches its horizon, the runs did not see the
    instability (nothing excited the fastest mode), and 2 bound, the bracket's top never tested unstable, is no
    measured stable step. Every run completing (a stand-in integrator), the search says so instead of 2 bound."""
    from mol_shell.analysis import stability

    class Complete:
        status, failure_time = "complete", float("nan")

    monkeypatch.setattr(stability.Leapfrog, "integrate", lambda self, *args, **kwargs: Complete())
    assert math.isnan(stability.stable_leapfrog_step(None, None, None, 1e-4)[0])  # it was 2e-4
    dt, horizon, note = stability.leapfrog_step_search(None, None, None, 1e-4)
    assert math.isnan(dt) and horizon == pytest.approx(3000 * 0.5e-4)
    assert note == "n/a: 2 bound ran stable (the top never tested unstable)"
