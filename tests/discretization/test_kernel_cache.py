"""The compiled-kernel cache's faults: a library cut short, changed or another kernel's under its name; no gcc or a
failing one; files of another user; a full disk; a path that is not UTF-8; the leftovers of a killed build."""

import builtins
import ctypes
import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from fake_gcc import install_failing_gcc

from mol_shell._core.errors import ParameterError
from mol_shell.discretization import compiled
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs.checks import resolve
from mol_shell.scenes import TwistedCylinder

ROOT = Path(__file__).resolve().parents[2]
#: mol_shell.discretization.kernel_cache, through compiled (so that each test fails on its own where it is missing)
#: a table large enough that the library spans many pages: a cut inside it leaves the loader pages beyond the file
#: end to touch (SIGBUS), the values known in closed form (k / 7)
TABLE = 6000
SOURCE = (f"static const double table[{TABLE}] = {{{', '.join(f'{k}.0 / 7.0' for k in range(TABLE))}}};\n"
          "double value(int k) { return table[k]; }\n")


def _env(**extra):
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
                OMP_NUM_THREADS="1", **extra)


_DAMAGED = textwrap.dedent("""
    import ctypes, os, sys
    from pathlib import Path
    from mol_shell.discretization import compiled
    def value(path):
        f = ctypes.CDLL(str(path)).value
        f.restype, f.argtypes = ctypes.c_double, [ctypes.c_int]
        return f(5000)
    source, lib, damaged = Path(sys.argv[1]).read_text(), Path(sys.argv[2]), Path(sys.argv[3])
    whole = lib.read_bytes()
    for case in sorted(damaged.iterdir()):  # a new file each time: one cut in place would cut the library loaded
        os.replace(case, lib)
        _, v = compiled.load_cached(source, "tbl", compiled.CFLAGS, value)
        print(case.name, repr(v), lib.read_bytes() == whole, flush=True)
""")


def test_a_library_cut_short_or_changed_is_compiled_again_not_loaded(tmp_path, monkeypatch):
    """Cut at several sizes (from 1,000 bytes to all but its last byte) the library crashed every later run with
    SIGBUS (the loader maps the missing pages; the first touch kills the process); a byte of its data changed, it
    returned a wrong value. Each is now compiled again, with one note, and the value is 5000 / 7 (in a process of
    its own: a SIGBUS kills that one, not the tests)."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    (tmp_path / "tbl.c").write_text(SOURCE)
    lib = compiled.compile_cached(SOURCE, "tbl")
    whole = lib.read_bytes()
    assert len(whole) > 40_000  # the table alone is 48 kB
    at = whole.index(np.float64(5000 / 7).tobytes())  # table[5000] in the file
    cases = {f"cut{cut:06d}": whole[:cut] for cut in (1000, len(whole) // 4, len(whole) // 2, 3 * len(whole) // 4,
                                                       len(whole) - 1)}
    cases["one-byte-changed"] = whole[:at] + np.float64(1.0).tobytes() + whole[at + 8:]
    (tmp_path / "damaged").mkdir()
    for name, data in cases.items():
        (tmp_path / "damaged" / name).write_bytes(data)
    out = subprocess.run([sys.executable, "-c", _DAMAGED, str(tmp_path / "tbl.c"), str(lib), str(tmp_path / "damaged")],
                         env=_env(MOL_SHELL_CACHE=str(tmp_path)), capture_output=True, text=True, timeout=120,
                         check=False)
    assert out.returncode == 0, (out.returncode, out.stdout, out.stderr[-300:])
    assert out.stdout.splitlines() == [f"{name} {5000 / 7!r} True" for name in sorted(cases)]
    notes = out.stderr.splitlines()
    assert len(notes) == len(cases) and all(
        line.startswith(f"mol-shell: note: the cached {lib.name} in {tmp_path} is damaged (")
        and line.endswith("; compiling it again") for line in notes), notes


def test_another_kernels_library_copied_onto_the_name_is_compiled_again(tmp_path, monkeypatch, capsys):
    """A whole, loadable library of another kernel under a key's name was loaded as that kernel (a dop853-c run then
    stopped at t = 1.9e-7 s, a leap-frog run gave a wrong r): its record names its own key."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    one, two = (f"double copied_value(void) {{ return {v}.0; }}\n" for v in (1, 2))
    lib_one = compiled.compile_cached(one, "cp")
    lib_two = compiled.compile_cached(two, "cp")
    lib_one.write_bytes(lib_two.read_bytes())

    def value(path):
        f = ctypes.CDLL(str(path)).copied_value
        f.restype = ctypes.c_double
        return f()

    path, v = compiled.load_cached(one, "cp", compiled.CFLAGS, value)
    assert path == lib_one and v == 1.0
    assert f"the library of another kernel: its record names key {lib_two.name[3:23]}" in capsys.readouterr().err


