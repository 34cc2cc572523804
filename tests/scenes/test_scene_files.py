"""Scene files: every parameter in one table, `scenes NAME --toml` round-trips to the same scene and the same run,
the examples run and do what their comments say, and every refusal is one line naming the file and the key."""

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell._core.errors import ParameterError
from mol_shell.results.dataset import read_netcdf
from mol_shell.scenes import SCENES
from mol_shell.scenes.base import DRIVES, LOADS
from mol_shell.scenes.files import EDGES, MATERIAL, TABLES, load_scene, table_of

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
NEEDS_A_FILE = {"meridian"}  # its points have no default


def test_every_parameter_of_every_scene_is_in_exactly_one_table():
    lists = {"material": MATERIAL, "edges": EDGES, "loads": LOADS}
    assert set(DRIVES) <= set(EDGES)
    for cls in SCENES.values():
        names = {f.name for f in dataclasses.fields(cls)}
        for name in names:
            base = name.removesuffix("_history")
            assert base in names, f"{cls.name}: {name} without {base}"
            claims = [t for t, members in {**lists, "initial": cls.initial}.items() if base in members]
            assert len(claims) <= 1, f"{cls.name}: {name} claimed by {claims}"
            table = table_of(cls, name)
            assert table == (claims[0] if claims else "geometry") and table in TABLES[:-1]


def _changed(scene, name, tmp_path):
    """``scene`` with parameter ``name`` moved a little (5 %, or 0.05 from zero; another built-in table of points),
    staying inside its allowed range; None where the scene holds it at its one value."""
    value = getattr(scene, name)
    if name == "points":  # a file: a flatter half ellipsoid than the built-in dome
        t = np.linspace(0.0, np.pi / 2, 17)
        path = tmp_path / "dome.txt"
        np.savetxt(path, np.column_stack([np.cos(t), 0.5 * np.sin(t)]))
        candidates = [str(path)]
    elif name == "segments":  # a meridian from segments: a capsule in place of the default vessel
        candidates = ["arc 1 -90, line 1.5, arc 1 -90"]
    elif value is None:  # R or dilation: automatic (the equilibrium) by default
        candidates = [1.02, 0.02]
    else:
        candidates = [value * 1.05, value * 0.95] if value else [0.05, -0.05]
    fixed = []
    for candidate in candidates:
        try:
            return dataclasses.replace(scene, **{name: candidate})
        except ParameterError as exc:
            one = re.match(r"\{([^,}]+)\}", str(exc.allowed))  # the scene holds it at its one value
            fixed.append(exc.name == name and one is not None and float(one.group(1)) == value)
    if all(fixed):  # spinning-ring's gamma: {0} (a twist is not uniform in s): nothing to move
        return None
    raise AssertionError(f"{type(scene).__name__}.{name}: no allowed change among {candidates}")


def _meridian(scene):
    mer = scene.meridian()
    return np.concatenate([[mer.length], *mer.at(np.linspace(0.0, mer.length, 9))])


@pytest.mark.parametrize("name", sorted(SCENES))
def test_geometry_parameters_shape_the_meridian_and_initial_ones_do_not(name, tmp_path):
    """What the tables claim, from the scene itself: a parameter of the [geometry] table (no other table claims it)
    changes the reference meridian; one of [initial] leaves it as it is (so a new initial-data parameter left out
    of a scene's ``initial`` lands in [geometry] and fails here)."""
    cls = SCENES[name]
    scene = cls()
    reference = _meridian(scene)
    tables = {f.name: table_of(cls, f.name) for f in dataclasses.fields(cls)}
    assert "geometry" in tables.values() and "initial" in tables.values()
    for param, table in tables.items():
        if table not in ("geometry", "initial"):
            continue
        changed = _changed(scene, param, tmp_path)
        if changed is None:
            continue
        moved = np.allclose(_meridian(changed), reference, rtol=1e-12, atol=0.0)
        assert moved == (table == "initial"), f"{name}: {param} is in [{table}] but the meridian " + (
            "does not change with it" if moved else "changes with it")


