"""Resource limits named before work starts: memory refused with the estimate, long runs warned about, progress
while compiling, adaptive runs that cannot reach their end stopped early."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time
import warnings

import numpy as np
import pytest
from build_guard import Built

import mol_shell
from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.cli.main import main
from mol_shell.runs import resources
from mol_shell.runs.resources import LongRunWarning


def test_output_estimate_is_the_dataset_s_size():
    """``times x (10 n + 8 + 17 (n - 1)) x 8 + 3 n x 8`` bytes bounds the variables of a run's Dataset (5 fields,
    5 rates per node; 8 totals per time for an elastic shell whose edges hold z: three energies, the angular
    momentum, delta_min, the ellipticity margin, the two edges' axial force; 17 stress values per cell; the
    reference meridian) to within the coordinates."""
    for scene, n, times in ((mol_shell.TwistedCylinder(), 7, [0, 1e-6, 2e-6]),
                            (mol_shell.Axisymmetric(), 9, [0, 1e-6])):
        ds = mol_shell.simulate(scene, n=n, times=times, progress=False)
        data = sum(v.nbytes for v in ds.data_vars.values())
        estimate = resources.output_bytes(len(times), n)
        assert data <= estimate <= data + 8 * len(times)


def test_too_many_saved_times_are_refused_before_they_are_made(monkeypatch, capsys, tmp_path, no_build):
    """``--times 0:0.001:1e-12`` is a billion saved times (3.3 TB of output at n = 40): refused at once, in one
    line naming --times, the estimate and what to change; the list of times is never expanded."""
    start = time.perf_counter()
    code = main(["run", "twisted-cylinder", "--times", "0:0.001:1e-12", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert time.perf_counter() - start < 5
    assert code == 2 and len(err.splitlines()) == 1, err
    assert err.startswith("mol-shell: error: --times = '0:0.001:1e-12' is outside at most ")
    # 1e9 times x (10 x 40 values per node + 8 per time) x 8 bytes = 3.264 TB (the stresses are left out at this size)
    assert "saved times at n = 40" in err and "the output alone 3.26 TB" in err and "--times" in err and "--n" in err


def test_memory_limit_follows_the_environment(monkeypatch, capsys, tmp_path, no_build):
    """With MOL_SHELL_MEMORY = 1G, 2e6 saved times of 40 nodes (640 MB of output, about 2.5 GB at the peak) are
    refused; 2,000 are not (the run then gets as far as building its graph)."""
    monkeypatch.setenv(resources.MEMORY_ENV, "1G")
    assert resources.available_memory() == (1024**3, "$MOL_SHELL_MEMORY")
    code = main(["run", "twisted-cylinder", "--times", "0:2:1e-6", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and "1.07 GB available ($MOL_SHELL_MEMORY)" in err, err
    with pytest.raises(Built):
        mol_shell.simulate("twisted-cylinder", times=np.arange(2001) * 1e-6)
    with pytest.raises(ParameterError, match=r"^times = .* is outside at most [\d,]+ saved times at n = 40"):
        mol_shell.simulate("twisted-cylinder", times=np.arange(2_000_001) * 1e-6)


def test_millions_of_nodes_are_refused_before_any_graph(capsys, tmp_path, no_build):
    """``--n 5000000``: about 200 GB for graphs and spectrum (40 kB per node, measured): refused before building."""
    start = time.perf_counter()
    code = main(["run", "twisted-cylinder", "--n", "5000000", "--t-end", "1e-3", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert time.perf_counter() - start < 5
    assert code == 2 and err.startswith("mol-shell: error: --n = 5000000 is outside integers 3..") and "GB" in err, err
    assert len(err.splitlines()) == 1


#: N x N doubles a dense linear solver keeps: CVODE its Newton matrix and the saved Jacobian (LU in place), IDA one
#: matrix; scikit-sundae's route adds the array its Jacobian callback fills (SUNDIALS' cvLs/idaLs, sksundae's np_JJ)
DENSE_MATRICES = {"cvode-bdf": 2, "cvode-adams": 2, "ida": 1, "sksundae-cvode-bdf": 3, "sksundae-ida": 2}


@pytest.mark.parametrize("integrator, options", [
    ("cvode-bdf", ["linsolver=dense"]), ("cvode-adams", ["iteration=newton", "linsolver=dense"]),
    ("ida", ["linsolver=lapack-dense"]), ("sksundae-cvode-bdf", ["linsolver=dense"]),
    ("sksundae-ida", ["linsolver=dense"]),
])
def test_a_dense_linear_solver_too_large_for_memory_is_refused_naming_linsolver(integrator, options, monkeypatch,
                                                                                capsys, tmp_path, no_build):
    """``--n 6000 --option linsolver=dense`` asked for N x N matrices of N = 2 x 5 x 6,000 = 60,000 unknowns (28.8 GB
    each) and ended in a segmentation fault (exit 139, nothing said): the estimate counted the matrix only up to
    2,000 unknowns. Now one line naming linsolver, the matrices' bytes and the largest n a dense solver fits at,
    exit 2, before any graph is built."""
    monkeypatch.setenv(resources.MEMORY_ENV, "16G")
    k = DENSE_MATRICES[integrator]
    matrices = k * (2 * 5 * 6000) ** 2 * 8  # 28.8 GB a matrix
    args = [arg for option in options for arg in ("--option", option)]
    code = main(["run", "twisted-cylinder", "--n", "6000", "--integrator", integrator, *args, "--t-end", "1e-5",
                 "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, err
    value = options[-1].split("=")[1]
    assert err.startswith(f"mol-shell: error: linsolver = '{value}' is outside {{auto, band, sparse}} at n = 6,000 ("
                          ), err
    assert f"of which {matrices / 1e9:.3g} GB for the dense solver's {k} matri" in err, err
    assert "17.2 GB available ($MOL_SHELL_MEMORY)" in err, err
    # the largest n: k (10 n)^2 x 8 bytes within 16 GiB less the rest (300 MB and 40 kB per node: a few per cent)
    largest = int(err.split("a dense solver up to n = ")[1].split(" ")[0].replace(",", ""))
    bound = (16 * 1024**3 / (k * 800)) ** 0.5
    assert 0.95 * bound < largest < bound, (largest, bound)
    with pytest.raises(ParameterError, match=r"^linsolver = .* is outside \{auto, band, sparse\} at n = 6,000"):
        mol_shell.simulate("twisted-cylinder", integrator, n=6000, t_end=1e-5,
                           **dict(option.split("=") for option in options))


@pytest.mark.parametrize("integrator", ["sksundae-cvode-bdf", "sksundae-ida"])
def test_scikit_sundaes_banded_solver_counts_its_full_array(integrator, monkeypatch, capsys, tmp_path, no_build):
    """scikit-sundae hands a banded solver's Jacobian callback a full N x N array (``np.zeros((N, N))``): at n = 6,000
    that is (10 x 6,000)^2 x 8 bytes = 28.8 GB (26.8 GiB), and ``linsolver=band`` ended after the build in "internal
    error: MemoryError" (exit 1). The estimate counts the array now: one line naming linsolver and the n a band fits
    at, exit 2, before any graph; the compiled route bands in C without it and gets to its build."""
    monkeypatch.setenv(resources.MEMORY_ENV, "16G")
    code = main(["run", "twisted-cylinder", "--n", "6000", "--integrator", integrator, "--option", "linsolver=band",
                 "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, err
    assert err.startswith("mol-shell: error: linsolver = 'band' is outside {auto, sparse} at n = 6,000 (band up to "
                          "n = "), err
    assert f"of which {(10 * 6000) ** 2 * 8 / 1e9:.3g} GB for the full 60,000 x 60,000 array" in err, err
    # the largest n: (10 n)^2 x 8 bytes within 16 GiB less the rest (300 MB and 40 kB per node: a few per cent)
    largest = int(err.split("band up to n = ")[1].split(" ")[0].replace(",", ""))
    bound = (16 * 1024**3 / 800) ** 0.5
    assert 0.95 * bound < largest < bound, (largest, bound)
    with pytest.raises(ParameterError, match=r"^linsolver = 'band' is outside \{auto, sparse\} at n = 6,000"):
        mol_shell.simulate("twisted-cylinder", integrator, n=6000, t_end=1e-5, linsolver="band")
    with pytest.raises(Built):  # SUNDIALS' own band matrix: N x (ml + mu + 1) doubles
        mol_shell.simulate("twisted-cylinder", integrator.removeprefix("sksundae-"), n=6000, t_end=1e-5,
                           linsolver="band")


def test_the_default_linear_solver_is_estimated_as_before(monkeypatch, no_build):
    """The default (``auto``: banded or sparse above 100 unknowns) and CVODE-Adams' fixed-point iteration keep no
    N x N matrix: the estimate at n = 6,000 is the one without a method, and such a run gets to its build."""
    monkeypatch.setenv(resources.MEMORY_ENV, "16G")
    plain = resources.estimate(6000, 11, 1e-5, "cvode-bdf").memory_bytes
    for name in ("cvode-bdf", "cvode-adams", "ida", "sksundae-cvode-bdf", "sksundae-ida"):
        method = mol_shell.integrators.INTEGRATORS[name]()
        assert method.dense_matrices(60000) == 0
        assert resources.estimate(6000, 11, 1e-5, name, method=method).memory_bytes == resources.estimate(
            6000, 11, 1e-5, name).memory_bytes
    assert resources.estimate(6000, 11, 1e-5, "cvode-bdf").memory_bytes == plain < 2e9
    for name in ("cvode-bdf", "ida"):
        with pytest.raises(Built):
            mol_shell.simulate("twisted-cylinder", name, n=6000, t_end=1e-5)


def _work_precision(**kwargs):
    from mol_shell.analysis.workprecision import work_precision

    return work_precision("sphere", ("leapfrog", "cvode-bdf"), **kwargs)


@pytest.mark.parametrize("command, what, call", [
    (["modes", "sphere"], "computing 10 modes needs about", lambda n: mol_shell.modes("sphere", n=n)),
    (["path", "sphere", "--param", "pressure=0:100"], "tracing a path of up to 200 steps needs about",
     lambda n: mol_shell.path("sphere", "pressure", 0.0, 100.0, n=n)),
    (["compare", "sphere", "--integrators", "leapfrog,cvode-bdf"], "each leapfrog run of the comparison needs about",
     lambda n: _work_precision(n=n)),
])
def test_modes_paths_and_comparisons_too_large_for_memory_are_refused_before_any_graph(command, what, call, capsys,
                                                                                        tmp_path, monkeypatch,
                                                                                        no_build):
    """``--n 1000000000`` filled the machine's memory until the kernel killed the process (modes), or ended in an
    internal MemoryError (path, compare): now one line naming n and the estimate, exit 2, before building. A size
    that fits gets past the check (to the graph's build)."""
    start = time.perf_counter()
    code = main([*command, "--n", "1000000000", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert time.perf_counter() - start < 5
    assert code == 2 and err.startswith("mol-shell: error: --n = 1000000000 is outside integers 3..") and what in err, err
    assert len(err.splitlines()) == 1 and "use fewer nodes (--n)" in err
    monkeypatch.setattr(sys.modules["mol_shell.analysis.equilibria"], "ShellSystem", sys.modules[
        "mol_shell.runs.building"].ShellSystem)  # the path's equations build their own system
    with pytest.raises(Built):
        call(41)


def test_a_study_of_paths_too_large_for_memory_is_refused_once_before_its_cases(capsys, tmp_path, no_build):
    """Each case was refused on its own (exit 3, nothing on stderr): now the study is, once, before any case."""
    code = main(["study", "sphere", "--vary", "nu=0.3,0.4", "--path", "pressure=0:100", "--n", "1000000000",
                 "--scheduler", "serial", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: --n = 1000000000 is outside integers 3..") and len(
        err.splitlines()) == 1 and "tracing each path of up to 200 steps needs about" in err, err
    assert not (tmp_path / "s.nc").exists()


def test_a_long_build_is_announced_before_it_starts(no_build):
    """At n = 100,000 the graph and the spectrum took 107 s in silence before the step was refused: a build
    projected (1.3 ms per node) past LONG_BUILD_S is announced first; n = 40 is not."""
    announced = r"^building the graphs and the spectrum at n = 100,000 takes about 2\.17 min before the first step"
    with pytest.warns(LongRunWarning, match=announced), pytest.raises(Built):
        mol_shell.simulate("twisted-cylinder", n=100_000, t_end=1e-3, progress=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(Built):
            mol_shell.simulate("twisted-cylinder", n=40, t_end=1e-3, progress=False)


def test_a_long_analysis_build_is_announced_once_before_it_starts(no_build):
    """Modes at n = 30,000 built the graphs and the exact Jacobian for 31 s in silence (minutes before the inverse
    mass matrix was inverted block by block): an analysis whose build is projected past LONG_ANALYSIS_BUILD_S says
    so, once (not again for the build inside it), before any graph; n = 400 does not."""
    with pytest.warns(LongRunWarning) as said, pytest.raises(Built):
        mol_shell.modes("sphere", n=30_000)
    lines = [str(w.message) for w in said if issubclass(w.category, LongRunWarning)]
    assert lines == ["building the graphs and the Jacobian at n = 30,000 takes about 39 s before computing 10 modes"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(Built):
            mol_shell.modes("sphere", n=400)


def test_a_comparison_takes_at_most_100_repeats(capsys, tmp_path, no_build):
    """``--repeats 1000000000`` was accepted, and the comparison would have run for years."""
    code = main(["compare", "sphere", "--integrators", "leapfrog", "--repeats", "1000000000", "-o",
                 str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: --repeats = 1000000000 is outside integers in [1, 100]"), err
    with pytest.raises(ParameterError, match=r"^repeats = 1000000000 is outside integers 1\.\.100"):
        _work_precision(repeats=1_000_000_000)


def test_a_study_too_large_for_memory_is_refused_before_its_cases_exist(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(sys.modules["mol_shell.runs.study"], "run_task", None)
    code = main(["study", "twisted-cylinder", "--vary", "gamma=0:1:1e-12", "--t-end", "1e-3", "-o",
                 str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: --vary gamma = '0:1:1e-12' is outside at most "), err


def test_a_run_of_more_than_an_hour_is_announced_before_it_starts(capsys, tmp_path, no_build):
    """Leap-frog to 10^4 s at the paper's dt: 10^10 steps at ~18 us, two days: one warning line (a
    LongRunWarning from Python), before the graph is built."""
    with pytest.warns(LongRunWarning, match=r"^this run will take about 2\.\d+ days \(1e\+10 steps at n = 40\)"):
        with pytest.raises(Built):
            mol_shell.simulate("twisted-cylinder", t_end=1e4)
    code = main(["run", "twisted-cylinder", "--t-end", "1e4", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.splitlines()
    assert code == 1 and err[0].startswith("mol-shell: warning: this run will take about 2."), err  # then Built
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(Built):
            mol_shell.simulate("twisted-cylinder", t_end=0.1)  # 100,000 steps: no warning


def test_an_explicit_method_s_lower_bound_is_announced_once_the_spectrum_is_known(monkeypatch):
    """scipy-rk45 over 10^5 s of the paper scene: its stability interval (3.5 on the imaginary axis) and
    max|eig J| = 5,290 /s need at least 1.5e8 steps of 6 evaluations: over an hour, warned before stepping."""

    class Stop(Exception):
        pass

    def integrate(self, *args, **kwargs):
        raise Stop

    monkeypatch.setattr(mol_shell.integrators.INTEGRATORS["scipy-rk45"], "integrate", integrate)
    with pytest.warns(LongRunWarning, match=r"will take at least about .* \(at least 1\.5\de\+08 steps at n = 40\)"):
        with pytest.raises(Stop):
            mol_shell.simulate("twisted-cylinder", "scipy-rk45", times=[0, 1e5])


_PEAK = textwrap.dedent("""
    import numpy as np
    import mol_shell
    from mol_shell.runs import resources

    def peak_rss():  # this process's own high-water mark: getrusage's ru_maxrss also counts the parent's
        # resident set at the fork (Linux keeps it across exec), the whole pytest process here
        with open("/proc/self/status") as status:
            return next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmHWM:"))

    mol_shell.simulate("twisted-cylinder", n=40, times=[0, 1e-6], progress=False)  # imports and build, cached
    base = peak_rss()
    times = np.arange(6001) * 1e-6
    mol_shell.simulate("twisted-cylinder", n=40, times=times, progress=False)
    peak = peak_rss()
    est = resources.estimate(40, len(times), times[-1], "leapfrog", dt=1e-6)
    print(base, peak, est.output_bytes, est.memory_bytes)
""")


@pytest.mark.slow
@pytest.mark.timeout(300)
def test_memory_estimate_bounds_a_measured_run():
    """6,001 saved times at n = 40 (51 MB of output with the stresses, far above the allocator's noise): the process's
    peak grows by more than the output, by at most the factor the estimate assumes, and stays below the estimate."""
    out = subprocess.run([sys.executable, "-c", _PEAK], capture_output=True, text=True, timeout=240, check=True)
    base, peak, output, estimate = (float(x) for x in out.stdout.split())
    assert output == pytest.approx(6001 * (400 + 8 + 17 * 39) * 8 + 3 * 40 * 8)  # the stresses: 17 fields at 39 cells
    assert output <= peak - base <= resources.ASSEMBLY_COPIES * output
    assert peak <= estimate


def test_compilation_that_takes_a_while_says_so(tmp_path, monkeypatch, capsys):
    from mol_shell.discretization import compiled

    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path))
    monkeypatch.setattr(compiled, "COMPILE_PROGRESS_AFTER", 0.001)  # gcc takes 0.04 s on an idle machine
    body = "\n".join(f"  x += {k} * 0.5;" for k in range(3000))
    source = f"double slow(void) {{ double x = 0;\n{body}\n  return x; }}\n"
    compiled.compile_cached(source, "slow", what="a test kernel")
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("mol-shell: compiling a test kernel (") and "s expected" in err[0], err
    assert err[-1].startswith("mol-shell: compiled a test kernel in "), err
    compiled.compile_cached(source, "slow", what="a test kernel")
    assert capsys.readouterr().err == ""  # from the cache: nothing to say


def test_compile_time_is_estimated_only_within_the_measured_sizes():
    from mol_shell.discretization.compiled import CompiledFunctions, estimated_compile_seconds

    assert 0.5 < estimated_compile_seconds(1e5) < 1.0  # a right-hand side at n = 40: ~0.6 s measured
    assert 2 < estimated_compile_seconds(1.1e6, CompiledFunctions.FLAGS) < 5  # a Jacobian at n = 40: ~3 s
    assert estimated_compile_seconds(3.2e8, CompiledFunctions.FLAGS) is None  # n = 10,240: compiled in 1.1 min


def test_step_budget_stops_what_cannot_reach_the_end():
    from mol_shell.integrators.base import StepBudget

    budget = StepBudget("test", t_end=1.0, max_steps=10_000)
    t = 0.0
    with pytest.raises(ModelLimitError, match=r"would need about 1e\+08 steps"):
        for _ in range(10_000):
            t += 1e-8
            budget.step(t)
    assert budget.steps == StepBudget.EVERY
    stuck = StepBudget("test", t_end=1.0, max_steps=10**9)
    with pytest.raises(ModelLimitError, match="would need about inf steps") as info:
        for _ in range(StepBudget.EVERY):
            stuck.step(0.0)
    assert info.value.status == "failed"
    fine = StepBudget("test", t_end=1.0, max_steps=10_000)
    for k in range(1, 2001):
        fine.step(k * 1e-3)  # 1000 steps per unit: reaches the end well within max_steps


def test_memory_sizes_parse():
    assert resources.parse_bytes("8G") == 8 * 1024**3 and resources.parse_bytes("512M") == 512 * 1024**2
    assert resources.parse_bytes("1e9") == 1e9
    with pytest.raises(ParameterError, match="MOL_SHELL_MEMORY = 'lots' is not a size"):
        resources.parse_bytes("lots")


@pytest.mark.parametrize("value", ["0", "1k", "286M", "-1", "-8G", "1e400"])
def test_a_memory_limit_too_small_for_any_run_is_refused_naming_it(value, monkeypatch, capsys, tmp_path, no_build):
    """``MOL_SHELL_MEMORY=0`` was refused as "n = 40 is outside integers 3..3", though n = 3 did not fit either, and
    ``1e400`` (infinite) passed as no limit. A limit below what the smallest run needs (the fixed 300 MB of a build,
    286.1 MiB, and a little for n = 3: 287M), a negative one and an infinite one are refused naming
    MOL_SHELL_MEMORY and its range, one line, exit 2."""
    monkeypatch.setenv(resources.MEMORY_ENV, value)
    code = main(["run", "twisted-cylinder", "--t-end", "1e-4", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, err
    assert err.startswith(f"mol-shell: error: MOL_SHELL_MEMORY = '{value}' is outside finite sizes of at least "
                          "287M ("), err
    assert 300e6 / 1024**2 < 287 < 300e6 / 1024**2 + 1


@pytest.mark.parametrize("value", ["abc", "1.2.3", ".", "5 X"])
def test_a_memory_limit_that_is_not_a_size_is_refused_naming_it(value, monkeypatch, capsys, tmp_path, no_build):
    """``1.2.3`` matched the pattern of a number and ended in a ValueError; every such value is one line, exit 2."""
    monkeypatch.setenv(resources.MEMORY_ENV, value)
    code = main(["run", "twisted-cylinder", "--t-end", "1e-4", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err == (f"mol-shell: error: MOL_SHELL_MEMORY = '{value}' is not a size; allowed: bytes, or "
                                 "a number with k, M, G or T\n"), err


def test_a_memory_limit_that_fits_a_run_is_used(monkeypatch, no_build):
    """``0.5G`` and ``16G`` (powers of 1024) are limits a run at the default n = 40 fits in: it gets to its build."""
    for value, size in (("0.5G", 0.5 * 1024**3), ("16G", 16 * 1024**3), ("287M", 287 * 1024**2)):
        monkeypatch.setenv(resources.MEMORY_ENV, value)
        assert resources.available_memory() == (size, "$MOL_SHELL_MEMORY")
    for value in ("0.5G", "16G"):
        monkeypatch.setenv(resources.MEMORY_ENV, value)
        with pytest.raises(Built):
            mol_shell.simulate("twisted-cylinder", t_end=1e-4)


def test_a_huge_mode_count_is_blamed_on_count_not_on_n(capsys, tmp_path):
    """``--count 1000000000`` was refused as ``n = 41 is outside integers 3..3 ... with 1,000,000,000 modes``: the
    memory check counts at most one mode per coordinate, and the count's own range names it."""
    code = main(["modes", "sphere", "--n", "9", "--count", "1000000000", "-o", str(tmp_path / "m.nc")])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("mol-shell: error: --count = 1000000000 is outside "
                                                             "integers 1.."), err


def test_a_script_filters_the_long_run_warning_by_its_name_from_the_package():
    """A script could not name ``LongRunWarning`` (it was only in ``mol_shell.runs.resources``) to filter it; every
    warning class the package raises is at its top level."""
    import warnings

    import mol_shell
    from mol_shell.runs import resources

    assert mol_shell.LongRunWarning is resources.LongRunWarning and "LongRunWarning" in mol_shell.__all__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", category=mol_shell.LongRunWarning)
        assert resources.warn_if_long(resources.estimate(40, 11, 1e4, "leapfrog", dt=1e-6))  # days of steps: filtered
    for name in ("MaterialWarning", "SceneWarning", "LongRunWarning"):
        assert issubclass(getattr(mol_shell, name), Warning)


def test_default_saved_times_that_do_not_fit_are_said_as_the_default(monkeypatch, capsys, tmp_path, no_build):
    """``MOL_SHELL_MEMORY=287M mol_shell run twisted-cylinder`` (no --times) was refused as ``times = '<11 saved
    times>' is outside at most 4 saved times``: a parameter never given. The default is said as the default, with
    what can change: --times, --n, MOL_SHELL_MEMORY. The memory is set for 8.5 of the per-time share of the output
    (``output x ASSEMBLY_COPIES / times``) above the rest: at most 8 saved times fit."""
    est = resources.estimate(11, 11, 0.01)
    per_time = est.output_bytes * resources.ASSEMBLY_COPIES / 11
    monkeypatch.setenv(resources.MEMORY_ENV, str(int(est.memory_bytes - 2.5 * per_time)))
    code = main(["run", "twisted-cylinder", "--n", "11", "--t-end", "0.01", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, err
    assert err.startswith("mol-shell: error: times = the default 11 saved times (none given) is outside at most 8 "
                          "saved times at n = 11 ("), err
    assert "'<" not in err and err.rstrip().endswith(
        "save fewer times (--times; the default is 10 intervals to t_end) or use fewer nodes (--n), or a larger "
        "MOL_SHELL_MEMORY)"), err
    # times given are said as given (the same 11 times, typed: the command line's own check, naming --times)
    code = main(["run", "twisted-cylinder", "--n", "11", "--times", "0:0.01:0.001", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mol-shell: error: --times = '0:0.01:0.001' is outside at most 8 saved "), err
    # and through the API: 11 even times given are not "the default", though they are the default's times
    for times in (np.linspace(0.0, 0.01, 11), np.linspace(0.0, 0.011, 12)):
        with pytest.raises(ParameterError, match=rf"^times = '<{len(times)} saved times>' is outside at most 8 saved "
                                                 "times at n = 11"):
            mol_shell.simulate("twisted-cylinder", n=11, times=times, progress=False)


def test_the_largest_n_a_refusal_suggests_runs(monkeypatch, capsys, tmp_path, no_build):
    """With MOL_SHELL_MEMORY=287M and 11 saved times, ``--n 12`` was refused as ``integers 3..8`` while n = 9 ran: the
    suggestion was a line through the refused n, and the spectrum's dense matrices grow as n^2. The largest n said now
    is the largest the run's own estimate fits (its next one does not): a memory just enough for n = 9 says 3..9."""
    fit = resources.estimate(9, 2, 0.01).memory_bytes
    monkeypatch.setenv(resources.MEMORY_ENV, str(int(fit)))
    code = main(["run", "twisted-cylinder", "--n", "40", "--times", "0,0.01", "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and "n = 40 is outside integers 3..9 on this machine" in err, err
    assert resources.estimate(9, 2, 0.01).memory_bytes <= fit < resources.estimate(10, 2, 0.01).memory_bytes
