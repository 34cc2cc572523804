"""Files at the edges: a file size limit (``ulimit -f``), a cache folder removed during a build, input names longer
than the file system takes, run file names that are not UTF-8 or hold a newline, ``-o`` onto a symbolic link, run
files without their attributes, and a study's cases folder that cannot be written."""

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import tomllib
import xarray as xr

from mol_shell._core import atomic, user_files
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import writable_path
from mol_shell.analysis.path_start import scene_params
from mol_shell.cli.main import main
from mol_shell.discretization import compiled, kernel_cache
from mol_shell.results import study_store
from mol_shell.results.dataset import write_netcdf
from mol_shell.scenes.file_writer import scene_toml
from mol_shell.scenes.files import load_scene
from mol_shell.scenes.shells import MeridianShell

ROOT = Path(__file__).resolve().parents[2]
#: a file size limit (bytes) far below what the writes of the child below need
LIMIT = 64 * 1024

CHILD = textwrap.dedent("""
    import json, resource, signal, sys
    from pathlib import Path
    import numpy as np, xarray as xr
    from mol_shell._core import atomic
    from mol_shell.discretization import compiled
    from mol_shell.results.dataset import write_netcdf
    from mol_shell._core.errors import ParameterError
    folder, limit = Path(sys.argv[1]), int(sys.argv[2])
    small = xr.Dataset({"x": ("i", np.arange(10.0))})
    write_netcdf(small, folder / "old.nc")
    before = (folder / "old.nc").read_bytes()
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # Python's own default: a write past the limit fails with EFBIG
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    said = {}
    big = xr.Dataset({"x": ("i", np.random.default_rng(0).random(4 * limit // 8))})  # netCDF: "NetCDF: HDF error"
    for key, write in (("netcdf", lambda: write_netcdf(big, folder / "old.nc")),
                       ("text", lambda: atomic.write_text(folder / "t.md", "x" * 2 * limit))):
        try:
            write()
            said[key] = "written"
        except atomic.NoSpaceError as exc:
            said[key] = [exc.errno, exc.filename, exc.strerror]
        except Exception as exc:
            said[key] = f"{type(exc).__name__}: {exc}"
    try:  # the C source of a kernel is larger than the limit: written into the cache before gcc runs
        compiled.compile_cached("/*" + "x" * 2 * limit + "*/ int f(void) { return 0; }\\n", "big")
        said["cache"] = "built"
    except ParameterError as exc:
        said["cache"] = [exc.name, type(exc).__name__, str(exc)]
    except Exception as exc:
        said["cache"] = f"{type(exc).__name__}: {exc}"
    said["kept"] = (folder / "old.nc").read_bytes() == before
    said["left"] = sorted(p.name for p in folder.iterdir() if p.name != "cache")
    print(json.dumps(said))
""")


