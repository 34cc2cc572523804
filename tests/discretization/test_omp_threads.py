"""Without ``$MOL_SHELL_THREADS`` the kernels follow ``$OMP_NUM_THREADS`` (what cluster job scripts and .ci/run set)
as OpenMP reads it, else take every usable CPU: OMP_NUM_THREADS=1 was ignored and two threads on a loaded 2-core
machine made a run 13x slower."""

import os

import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.discretization import threads


def test_omp_num_threads_gives_the_default_count(monkeypatch):
    monkeypatch.delenv("MOL_SHELL_THREADS", raising=False)
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    for given, count in [("1", 1), ("3", 3), (" 2 ", 2), ("4,2", 4), (str(10**9), threads.max_threads()),
                         ("0", usable), ("-2", usable), ("two", usable), ("", usable), (None, usable)]:
        monkeypatch.setattr(threads, "OMP_NUM_THREADS_GIVEN", given)
        assert threads.default_threads() == count, given
    monkeypatch.setattr(threads, "OMP_NUM_THREADS_GIVEN", "1")
    monkeypatch.setenv("MOL_SHELL_THREADS", "2")  # the package's own variable first
    assert threads.default_threads() == 2
    monkeypatch.setenv("MOL_SHELL_THREADS", "0")  # and still refused when bad, whatever OpenMP says
    with pytest.raises(ParameterError, match="MOL_SHELL_THREADS"):
        threads.default_threads()


def test_the_value_is_read_before_the_package_defaults_it_for_superlu(monkeypatch):
    """The package sets OMP_NUM_THREADS = 1 when unset (SuperLU_MT spins otherwise), after reading it: that default
    is not taken for the user's choice, and a value given (conftest's 1, .ci/run's 1) is followed."""
    monkeypatch.delenv("MOL_SHELL_THREADS", raising=False)
    assert os.environ["OMP_NUM_THREADS"] == (threads.OMP_NUM_THREADS_GIVEN or "1")
    if threads.OMP_NUM_THREADS_GIVEN == "1":
        assert threads.default_threads() == 1
