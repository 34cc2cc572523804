"""Going on along a path from one of its steps (``continue_path``, ``mol-shell path --from PATH.nc --stop X``).

Until December 7 a path that stopped short (``max_steps``) could only be traced again from its start. A continued
path starts from the step's state and leaves it along the chord from the step before: past a fold, where the load
turns, the tangent towards ``stop`` would lead back to the fold instead.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from reference_cap import cap_params, p_classical

import mol_shell
from mol_shell.analysis.path_continue import continue_path
from mol_shell.cli.main import main

STOP = 2e5  # Pa on the default sphere, which stiffens monotonically: one branch, no critical point


@pytest.fixture(scope="module")
def short():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the default law's note at nu = 0.49
        return mol_shell.path("sphere", "pressure", 0.0, STOP, n=13, max_steps=3, progress=False)


def test_a_continued_path_ends_at_the_equilibrium_the_whole_path_reaches(short):
    assert short.attrs["status"] == "max_steps"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        more = continue_path(short, STOP)
        whole = mol_shell.path("sphere", "pressure", 0.0, STOP, n=13, progress=False)
    assert more.attrs["status"] == whole.attrs["status"] == "complete"
    assert float(more.parameter[0]) == float(short.parameter[-1]) and float(more.parameter[-1]) == STOP
    for field in ("z", "r"):  # one branch: Newton's equilibria at 2e5 Pa, reached along two sequences of steps
        np.testing.assert_allclose(more[field].values[-1], whole[field].values[-1], rtol=0, atol=1e-12)
    assert more.attrs["continued_from"].startswith("<xarray.Dataset>, step 3 of 4 (pressure = ")
    assert more.attrs["initial_state"].startswith("equilibrium path step 3: pressure = ")


def test_past_a_fold_the_continuation_goes_on_along_the_branch_not_back_to_the_fold():
    """The clamped cap under external pressure folds at about -75.6 Pa (n = 21); the step just past the fold is on
    the unstable branch (one negative eigenvalue), where the load rises again. Towards stop (below) would lead back
    to the fold, and so did the chord from the step before with its load (it crosses the fold: the load still
    falling along it): the continuation went back over the fold onto the stable branch. It goes the way the
    displacements went, in the path's own metric (its arclength scales, in attrs)."""
    cap = mol_shell.Sphere(**cap_params(5.0))
    stop = -0.7 * p_classical()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traced = mol_shell.path(cap, "pressure", 0.0, stop, n=21, max_steps=16, progress=False)
    fold = int(traced.point_step.values[0])  # located between this step and the next
    assert str(traced.point_kind.values[0]) == "limit" and traced.sizes["step"] > fold + 2
    k = fold + 1
    assert traced.negative_eigenvalues.values[k] == 1 and traced.parameter.values[k] < traced.parameter.values[k - 1]
    more = continue_path(traced, stop, step=k, max_steps=3)
    loads = more.parameter.values
    assert np.all(np.diff(loads) > 0), loads  # on along the branch, the load rising (away from the fold)
    assert np.all(more.negative_eigenvalues.values == 1) and more.sizes["point"] == 0
    for scale in ("arclength_displacement_scale", "arclength_load_scale"):
        assert more.attrs[scale] == traced.attrs[scale]


def test_the_command_line_goes_on_from_a_path_file(short, tmp_path, capsys):
    first = tmp_path / "a.nc"
    assert main(["path", "sphere", "--param", f"pressure=0:{STOP:g}", "--n", "13", "--max-steps", "2",
                 "-o", str(first)]) == 0
    err = capsys.readouterr().err
    assert f"(to go on from its last step: mol-shell path --from {first} --stop {STOP!r})" in err
    out = tmp_path / "b.nc"
    assert main(["path", "--from", str(first), "--stop", f"{STOP:g}", "--max-steps", "1", "-o", str(out)]) == 0
    ds = mol_shell.read_netcdf(out)
    assert ds.attrs["continued_from"].startswith(f"{first}, step 2 of 3 (pressure = ")
    assert ds.sizes["step"] == 2 and ds.attrs["scene"] == "sphere"


