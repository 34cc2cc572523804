"""Scene files and the files they name as a new user gives them (docs/scene-files.md): a device or a named pipe as
``points`` or as the scene file is refused before it is read (``/dev/zero`` was read until the machine ran out of
memory, a pipe nobody writes to hung the run), a history table's points too close are blamed on the history, refused
values are shown as the file writes them, a missing ``t_end`` names the file, ``scenes`` says what it takes, and
``material_parameters`` take numbers as every numeric parameter does."""

import os
import threading
import time
from contextlib import contextmanager
from pathlib import Path

import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.model.loads import parse_history

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SCENES = "{axisymmetric, cone, meridian, sphere, spinning-ring, torus, twisted-cylinder, unshearable, vessel}"
POINTS_ALLOWED = "a text file with two columns r z (m), at least 4 rows, at most 64 MB"


def _refused(capsys, args):
    """The one error line (without ``mol-shell: error: ``) of ``main(args)``, which exits with 2."""
    code = main([str(a) for a in args])
    lines = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert code == 2 and len(lines) == 1, (code, lines)
    return lines[0].removeprefix("mol-shell: error: ")


@contextmanager
def _fifo(path):
    """A named pipe at ``path`` whose readers are let go: a writer opens and closes it whenever one waits (the code
    before the fix waited for a writer for ever); yields the list of times it found one (none: it was never opened
    for reading)."""
    os.mkfifo(path)
    opened, done = [], threading.Event()

    def release():
        while not done.wait(0.05):
            try:
                os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))  # ENXIO while no reader has it open
                opened.append(time.monotonic())
            except OSError:  # ENXIO: no reader waits
                pass

    writer = threading.Thread(target=release, daemon=True)
    writer.start()
    try:
        yield opened
    finally:
        done.set()
        writer.join()


# -- 1: devices and named pipes, refused before they are opened --------------------------------------------------
@pytest.mark.parametrize("how", ["points in the file", "--set points", "the scene file"])
def test_a_named_pipe_as_points_or_as_the_scene_file_is_refused_unopened(how, tmp_path, capsys):
    fifo = tmp_path / ("fifo.toml" if how == "the scene file" else "fifo")
    scene = tmp_path / "mer.toml"
    scene.write_text('scene = "meridian"\n[geometry]\npoints = "fifo"\n' if how == "points in the file" else
                     'scene = "meridian"\n')
    given = {"points in the file": [scene], "--set points": [scene, "--set", f"points={fifo}"],
             "the scene file": [fifo]}[how]
    with _fifo(fifo) as opened:
        err = _refused(capsys, ["run", *given, "--n", "9", "--t-end", "1e-5", "-o", tmp_path / "x.nc"])
    assert not opened, "the pipe was opened for reading"
    said = {"points in the file": f"{scene}: [geometry] points = '{fifo}' is a named pipe (FIFO), not a regular file; "
            f"allowed: {POINTS_ALLOWED}",
            "--set points": f"points = '{fifo}' is a named pipe (FIFO), not a regular file; allowed: {POINTS_ALLOWED}",
            "the scene file": f"{fifo}: the scene file is a named pipe (FIFO), not a regular file; allowed: a TOML "
            "file of at most 64 MB"}[how]
    assert err == said


def test_a_device_as_points_or_as_the_scene_file_is_refused_before_it_is_read(tmp_path, capsys):
    from mol_shell._core.user_files import not_regular  # missing before the fix: /dev/zero is then never read

    assert not_regular("/dev/zero") == "is a character device, not a regular file"
    scene = tmp_path / "mer.toml"
    scene.write_text('scene = "meridian"\n[geometry]\npoints = "/dev/zero"\n')
    options = ["--n", "9", "--t-end", "1e-5", "-o", tmp_path / "x.nc"]
    assert _refused(capsys, ["run", scene, *options]) == (f"{scene}: [geometry] points = '/dev/zero' is a character "
                                                          f"device, not a regular file; allowed: {POINTS_ALLOWED}")
    zero = tmp_path / "zero.toml"
    zero.symlink_to("/dev/zero")
    assert _refused(capsys, ["run", zero, *options]) == (f"{zero}: the scene file is a character device, not a "
                                                         "regular file; allowed: a TOML file of at most 64 MB")
    assert _refused(capsys, ["scenes", zero]) == (f"FILE = '{zero}' is a character device, not a regular file; "
                                                  f"allowed: a scene in {SCENES} or a run file RUN.nc (with --toml)")