def _printed(name, capsys):
    assert main(["scenes", name, "--toml"]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("name", sorted(set(SCENES) - NEEDS_A_FILE))
def test_printed_scene_files_load_and_run_as_the_built_in_scene(name, tmp_path, capsys):
    path = tmp_path / f"{name}.toml"
    path.write_text(_printed(name, capsys))
    scene, run = load_scene(path, with_run=True)
    assert scene == SCENES[name]() and run == {"integrator": "leapfrog", "n": 40, "t_end": 0.01}
    outs = []
    for what in (name, str(path)):  # on the file's own n = 40, which test_newcomer_more's run of the printed file
        outs.append(tmp_path / f"{len(outs)}.nc")  # compiles as well: one kernel per scene for both tests
        assert main(["run", what, "--n", "40", "--t-end", "1e-5", "-o", str(outs[-1])]) == 0
    a, b = (read_netcdf(p) for p in outs)
    assert list(a.data_vars) == list(b.data_vars)
    for var in a.data_vars:
        np.testing.assert_array_equal(a[var].values, b[var].values, err_msg=var)
    for field in dataclasses.fields(SCENES[name]):
        assert a.attrs[field.name] == b.attrs[field.name]


def test_a_meridian_file_reads_its_points_next_to_it(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "shell"
    folder.mkdir()
    np.savetxt(folder / "pts.txt", [[1.0, z] for z in np.linspace(0, 1, 6)])
    text = _printed("meridian", capsys)
    assert 'points = ""' in text
    (folder / "m.toml").write_text(text.replace('points = ""', 'points = "pts.txt"'))
    monkeypatch.chdir(tmp_path)  # elsewhere: the path is the file's folder's
    scene = load_scene("shell/m.toml")
    assert scene == mol_shell.scenes.MeridianShell(points=str(Path("shell") / "pts.txt"))


def test_run_defaults_come_from_the_file_and_the_command_line_wins(tmp_path):
    path = tmp_path / "drum.toml"
    path.write_text('scene = "twisted-cylinder"\n[initial]\nR = 1.0\nomega = 2\n'
                    '[loads]\npressure_history = {kind = "table", t = [0, 1e-5], h = [0, 1]}\n'
                    "[run]\nn = 8\ntimes = [0, 5e-6, 1e-5]\ndt = 5e-7\n")
    scene, run = mol_shell.load_scene(path, with_run=True)
    assert scene.omega == 2.0 and isinstance(scene.omega, float) and scene.pressure_history == "table 0:0 1e-05:1"
    ds = mol_shell.simulate(scene, progress=False, **run)
    assert ds.sizes["s"] == 8 and list(ds.time.values) == [0, 5e-6, 1e-5] and ds.attrs["n_steps"] == 20
    out = tmp_path / "a.nc"
    assert main(["run", str(path), "-o", str(out)]) == 0
    np.testing.assert_array_equal(read_netcdf(out).r.values, ds.r.values)
    assert main(["run", str(path), "--n", "9", "--t-end", "2e-5", "--set", "omega=3", "-o", str(out)]) == 0
    ds = read_netcdf(out)
    assert ds.sizes["s"] == 9 and ds.time.values[-1] == 2e-5 and ds.attrs["omega"] == 3 and ds.attrs["R"] == 1
    assert ds.attrs["dt"] == 5e-7  # the file's, as no option replaced it


def test_the_command_lines_integrator_leaves_out_the_files_options_for_another(tmp_path, capsys):
    """A file for leap-frog (``dt``) run with ``--integrator cvode-bdf`` was refused ("dt is not an option of
    cvode-bdf"), naming neither the file nor its key, and the command line could not override it."""
    path = tmp_path / "lf.toml"
    path.write_text('scene = "sphere"\n[run]\nn = 8\nt_end = 1e-5\ndt = 5e-7\n')
    out = tmp_path / "a.nc"
    assert main(["run", str(path), "--integrator", "cvode-bdf", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "note: the scene file's [run] dt = 5e-07 is not an option of cvode-bdf (--integrator): left out" in err
    assert read_netcdf(out).attrs["integrator"] == "cvode-bdf"
    assert main(["run", str(path), "--integrator", "leapfrog", "-o", str(out)]) == 0  # the file's own: kept
    assert read_netcdf(out).attrs["dt"] == 5e-7 and "left out" not in capsys.readouterr().err


# -- the examples ---------------------------------------------------------------------------------------
def _run_example(name, tmp_path, t_end="0.005"):
    out = tmp_path / f"{name}.nc"
    assert main(["run", str(EXAMPLES / f"{name}.toml"), "--n", "11", "--t-end", t_end, "-o", str(out)]) == 0
    return read_netcdf(out)


def test_every_example_is_tested():
    assert {p.stem for p in EXAMPLES.glob("*.toml")} == {"pressurised_sphere", "drum_spin_down", "cone_spin_up",
                                                         "torus_gravity"}


def test_the_pressurised_sphere_grows_under_its_ramp(tmp_path):
    ds = _run_example("pressurised_sphere", tmp_path)
    r_eq = ds.r.isel(s=ds.sizes["s"] // 2).values  # the equator
    assert r_eq[0] == pytest.approx(1.0, abs=1e-12)  # R = auto under the ramp's zero load: the natural sphere
    assert np.all(np.diff(r_eq) > 0) and 1e-5 < r_eq[-1] - 1 < 1e-3
    assert abs(float(ds.attrs["energy_balance_error"])) < 1e-6


def test_the_drum_spins_down_at_the_drag_rate(tmp_path):
    ds = _run_example("drum_spin_down", tmp_path)
    H = ds.angular_momentum.values
    assert np.all(np.diff(H) < 0)
    # the spin's decay exp(-drag t / rho_A), rho_A = rho 2h the mass per unit area
    expected = math.exp(-ds.attrs["drag"] * ds.time.values[-1] / ds.attrs["rho_A"])
    assert H[-1] / H[0] == pytest.approx(expected, rel=1e-3)


def test_the_cone_spins_up_from_its_driven_edge(tmp_path):
    """The driven edge turns by the integral of its ramped rate, 10 rad/s x min(t/0.02, 1):
    chi = 250 t^2 before 0.02 s, 0.1 + 10 (t - 0.02) after (leap-frog integrates the prescribed rate, second
    order in dt); the drive's torque has spun the shell up (positive angular momentum and reaction)."""
    ds = _run_example("cone_spin_up", tmp_path)
    t = ds.time.values
    expected = np.where(t < 0.02, 250 * t**2, 0.1 + 10 * (t - 0.02))
    np.testing.assert_allclose(ds.chi.isel(s=0).values, expected, atol=1e-8)
    assert ds.angular_momentum.values[-1] > 0 and np.nanmax(ds.reaction_torque.values[:, 0]) > 0
    assert np.all(ds.reaction_torque.values[:, 1] == 0)  # the free edge: nothing holds it, no torque there


def test_the_torus_sags_under_gravity(tmp_path):
    ds = _run_example("torus_gravity", tmp_path)
    dz = ds.z.isel(s=ds.sizes["s"] // 2).values - ds.z.isel(s=ds.sizes["s"] // 2).values[0]
    t = ds.time.values
    assert np.all(np.diff(dz) < 0)
    # the equator falls freely until the edges' waves arrive (and a little slower after)
    assert dz[1] == pytest.approx(-0.5 * 9.81 * t[1] ** 2, rel=1e-3) and -0.5 * 9.81 * t[-1] ** 2 < dz[-1] < 0


def test_the_readme_file_is_the_pressurised_sphere_example(tmp_path):
    import re

    blocks = re.findall(r"^```toml\n(.*?)^```", (EXAMPLES.parent / "README.md").read_text(), flags=re.S | re.M)
    assert len(blocks) == 1
    (tmp_path / "readme.toml").write_text(blocks[0])
    scene, run = load_scene(tmp_path / "readme.toml", with_run=True)
    example, example_run = load_scene(EXAMPLES / "pressurised_sphere.toml", with_run=True)
    assert scene == example and dict(run, integrator="leapfrog") == example_run


# -- refusals -------------------------------------------------------------------------------------------
BAD = [
    ('scene = "sphere"\n[material]\nnu = 0.7\n', "[material] nu = 0.7 is outside (-1, 0.5)"),
    ('scene = "sphere"\n[geometri]\na = 1\n', "[geometri] is not a table of a scene file; allowed: scene = NAME and"),
    ('scene = "sphere"\ncolour = 1\n', "colour is not a key of a scene file; allowed: scene = NAME and [geometry]"),
    ('scene = "sphere"\n[geometry]\ncolour = 1\n', "[geometry] colour is not a parameter of scene sphere; allowed: a, alpha1, alpha2"),
    ('scene = "sphere"\n[geometry]\nh = 0.01\n', "[geometry] h belongs in [material], not [geometry]"),
    ('scene = "sphere"\nh = 0.01\n', "h = 0.01 belongs in [material]"),
    ('scene = "sphere"\nmaterial = "svk"\n', 'material = "svk" belongs in [material]'),
    ('scene = "sphere"\n[geometry]\na = "big"\n', "[geometry] a = 'big' is not a number; allowed: (0, inf) m"),
    ('scene = "sphere"\n[material]\nE = true\n',
     "[material] E = true is not a number; allowed: [2.2250738585072014e-308, inf) Pa"),
    ('scene = "sphere"\n[material]\nn_quad = 4.0\n', "[material] n_quad = 4.0 is not an integer; allowed: integers 2..32"),
    ('scene = "sphere"\n[initial]\nR = 5\n', "[initial] R = 5 is outside (a/2, 2a) = (0.5, 2) m"),
    ('scene = "torus"\n[geometry]\nalpha2 = [1, 2]\n', "[geometry] alpha2 = [1, 2] is not a number"),
    ('scene = "sphere"\n[edges]\nend1 = "glued"\n', "[edges] end1 = 'glued' is outside {magnet, clamped"),
    # each says what is wrong (they all said the same 400 characters of every form)
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "ramp", t1 = -1}\n',
     ("[loads] pressure_history = {kind = \"ramp\", t1 = -1} is outside {kind = \"ramp\", t1 = T1} (as 'ramp T1' "
     "(t/T1 up to 1, T1 >= 1e-300 s))")),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "ramp", t = 1}\n',
     ('[loads] pressure_history = {kind = "ramp", t = 1} is outside {kind = "ramp", t1 = T1} (ramp takes t1; t1 '
     'missing, not t)')),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "ramp", T1 = 1}\n',  # both said
     ('[loads] pressure_history = {kind = "ramp", T1 = 1} is outside {kind = "ramp", t1 = T1} (ramp takes t1; t1 '
      'missing, not T1)')),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "ramp", t1 = 1, extra = 3}\n',
     ('[loads] pressure_history = {kind = "ramp", t1 = 1, extra = 3} is outside {kind = "ramp", t1 = T1} (ramp takes '
     't1; not extra)')),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "table", t = [0, 2, 1], h = [0, 1, 1]}\n',
     ('[loads] pressure_history = {kind = "table", t = [0, 2, 1], h = [0, 1, 1]} is outside {kind = "table", '
     "t = [t0, t1, ...], h = [h0, h1, ...]} (as 'table t0:h0 t1:h1 ...' (linear between, held beyond; times "
     "increasing, at least 1e-300 s apart, slopes finite))")),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "table", t = [0, 1], h = [0, 1, 1]}\n',
     ('[loads] pressure_history = {kind = "table", t = [0, 1], h = [0, 1, 1]} is outside {kind = "table", '
     't = [t0, t1, ...], h = [h0, h1, ...]} (t has 2 values and h 3: one h for each t)')),
    ('scene = "sphere"\n[loads]\npressure = 1\npressure_history = {kind = "linear", t1 = 1}\n',
     '[loads] pressure_history = {kind = "linear", t1 = 1} is outside {kind = "constant"}, {kind = "step", t0 = T0}'),
    ('scene = "sphere"\n[loads]\npressure_history = "ramp"\n', "[loads] pressure_history = 'ramp' is outside 'constant'"),
    ('scene = "sphere"\n[run]\nn = 2\n', "[run] n = 2 is outside integers >= 3"),
    ('scene = "sphere"\n[run]\nt_end = "long"\n', "[run] t_end = 'long' is not a number; allowed: (0, inf) s"),
    ('scene = "sphere"\n[run]\nsteps = 2\n', "[run] steps is not a key of [run]; allowed: integrator, n, t_end"),
    ('scene = "sphere"\n[run]\nintegrator = "euler"\n', "[run] integrator = 'euler' is outside {leapfrog"),
    ('scene = "sphere"\n[run]\ntimes = [0, 1, 1]\n', "[run] times = [0, 1, 1] is outside increasing"),
    # (on an integrator that takes atol: on leap-frog, the default, it is said to be no option of it first)
    ('scene = "sphere"\n[run]\nintegrator = "cvode-bdf"\natol = {q = 1e-9}\n',
     "[run] atol = 'q' is outside {z, r, chi, theta, psi}"),
    # the integrator's checks across options: they named no file and table (and jac_every was kept unused)
    ('scene = "sphere"\n[run]\nintegrator = "cvode-bdf"\nmax_order = 9\n', "[run] max_order = 9 is outside integers "
     "in [1, 5]"),
    ('scene = "sphere"\n[run]\nintegrator = "cvode-adams"\njac_every = 20\n', "[run] jac_every = 20 is an option of "
     "Newton's iteration, which cvode-adams runs only with iteration = 'newton'"),
    ('scene = "sphere"\n[geometry\na = 1\n', "not valid TOML: Expected ']' at the end of a table declaration (at line 2"),
    ('scene = "drum"\n', "scene = 'drum' is outside {axisymmetric, cone, meridian"),
    ('[geometry]\na = 1\n', "scene is missing: give scene = NAME with NAME in {axisymmetric"),
    ('scene = "meridian"\n[geometry]\npoints = "nope.txt"\n', "[geometry] points = "),
]