def test_the_record_check_costs_under_a_millisecond(tmp_path):
    """Checked before every load: the whole image is digested up to 512 KiB, the ends of a larger one."""
    sizes = (60_000, compiled.kernel_cache.DIGEST_WHOLE, 8 * compiled.kernel_cache.DIGEST_WHOLE)
    for size in sizes:
        lib = tmp_path / f"x{size}.so"
        lib.write_bytes(np.random.default_rng(0).bytes(size))
        compiled.kernel_cache.seal(lib, "0123456789abcdef0123")
        assert lib.stat().st_size == size + compiled.kernel_cache.RECORD_BYTES
        assert compiled.kernel_cache.damage(lib, "0123456789abcdef0123") is None
        start = time.perf_counter()
        for _ in range(20):
            compiled.kernel_cache.damage(lib, "0123456789abcdef0123")
        assert (time.perf_counter() - start) / 20 < 2e-3  # 0.04-0.7 ms measured; a margin for a busy machine
    assert compiled.kernel_cache.damage(tmp_path / "none.so", "0123456789abcdef0123") == compiled.kernel_cache.MISSING
    assert "another kernel" in compiled.kernel_cache.damage(lib, "f" * 20)


# -- no gcc, or one that fails -----------------------------------------------------------------------------
def test_without_gcc_a_build_is_refused_in_one_line_and_the_rhs_runs_in_casadis_vm(tmp_path, monkeypatch):
    """No gcc on PATH and nothing cached: an internal FileNotFoundError before. Now the RHS runs in CasADi's virtual
    machine (the same values as the SX graph), and what needs C refuses naming gcc and what needs it."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    with pytest.raises(compiled.CompilerMissing, match="^gcc not found on PATH: building a test kernel needs a C "
                                                       "compiler .*leapfrog, dop853-c, rk45-c and casadi-cvodes-c"):
        compiled.compile_cached("int f(void) { return 1; }", "nogcc", what="a test kernel")
    scene = resolve(TwistedCylinder())
    system = ShellSystem(scene, 6)
    rhs = compiled.CompiledRHS(system.rhs_mapped, system.limits_mapped, threads=2)
    assert rhs.path is None and rhs.vm_reason.startswith("gcc not found on PATH") and rhs.threads == 1
    y = system.initial_state(scene) * (1 + 1e-3 * np.sin(np.arange(system.size)))
    np.testing.assert_array_equal(rhs.evaluator()(y, 0.0), np.array(system.rhs_mapped(0.0, y)).ravel())
    with pytest.raises(ParameterError, match="^gcc not found on PATH: building the leap-frog's step loop needs"):
        rhs.leapfrog(y.copy(), y.copy(), 1, 1e-6)
    assert [p.name for p in tmp_path.iterdir() if p.name != "no-bin"] == []  # nothing compiled, nothing locked


def _cli(tmp_path, integrator, path):
    return subprocess.run([sys.executable, "-m", "mol_shell", "run", "twisted-cylinder", "--n", "9", "--t-end", "0.001",
                           "--set", "nu=0.3", "--integrator", integrator, "-o", str(tmp_path / "run.nc")],
                          env=_env(MOL_SHELL_CACHE=str(tmp_path / "cache"), PATH=path), capture_output=True, text=True,
                          timeout=120, check=False)


def test_without_gcc_cvode_takes_the_python_route_saying_why(tmp_path):
    """docs/integrators.md's promise: without gcc cvode-bdf runs scikit-sundae's loop, saying why in one line (it ended
    in an internal FileNotFoundError: the RHS was compiled before any route was chosen)."""
    out = _cli(tmp_path, "cvode-bdf", str(tmp_path / "no-bin"))
    assert out.returncode == 0, out.stderr
    assert out.stderr.splitlines() == [("mol-shell: cvode-bdf runs scikit-sundae's Python loop: the compiled SUNDIALS "
                                        "driver is unavailable (gcc not found on PATH)")]


def test_without_gcc_dop853_c_is_refused_in_one_line(tmp_path):
    """dop853-c has no route without C: one line naming gcc and what needs it, exit 2 (an internal error before)."""
    out = _cli(tmp_path, "dop853-c", str(tmp_path / "no-bin"))
    assert out.returncode == 2
    lines = out.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("mol-shell: error: gcc not found on PATH: building the Runge-Kutta "
                                                   "step loop of dop853-c and rk45-c needs a C compiler"), lines


def test_a_failing_gcc_is_said_with_its_own_last_lines(tmp_path, monkeypatch):
    """A gcc that exits 1 ended in an internal CalledProcessError without gcc's text."""
    install_failing_gcc(tmp_path, monkeypatch)
    with pytest.raises(compiled.CompilerError, match=r"^gcc failed building a test kernel \(exit status 1\): cc1: "
                                                     r"fatal error: out of luck / compilation terminated\.$"):
        compiled.compile_cached("int f(void) { return 1; }", "bad", what="a test kernel")
    assert [p.name for p in (tmp_path / "cache").iterdir()] == [".bad_" + _key_of(tmp_path / "cache") + ".lock"]