def test_a_file_beyond_the_bound_is_refused_by_its_size(tmp_path):
    from mol_shell._core.user_files import MAX_USER_FILE_BYTES, UserFileError, read_user_file

    assert MAX_USER_FILE_BYTES == 64_000_000
    path = tmp_path / "p.txt"
    path.write_bytes(b"0 0\n1 1\n0 2")  # 11 bytes
    assert read_user_file(path, limit=11) == b"0 0\n1 1\n0 2"
    with pytest.raises(UserFileError) as refused:
        read_user_file(path, limit=10)
    assert refused.value.problem == "is larger than 10 bytes, the most a file read as a scene file or a table of " \
        "points may hold"


# -- 2: a history table's points too close: the history is named, with the spacing it takes -------------------------
@pytest.mark.parametrize("given", ["inline", "string", "--set"])
def test_a_history_table_with_points_too_close_names_the_history_and_its_spacing(given, tmp_path, capsys):
    """1e-310 s is below the ramp's floor 1e-300 s (the slope 1/1e-310 overflows double precision): it was blamed
    on the load, ``pressure = 100.0 is outside about (-inf, 1e-300] Pa``."""
    history = {"inline": 'pressure_history = {kind = "table", t = [0, 1e-310], h = [0, 1]}\n',
               "string": 'pressure_history = "table 0:0 1e-310:1"\n', "--set": ""}[given]
    scene = tmp_path / "p.toml"
    scene.write_text(f'scene = "sphere"\n[loads]\npressure = 100.0\n{history}')
    sets = ["--set", "pressure_history=table 0:0 1e-310:1"] if given == "--set" else []
    err = _refused(capsys, ["run", scene, *sets, "--n", "9", "--t-end", "1e-5", "-o", tmp_path / "x.nc"])
    start = {"inline": f"{scene}: [loads] pressure_history = {{kind", "string": f"{scene}: [loads] pressure_history = "
             "'table", "--set": "pressure_history = 'table"}[given]
    assert err.startswith(start) and "at least 1e-300 s apart" in err and "points 1e-310 s apart, at t = 0 s" in err, err


def test_a_history_table_s_floor_is_the_ramp_s():
    """Points 1e-300 s apart (a slope of 1e300 per s, as ``ramp 1e-300``) run; a slope beyond double precision
    (1e300 in 1e-300 s) is refused."""
    assert parse_history("p", "table 0:0 1e-300:1") == ("table", ((0.0, 1e-300), (0.0, 1.0)))
    with pytest.raises(ParameterError, match=r"from t = 0 s to 1e-300 s h goes from 0 to 1e\+300: a slope beyond"):
        parse_history("p", "table 0:0 1e-300:1e300")


