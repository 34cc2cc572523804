"""A scene file's values as a new user writes them: long strings and ``~user`` strings are no paths, integers beyond
the floats' range are refused by key, refusals found as the file's scene runs name the file and the table, a
history is one string however it was given, messages spell values as TOML does, and a run file is written back as a
scene file that runs it again to the bit."""

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.inputs import scene_file_inputs
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf
from mol_shell.scenes.files import load_scene

NO_USER = "~mol_shell_no_such_user_4711"  # a home directory no machine has
BIG = "1" + "0" * 400  # TOML's integers are unbounded: 1e400, beyond double precision's 1.8e308
FLOAT_RANGE = "beyond the floats' range (magnitude up to 1.798e+308)"
FIELDS = ("z", "r", "chi", "theta", "psi")


def _refused(tmp_path, capsys, text, *args, name="bad.toml"):
    """stderr's one line (without ``mol-shell: error: ``) of ``run FILE`` of a scene file ``text``, exit code 2."""
    path = tmp_path / name
    path.write_text(text)
    code = main(["run", str(path), *args, "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, (code, err)
    assert err.startswith("mol-shell: error: ")
    return err.removeprefix("mol-shell: error: ").strip(), path


# -- 1: strings that are no paths, and paths that cannot be --------------------------------------------------------
def test_a_history_longer_than_a_file_name_runs(tmp_path, capsys):
    """A table of 30 points (over 255 bytes) was taken as a path: File name too long, an internal error."""
    table = " ".join(f"{k * 1e-6:.7f}:{k / 29:.6f}" for k in range(30))
    assert len(table) > 255
    path = tmp_path / "hist.toml"
    path.write_text(f'scene = "sphere"\n[loads]\npressure = 1000.0\npressure_history = "table {table}"\n'
                    "[run]\nn = 8\nt_end = 1e-5\n")
    assert main(["run", str(path), "-o", str(tmp_path / "h.nc")]) == 0, capsys.readouterr().err
    history = read_netcdf(tmp_path / "h.nc").attrs["pressure_history"]
    assert history.startswith("table 0:0 1e-06:0.034483 2e-06:0.068966") and len(history.split()) == 31


@pytest.mark.parametrize("table,key,value", [
    ("material", "h_profile", "'" + " ".join(["0.006"] * 60) + "'"),
    ("geometry", "segments", "'" + "; ".join(["line 0.1"] * 40) + "'"),
    ("material", "layers", "'" + "; ".join(["0.001 svk"] * 40) + "'"),
    ("material", "material", "'" + "x" * 300 + "'"),
    ("material", "material", f"'{NO_USER}'"),
])
def test_long_and_tilde_strings_are_refused_as_values_not_crashed_on_as_paths(table, key, value, tmp_path, capsys):
    scene = "vessel" if key == "segments" else "sphere"
    err, path = _refused(tmp_path, capsys, f'scene = "{scene}"\n[{table}]\n{key} = {value}\n', "--n", "8",
                         "--t-end", "1e-5")
    assert err.startswith(f"{path}: [{table}] {key}"), err


def test_a_points_path_of_no_user_s_home_is_refused_naming_file_and_key(tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, f'scene = "meridian"\n[geometry]\npoints = "{NO_USER}/p.txt"\n')
    assert err.startswith(f"{path}: [geometry] points = '{NO_USER}/p.txt' starts with {NO_USER}, which is no user's "
                          "home directory; allowed: a file path"), err


def test_a_points_name_too_long_for_the_file_system_is_refused_by_name(tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, f'scene = "meridian"\n[geometry]\npoints = "{"p" * 300}.txt"\n')
    assert err.startswith(f"{path}: [geometry] points = ") and "is not a readable file (File name too long)" in err
    assert main(["run", "meridian", "--set", f"points={'p' * 300}", "-o", str(tmp_path / "x.nc")]) == 2
    assert "points = " in capsys.readouterr().err


def test_a_scene_file_in_no_user_s_home_is_refused_by_name(tmp_path, capsys):
    assert main(["run", f"{NO_USER}/x.toml", "-o", str(tmp_path / "x.nc")]) == 2
    assert capsys.readouterr().err == (f"mol-shell: error: {NO_USER}/x.toml: cannot read the scene file ({NO_USER} is "
                                       "no user's home directory)\n")


def test_only_keys_that_name_files_are_looked_up_as_files(tmp_path):
    (tmp_path / "p.txt").write_text("1 0\n0.9 0.3\n0.5 0.55\n0 0.6\n")
    (tmp_path / "svk").write_text("a file named as a law")
    path = tmp_path / "s.toml"
    path.write_text(f'scene = "meridian"\n[geometry]\npoints = "p.txt"\n[material]\nmaterial = "svk"\n'
                    f'h_profile = "{"0.006 " * 60}"\n[loads]\npressure_history = "{NO_USER}/x"\n')
    assert scene_file_inputs(path) == {f"{path}: [geometry] points": str(tmp_path / "p.txt")}
    assert scene_file_inputs(path, skip={"points"}) == {}


# -- 2: integers beyond the floats' range ---------------------------------------------------------------------------
@pytest.mark.parametrize("text,message", [
    (f"[material]\nE = {BIG}\n", (f"[material] E = 100000000000000000...0000000000000000000 is {FLOAT_RANGE}; "
                                   "allowed: [2.2250738585072014e-308, inf) Pa")),
    (f"[geometry]\nalpha2 = -{BIG}\n", ("[geometry] alpha2 = -10000000000000000...0000000000000000000 is "
                                        f"{FLOAT_RANGE}; allowed: (0, pi] rad")),
    (f'[[layer]]\nthickness = {BIG}\nmaterial = "svk"\n', ("[[layer]] 1 (from the lower face): thickness = "
                                                           f"100000000000000000...0000000000000000000 is {FLOAT_RANGE}; "
                                                           "allowed: finite numbers")),
    (f'[material]\nmaterial = "neo-hookean"\nmaterial_parameters = {{mu = {BIG}}}\n',
     f"[material] material_parameters.mu = 100000000000000000...0000000000000000000 is {FLOAT_RANGE}"),
    (f'[loads]\npressure = 1\npressure_history = {{kind = "ramp", t1 = {BIG}}}\n',
     f"[loads] pressure_history.t1 = 100000000000000000...0000000000000000000 is {FLOAT_RANGE}"),
    (f'[loads]\npressure = 1\npressure_history = {{kind = "table", t = [0, {BIG}], h = [0, 1]}}\n',
     "[loads] pressure_history.t holds 100000000000000000...0000000000000000000, beyond the floats' range"),
    (f"[run]\ntimes = [0, {BIG}]\n", ("[run] times = [0, 100000000000000000...0000000000000000000] holds "
                                      "100000000000000000...0000000000000000000, beyond the floats' range; allowed: "
                                      "increasing finite times")),
    (f"[run]\nt_end = {BIG}\n", (f"[run] t_end = 100000000000000000...0000000000000000000 is {FLOAT_RANGE}; "
                                  "allowed: (0, inf) s")),
])
def test_an_integer_beyond_the_floats_range_is_refused_naming_file_table_and_key(text, message, tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, 'scene = "sphere"\n' + text)
    assert err.startswith(f"{path}: {message}"), err
    with pytest.raises(ParameterError, match="beyond the floats' range"):
        load_scene(path)


def test_a_node_count_beyond_64_bits_is_refused_naming_the_file(tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, f'scene = "sphere"\n[run]\nn = {BIG}\nt_end = 1e-5\n')
    assert err == (f"{path}: [run] n = 100000000000000000...0000000000000000000 is outside integers in "
                   "[3, 9,223,372,036,854,775,807] (NumPy's 64-bit indices)")


# -- 3: refusals found as the file's scene runs -----------------------------------------------------------------------
@pytest.mark.parametrize("text,message", [
    ("[run]\nn = 8\nt_end = 0.001\ndt = 0.001\n", "[run] dt = 0.001 is outside (0, "),  # the stability bound
    ("[run]\nn = 8\nt_end = 0.002\ntimes = [0, 0.001]\n", "[run] t_end = 0.002 is outside the last saved time 0.001 s"),
    ("[run]\nn = 8\ntimes = [0, 0.0000015]\n", "[run] times = 1.5e-06 is outside multiples of dt = 1e-06 s"),
    ("[run]\nn = 9223372036854775807\nt_end = 1e-5\n", "[run] n = 9223372036854775807 is outside integers 3.."),
    ('[edges]\nend1 = "clamped"\n[run]\nn = 8\nt_end = 1e-5\n', "[edges] end1 = 'clamped' is outside {pole, auto}"),
])
def test_a_refusal_of_a_file_s_value_found_as_it_runs_names_file_and_table(text, message, tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, 'scene = "sphere"\n' + text)
    assert err.startswith(f"{path}: {message}"), err


def test_a_value_the_command_line_gave_is_said_as_the_command_line_gave_it(tmp_path, capsys):
    err, _ = _refused(tmp_path, capsys, 'scene = "sphere"\n[edges]\nend1 = "auto"\n[run]\nn = 8\ndt = 1e-7\n',
                      "--set", "end1=clamped", "--t-end", "1e-5")
    assert err.startswith("end1 = 'clamped' is outside {pole, auto}"), err
    err, _ = _refused(tmp_path, capsys, 'scene = "sphere"\n[run]\nn = 8\ndt = 1e-7\nt_end = 0.001\n',
                      "--dt", "0.001")
    assert err.startswith("dt = 0.001 is outside (0, "), err


# -- 4: one history, however it was given ---------------------------------------------------------------------------
def test_a_history_from_an_inline_table_and_from_the_command_line_are_one_string(tmp_path, capsys):
    inline = tmp_path / "inline.toml"
    inline.write_text('scene = "sphere"\n[loads]\ngravity = 1.0\n'
                      'gravity_history = {kind = "table", t = [0, 0.001, 0.002], h = [0, 1, 0.5]}\n')
    plain = tmp_path / "plain.toml"
    plain.write_text('scene = "sphere"\n[loads]\ngravity = 1.0\n')
    typed = "table 0:0 0.001:1 0.002:0.5"
    assert load_scene(inline).gravity_history == typed
    assert load_scene(inline).params() == load_scene(plain, overrides={"gravity_history": typed}).params() \
        == mol_shell.Sphere(gravity=1.0, gravity_history="Table 0.0:0.0, 1e-3:1.0 0.002:5e-1").params()
    for name, extra in (("a", []), ("b", ["--set", f"gravity_history={typed}"])):
        path = inline if name == "a" else plain
        assert main(["run", str(path), *extra, "--n", "8", "--t-end", "1e-5", "-o", str(tmp_path / f"{name}.nc")]) == 0
    a, b = read_netcdf(tmp_path / "a.nc").attrs, read_netcdf(tmp_path / "b.nc").attrs
    assert a["gravity_history"] == b["gravity_history"] == typed
    skip = {"history", "wall_time_s", "setup_time_s", "build_time_s"}
    assert {k: str(v) for k, v in a.items() if k not in skip} == {k: str(v) for k, v in b.items() if k not in skip}


# -- 5: messages ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("text,message", [
    ("[[material]]\nnu = 0.3\n", "material is an array of tables ([[material]]); allowed: [material], one table"),
    ("t_end = 0.1\n", "t_end = 0.1 belongs in [run]"),
    ("jac_every = 3\n", "jac_every = 3 belongs in [run]"),
    ('[initial]\nintegrator = "leapfrog"\n', "[initial] integrator belongs in [run], not [initial]"),
    ("[run]\nE = 1e6\n", "[run] E belongs in [material], not [run]"),
    ("[material]\nE = true\n", "[material] E = true is not a number"),
    ("[material]\nE = 1979-05-27\n", "[material] E = 1979-05-27 is not a number"),
    ("[run]\nt_end = 1979-05-27T07:32:00\n", "[run] t_end = 1979-05-27T07:32:00 is not a number"),
    ("[edges]\nend1 = false\n", "[edges] end1 = false is outside {magnet"),
    ('[[layer]]\nthickness = 0.01\nmaterial = true\n', "[[layer]] 1 (from the lower face): material = true is not"),
])
def test_messages_say_what_the_file_wrote_and_where_it_belongs(text, message, tmp_path, capsys):
    err, path = _refused(tmp_path, capsys, 'scene = "sphere"\n' + text)
    assert err.startswith(f"{path}: {message}"), err