def _key_of(cache):
    return next(cache.glob(".*.lock")).name.split("_")[1][:20]


# -- a cache shared by users, a full disk ---------------------------------------------------------------------
def _not_writable(monkeypatch, *paths):
    """``paths`` as another user's files are to this one: read-only (chmod 0o444); as root, where chmod does not stop
    a write, every open of them for writing raises PermissionError."""
    for path in paths:
        path.chmod(0o444)
    if os.geteuid() != 0:
        return
    denied = {os.fspath(p) for p in paths}
    real_open, real_os_open = builtins.open, os.open

    def fake_open(file, mode="r", *args, **kwargs):
        if isinstance(file, (str, os.PathLike)) and os.fspath(file) in denied and set(mode) & set("wax+"):
            raise PermissionError(errno.EACCES, "Permission denied", os.fspath(file))
        return real_open(file, mode, *args, **kwargs)

    def fake_os_open(path, flags, *args, **kwargs):
        if os.fspath(path) in denied and flags & (os.O_WRONLY | os.O_RDWR):
            raise PermissionError(errno.EACCES, "Permission denied", os.fspath(path))
        return real_os_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", fake_open)
    monkeypatch.setattr(os, "open", fake_os_open)


@pytest.mark.parametrize("theirs", ["lock", "builds.log"])
def test_another_users_read_only_lock_or_build_log_does_not_stop_a_build(tmp_path, monkeypatch, theirs):
    """builds.log of another user: the kernel compiled, then an internal PermissionError; a lock file left by another
    user's interrupted build: an internal PermissionError on every run. The log is written where it can be, the lock
    opened for reading (flock needs no more)."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    source = "int shared_answer(void) { return 42; }\n"
    real = compiled.run_compiler

    def interrupted(command, what, source_bytes, flags):
        raise OSError(errno.EIO, "the other user's build, interrupted")

    monkeypatch.setattr(compiled, "run_compiler", interrupted)
    with pytest.raises(OSError, match="interrupted"):
        compiled.compile_cached(source, "shared")
    monkeypatch.setattr(compiled, "run_compiler", real)
    (lock,) = tmp_path.glob(".shared_*.lock")  # left by that build
    log = tmp_path / "builds.log"
    log.write_text("someone else's build\n")
    _not_writable(monkeypatch, lock if theirs == "lock" else log)
    lib = compiled.compile_cached(source, "shared")
    assert ctypes.CDLL(str(lib)).shared_answer() == 42
    assert log.read_text().splitlines()[0] == "someone else's build"
    assert len(log.read_text().splitlines()) == (1 if theirs == "builds.log" else 2)  # written where it can be


def test_a_library_the_cache_may_not_replace_is_refused_naming_mol_shell_cache(tmp_path, monkeypatch):
    """A true refusal (another user's file in a sticky directory): one line naming MOL_SHELL_CACHE."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    real_replace = os.replace

    def refuse(src, dst):
        if Path(dst).suffix == ".so":
            raise PermissionError(errno.EPERM, "Operation not permitted", os.fspath(dst))
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(ParameterError, match=f"^MOL_SHELL_CACHE = '{tmp_path}' cannot be written \\(building "
                                             "perm_.*Operation not permitted"):
        compiled.compile_cached("int f(void) { return 1; }", "perm")


@pytest.mark.parametrize("how", ["write", "gcc"])
def test_a_full_disk_is_said_in_one_line_and_leaves_nothing_half_written(tmp_path, monkeypatch, how):
    """ENOSPC writing the build (an internal OSError), or gcc failing to write its output (an internal
    CalledProcessError): one line naming MOL_SHELL_CACHE and the full disk; no library, no temporary folder."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))

    def full(command, what, source_bytes, flags):
        out = Path(command[command.index("-o") + 1])
        out.write_bytes(b"\x7fELF half")
        if how == "write":
            raise OSError(errno.ENOSPC, "No space left on device")
        raise subprocess.CalledProcessError(1, command, b"", b"/usr/bin/ld: final link failed: No space left on "
                                            b"device\ncollect2: error: ld returned 1 exit status\n")

    monkeypatch.setattr(compiled, "run_compiler", full)
    source = "int f(void) { return 1; }"
    with pytest.raises(ParameterError, match=f"^MOL_SHELL_CACHE = '{tmp_path}' has no space left on device"):
        compiled.compile_cached(source, "full")
    assert [p.name[:6] + p.name[-5:] for p in tmp_path.iterdir()] == [".full_.lock"]  # the lock file alone


def test_a_cache_path_that_is_not_utf8_is_refused_naming_it(tmp_path, monkeypatch):
    """CasADi loads by a UTF-8 path: every run compiled twice, then failed (Cannot load shared library '.so')."""
    monkeypatch.setenv("MOL_SHELL_CACHE", os.fsdecode(os.fsencode(str(tmp_path)) + b"/lat\xe9"))
    with pytest.raises(ParameterError, match=r"^MOL_SHELL_CACHE = b'.*/lat\\xe9' is not a UTF-8 path"):
        compiled.cache_dir()


# -- a build killed with SIGKILL ------------------------------------------------------------------------------
_KILLED = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from mol_shell.discretization import compiled
    def stuck(command, what, source_bytes, flags):
        Path(command[command.index("-o") + 1]).write_bytes(b"half")
        print("compiling", flush=True)
        time.sleep(60)
    compiled.run_compiler = stuck
    compiled.compile_cached("int killed(void) { return 1; }", "killed")
""")