# -- 3: values as the file writes them -----------------------------------------------------------------------------
@pytest.mark.parametrize("scene,text,said", [
    ("sphere", "[material]\nnu = 7e-1   # rubber", "[material] nu = 7e-1 is outside (-1, 0.5)"),
    ("sphere", '[material]\nE = {value = 1e6, unit = "Pa"}', ('[material] E = {value = 1e6, unit = "Pa"} is not a '
                                                              "number; allowed: [2.2250738585072014e-308, inf) Pa")),
    ("sphere", '[material]\nh_profile = {kind="table", t = [0, 1], h = [0, 1]}',
     '[material] h_profile = {kind="table", t = [0, 1], h = [0, 1]} is not a string'),
    ("sphere", "[run]\ntimes = {a = 1}", "[run] times = {a = 1} is not a list of numbers"),
    ("twisted-cylinder", '[edges]\nend1 = ["r","theta"]', '[edges] end1 = ["r","theta"] is outside {magnet'),
    ("twisted-cylinder", "[edges]\nend1 = [\n  'r', 'theta']", '[edges] end1 = ["r", "theta"] is outside {magnet'),  # 2 lines
    ("sphere", ("[[layer]]\nthickness = 0.006\nmaterial = 'svk'\n[[layer]]\nthickness = 0.006\nmaterial = 'svk'\n"
                "[[layer]]\nthickness = 0.0\nmaterial = 'svk'"),
     ("[[layer]] 3 (from the lower face): a thickness 0, not a positive finite number; allowed: thickness (m, a "
      "positive finite number), material and E, nu")),
])
def test_refused_values_are_shown_as_the_file_writes_them(scene, text, said, tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text(f'scene = "{scene}"\n{text}\n')
    err = _refused(capsys, ["run", path, "--n", "9", "--t-end", "1e-5", "-o", tmp_path / "x.nc"])
    assert err.startswith(f"{path}: {said}"), err


# -- 4, 5, 6 --------------------------------------------------------------------------------------------------------
def test_a_missing_t_end_names_the_file_and_its_run_table(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("c1.toml").write_text('scene = "sphere"\n[run]\nn = 9\n')
    assert _refused(capsys, ["run", "c1.toml", "-o", "x.nc"]) == ("c1.toml: [run] t_end is missing: give t_end in "
                                                                 "(0, inf) s, or times")


def test_scenes_says_what_it_takes_alike_for_a_scene_file_a_missing_file_and_a_pipe(tmp_path, capsys):
    """``scenes`` takes a scene or a run file (docs/cli.md); a missing file's refusal offered "a scene file", which
    ``scenes FILE.toml`` refuses as "a scene file (TOML), not a run file"."""
    allowed = f"allowed: a scene in {SCENES} or a run file RUN.nc (with --toml)"
    missing = tmp_path / "nosuch.toml"
    assert _refused(capsys, ["scenes", missing]) == f"FILE = '{missing}' does not exist; {allowed}"
    torus = EXAMPLES / "torus_gravity.toml"
    assert f"FILE = '{torus}' is a scene file (TOML), not a run file" in _refused(capsys, ["scenes", torus])
    with _fifo(tmp_path / "run.nc") as opened:
        err = _refused(capsys, ["scenes", tmp_path / "run.nc", "--toml"])
    assert not opened and err == f"FILE = '{tmp_path / 'run.nc'}' is a named pipe (FIFO), not a regular file; {allowed}"


def test_material_parameters_are_numbers_as_every_numeric_parameter(tmp_path, capsys):
    """``E = "1e6"`` is refused as not a number; ``material_parameters = {mu = "2e5"}`` was taken."""
    path = tmp_path / "s.toml"
    path.write_text('scene = "sphere"\n[material]\nmaterial_parameters = {mu = "2e5"}\n')
    assert _refused(capsys, ["run", path, "--n", "9", "--t-end", "1e-5", "-o", tmp_path / "x.nc"]) == \
        f"{path}: [material] material_parameters.mu = '2e5' is not a number; allowed: finite numbers"


# -- run files and outputs that are named pipes --------------------------------------------------------------------
@pytest.mark.parametrize("command", [["plot", "{fifo}", "-o", "{tmp}/x.png"], ["export", "{fifo}", "-o", "{tmp}/x.pvd"],
                                     ["animate", "{fifo}", "-o", "{tmp}/x.gif"], ["scenes", "{fifo}", "--toml"]])
def test_a_named_pipe_as_a_run_file_is_refused_unopened(command, tmp_path, capsys):
    """``plot f.nc`` of a named pipe waited in netCDF's open for ever, deaf to SIGTERM; now refused as the pipe it is,
    before it is opened (the helper lets a reader go, so the code before the fix failed on an empty file instead)."""
    fifo = tmp_path / "f.nc"
    with _fifo(fifo) as opened:
        err = _refused(capsys, [a.format(fifo=fifo, tmp=tmp_path) for a in command])
    assert not opened, "the pipe was opened for reading"
    assert f"'{fifo}' is a named pipe (FIFO), not a regular file; allowed: " in err


def test_a_named_pipe_as_the_output_is_refused_unopened(tmp_path, capsys):
    """``-o f.nc`` of a named pipe: the writable-place probe opened it for appending and waited for a reader for ever;
    now refused. A reader is let in after 2 s, so the code before the fix ended too (and wrote into the pipe)."""
    fifo = tmp_path / "f.nc"
    os.mkfifo(fifo)
    opened, done = [], threading.Event()

    def reader():
        if not done.wait(2.0):
            fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
            opened.append(fd)

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    try:
        err = _refused(capsys, ["run", "twisted-cylinder", "--n", "9", "--t-end", "1e-5", "-o", fifo])
    finally:
        done.set()
        thread.join()
        for fd in opened:
            os.close(fd)
    assert not opened and err == (f"-o = '{fifo}' is a named pipe (FIFO), not a regular file; allowed: a file path in "
                                  "a writable place (missing directories are created)")