# -- 6: a run file written back as a scene file ---------------------------------------------------------------------
RUNS = {
    "sphere with a history": ["sphere", "--set", "pressure=100", "--set", "pressure_history=ramp 1e-4",
                              "--times", "0,0.0001,0.0003", "--dt", "5e-7", "--option", "restart=0.0002"],
    "cylinder with layers and fibres": ["twisted-cylinder", "--integrator", "cvode-bdf", "--rtol", "1e-7", "--atol",
                                        "r=1e-8", "--option", "max_order=4", "--set", "h=0.006", "--set",
                                        "layers=0.004 svk; 0.008 neo-hookean", "--set", "fibre_E=1e5", "--set",
                                        "fibre_angle=0.3", "--t-end", "5e-4"],
    "meridian of a points file": ["meridian", "--set", "points=PTS", "--set", "gravity=9.81", "--set",
                                  "gravity_history=table 0:0 1e-4:1", "--t-end", "2e-4"],
}


@pytest.mark.parametrize("case", list(RUNS))
def test_a_run_file_written_back_as_a_scene_file_runs_again_to_the_bit(case, tmp_path, capsys):
    t = np.linspace(0, np.pi / 2, 9)
    np.savetxt(tmp_path / "pts.txt", np.c_[np.cos(t), 0.6 * np.sin(t)])
    args = [arg.replace("PTS", str(tmp_path / "pts.txt")) for arg in RUNS[case]]
    assert main(["run", *args, "--n", "9", "-o", str(tmp_path / "a.nc")]) == 0
    capsys.readouterr()
    assert main(["scenes", str(tmp_path / "a.nc"), "--toml"]) == 0
    (tmp_path / "a.toml").write_text(capsys.readouterr().out)
    assert main(["run", str(tmp_path / "a.toml"), "-o", str(tmp_path / "b.nc")]) == 0
    a, b = read_netcdf(tmp_path / "a.nc"), read_netcdf(tmp_path / "b.nc")
    assert np.array_equal(a.time.values, b.time.values)
    for field in FIELDS:
        assert np.array_equal(a[field].values, b[field].values), field
    _, run = load_scene(tmp_path / "a.toml", with_run=True)
    assert run["integrator"] == a.attrs["integrator"] and run["n"] == 9


def test_scenes_of_a_run_file_wants_toml_and_of_another_file_is_refused(tmp_path, capsys):
    (tmp_path / "s.toml").write_text('scene = "sphere"\n')
    assert main(["scenes", str(tmp_path / "none.nc"), "--toml"]) == 2
    assert "does not exist; allowed: a netCDF file written by mol-shell run" in capsys.readouterr().err
    assert main(["scenes", str(tmp_path / "s.toml"), "--toml"]) == 2
    assert "is a scene file (TOML), not a run file" in capsys.readouterr().err