@pytest.mark.parametrize("argv, said", [
    (["sphere", "--from", "F", "--stop", "1"], "SCENE_OR_FILE is not taken with --from PATH.nc"),
    (["--from", "F", "--param", "pressure=0:1", "--stop", "1"], "--param is not taken with --from PATH.nc"),
    (["--from", "F", "--set", "h=0.1", "--stop", "1"], "--set is not taken with --from PATH.nc"),
    (["--from", "F"], "--stop is missing: give --stop X with --from PATH.nc"),
    (["--from", "F", "--stop", "1", "--step", "9"], "--step = 9 is outside integers 0..3 (the path's steps)"),
    (["--from", "F", "--stop", "1", "--n", "30"], "--n = 30 is outside {13} with --from (the path's nodes)"),
    (["sphere", "--param", "pressure=0:1", "--stop", "3"], "--stop is an option with --from PATH.nc only"),
    (["--param", "pressure=0:1"], "SCENE_OR_FILE is missing"),
])
def test_refusals_name_the_option(short, tmp_path, capsys, argv, said):
    source = tmp_path / "short.nc"
    mol_shell.write_netcdf(short, source)
    argv = [str(source) if a == "F" else a for a in argv]
    assert main(["path", *argv, "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and said in err[0], err
    assert not (tmp_path / "x.nc").exists()


def test_a_stop_at_the_steps_load_is_refused_as_stop(short, tmp_path, capsys):
    source = tmp_path / "short.nc"
    mol_shell.write_netcdf(short, source)
    value = float(short.parameter.values[-1])
    assert main(["path", "--from", str(source), "--stop", repr(value), "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("mol-shell: error: --stop = ") and "the step's load" in err


def test_initial_fields_of_another_shape_are_refused_by_name():
    with pytest.raises(mol_shell.ParameterError, match=r"^initial = .* is outside finite arrays of shape \(5, 13\)"):
        mol_shell.path("sphere", "pressure", 0.0, STOP, n=13, initial=np.zeros((5, 12)), progress=False)


def test_a_stop_back_towards_the_start_is_reached_not_run_away_from(short):
    """Along the chord from the step before, a stop behind the step (0, where the path came from) was never reached:
    200 steps up to 653 kPa, status max_steps. It now heads for it, and ends at the natural state (no load)."""
    back = continue_path(short, 0.0, max_steps=40)
    assert back.attrs["status"] == "complete", back.attrs["message"]
    assert np.all(np.diff(back.parameter.values) < 0) and float(back.parameter[-1]) == 0.0
    for field in ("z", "r"):  # unloaded: the reference, the path's own step 0
        np.testing.assert_allclose(back[field].values[-1], short[field].values[0], rtol=0, atol=1e-12)


def test_a_step_that_is_no_equilibrium_is_refused_naming_the_file(short, tmp_path, capsys):
    damaged = short.copy(deep=True)
    damaged["r"].values[-1, 3:8] *= 1.5
    source = tmp_path / "bad.nc"
    mol_shell.write_netcdf(damaged, source)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code = main(["path", "--from", str(source), "--stop", f"{STOP!r}", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"mol-shell: error: --from = '{source}' holds a state at step 3 that is no equilibrium")


def test_a_continued_paths_scene_file_names_the_command_that_traces_it_again(short, tmp_path, capsys):
    """``scenes CONTINUED.nc --toml`` said ``mol-shell path THIS.toml --param START:STOP`` traces it again; from the
    scene's own state at START that path may lie on another branch (a continuation past a fold)."""
    first, more = tmp_path / "a.nc", tmp_path / "b.nc"
    mol_shell.write_netcdf(short, first)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["path", "--from", str(first), "--stop", f"{STOP!r}", "--max-steps", "1", "-o", str(more)]) == 0
    capsys.readouterr()
    assert main(["scenes", str(more), "--toml"]) == 0
    text = capsys.readouterr().out
    assert (f"# It was continued from {first}, step 3 of 4 (pressure = " in text
            and f"mol-shell path --from {first} --step 3 --stop {STOP:g} -o PATH.nc traces it again" in text), text


def test_a_file_whose_load_the_scene_cannot_take_is_refused_naming_from(short, tmp_path, capsys):
    """It was said as ``--param = None``, an option not given."""
    damaged = short.copy()
    damaged.attrs["parameter"] = "end1_torque"  # a closed sphere has no edge
    source = tmp_path / "bad.nc"
    mol_shell.write_netcdf(damaged, source)
    assert main(["path", "--from", str(source), "--stop", "1", "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"mol-shell: error: --from = '{source}' continues 'end1_torque'"), err


@pytest.mark.parametrize("keywords, name", [
    ({"scales": (0.0, 2e5)}, "scales"), ({"scales": 1.0}, "scales"), ({"scales": (1.0, np.inf)}, "scales"),
    ({"heading": "previous"}, "heading"), ({"heading": np.zeros((5, 3))}, "heading"),
])
def test_a_start_that_is_not_one_is_refused_by_name(short, keywords, name):
    """A zero or infinite scale ended in 'Factor is exactly singular' (RuntimeError), a float in a TypeError."""
    fields = np.stack([short[f].values[-1] for f in ("z", "r", "chi", "theta", "psi")])
    with pytest.raises(mol_shell.ParameterError) as refused:
        mol_shell.path("sphere", "pressure", float(short.parameter[-1]), STOP, n=13, initial=fields, progress=False,
                       **keywords)
    assert refused.value.name == name


def test_continue_path_names_its_source_and_stop(short, tmp_path):
    with pytest.raises(mol_shell.ParameterError, match=r"^source = 'nofile.nc' does not exist"):
        continue_path("nofile.nc", STOP)
    with pytest.raises(mol_shell.ParameterError, match=r"^stop = None is not a finite number"):
        continue_path(short, None)
    damaged = short.assign_attrs(arclength_load_scale=0.0)
    with pytest.raises(mol_shell.ParameterError, match=r"holds arclength_load_scale = 0.0, not a finite positive"):
        continue_path(damaged, STOP)


def test_a_path_that_took_no_step_lends_no_metric(short):
    """A path that failed at its start (its range far too wide: 0:1e12 on the sphere) recorded the scales of that
    range, and a continuation towards a near stop, in them, failed again at its start; it weighs at its own start now."""
    failed = short.isel(step=[0]).assign_attrs(arclength_load_scale=1e12, stop=1e12, status="failed")
    more = continue_path(failed, STOP, max_steps=2)
    assert more.attrs["arclength_load_scale"] == abs(STOP - float(short.parameter[0]))


def test_continue_path_takes_no_names_and_its_refusals_name_its_parameters(short):
    """``names`` (how refusals name the path and the step) was the command line's plumbing in the public signature:
    ``names={'step': '--step'}`` raised ``KeyError: 'ds'``. The public function names its own parameters; the
    command line's flags are its internal function's (``continue_named``)."""
    with pytest.raises(TypeError, match="names"):
        continue_path(short, STOP, names={"step": "--step"})
    for step in (10**6, -1, 1.5):  # the path has steps 0 .. 3
        with pytest.raises(mol_shell.ParameterError, match=rf"^step = {step} is outside integers 0\.\.3") as refused:
            continue_path(short, STOP, step=step)
        assert refused.value.name == "step"
    with pytest.raises(mol_shell.ParameterError, match=r"^stop = inf is not a finite number") as refused:
        continue_path(short, float("inf"))
    assert refused.value.name == "stop"
    damaged = short.copy(deep=True)
    damaged["r"].values[-1, 2] = np.nan
    with pytest.raises(mol_shell.ParameterError, match=r"^source = .* holds values of r at step 3 that are not") as \
            refused:
        continue_path(damaged, STOP)
    assert refused.value.name == "source"
