"""Kernels in the cache are used without gcc: only what must be built needs one. A small scene's kernels are built with
gcc into a cache of this module's own; then gcc is hidden (``PATH``) and the runs load them: the compiled Jacobian as
the default ``jacobian``, the compiled SUNDIALS loop, the leap-frog's stencil, with the results of the runs with gcc.
With an empty cache and no gcc the fallbacks are those said before, in one line each."""

import shutil
import sys

import numpy as np
import pytest

import mol_shell
from mol_shell.discretization import sundials_driver
from mol_shell.integrators import buildable, sundials_c

#: a shell of its own (no other test builds its graphs), small: its kernels compile in a few seconds
SCENE = {"nu": 0.3, "E": 2.4567e6}
N, T_END = 4, 2e-4
#: the runs made with gcc and again without: (integrator, options)
CASES = {
    "sksundae-cvode-bdf": ("sksundae-cvode-bdf", {}),  # jacobian: its default, compiled
    "scipy-bdf": ("scipy-bdf", {}),
    "cvode-bdf": ("cvode-bdf", {}),  # the compiled loop, the driver's difference quotients
    "cvode-bdf sparse": ("cvode-bdf", {"linsolver": "sparse"}),  # the compiled loop on the compiled Jacobian
    "ida": ("ida", {}),  # the compiled loop on IDA's compiled residual
    "leapfrog": ("leapfrog", {}),  # the vectorised stencil
}
NO_GCC = "gcc not found on PATH"


def _fresh():
    """No built system, no loaded driver kept by this process: the next run takes its kernels from the cache."""
    sys.modules["mol_shell.runs.simulate"]._built.cache_clear()
    sundials_driver._load.cache_clear()


def _run(case):
    integrator, options = CASES[case]
    return mol_shell.simulate(mol_shell.TwistedCylinder(**SCENE), integrator, n=N, t_end=T_END, stresses=False,
                              progress=False, **options)


def _builds(cache):
    log = cache / "builds.log"
    return log.read_text().splitlines() if log.exists() else []


@pytest.fixture(scope="module")
def with_gcc(tmp_path_factory):
    """The cache the runs with gcc built, and their Datasets."""
    if shutil.which("gcc") is None:
        pytest.skip("the kernels are built with gcc first")
    cache = tmp_path_factory.mktemp("kernels")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("MOL_SHELL_CACHE", str(cache))
        _fresh()
        try:
            runs = {case: _run(case) for case in CASES}
        finally:
            _fresh()
    return cache, runs


@pytest.fixture
def hide_gcc(tmp_path, monkeypatch):
    """No gcc on PATH; the lines said once per process said again; ``hide_gcc(cache)`` points at a cache."""
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    monkeypatch.setattr(buildable, "_SAID", set())
    monkeypatch.setattr(buildable, "_SETTLED", {}, raising=False)  # the defaults settled for earlier graphs
    monkeypatch.setattr(sundials_c, "_REPORTED", set())
    _fresh()
    yield lambda cache: monkeypatch.setenv("MOL_SHELL_CACHE", str(cache))
    _fresh()


def _same(ds, ref):
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] == ref.attrs["n_steps"]
    np.testing.assert_array_equal(ds["r"].values, ref["r"].values)
    np.testing.assert_array_equal(ds["psi"].values, ref["psi"].values)


@pytest.mark.parametrize("case", ["sksundae-cvode-bdf", "scipy-bdf"])
def test_without_gcc_a_cached_compiled_jacobian_is_the_default(with_gcc, hide_gcc, capsys, case):
    """The default jacobian was the VM's whenever gcc did not work, though the compiled Jacobian of this very graph was
    in the cache (built earlier, or copied there): a line said it could not be built. It is loaded from the cache: the
    file records jacobian = compiled, nothing is said, nothing compiled, and the run is the run with gcc, bit for bit."""
    cache, runs = with_gcc
    hide_gcc(cache)
    built = _builds(cache)
    ds = _run(case)
    assert capsys.readouterr().err == ""
    assert ds.attrs["jacobian"] == "compiled"
    _same(ds, runs[case])
    assert _builds(cache) == built


