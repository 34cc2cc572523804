"""Faults survived: killed studies, damaged case files, dead workers, concurrent compilers, writes cut short."""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mol_shell
from mol_shell.results.dataset import read_run
from mol_shell.runs.study import study

#: fault drills: subprocesses killed, pools broken, compilers racing (each several seconds); still run by CI
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
FIELDS = ("z", "r", "chi", "theta", "psi", "energy", "angular_momentum")


def _env(**extra):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""), **extra)
    env.setdefault("OMP_NUM_THREADS", "1")
    return env


def _same_cases(a, b):
    assert (a.status.values == b.status.values).all()
    for name in FIELDS:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


# -- a study killed with SIGKILL -----------------------------------------------------------------------
STUDY = ["study", "twisted-cylinder", "--vary", "gamma=0.02:0.12:0.02", "--n", "10", "--t-end", "0.1",
         "--scheduler", "serial"]


def _stored(cases):
    """The finished case files in ``cases``: non-empty. The writer's probe of a writable path creates an empty file of
    the case's name for a moment before the data are written under another name and renamed onto it."""
    found = []
    for path in cases.glob("*.nc") if cases.is_dir() else ():
        try:
            if path.stat().st_size > 0:
                found.append(path)
        except FileNotFoundError:  # the probe, removed meanwhile
            pass
    return found