def test_a_file_option_the_command_lines_integrator_refuses_as_set_is_left_out_with_a_note(tmp_path, capsys):
    """A cvode-bdf file's jac_every run with --integrator cvode-adams (fixed-point: no Newton) was refused blaming
    an iteration the user never set; it is left out with a note, as an option the integrator does not have is."""
    path = tmp_path / "bdf.toml"
    path.write_text('scene = "twisted-cylinder"\n[run]\nintegrator = "cvode-bdf"\njac_every = 5\nn = 8\n'
                    't_end = 0.001\n')
    assert main(["run", str(path), "--integrator", "cvode-adams", "-o", str(tmp_path / "x.nc")]) == 0
    err = capsys.readouterr().err
    assert "note: the scene file's [run] jac_every = 5 is not taken by cvode-adams (--integrator) as it is set" in err


@pytest.mark.parametrize("text,message", BAD)
def test_a_bad_file_is_refused_in_one_line_naming_file_and_key(text, message, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    out = tmp_path / "out" / "x.nc"
    assert main(["run", str(path), "--t-end", "1e-5", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert not out.exists() and not out.parent.exists()
    with pytest.raises(ParameterError) as refused:
        load_scene(path)
    assert str(refused.value).startswith(f"{path}: {message}"), refused.value
    assert err.splitlines() == [f"mol-shell: error: {refused.value}"], err  # the library's message, all of stderr


def test_a_missing_file_and_a_missing_name_are_refused(tmp_path, capsys):
    path = tmp_path / "none.toml"
    assert main(["run", str(path), "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]) == 2
    assert capsys.readouterr().err == f"mol-shell: error: {path}: cannot read the scene file (No such file or directory)\n"
    assert main(["run", str(tmp_path), "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]) == 2  # not a .toml: a scene
    assert "scene = " in capsys.readouterr().err
    assert main(["scenes", "--toml"]) == 2
    assert capsys.readouterr().err.startswith("mol-shell: error: name is missing: give mol-shell scenes NAME --toml")


def test_load_scene_of_something_not_a_path_is_refused_by_name():
    """load_scene(None) raised TypeError."""
    for bad in (None, 3):
        with pytest.raises(ParameterError, match=f"^scene file = {bad} is not a file path"):
            load_scene(bad)


def test_compare_takes_the_files_saved_times(tmp_path, capsys):
    """``[run] times`` was ignored by compare, which ran the paper's snapshots to 0.143 s instead."""
    path = tmp_path / "t.toml"
    path.write_text('scene = "sphere"\n[run]\nn = 8\ntimes = [0, 1e-5, 2e-5]\n')
    out = tmp_path / "c.nc"
    assert main(["compare", str(path), "--integrators", "dop853-c", "--repeats", "1", "-o", str(out)]) == 0
    assert read_netcdf(out).attrs["times"] == "0,1e-05,2e-05"


def test_layers_tables_by_a_plural_name_point_to_layer(tmp_path):
    """``[[layers]]`` (a typo of ``[[layer]]``) was refused as "layers = [...] belongs in [material]"."""
    path = tmp_path / "typo.toml"
    path.write_text('scene = "sphere"\n[material]\nh = 0.01\n[[layers]]\nthickness = 0.01\nmaterial = "svk"\n'
                    '[[layers]]\nthickness = 0.01\nmaterial = "svk"\n')
    with pytest.raises(ParameterError, match=r"typo.toml: \[\[layers\]\] tables are not read; allowed: \[\[layer\]\] "):
        load_scene(path)


def test_a_run_table_sets_any_option_of_its_integrator(tmp_path, capsys):
    """cli.md promised the [run] table "the integrator and its options", but only dt, rtol, atol and max_step were
    keys: ``jac_every = 20`` was "not a key of [run]". The integrator's declared options are keys now, checked
    against their declared ranges, and reach the run (its file records them)."""
    scene_file = tmp_path / "a.toml"
    table = '[run]\nintegrator = "cvode-adams"\niteration = "newton"\njac_every = 20\nn = 12\nt_end = 0.002\n'
    scene_file.write_text('scene = "twisted-cylinder"\n' + table)
    _, run = load_scene(scene_file, with_run=True)
    assert (run["iteration"], run["jac_every"]) == ("newton", 20)
    assert main(["run", str(scene_file), "-o", str(tmp_path / "a.nc")]) == 0
    ds = read_netcdf(tmp_path / "a.nc")
    assert (ds.attrs["iteration"], int(ds.attrs["jac_every"])) == ("newton", 20)
    scene_file.write_text('scene = "twisted-cylinder"\n' + table.replace("jac_every = 20", "jac_every = -1"))
    assert main(["run", str(scene_file), "-o", str(tmp_path / "b.nc")]) == 2
    assert capsys.readouterr().err.strip().endswith(
        "[run] jac_every = -1 is outside integers in [0, 2147483647] (0: SUNDIALS' 51)")
    scene_file.write_text('scene = "twisted-cylinder"\n' + table.replace("jac_every", "jacevery"))
    assert main(["run", str(scene_file), "-o", str(tmp_path / "c.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert "jacevery is not a key of [run]" in err and "the options of cvode-adams: anderson" in err, err


def test_the_refusal_of_an_option_lists_all_the_integrator_s_options(tmp_path, capsys):
    """The refusal listed the three options of the command line as all an integrator's options (it has 16); every
    one is now given on the command line too (the flags, and --option NAME=VALUE for the others)."""
    assert main(["run", "sphere", "--integrator", "cvode-bdf", "--dt", "1e-6", "--n", "10", "--t-end", "0.001",
                 "-o", str(tmp_path / "a.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("mol-shell: error: dt is not an option of cvode-bdf (its options: anderson, atol, ") \
        and "jac_every" in err and "rtol" in err, err


def test_the_command_line_can_mend_a_file_s_run_options(tmp_path, capsys):
    """A file's [run] options were checked across each other for its own integrator as it was read, before
    --integrator or --option applied: cvode-adams with jac_every (Newton's) could not be run as cvode-bdf or with
    --option iteration=newton. They are checked with the command line's applied, and a file's own mistake still names
    the file and [run] (a file's dt on cvode-bdf did not)."""
    f = tmp_path / "adams.toml"
    f.write_text('scene = "twisted-cylinder"\n[run]\nintegrator = "cvode-adams"\njac_every = 20\nn = 8\nt_end = 0.0005\n')
    out = str(tmp_path / "x.nc")
    assert main(["run", str(f), "-o", out]) == 2
    assert capsys.readouterr().err.startswith(f"mol-shell: error: {f}: [run] jac_every = 20 is an option of Newton's")
    assert main(["run", str(f), "--integrator", "cvode-bdf", "-o", out]) == 0
    assert main(["run", str(f), "--option", "iteration=newton", "-o", out]) == 0
    assert read_netcdf(out).attrs["jac_every"] == 20
    with pytest.raises(ParameterError, match=r"\[run\] jac_every = 20 is an option of Newton's"):
        load_scene(f, with_run=True)  # Python reads the file as it stands
    g = tmp_path / "bdf.toml"
    g.write_text('scene = "twisted-cylinder"\n[run]\nintegrator = "cvode-bdf"\ndt = 1e-6\nn = 8\nt_end = 0.0005\n')
    capsys.readouterr()
    assert main(["run", str(g), "-o", out]) == 2
    assert capsys.readouterr().err.startswith(f"mol-shell: error: {g}: [run] dt is not an option of cvode-bdf")


def test_a_scene_file_saved_with_a_byte_order_mark_is_read(tmp_path):
    """A file saved by Windows Notepad starts with a UTF-8 byte-order mark: it was refused as ``not valid TOML:
    Invalid statement (at line 1, column 1)``, with nothing to see in the file."""
    plain, marked = tmp_path / "plain.toml", tmp_path / "marked.toml"
    text = 'scene = "sphere"\n[geometry]\na = 2.0\n[run]\nn = 8\nt_end = 0.001\n'
    plain.write_text(text, encoding="utf-8")
    marked.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    assert load_scene(marked, with_run=True) == load_scene(plain, with_run=True)


@pytest.mark.parametrize("a", [1e-9, 1e-4])
def test_a_shell_too_small_for_its_wall_is_refused_naming_its_size_in_the_file(a, tmp_path):
    """A sphere of radius 1e-9 m with the default wall (h = 6.3 mm) passed the scene's check (its test of the
    faces left out every node as a pole: r below 1e-9 m) and was refused only as the system was built, naming the
    default h and no file. The scene now refuses it, naming the file, its table and ``a``."""
    path = tmp_path / "tiny.toml"
    path.write_text(f'scene = "sphere"\n[geometry]\na = {a!r}\n[run]\nn = 8\nt_end = 0.001\n')
    with pytest.raises(ParameterError, match=rf"^{re.escape(str(path))}: \[geometry\] a = {a:g} is outside values for "
                       r"which h = 0.006283 m fits"):
        load_scene(path)


def test_set_replaces_a_file_s_value_before_the_file_s_value_is_read(tmp_path, capsys):
    """A scene file whose law does not import (``material = "nomod:rubber"``) was refused before ``--set
    material=...`` could replace it: the file was made into a scene first. ``--set`` values now go in before the
    scene is made, so a value they replace is never read; a refusal of one of them is said as the command line's."""
    path = tmp_path / "bad.toml"
    path.write_text('scene = "sphere"\n[material]\nmaterial = "nomod:rubber"\nnu = 0.3\n[run]\nn = 8\nt_end = 1e-4\n')
    out = tmp_path / "a.nc"
    assert main(["run", str(path), "-o", str(out)]) == 2
    assert "[material] material = 'nomod:rubber'" in capsys.readouterr().err
    assert main(["run", str(path), "--set", "material=svk-plane-stress", "-o", str(out)]) == 0
    ds = read_netcdf(out)
    assert ds.attrs["material"] == "svk-plane-stress" and ds.attrs["nu"] == 0.3  # the file's other values kept
    capsys.readouterr()
    assert main(["run", str(path), "--set", "material=svk-plane-stress", "--set", "nu=0.7", "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == "mol-shell: error: nu = 0.7 is outside (-1, 0.5)"
    scene = load_scene(path, overrides={"material": "svk", "gamma": "0.2"})
    assert scene.material == "svk" and scene.gamma == 0.2 and scene.nu == 0.3
