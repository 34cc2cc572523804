"""``mol-shell run|modes --from PATH.nc --step K|--point K [--perturb A]`` and ``mol-shell plot PATH.nc``."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from reference_cap import cap_params, p_classical

import mol_shell.cli.path as cli_path
from mol_shell import ParameterError, Sphere, modes, path
from mol_shell.analysis.path_inputs import DS_MIN, STEPS_MAX
from mol_shell.analysis.path_start import path_start
from mol_shell.cli.main import main

N = 21


def sets(lam=5.0):
    out = []
    for k, v in cap_params(lam).items():
        out += ["--set", f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"]
    return out


@pytest.fixture(scope="module")
def cap_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("path") / "cap.nc"
    code = main(["path", "sphere", "--param", f"pressure=0:{-0.7 * p_classical():.6g}", "--n", str(N), *sets(),
                 "--max-steps", "40", "-o", str(out)])
    assert code == 0
    return out


def test_modes_from_a_step_are_the_prestressed_frequencies(cap_file, tmp_path, capsys):
    with xr.open_dataset(cap_file) as p:
        w2 = float(p.smallest_eigenvalues[3, 0])
        value = float(p.parameter[3])
    out = tmp_path / "m.nc"
    assert main(["modes", "--from", str(cap_file), "--step", "3", "--count", "2", "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert float(ds.frequency[0]) ** 2 == pytest.approx(w2, rel=1e-6)
        assert ds.attrs["pressure"] == value and "step 3" in ds.attrs["initial_state"]


def test_run_from_a_critical_point_perturbed_along_its_mode(cap_file, tmp_path, capsys):
    out = tmp_path / "r.nc"
    code = main(["run", "--from", str(cap_file), "--point", "0", "--perturb", "1e-4", "--integrator", "cvode-bdf",
                 "--t-end", "0.02", "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    with xr.open_dataset(out) as ds, xr.open_dataset(cap_file) as p:
        start = p.point_z.values[0] + 1e-4 * p.point_mode_z.values[0]
        assert abs(ds.z.isel(time=0).values - start).max() < 1e-12
        assert "critical point 0 (limit)" in ds.attrs["initial_state"]
        assert ds.attrs["pressure"] == float(p.point_parameter[0])


def test_plot_of_a_path(cap_file, tmp_path, capsys):
    out = tmp_path / "p.png"
    assert main(["plot", str(cap_file), "--response", "r@0", "-o", str(out)]) == 0
    assert out.stat().st_size > 10000
    assert main(["plot", str(cap_file), "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert "against load_conjugate" in said
    states = xr.open_dataset(cap_file).sizes["step"]  # the states; the steps are one fewer (it said "N steps")
    assert f"{states} states ({states - 1} steps)" in said, said


def test_a_path_cut_after_it_was_written_is_refused_by_plot_in_one_line(cap_file, tmp_path, capsys):
    """A path cut with xarray (``isel(step=slice(0, K))``) or thinned to its stable steps keeps its critical points
    with the steps they had: `plot` failed with an internal IndexError (exit 1), or drew the points on other states.
    Such a file is refused naming it and the point that does not fit (exit 2); the whole file, and a cut that keeps
    the points' steps, are drawn."""
    with xr.open_dataset(cap_file) as full:
        full = full.load()
    first = int(full.point_step.values[0])
    assert full.sizes["point"] >= 1 and first + 2 < full.sizes["step"]
    cut, kept, thinned = tmp_path / "cut.nc", tmp_path / "kept.nc", tmp_path / "thinned.nc"
    full.isel(step=slice(0, first)).to_netcdf(cut)  # the first point lies beyond the states kept
    full.isel(step=slice(0, first + 2), point=[0]).to_netcdf(kept)  # the point and its steps kept
    full.isel(step=slice(None, None, 2)).to_netcdf(thinned)  # every other state: the point falls among far states
    for damaged in (cut, thinned):
        assert main(["plot", str(damaged), "-o", str(tmp_path / "x.png")]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"FILE = '{damaged}' holds " in err and "critical point 0" in err, err
    assert main(["plot", str(kept), "-o", str(tmp_path / "k.png")]) == 0
    assert "1 critical point" in capsys.readouterr().out


def test_a_path_file_whose_state_is_not_finite_is_refused_naming_the_file(cap_file, tmp_path, capsys):
    """A path file whose r was damaged to NaN was refused as `initial = <array of 105 values ...> is outside finite
    arrays`: a name the user never typed, neither the file nor the variable. It names both now."""
    with xr.open_dataset(cap_file) as full:
        damaged = full.load()
    damaged["r"][:] = np.nan
    damaged["point_theta"][:] = np.nan
    bad = tmp_path / "rnan.nc"
    damaged.to_netcdf(bad)
    assert main(["modes", "--from", str(bad), "--step", "1", "-o", str(tmp_path / "m.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"mol-shell: error: --from = '{bad}' holds values of r at step 1 that are not finite; allowed: a " \
        "netCDF file written by mol-shell path", err
    assert main(["run", "--from", str(bad), "--point", "0", "--t-end", "0.01", "-o", str(tmp_path / "r.nc")]) == 2
    assert "holds values of point_theta at critical point 0 that are not finite" in capsys.readouterr().err


@pytest.mark.parametrize("argv, option", [
    (["modes", "--from", "{f}", "--step", "99"], "--step"),
    (["modes", "--from", "{f}", "--point", "5"], "--point"),
    (["modes", "--from", "{f}"], "--step"),
    (["run", "--from", "{f}", "--step", "2", "--perturb", "1e-3", "--t-end", "0.01"], "--perturb"),
    # no perturbation: far beyond the shell's size, or r < 0 (each failed on another check: dt, SUNDIALS, r <= 0)
    (["run", "--from", "{f}", "--point", "0", "--perturb", "1e300", "--t-end", "0.01"], "--perturb"),
    (["run", "--from", "{f}", "--point", "0", "--perturb", "1e5", "--integrator", "cvode-bdf"], "--perturb"),
    (["run", "--from", "{f}", "--point", "0", "--perturb", "-1e3", "--integrator", "dop853-c"], "--perturb"),
    (["modes", "sphere", "--step", "2"], "--step"),
    (["modes", "sphere", "--from", "{f}", "--step", "2"], "--from"),
    (["modes", "--from", "{f}", "--step", "2", "--n", "30"], "--n"),
    (["plot", "{f}", "--response", "speed"], "--response"),
    (["plot", "{f}", "--figure", "fibres"], "--figure"),
    (["modes", "--from", "nothing.nc", "--step", "1"], "--from"),
])
def test_bad_input_exits_2_with_one_line_naming_the_option(cap_file, tmp_path, capsys, argv, option):
    argv = [a.replace("{f}", str(cap_file)) for a in argv] + ["-o", str(tmp_path / ("x.png" if argv[0] == "plot"
                                                                                   else "x.nc"))]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and option in err


def test_a_path_cut_short_by_max_steps_says_so_and_exits_0(tmp_path, capsys):
    out = tmp_path / "short.nc"
    code = main(["path", "sphere", "--param", f"pressure=0:{-0.7 * p_classical():.6g}", "--n", str(N), *sets(),
                 "--max-steps", "3", "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 0
    assert "note: the path did not reach pressure" in captured.err and "to go on from its last step: mol-shell path --from " in captured.err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "max_steps" and ds.attrs["complete"] == 0 and ds.sizes["step"] == 4


def test_modes_at_a_critical_point_list_the_critical_mode_at_zero_frequency(cap_file, tmp_path):
    """At the limit point the tangent stiffness is singular along the critical mode: modes lists it first at
    frequency ~0 (it is not one of the rigid motions, of which this clamped cap has none)."""
    out = tmp_path / "m.nc"
    assert main(["modes", "--from", str(cap_file), "--point", "0", "--count", "2", "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["zero_modes"] == 0
        assert float(ds.frequency[0]) < 1e-2 * float(ds.frequency[1])


def test_a_response_beyond_the_meridian_is_refused(cap_file, tmp_path, capsys):
    """``--response r@100`` on a meridian 0.279 m long drew the last node's r: S must lie on the meridian."""
    with xr.open_dataset(cap_file) as p:
        length = float(p.s[-1])
    for at in ("100", "-0.1", f"{1.001 * length!r}"):
        code = main(["plot", str(cap_file), "--response", f"r@{at}", "-o", str(tmp_path / "p.png")])
        err = capsys.readouterr().err
        assert code == 2 and len(err.splitlines()) == 1, err
        assert f"--response = 'r@{at}' is outside FIELD@S with S in [0, {length:.6g}] m" in err
    assert main(["plot", str(cap_file), "--response", f"chi@{length!r}", "-o", str(tmp_path / "p.png")]) == 0


def test_one_critical_point_is_said_in_the_singular(cap_file, tmp_path, capsys):
    with xr.open_dataset(cap_file) as p:
        assert p.sizes["point"] == 1
    assert main(["plot", str(cap_file), "-o", str(tmp_path / "p.png")]) == 0
    out = capsys.readouterr().out
    # (this path stopped at max_steps: the line then ends with where, tests/views/test_incomplete_said.py)
    assert ", 1 critical point" in out and "critical points" not in out


@pytest.mark.parametrize("argv", [["sphere", "--param", "pressure=0:1e24"],
                                  ["twisted-cylinder", "--param", "end2_dz=0:1e30"]])
def test_a_range_far_past_any_equilibrium_stops_at_the_start_and_exits_3(argv, tmp_path, capsys):
    """The first load past the start (the range over the steps, halved) is so large that the tangent stiffness
    there is exactly singular: SuperLU's RuntimeError was an internal error. Now the start's Newton gives up and the
    path stops where it is, saying so."""
    out = tmp_path / "p.nc"
    assert main(["path", *argv, "--n", "10", "--max-steps", "5", "-o", str(out)]) == 3
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("mol-shell: path stopped: the path cannot continue from") and "0 steps" in err, err
    assert xr.open_dataset(out).sizes["step"] == 1


def test_a_load_the_scene_refuses_is_refused_at_the_users_value(tmp_path, capsys):
    """The unshearable scene takes no loads: the refusal named "pressure = 1.0", the unit load used inside."""
    assert main(["path", "unshearable", "--param", "pressure=0:1000", "--n", "8", "-o", str(tmp_path / "p.nc")]) == 2
    assert "pressure = 1000.0 is outside 0" in capsys.readouterr().err


def test_a_points_file_edited_since_the_path_is_refused_by_from(tmp_path, capsys):
    """``run --from`` reads the meridian's points file again: edited since the path, the states of the old shell
    started the new one silently."""
    points = tmp_path / "p.txt"
    points.write_text("1.0 0.0\n0.9 0.3\n0.7 0.5\n0.4 0.55\n0.0 0.6\n")
    traced = tmp_path / "p.nc"
    assert main(["path", "meridian", "--set", f"points={points}", "--param", "pressure=0:100", "--n", "10",
                 "--max-steps", "2", "-o", str(traced)]) == 0
    run = ["run", "--from", str(traced), "--step", "1", "--t-end", "1e-5", "-o", str(tmp_path / "r.nc")]
    assert main(run) == 0
    points.write_text("1.0 0.0\n0.9 0.3\n0.7 0.5\n0.4 0.58\n0.0 0.65\n")
    capsys.readouterr()
    assert main(run) == 2
    assert f"points = '{points}' describes another meridian now" in capsys.readouterr().err


def test_a_points_file_edited_keeping_its_count_and_length_is_refused_by_from(tmp_path, capsys):
    """The meridian was told apart by its point count and length: a mirrored file (same count, same length, another
    shell) started the new run from the old shell's states."""
    points = tmp_path / "p.txt"
    points.write_text("1.0 0.0\n0.9 0.3\n0.7 0.5\n0.4 0.55\n0.0 0.6\n")
    traced = tmp_path / "p.nc"
    assert main(["path", "meridian", "--set", f"points={points}", "--param", "pressure=0:100", "--n", "10",
                 "--max-steps", "2", "-o", str(traced)]) == 0
    points.write_text("1.0 0.0\n0.9 -0.3\n0.7 -0.5\n0.4 -0.55\n0.0 -0.6\n")  # mirrored in z: same count, length
    capsys.readouterr()
    run = ["run", "--from", str(traced), "--step", "1", "--t-end", "1e-5", "-o", str(tmp_path / "r.nc")]
    assert main(run) == 2
    assert f"points = '{points}' describes another meridian now" in capsys.readouterr().err


def test_a_path_on_a_meridian_this_version_draws_differently_is_refused_naming_from(tmp_path, capsys):
    """A vessel drawn down ran mirrored until December 7 and is drawn where the user put it since: ``--from`` on a
    path traced before then was refused as ``points = 'vessel' describes another meridian now``, naming a points
    file the vessel has not got."""
    traced = tmp_path / "p.nc"
    assert main(["path", "vessel", "--param", "pressure=0:100", "--n", "10", "--max-steps", "2",
                 "-o", str(traced)]) == 0
    with xr.open_dataset(traced) as ds:
        old = ds.load()
    old.attrs["meridian"] = old.attrs["meridian"].replace("(", "(mirrored, ", 1)  # another version's drawing
    older = tmp_path / "older.nc"
    old.to_netcdf(older)
    capsys.readouterr()
    assert main(["run", "--from", str(older), "--step", "1", "--t-end", "1e-5", "-o", str(tmp_path / "r.nc")]) == 2
    err = capsys.readouterr().err
    assert f"--from = '{older}' was traced on a vessel meridian this version draws differently" in err, err
    assert "points" not in err.split(";")[0], err


def test_a_range_far_beyond_what_the_shell_carries_says_so_when_the_path_cannot_leave_its_start(tmp_path, capsys):
    """pressure = 0:1e12 Pa on the default sphere (E = 1 MPa; Newton reaches about 3e7 Pa, at 71 times its radius):
    the smallest first step, 1e12 / 20 steps / 2^10 = 4.88e7 Pa, is already past it. The message blamed the tangent
    only."""
    out = tmp_path / "p.nc"
    assert main(["path", "sphere", "--param", "pressure=0:1e12", "--n", "10", "-o", str(out)]) == 3
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "no equilibrium found at pressure = 4.88281e+07 Pa" in err, err
    assert "or the range is too wide for a first step (a nearer stop or more steps, --steps, shorten it)" in err, err


def test_a_path_written_before_the_points_digest_still_starts_a_run(tmp_path, capsys):
    """Path files whose meridian description has no digest (written before it was added) are compared without it:
    the unedited file was refused as "another meridian"."""
    import netCDF4

    points = tmp_path / "p.txt"
    points.write_text("1.0 0.0\n0.9 0.3\n0.7 0.5\n0.4 0.55\n0.0 0.6\n")
    traced = tmp_path / "p.nc"
    assert main(["path", "meridian", "--set", f"points={points}", "--param", "pressure=0:100", "--n", "10",
                 "--max-steps", "2", "-o", str(traced)]) == 0
    with netCDF4.Dataset(traced, "a") as handle:  # as the earlier code wrote it
        described = handle.getncattr("meridian")
        assert ", sha256 " in described
        handle.setncattr("meridian", described.split(", sha256 ")[0] + ")")
    run = ["run", "--from", str(traced), "--step", "1", "--t-end", "1e-5", "-o", str(tmp_path / "r.nc")]
    assert main(run) == 0, capsys.readouterr().err


def test_modes_about_a_state_past_a_bifurcation_say_it_is_unstable(tmp_path, capsys):
    """On the branch past the sphere's first bifurcation the path records one negative eigenvalue (-434 s-2 at its
    step 30). ``modes --from`` printed that mode at "0 rad/s" (the square root of max(omega^2, 0)), silently. The
    path's own eigen solve (shift-invert on its equations) is the second route: the same omega^2."""
    traced = tmp_path / "branch.nc"
    assert main(["path", "sphere", "--param", "pressure=0:-775", "--n", "60", "--set", "h=0.012517", "--set", "nu=0.3",
                 "--set", "material=svk-plane-stress", "--branch", "0", "--max-steps", "40", "-o", str(traced)]) == 0
    path_ds = xr.open_dataset(traced)
    step = 30
    assert int(path_ds.negative_eigenvalues[step]) == 1
    capsys.readouterr()
    out = tmp_path / "modes.nc"
    assert main(["modes", "--from", str(traced), "--step", str(step), "--n", "60", "--count", "2", "-o", str(out)]) == 0
    text = capsys.readouterr()
    assert "the state the modes are taken about is unstable: 1 mode with omega^2 < 0" in text.err
    assert "mode  1: unstable: omega^2 = " in text.out and " 0 rad/s" not in text.out
    ds = xr.open_dataset(out)
    expected = np.sort(path_ds.smallest_eigenvalues.values[step])
    assert np.isnan(float(ds.frequency[0])) and int(ds.attrs["unstable_modes"]) == 1
    np.testing.assert_allclose(ds.omega_squared.values[:2], expected[:2], rtol=1e-6)
    assert float(ds.frequency[1]) ** 2 == pytest.approx(expected[1], rel=1e-6)


def test_too_many_steps_for_memory_are_blamed_on_max_steps(tmp_path, capsys):
    """``--max-steps 1e10`` at n = 20 was refused as "n = 20 is outside integers 3..3": no n would do."""
    assert main(["path", "sphere", "--param", "pressure=0:100", "--n", "20", "--max-steps", "10000000000",
                 "-o", str(tmp_path / "p.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("mol-shell: error: --max-steps = 10000000000 is outside at most ") and " steps at n = 20" in err
    assert "allow fewer steps (--max-steps)" in err and len(err.splitlines()) == 1


def test_a_second_param_is_refused_not_followed_silently(tmp_path, capsys):
    """``--param pressure=0:100 --param gravity=0:1`` traced gravity alone, the pressure range dropped silently."""
    assert main(["path", "sphere", "--param", "pressure=0:100", "--param", "gravity=0:1", "--n", "8",
                 "-o", str(tmp_path / "p.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("mol-shell: error: --param = 'gravity=0:1' follows --param = 'pressure=0:100'; allowed: one (a path "
                   "follows one parameter; vary the others with study)")
    assert not (tmp_path / "p.nc").exists()


def test_the_first_step_is_set_with_steps_as_in_python(tmp_path, capsys):
    """The docs and the stop's message said "more --steps" and the command had no such option."""
    loads = {}
    for steps in (10, 40):
        out = tmp_path / f"p{steps}.nc"
        assert main(["path", "sphere", "--param", "pressure=0:1000", "--n", "20", "--steps", str(steps),
                     "--max-steps", "1", "-o", str(out)]) == 0
        loads[steps] = xr.open_dataset(out).parameter.values
    same = path(Sphere(), "pressure", 0.0, 1000.0, n=20, steps=40, max_steps=1).parameter.values
    np.testing.assert_array_equal(loads[40], same)
    assert 0 < loads[40][1] < loads[10][1]  # the first step: a quarter of the range's share
    assert main(["path", "sphere", "--param", "pressure=0:1000", "--steps", "0", "-o", str(tmp_path / "x.nc")]) == 2
    assert capsys.readouterr().err.strip().splitlines()[-1].startswith("mol-shell: error: --steps = 0 is outside")


def test_a_point_the_path_did_not_locate_is_marked_in_the_listing(tmp_path, capsys, monkeypatch):
    """The listing printed a point whose search stopped early (``point_located = 0``) exactly like a located one; it
    is marked now, with the steps around its estimate, as points past the loss of ellipticity are."""
    def unlocated(*args, **kwargs):  # the path's first point, as a search that stopped early keeps it
        ds = path(*args, **kwargs)
        ds["point_located"][0] = 0
        return ds

    monkeypatch.setattr(cli_path, "path", unlocated)
    assert main(["path", "sphere", "--param", f"pressure=0:{-0.7 * p_classical():.6g}", "--n", str(N), *sets(),
                 "--max-steps", "40", "-o", str(tmp_path / "p.nc")]) == 0
    ds = xr.open_dataset(tmp_path / "p.nc")
    step = int(ds.point_step[0])
    line = capsys.readouterr().out.splitlines()[1]
    assert line.startswith("  limit at pressure = ") and line.endswith(
        f"; not located: the search's last estimate, between steps {step} and {step + 1})"), line


def _unlocated_copy(cap_file, tmp_path, dr=0.0):
    """The cap's path file with its critical point marked as not located and its state's r moved by ``dr`` at its
    middle node (the pole and the clamped edge impose theirs)."""
    with xr.open_dataset(cap_file) as full:
        ds = full.load()
    ds["point_located"][0] = 0
    ds["point_r"][0, N // 2] = ds["point_r"][0, N // 2] + dr
    out = tmp_path / "unlocated.nc"
    ds.to_netcdf(out)
    return out, int(ds.point_step[0])


def test_modes_at_an_unlocated_point_that_is_no_equilibrium_refuse_naming_point(cap_file, tmp_path, capsys):
    """A point the search did not locate kept its last trial state, which (before the locating Newton checked its
    last step) could be no equilibrium: ``modes --from --point K`` blamed the scene (``scene = 'axisymmetric' is
    outside a scene whose initial state is an equilibrium ... R = auto ...``). It names --point and the steps."""
    bad, step = _unlocated_copy(cap_file, tmp_path, dr=1e-4)
    assert main(["modes", "--from", str(bad), "--point", "0", "-o", str(tmp_path / "m.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: --point = 0 is a critical point the "
                                                         "path did not locate (point_located = 0)"), err
    assert "is no equilibrium (residual force " in err and f"--step {step} or --step {step + 1}" in err
    assert "scene" not in err and "R = auto" not in err


@pytest.mark.parametrize(("command", "options", "subject"), [
    ("modes", ["--count", "2"], "the modes are about"),
    ("run", ["--t-end", "1e-4"], "the run starts from"),  # it started there without a word, where modes said it
])
def test_a_start_at_an_unlocated_point_that_is_an_equilibrium_says_it_was_not_located(cap_file, tmp_path, capsys,
                                                                                        command, options, subject):
    unlocated, step = _unlocated_copy(cap_file, tmp_path)
    out = tmp_path / "m.nc"
    assert main([command, "--from", str(unlocated), "--point", "0", *options, "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"mol-shell: note: critical point 0 was not located (point_located = 0): {subject} the " \
        "search's last estimate" in err and f"--step {step} or --step {step + 1}" in err, err
    assert "not located" in xr.open_dataset(out).attrs["initial_state"]


@pytest.mark.parametrize(("command", "options", "kind", "code"), [
    ("run", ["--t-end", "1e-5"], "located", 0),
    ("modes", ["--count", "1"], "located", 0),
    ("run", ["--t-end", "1e-5"], "unlocated", 0),
    ("modes", ["--count", "1"], "unlocated", 0),
    ("modes", ["--count", "1"], "no equilibrium", 2),  # refused naming --point: the file's point_located said why
])
def test_a_start_from_a_path_reads_the_path_file_once(cap_file, tmp_path, monkeypatch, capsys, command, options,
                                                      kind, code):
    """``run|modes --from PATH.nc --point K`` read the path file for the start, again for the note on a point the
    path did not locate, and again for the refusal of a state out of equilibrium: the file is opened once, and what
    was read is passed on."""
    source = cap_file if kind == "located" else _unlocated_copy(cap_file, tmp_path, dr=1e-4 * (kind != "unlocated"))[0]
    opened, open_dataset = [], xr.open_dataset

    def counted(filename, *args, **kwargs):
        opened.append(Path(filename).resolve())
        return open_dataset(filename, *args, **kwargs)

    monkeypatch.setattr(xr, "open_dataset", counted)
    assert main([command, "--from", str(source), "--point", "0", *options, "-o", str(tmp_path / "out.nc")]) == code
    assert opened.count(Path(source).resolve()) == 1, capsys.readouterr().err


def test_fields_that_are_no_equilibrium_are_refused_naming_initial(cap_file):
    """``modes(scene, initial=fields)`` with fields out of equilibrium blamed the scene and suggested R = auto,
    which the fields given replace."""
    scene, n, fields, _ = path_start(xr.open_dataset(cap_file), step=2)
    fields[1, N // 2] += 1e-4  # r at the middle node (the pole and the clamped edge impose theirs)
    with pytest.raises(ParameterError, match=r"^initial \(the fields given\) is outside equilibria at rest under "
                       r"the loads of scene 'sphere' \(residual force ") as refused:
        modes(scene, n=n, count=1, initial=fields)
    assert refused.value.name == "initial" and "R = auto" not in str(refused.value)


def test_more_steps_than_the_smallest_first_step_allows_are_refused(tmp_path, capsys):
    """``--steps 99999999999999999999999`` took a first step of 1.4e-23 (scaled arclength), below the corrector's
    noise, and stopped with exit 3 ("left the predictor's neighbourhood"). The first step, sqrt(2) / steps, may not be
    below the least ``ds`` the path takes (``DS_MIN``)."""
    assert math.sqrt(2) / STEPS_MAX >= DS_MIN > math.sqrt(2) / (STEPS_MAX + 1)
    for steps in ("99999999999999999999999", str(STEPS_MAX + 1)):
        assert main(["path", "sphere", "--param", "pressure=0:100", "--steps", steps, "--max-steps", "3",
                     "-o", str(tmp_path / "p.nc")]) == 2
        err = capsys.readouterr().err.strip()
        assert err == f"mol-shell: error: --steps = {steps} is outside integers in [1, {STEPS_MAX}]", err
    assert not (tmp_path / "p.nc").exists()
    with pytest.raises(ParameterError, match=rf"^steps = {STEPS_MAX + 1} is outside integers 1\.\.{STEPS_MAX} "):
        path(Sphere(), "pressure", 0.0, 100.0, n=8, steps=STEPS_MAX + 1, max_steps=3)
    ds = path(Sphere(), "pressure", 0.0, 100.0, n=8, steps=STEPS_MAX, max_steps=1, progress=False)
    assert ds.sizes["step"] == 2