def test_a_file_size_limit_is_said_as_a_full_disk_is_naming_the_file_and_the_cache(tmp_path):
    """``ulimit -f``: netCDF's ``NetCDF: HDF error`` and an ``EFBIG`` of a plain write were a bug (an internal error),
    a kernel's C source written into the cache one too; now each says the limit and that nothing was written (the
    command line: ``-o = ... cannot be written: File too large (...)``, exit 2, as for a full disk)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), MOL_SHELL_CACHE=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path), str(LIMIT)], capture_output=True, text=True,
                          env=env, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    said = json.loads(done.stdout.splitlines()[-1])
    too_large = f"File too large (the file size limit, ulimit -f, is {LIMIT} bytes); nothing was written"
    assert said["netcdf"] == [27, str(tmp_path / "old.nc"), too_large]  # EFBIG is 27 on Linux
    assert said["text"] == [27, str(tmp_path / "t.md"), too_large]
    name, kind, text = said["cache"]
    assert name == "MOL_SHELL_CACHE" and kind == "CacheFull" and "File too large" in text and str(LIMIT) in text
    assert said["kept"] and said["left"] == ["old.nc"]  # the previous run whole, no temporary left


def test_a_cache_folder_removed_during_the_build_is_said_naming_the_variable(tmp_path, monkeypatch):
    """``rm -rf $MOL_SHELL_CACHE`` while gcc builds: an internal ``FileNotFoundError`` (sealing the library) or gcc
    blamed (``ld: cannot open output file``); now one line naming ``MOL_SHELL_CACHE``."""
    folder = tmp_path / "c3"
    monkeypatch.setenv("MOL_SHELL_CACHE", str(folder))
    source = "int ms_vanish(void) { return %d; }\n"

    def removed(command, *args):  # the folder goes while "gcc" runs; gcc itself then wrote its output or failed
        Path(command[command.index("-o") + 1]).write_bytes(b"\x7fELF")
        shutil.rmtree(folder)

    def removed_then_failed(command, *args):
        shutil.rmtree(folder)
        raise subprocess.CalledProcessError(1, command, b"", b"/usr/bin/ld: cannot open output file x.so: No such "
                                            b"file or directory\ncollect2: error: ld returned 1 exit status\n")

    for i, build in enumerate((removed, removed_then_failed)):
        monkeypatch.setattr(compiled, "run_compiler", build)
        with pytest.raises(ParameterError) as raised:
            compiled.compile_cached(source % i, "vanish")
        assert raised.value.name == "MOL_SHELL_CACHE" and not isinstance(raised.value, kernel_cache.CompilerError)
        assert str(raised.value).startswith(f"MOL_SHELL_CACHE = '{folder}' vanished while vanish_")
        assert "removed during the build" in str(raised.value)


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("run") / "r.nc"
    assert main(["run", "twisted-cylinder", "--n", "11", "--t-end", "0.001", "-o", str(path)]) == 0
    return path


def _error(capsys):
    lines = capsys.readouterr().err.splitlines()
    return [line for line in lines if "warning" not in line]


def test_an_input_name_longer_than_the_file_system_takes_is_refused_naming_the_argument(tmp_path, capsys,
                                                                                        monkeypatch):
    """``plot``, ``scenes --toml``, ``run --from``, ``export``, ``animate`` of a 303-byte name: ``OSError: [Errno 36]
    File name too long``, an internal error; now a refusal naming FILE or --from."""
    monkeypatch.chdir(tmp_path)
    name = "a" * 300 + ".nc"
    for command, option in ((["plot", name, "-o", "x.png"], "FILE"), (["scenes", name, "--toml"], "FILE"),
                            (["run", "--from", name, "--step", "1", "-o", "y.nc"], "--from"),
                            (["export", name, "-o", "e.xdmf"], "FILE"), (["animate", name, "-o", "a.gif"], "FILE")):
        assert main(command) == 2, command
        err = _error(capsys)
        assert len(err) == 1 and err[0].startswith(f"mol-shell: error: {option} = '{name}' cannot be read (File "
                                                   "name too long)"), (command, err)


def test_a_run_file_name_not_utf8_or_with_a_newline_is_escaped_in_the_scene_file(run_file, tmp_path, capsys):
    """``scenes RUN.nc --toml`` copied the name raw into its header: bytes that are not UTF-8 made a file that does
    not read (``'utf-8' codec can't decode byte 0xe9``), a newline set a key of its own (``nu = 0.3``)."""
    plain = tmp_path / "plain.nc"
    plain.write_bytes(run_file.read_bytes())
    assert main(["scenes", str(plain), "--toml"]) == 0
    expected = tomllib.loads(capsys.readouterr().out)
    folder = Path(os.fsdecode(bytes(tmp_path) + b"/lat\xe9"))
    folder.mkdir()
    for name in (folder / os.fsdecode(b"r\xe9s.nc"), tmp_path / "r\nnu = 0.3\n#.nc"):
        name.write_bytes(run_file.read_bytes())
        assert main(["scenes", str(name), "--toml"]) == 0
        text = capsys.readouterr().out
        assert tomllib.loads(text.encode("utf-8").decode("utf-8")) == expected  # UTF-8, and no key of the name's
        if "lat" in str(name):
            assert f"# Written from the run {tmp_path}/lat\\xe9/r\\xe9s.nc (mol_shell " in text
    assert f"# Written from the run {tmp_path}/r\\nnu = 0.3\\n#.nc (mol_shell " in text


def test_a_points_file_name_not_utf8_is_stored_escaped_and_found_again(tmp_path):
    """A meridian's ``points`` named by bytes that are not UTF-8: netCDF4 refused the attribute after the run
    (``UnicodeEncodeError ... surrogates not allowed``, an internal error). Now stored as ``\\xfc`` text, and the run's
    scene (``run --from``, ``scenes --toml``) and its scene file find the file again."""
    points = Path(os.fsdecode(bytes(tmp_path) + b"/lat\xfc.txt"))
    t = np.linspace(0.1, np.pi - 0.1, 12)  # a sphere's meridian, r = sin, z = -cos
    points.write_text("\n".join(f"{np.sin(a):.6f} {-np.cos(a):.6f}" for a in t))
    escaped = str(tmp_path) + "/lat\\xfc.txt"
    ds = xr.Dataset({"x": ("i", np.arange(3.0))}, attrs={"scene": "meridian", "points": str(points)})
    write_netcdf(ds, tmp_path / "m.nc")
    with xr.open_dataset(tmp_path / "m.nc") as back:
        assert back.attrs["points"] == escaped
        assert scene_params(back)["points"] == str(points)  # the file's own name again
    unknown = str(tmp_path / "x\\xfc")  # no file of either name: the text as it is
    assert user_files.name_from_text(escaped) == str(points) and user_files.name_from_text(unknown) == unknown
    text = scene_toml(MeridianShell(points=str(points)))
    assert f'points = "{escaped.replace(chr(92), chr(92) * 2)}"' in text
    (tmp_path / "s.toml").write_bytes(text.encode("utf-8"))  # UTF-8: it encodes
    assert load_scene(tmp_path / "s.toml").points == str(points)


def test_an_output_that_is_a_symbolic_link_is_written_through_it(tmp_path):
    """``-o`` onto a link: the atomic rename replaced a live link by a file (its target kept the old data), and a
    dangling link was refused as ``cannot be written (File exists)``. Now the target is written, as a shell's ``>``
    writes it; a loop of links is refused."""
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "target.nc"
    write_netcdf(xr.Dataset({"x": ("i", np.zeros(2))}), target)
    (tmp_path / "sl.nc").symlink_to("real/target.nc")
    write_netcdf(xr.Dataset({"x": ("i", np.ones(3))}), tmp_path / "sl.nc")
    assert (tmp_path / "sl.nc").is_symlink()
    with xr.open_dataset(target) as back:
        assert back["x"].values.tolist() == [1.0, 1.0, 1.0]
    (tmp_path / "dang.md").symlink_to("real/nothere.md")
    atomic.write_text(writable_path(tmp_path / "dang.md"), "new")
    assert (tmp_path / "dang.md").is_symlink() and (tmp_path / "real" / "nothere.md").read_text() == "new"
    (tmp_path / "l1.png").symlink_to("l2.png")
    (tmp_path / "l2.png").symlink_to("l1.png")
    with pytest.raises(ParameterError, match="-o = '.*l1.png' is a chain of more than 40 symbolic links"):
        writable_path(tmp_path / "l1.png", "-o")
    (tmp_path / "sl.png").symlink_to("real/target.nc")
    with pytest.raises(ParameterError, match="-o = '.*sl.png' is a symbolic link to '.*target.nc', which ends in .nc"):
        writable_path(tmp_path / "sl.png", "-o", suffixes={"png"})


def test_a_run_file_without_its_attributes_is_refused_naming_what_is_missing(run_file, tmp_path, capsys):
    """``scenes FILE.nc --toml`` of a run saved again without most attrs: ``KeyError: 'integrator'``, a bug; without
    any, "refused by this version (? wrote it)". Now the attributes missing, by name."""
    with xr.open_dataset(run_file) as ds:
        ds = ds.load()
    few, none = ds.copy(), ds.copy()
    few.attrs = {k: ds.attrs[k] for k in ("title", "source", "Conventions", "scene", "complete")}
    none.attrs = {}
    for kept, name, missing in ((few, "few.nc", "'integrator'"), (none, "none.nc", "'scene' or 'integrator'")):
        kept.to_netcdf(tmp_path / name)
        assert main(["scenes", str(tmp_path / name), "--toml"]) == 2
        them = "them" if " or " in missing else "it"
        assert _error(capsys) == [(f"mol-shell: error: FILE = '{tmp_path / name}' has no attribute {missing}: a run "
                                   f"file without {them} cannot be written back as a scene file (saved again without "
                                   "its attributes?); allowed: a netCDF file written by mol-shell run or mol-shell "
                                   "path")]


def test_a_study_cases_folder_that_cannot_be_written_is_said_naming_the_output(tmp_path, monkeypatch, capsys):
    """A read-only ``X.cases/``: refused at the first case as ``path = '.../X.cases/8c4c....nc' cannot be written``;
    now ``-o`` before any case runs (the probe's failure stands in for a read-only folder: root writes any)."""
    (tmp_path / "s.cases").mkdir()

    class ReadOnly:
        @staticmethod
        def TemporaryFile(*args, **kwargs):
            raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(study_store, "tempfile", ReadOnly, raising=False)
    out = tmp_path / "s.nc"
    assert main(["study", "twisted-cylinder", "--vary", "gamma=0,1", "--n", "11", "--t-end", "0.001",
                 "-o", str(out)]) == 2
    assert _error(capsys) == [(f"mol-shell: error: -o = '{out}' keeps its finished cases in {tmp_path}/s.cases/, "
                               "which cannot be written (Permission denied); allowed: an output beside which "
                               "<stem>.cases/ is a writable directory")]
    with pytest.raises(ParameterError, match=f"output = '{out}' keeps its finished cases"):
        study_store.Store(out)
