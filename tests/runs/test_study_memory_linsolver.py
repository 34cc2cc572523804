"""A study's and a comparison's memory check up front counts each run's linear solver as the run's own check does.

``study --option linsolver=dense`` at a size whose dense matrices do not fit: each case's run refused it naming
linsolver, but the study's check (which did not know the linear solver) let it start, ran every case to its refusal
and wrote a file of refused cases. Now the study is refused before it starts, in the run's one line. A comparison's
check counted one N x N matrix for every implicit integrator, where its default linear solver keeps up to three.
"""

from __future__ import annotations

import sys

import pytest
from build_guard import Built

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.workprecision import work_precision
from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS
from mol_shell.runs import resources
from mol_shell.runs.study import study

TIMES = [0.0, 1e-3]


def limit_between(n, integrator, matrices, fitting):
    """A memory limit (bytes) that fits the run of ``integrator`` at ``n`` nodes with ``fitting`` of its ``matrices``
    N x N matrices (N = 2 x 5 fields x n unknowns, 8 bytes each) but not with all of them: halfway between."""
    matrix = (2 * 5 * n) ** 2 * 8
    method = INTEGRATORS[integrator](**({"linsolver": "dense"} if integrator == "cvode-bdf" else {}))
    full = resources.estimate(n, len(TIMES), TIMES[-1], integrator, method=method).memory_bytes
    return int(full - (matrices - fitting) * matrix / 2)


def test_a_study_whose_every_case_a_dense_solver_does_not_fit_is_refused_before_it_starts(monkeypatch, capsys,
                                                                                         tmp_path):
    """cvode-bdf's dense solver keeps two N x N matrices (the Newton matrix and the saved Jacobian): 2 x 110^2 x 8
    = 193.6 kB at n = 11. With memory for all but half of them, the run is refused naming linsolver, and so is a
    study of such runs: exit 2, the same one line, before any case runs and with nothing written."""
    monkeypatch.setenv(resources.MEMORY_ENV, str(limit_between(11, "cvode-bdf", 2, 1)))
    options = ["--n", "11", "--times", "0,0.001", "--integrator", "cvode-bdf", "--option", "linsolver=dense"]
    assert main(["run", "twisted-cylinder", *options, "-o", str(tmp_path / "run.nc")]) == 2
    run_refusal = capsys.readouterr().err.strip()  # n = 10 fits: 2 x (110^2 - 100^2) x 8 = 33.6 kB of matrices,
    # 40 kB of graphs and 4 x (110^2 - 100^2) x 8 = 67.2 kB of spectrum fewer, more than the 96.8 kB missing
    assert run_refusal.startswith("mol-shell: error: linsolver = 'dense' is outside {auto, band, sparse} at n = 11 "
                                  "(a dense solver up to n = 10 here)"), run_refusal
    assert "of which 194 kB for the dense solver's 2 matrices of 110 x 110 unknowns" in run_refusal, run_refusal

    def no_case(task):
        raise AssertionError("a case ran")

    monkeypatch.setattr(sys.modules["mol_shell.runs.study"], "run_task", no_case)
    out = tmp_path / "study" / "s.nc"
    code = main(["study", "twisted-cylinder", "--vary", "gamma=0.1,0.2", *options, "--scheduler", "serial",
                 "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err == run_refusal, err
    assert not (tmp_path / "study").exists()  # neither the file nor its cases' folder (nor the folder made for -o)
    with pytest.raises(ParameterError, match=r"^linsolver = 'dense' is outside") as refused:
        study("twisted-cylinder", {"gamma": [0.1, 0.2]}, "cvode-bdf", n=11, times=TIMES, scheduler="serial",
              linsolver="dense")
    assert refused.value.name == "linsolver"


def test_a_study_with_a_case_that_fits_goes_ahead(monkeypatch):
    """Cases that vary the linear solver: the sparse one fits where the dense one does not, so the study starts
    (its dense cases are refused one by one, as their runs are); only dense ones: refused up front."""
    monkeypatch.setenv(resources.MEMORY_ENV, str(limit_between(11, "cvode-bdf", 2, 1)))
    dense, sparse = INTEGRATORS["cvode-bdf"](linsolver="dense"), INTEGRATORS["cvode-bdf"](linsolver="sparse")
    resources.check_study(2, 11, TIMES, "cvode-bdf", methods=[dense, sparse])
    with pytest.raises(ParameterError, match=r"^linsolver = 'dense' is outside"):
        resources.check_study(2, 11, TIMES, "cvode-bdf", methods=[dense, dense])
    resources.check_study(2, 11, TIMES, "cvode-bdf")  # no methods known: the estimate without a linear solver


def test_a_comparison_counts_each_integrator_s_own_matrices(monkeypatch, no_build):
    """scikit-sundae's CVODE with its default linear solver (dense at 100 unknowns, n = 10) keeps three N x N
    matrices (SUNDIALS' matrix, CVODE's saved Jacobian, the array its Jacobian callback fills): 3 x 100^2 x 8 =
    240 kB; the comparison's check counted one. With memory for two of them, the comparison is refused before any
    graph, naming n (its runs' linear solver is not an option of compare), as a run is."""
    monkeypatch.setenv(resources.MEMORY_ENV, str(limit_between(10, "sksundae-cvode-bdf", 3, 2)))
    with pytest.raises(ParameterError, match=r"^n = 10 is outside integers 3\.\.") as refused:
        work_precision("twisted-cylinder", ["sksundae-cvode-bdf"], n=10, times=TIMES, log=lambda text: None)
    assert "each sksundae-cvode-bdf run of the comparison needs about" in str(refused.value)
    with pytest.raises(ParameterError, match=r"^n = 10 is outside integers 3\.\.") as refused:
        mol_shell.simulate("twisted-cylinder", "sksundae-cvode-bdf", n=10, times=TIMES)
    assert "linsolver" not in str(refused.value)  # was "linsolver = 'auto' is outside {auto, band, sparse}"


def test_a_comparison_checks_the_memory_of_its_reference_runs_too(monkeypatch, no_build):
    """The reference runs (cvode-adams and ida at rtol 1e-12) run whatever ``integrators`` holds; a comparison of
    leap-frog alone checked leap-frog's run only, built the graphs and ran the references into a memory they do not
    fit. With memory for leap-frog's run but not for cvode-adams's (halfway between their estimates, which differ by
    the 100 x 100 Jacobian and the solver vectors an implicit integrator keeps at n = 10), the comparison is refused
    before any graph, naming n and the reference run; with memory for both references it goes on to build."""
    n = 10
    leapfrog = resources.estimate(n, len(TIMES), 0.0, "leapfrog", method=INTEGRATORS["leapfrog"]()).memory_bytes
    references = [resources.estimate(n, len(TIMES), 0.0, name, method=INTEGRATORS[name](rtol=1e-12, atol=1e-15))
                  .memory_bytes for name in ("cvode-adams", "ida")]
    assert leapfrog < min(references)
    monkeypatch.setenv(resources.MEMORY_ENV, str(int((leapfrog + references[0]) / 2)))
    with pytest.raises(ParameterError, match=r"^n = 10 is outside integers 3\.\.") as refused:
        work_precision("twisted-cylinder", ["leapfrog"], n=n, times=TIMES, log=lambda text: None)
    assert "the reference cvode-adams run of the comparison needs about" in str(refused.value)
    monkeypatch.setenv(resources.MEMORY_ENV, str(int(max(references) * 1.01)))
    with pytest.raises(Built):
        work_precision("twisted-cylinder", ["leapfrog"], n=n, times=TIMES, log=lambda text: None)