@pytest.mark.parametrize("case", ["cvode-bdf", "cvode-bdf sparse", "ida"])
def test_without_gcc_a_cached_sundials_driver_runs_the_compiled_loop(with_gcc, hide_gcc, capsys, case):
    """The compiled SUNDIALS driver was refused without gcc on PATH although its library was in the cache ("the
    compiled SUNDIALS driver is unavailable (gcc not found on PATH)", and scikit-sundae's loop). It is loaded: the run
    takes the compiled loop (the compiled Jacobian in it with linsolver = sparse), says nothing, and is the run with
    gcc, bit for bit."""
    cache, runs = with_gcc
    hide_gcc(cache)
    ds = _run(case)
    assert capsys.readouterr().err == ""
    assert ds.attrs["route"] == "compiled C"
    assert ds.attrs["jacobian_kind"] == ("compiled" if case.endswith("sparse") else "dq")
    _same(ds, runs[case])


def test_without_gcc_a_cached_stencil_runs_the_leapfrog_with_the_right_hand_side_in_the_vm(with_gcc, hide_gcc,
                                                                                           tmp_path, capsys):
    """A cache holding the leap-frog's stencil and the SUNDIALS driver but not the right-hand side (copied in part):
    without gcc the leap-frog was refused ("building the leap-frog's step loop needs a C compiler") though its loop was
    cached; it runs on the stencil (its start and restarts from the VM's right-hand side: the run with gcc to
    round-off). cvode-bdf, whose loop calls the compiled right-hand side, takes scikit-sundae's loop saying why."""
    cache, runs = with_gcc
    part = tmp_path / "part"
    part.mkdir()
    for lib in cache.glob("*.so"):
        if not lib.name.startswith("rhs_"):
            shutil.copy(lib, part)
    hide_gcc(part)
    ds = _run("leapfrog")
    assert capsys.readouterr().err == ""
    assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] == runs["leapfrog"].attrs["n_steps"]
    np.testing.assert_allclose(ds["r"].values, runs["leapfrog"]["r"].values, rtol=1e-12)
    ds = _run("cvode-bdf")
    assert capsys.readouterr().err.splitlines() == [
        ("mol-shell: cvode-bdf runs scikit-sundae's Python loop: the compiled SUNDIALS driver is unavailable (the "
         f"compiled right-hand side is not in the cache and cannot be built ({NO_GCC}))")]
    assert ds.attrs["complete"] == 1 and ds.attrs["route"] == "scikit-sundae" and "jacobian_kind" not in ds.attrs
    assert not list(part.glob("rhs_*.so"))


def test_with_an_empty_cache_and_no_gcc_the_fallbacks_are_said_as_before(hide_gcc, tmp_path, capsys):
    """Nothing cached and no gcc: the SUNDIALS routes take scikit-sundae's loop, the defaults the VM's Jacobian, each
    said in its line; the leap-frog is refused naming gcc. A fallback's file said route = compiled C (the route asked
    for, over the statistics of the route taken); it records the route taken."""
    hide_gcc(tmp_path / "cache")
    ds = _run("cvode-bdf")
    assert ds.attrs["complete"] == 1 and ds.attrs["route"] == "scikit-sundae" and "jacobian_kind" not in ds.attrs
    ds = _run("sksundae-cvode-bdf")
    assert ds.attrs["complete"] == 1 and ds.attrs["jacobian"] == "vm"
    assert capsys.readouterr().err.splitlines() == [
        ("mol-shell: cvode-bdf runs scikit-sundae's Python loop: the compiled SUNDIALS driver is unavailable "
         f"({NO_GCC})"),
        ("mol-shell: sksundae-cvode-bdf takes its Jacobian from CasADi's virtual machine (jacobian=vm): the compiled "
         f"Jacobian cannot be built ({NO_GCC})")]
    with pytest.raises(mol_shell.ParameterError, match=f"^{NO_GCC}: building the leap-frog's step loop needs a C "):
        _run("leapfrog")
    assert sorted(p.name for p in (tmp_path / "cache").iterdir()) == []  # nothing built, nothing locked