def test_what_a_killed_build_leaves_is_removed_at_a_later_build_once_stale(tmp_path, monkeypatch):
    """SIGKILL in the middle of a build left its source folder and its staging folder in the cache for good. A later
    build removes them once an hour old (their process gone), and keeps younger ones and a live process's."""
    proc = subprocess.Popen([sys.executable, "-c", _KILLED], env=_env(MOL_SHELL_CACHE=str(tmp_path)),
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "compiling\n"
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    left = sorted(p.name for p in tmp_path.iterdir() if p.is_dir())
    assert len(left) == 2 and any(name.endswith(".part") for name in left), left
    young = tmp_path / f".young_{'a' * 20}.{proc.pid}.abcdefgh"
    alive = tmp_path / f".alive_{'b' * 20}.1.abcdefgh"  # pid 1 runs while this does
    for folder in (young, alive):
        folder.mkdir()
    old = time.time() - 2 * 3600  # removed from an hour on
    for name in [*left, alive.name]:
        os.utime(tmp_path / name, (old, old))
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    compiled.compile_cached("int later(void) { return 2; }", "later")
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == sorted([young.name, alive.name])


def test_the_lock_file_is_opened_for_writing_where_it_can_be(tmp_path, monkeypatch):
    """An exclusive flock on NFS (byte-range locks underneath) needs a file open for writing: opened read-only, the lock
    failed there, silently, and every builder of one library compiled it at once. Read-only is the fallback only."""
    kernel_cache = compiled.kernel_cache
    opened = []
    real_open = os.open

    def recording_open(path, flags, *args):
        opened.append(flags & (os.O_RDONLY | os.O_WRONLY | os.O_RDWR))
        return real_open(path, flags, *args)

    monkeypatch.setattr(kernel_cache.os, "open", recording_open)
    with kernel_cache.locked(tmp_path / ".x.lock"):
        pass
    assert opened == [os.O_RDWR]


def _value(path):
    f = ctypes.CDLL(str(path)).dir_value
    f.restype = ctypes.c_double
    return f()


@pytest.mark.parametrize("prefix", ["rhs", "funcs", "stencil", "sundials"])
def test_an_empty_directory_where_a_library_goes_is_removed_and_the_library_built(tmp_path, monkeypatch, capsys,
                                                                                 prefix):
    """``mkdir $MOL_SHELL_CACHE/rhs_<key>.so`` was an internal IsADirectoryError from the rename of the build (exit 1),
    for every kind of library (all are loaded through ``load_cached``). The empty directory is now removed, with one
    note, and the library built in its place: its value 3 / 8, no temporary folder left."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    source = f"double dir_value(void) {{ return 3.0 / 8.0; }} /* {prefix} */\n"
    lib, _ = compiled.kernel_cache.library(source, prefix, compiled.CFLAGS)
    lib.mkdir()
    path, v = compiled.load_cached(source, prefix, compiled.CFLAGS, _value)
    assert path == lib and lib.is_file() and v == 0.375
    assert capsys.readouterr().err == (f"mol-shell: note: an empty directory {lib.name} stood in {tmp_path} where a "
                                       "library goes; removed it, compiling the library\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([f".{lib.stem}.lock", "builds.log", lib.name])


def test_a_directory_with_files_where_a_library_goes_is_refused_naming_the_cache_and_it(tmp_path, monkeypatch):
    """One that holds files is not removed: one line naming MOL_SHELL_CACHE and the directory (exit 2 on the
    command line), its file kept, nothing built, no temporary folder left."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    source = "double dir_value(void) { return 1.0; }\n"
    lib, _ = compiled.kernel_cache.library(source, "rhs", compiled.CFLAGS)
    lib.mkdir()
    (lib / "mine.txt").write_text("kept")
    with pytest.raises(ParameterError, match=f"^MOL_SHELL_CACHE = '{tmp_path}' holds a directory where a library goes "
                                             f"\\({lib}: not empty\\); allowed: .*remove that directory"):
        compiled.load_cached(source, "rhs", compiled.CFLAGS, _value)
    assert (lib / "mine.txt").read_text() == "kept"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([f".{lib.stem}.lock", lib.name])


def test_a_fifo_where_a_library_goes_is_replaced_not_waited_on(tmp_path, monkeypatch, capsys):
    """A FIFO under a library's name: its check opened it and waited for a writer forever; it is now said to be no
    regular file and the library is built in its place (the rename replaces it)."""
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    source = "double dir_value(void) { return 5.0 / 4.0; }\n"
    lib, _ = compiled.kernel_cache.library(source, "stencil", compiled.CFLAGS)
    os.mkfifo(lib)
    previous = signal.signal(signal.SIGALRM, lambda *_: pytest.fail("the FIFO was opened and waited on"))
    signal.alarm(20)
    try:
        path, v = compiled.load_cached(source, "stencil", compiled.CFLAGS, _value)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert path == lib and lib.is_file() and v == 1.25
    assert "is damaged (a named pipe (FIFO), not a regular file); compiling it again" in capsys.readouterr().err