@pytest.mark.timeout(300)
def test_study_killed_with_sigkill_resumes_to_the_same_results(tmp_path):
    """SIGKILL once two of six cases are stored (each ~0.5 s of leap-frog): the rerun reuses what was stored,
    runs the rest, and every case equals the uninterrupted study's bit for bit."""
    reference = tmp_path / "ref" / "s.nc"
    done = subprocess.run([sys.executable, "-m", "mol_shell", *STUDY, "-o", str(reference)], env=_env(),
                          capture_output=True, text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    out = tmp_path / "killed" / "s.nc"
    cases = out.parent / "s.cases"
    proc = subprocess.Popen([sys.executable, "-m", "mol_shell", *STUDY, "-o", str(out)], env=_env(),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 200
    while time.monotonic() < deadline and proc.poll() is None:
        if len(_stored(cases)) >= 2:
            proc.send_signal(signal.SIGKILL)
            break
        time.sleep(0.01)
    proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL, "the study ended before it could be killed"
    stored = len(_stored(cases))
    assert 2 <= stored < 6 and not out.exists()
    done = subprocess.run([sys.executable, "-m", "mol_shell", *STUDY, "-o", str(out)], env=_env(),
                          capture_output=True, text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    assert f"ran {6 - stored}, reused {stored}" in done.stdout, done.stdout
    _same_cases(mol_shell.read_netcdf(out), mol_shell.read_netcdf(reference))


# -- damaged case files ---------------------------------------------------------------------------------
def test_truncated_or_corrupted_case_files_are_run_again(tmp_path):
    """Four stored cases damaged four ways (cut in half, emptied, one byte of r changed, replaced by garbage)
    and a stray temporary file left by a killed write: the rerun runs exactly the four damaged cases again,
    and the study equals the first one."""
    out = tmp_path / "s.nc"
    vary = {"gamma": [0.02, 0.04, 0.06, 0.08, 0.1]}
    first = study("twisted-cylinder", vary, n=10, t_end=0.002, scheduler="serial", output=out)
    files = sorted((tmp_path / "s.cases").glob("*.nc"))
    assert len(files) == 5
    by_gamma = {float(mol_shell.read_netcdf(f).attrs["gamma"]): f for f in files}
    half = by_gamma[0.02]
    half.write_bytes(half.read_bytes()[: half.stat().st_size // 2])
    by_gamma[0.04].write_bytes(b"")
    flipped = by_gamma[0.06]
    data = bytearray(flipped.read_bytes())
    needle = first.r.sel(gamma=0.06).values[3].tobytes()  # r at the fourth saved time, as stored
    at = bytes(data).find(needle)
    assert at > 0, "r's values are not stored contiguously: the test cannot place its damage"
    data[at + 5] ^= 0x40  # r changes in its 3rd significant digit; the file stays readable
    flipped.write_bytes(bytes(data))
    assert float(abs(mol_shell.read_netcdf(flipped).r - first.r.sel(gamma=0.06)).max()) > 0  # readable, wrong
    by_gamma[0.08].write_bytes(os.urandom(4000))
    (tmp_path / "s.cases" / f".{by_gamma[0.1].name}.999.deadbeef.part").write_bytes(b"\x89HDF half a file")
    with pytest.warns(UserWarning, match=r"4 stored case files could not be reused and run again \(.* and 3 more\)"):
        again = study("twisted-cylinder", vary, n=10, t_end=0.002, scheduler="serial", output=out)
    assert (again.attrs["n_executed"], again.attrs["n_reused"]) == (4, 1)
    _same_cases(again, first)
    final = study("twisted-cylinder", vary, n=10, t_end=0.002, scheduler="serial", output=out)
    assert (final.attrs["n_executed"], final.attrs["n_reused"]) == (0, 5)


def test_a_case_files_run_attribute_edited_by_hand_is_run_again(tmp_path):
    """The checksum covered the values and the ``case_*`` record only: a stored case whose ``E`` attribute was edited
    (as a user might, to "relabel" it) was reused, and the study reported the edited modulus beside the first run's
    values. Now every attribute is in the checksum: that case runs again and the study equals the first one."""
    netCDF4 = pytest.importorskip("netCDF4")
    out = tmp_path / "s.nc"
    vary = {"gamma": [0.02, 0.04]}
    first = study("twisted-cylinder", vary, n=10, t_end=0.002, scheduler="serial", output=out)
    stored = min((tmp_path / "s.cases").glob("*.nc"))
    with netCDF4.Dataset(stored, "a") as handle:
        handle.setncattr("E", 2e6)
    with pytest.warns(UserWarning, match=r"1 stored case file could not be reused and runs again \(checksum mismatch: "):
        again = study("twisted-cylinder", vary, n=10, t_end=0.002, scheduler="serial", output=out)
    assert (again.attrs["n_executed"], again.attrs["n_reused"]) == (1, 1)
    assert float(again.attrs["E"]) == float(first.attrs["E"]) == 1e6
    _same_cases(again, first)


# -- dead workers ---------------------------------------------------------------------------------------
SLOW_CASES = {"gamma": [0.05, 0.1, 0.15, 0.2]}
SLOW_RUN = {"n": 40, "t_end": 0.8}  # ~3.5 s of CPU per case, after a worker's imports (~1 s) and build (~0.4 s)


def _kill_when_busy(pids_of_busy, killed, settle=2.0, timeout=120):
    """A thread: once ``pids_of_busy()`` names a process running a case, wait ``settle`` s and SIGKILL it."""

    def run():
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            pids = pids_of_busy()
            if pids:
                time.sleep(settle)
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])
                return
            time.sleep(0.05)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_local_worker_killed_during_a_case_is_run_again():
    """SIGKILL of a local worker process mid-case breaks the process pool; the unfinished cases run again in a
    new pool, and the study completes with every case."""
    psutil = pytest.importorskip("psutil")
    me = psutil.Process()

    def busy():
        """Workers in a case: past their imports (a spawned one's, about 1 s of CPU) and build (0.4 s), 1.5 s into a
        case of ~3.5 s. CPU time, not wall time: on a loaded machine (parallel tests) a worker's imports alone can
        take several seconds. A forked worker has this process's command line and starts without imports."""
        found = []
        for p in me.children():
            try:
                command = p.cmdline()
                start = 1.5 if "spawn_main" in " ".join(command) else 0.4 if command == me.cmdline() else None
                if start is not None and sum(p.cpu_times()[:2]) > start + 1.5:
                    found.append(p.pid)
            except psutil.NoSuchProcess:
                pass
        return found

    killed = []
    thread = _kill_when_busy(busy, killed, settle=0.0)
    ds = study("twisted-cylinder", SLOW_CASES, **SLOW_RUN, workers=2)
    thread.join(timeout=1)
    assert killed, "no worker was killed"
    assert (ds.status == "complete").all(), ds.message.values
    again = [w for w, m in zip(ds.worker.values.ravel(), ds.message.values.ravel()) if "run 2 times" in m]
    # the case the killed worker was running came from another process (on a fast machine the worker may have
    # finished a case before it, recorded under its pid)
    assert again and str(killed[0]) not in {w.split(":")[1] for w in again}


@pytest.mark.timeout(120)
def test_local_cases_run_once_each_by_whichever_process_claims_them(tmp_path):
    """This process takes cases from the back, the worker from the front; the worker skips those this process
    took (they were handed to its pool too): every case runs exactly once, and both processes ran some."""
    from mol_shell.runs import scheduling

    from poison_cases import Case, run

    me, log = os.getpid(), str(tmp_path)
    cases = [Case((k,), me, seconds=0.25, log=log) for k in range(16)]
    results = list(scheduling.execute(run, cases, None, 2))
    runs = [int(p.name.split("-")[0]) for p in tmp_path.iterdir()]
    assert sorted(runs) == list(range(16)) and len(results) == 16
    ran_here = {index[0] for index, _, info in results if info["worker"] == str(me)}
    assert ran_here and len(ran_here) < 16  # both took cases
    assert ran_here == set(range(16 - len(ran_here), 16))  # this process, from the back


@pytest.mark.timeout(120)
def test_a_case_that_kills_every_worker_is_lost_and_no_other_case_is_blamed(tmp_path):
    """The local scheduler knows which case a dead worker was running (the shared claims table): that case is
    run again, up to LOST_RETRIES times, then recorded ``lost``; the cases the worker had not started run
    again without counting an attempt, and none runs twice."""
    from mol_shell.runs import scheduling

    from poison_cases import Case, run

    me, log = os.getpid(), str(tmp_path)
    cases = [Case((0,), me, poisoned=True, log=log)] + [Case((k,), me, seconds=0.4, log=log) for k in range(1, 7)]
    results = list(scheduling.execute(run, cases, None, 2))
    runs = [int(p.name.split("-")[0]) for p in tmp_path.iterdir()]
    assert [runs.count(k) for k in range(1, 7)] == [1] * 6
    by_case = {index: info for index, _, info in results}
    assert sorted(by_case) == [(k,) for k in range(7)] and len(results) == 7  # each case once
    poisoned = by_case[(0,)]
    if poisoned["worker"] == str(me):  # this process took it before a worker started: nothing to test
        pytest.skip("the poisoned case ran in this process")
    assert poisoned["status"] == "lost", poisoned
    assert f"run {scheduling.LOST_RETRIES + 1} times" in poisoned["message"], poisoned["message"]
    assert runs.count(0) == scheduling.LOST_RETRIES + 1
    for k in range(1, 7):
        assert by_case[(k,)]["status"] == "complete" and "times" not in by_case[(k,)]["message"], by_case[(k,)]


@pytest.mark.slow
@pytest.mark.timeout(300)
@pytest.mark.parametrize("allowed_failures", [3, 0])
def test_dask_worker_killed_during_a_case(allowed_failures):
    """SIGKILL of a dask worker mid-case: with dask's default (3 failures allowed) the case is retried on
    another worker; with none allowed it is recorded as ``lost`` (KilledWorker). Either way the study
    completes and the other cases are complete."""
    distributed = pytest.importorskip("distributed")
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": allowed_failures}):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        with cluster, distributed.Client(cluster) as client:
            pids = client.run(os.getpid)

            def busy():
                return [pids[w] for w, keys in client.processing().items() if keys and w in pids]

            killed = []
            thread = _kill_when_busy(busy, killed, settle=2.5)  # into the imports, build and case of ~5 s
            ds = study("twisted-cylinder", SLOW_CASES, **SLOW_RUN, scheduler=client)
            thread.join(timeout=1)
    assert killed, "no worker was killed"
    status = list(ds.status.values)
    assert len(status) == 4 and "interrupted" not in status
    if allowed_failures:
        assert status == ["complete"] * 4, ds.message.values
    else:
        assert status.count("lost") >= 1 and "KilledWorker" in " ".join(ds.message.values)
        assert status.count("complete") == 4 - status.count("lost")
    assert str(killed[0]) not in {w.split(":")[-1] for w in ds.worker.values if w}


# -- concurrent compilers ---------------------------------------------------------------------------------
_RACE = textwrap.dedent("""
    import ctypes, os, sys, time
    from pathlib import Path
    from mol_shell.discretization.compiled import compile_cached, cache_dir
    role, start, source = sys.argv[1], float(sys.argv[2]), Path(sys.argv[3]).read_text()
    while time.time() < start:
        time.sleep(0.001)
    if role == "reader":  # loads the library the moment its name appears
        while not list(cache_dir().glob("race_*.so")):
            time.sleep(0.0005)
        lib = next(cache_dir().glob("race_*.so"))
    else:
        lib = compile_cached(source, "race")
    value = ctypes.CDLL(str(lib)).race_value
    value.restype = ctypes.c_double
    print(value())
""")


def _race_source(terms=4000):
    """C that gcc takes about a second over (a long sum), returning a known value."""
    body = "\n".join(f"  x += (double)({k} % 7) * 0.5;" for k in range(terms))
    return f"double race_value(void) {{\n  double x = 0;\n{body}\n  return x;\n}}\n"


@pytest.mark.timeout(300)
def test_processes_compiling_the_same_kernel_at_once_never_load_half_a_library(tmp_path):
    """Four processes compile the same new source into an empty cache at the same moment, and two more load
    the library as soon as its name appears: all six load a complete library and get its value; the
    cache holds one library and no temporary files."""
    cache = tmp_path / "cache"
    source = tmp_path / "race.c"
    source.write_text(_race_source())
    expected = sum((k % 7) * 0.5 for k in range(4000))
    start = time.time() + 3.0  # after every interpreter has started
    roles = ["writer"] * 4 + ["reader"] * 2
    procs = [subprocess.Popen([sys.executable, "-c", _RACE, role, str(start), str(source)], env=_env(
        MOL_SHELL_CACHE=str(cache)), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for role in roles]
    results = [p.communicate(timeout=240) for p in procs]
    for (out, err), p in zip(results, procs):
        assert p.returncode == 0, err
        assert float(out.strip()) == expected
    # one library, its lock file and the build log: no temporary files, and the lock let one process compile
    lib = next(cache.glob("race_*.so")).name
    assert sorted(p.name for p in cache.iterdir()) == sorted([lib, "." + lib[:-3] + ".lock", "builds.log"])
    assert len((cache / "builds.log").read_text().splitlines()) == 1


def test_a_library_appears_in_the_cache_only_when_complete(tmp_path, monkeypatch):
    """Deterministic: a compiler that writes its output in two halves with a pause between; the cache name
    never exists while the library is incomplete (it is renamed into place when whole)."""
    from mol_shell.discretization import compiled

    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    seen = []

    def slow_compiler(command, what, source_bytes, flags):
        out = Path(command[command.index("-o") + 1])
        with open(out, "wb") as f:
            f.write(b"\x7fELF" + b"\0" * 1000)
            f.flush()
            seen.append(sorted(p.name for p in tmp_path.glob("*.so")))  # mid-write: nothing under a cache name
            f.write(b"\0" * 1000)

    monkeypatch.setattr(compiled, "run_compiler", slow_compiler)
    lib = compiled.compile_cached("int f(void) { return 1; }", "half")
    assert seen == [[]] and lib.exists() and lib.stat().st_size == 2004 + compiled.kernel_cache.RECORD_BYTES  # + its record
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([lib.name, "." + lib.name[:-3] + ".lock", "builds.log"])


def test_a_damaged_cached_library_is_rebuilt(tmp_path, monkeypatch):
    from mol_shell.discretization import compiled

    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    source = "int answer(void) { return 42; }\n"
    lib = compiled.compile_cached(source, "dmg")
    lib.write_bytes(lib.read_bytes()[:100])  # cut short (as a copy or a disk error could leave it)
    path, value = compiled.load_cached(source, "dmg", compiled.CFLAGS, lambda p: ctypes.CDLL(str(p)).answer())
    assert path == lib and value == 42 and lib.stat().st_size > 1000


# -- an output file written while the process is killed ------------------------------------------------
_WRITER = textwrap.dedent("""
    import sys
    import numpy as np, xarray as xr
    import mol_shell
    ds = xr.Dataset({"r": (("time", "s"), np.random.default_rng(0).random((4000, 20000)))})  # 640 MB
    print("writing", flush=True)
    mol_shell.write_netcdf(ds, sys.argv[1])
""")


@pytest.mark.timeout(300)
def test_a_run_killed_while_writing_leaves_the_previous_file_intact(tmp_path):
    """The previous file at the path survives a process killed in the middle of writing a new one (the new
    one goes to a hidden temporary name first); the temporary file is all that is left."""
    path = tmp_path / "run.nc"
    previous = mol_shell.simulate("spinning-ring", n=5, times=[0, 1e-5], progress=False)
    mol_shell.write_netcdf(previous, path)
    before = path.read_bytes()
    proc = subprocess.Popen([sys.executable, "-c", _WRITER, str(path)], env=_env(), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing", proc.stderr.read()
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        sizes = [p.stat().st_size for p in tmp_path.rglob("*") if p.is_file()]  # the temporary: in .run.nc.*.part/
        if max(sizes) > 20e6:  # 20 MB of the new file written (under whatever name)
            proc.send_signal(signal.SIGKILL)
            break
        time.sleep(0.01)
    proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL, "the write ended before it could be interrupted"
    assert path.read_bytes() == before
    assert len(list(tmp_path.glob(".run.nc.*.part"))) == 1
    back = read_run(path)
    np.testing.assert_array_equal(back.r.values, previous.r.values)
