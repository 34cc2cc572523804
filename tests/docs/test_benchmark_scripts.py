"""The benchmarks' command lines refuse what they cannot measure in one line (exit code 2), and every option says
its default in ``--help``; no benchmark is run here.

rhs_side_by_side.py and performance.py ended in a FileNotFoundError traceback on a --baseline that does not
exist, and rhs_side_by_side.py measured whatever mol_shell was importable on a folder that is no checkout (and
printed a ratio of this tree to itself); materials_cost.py ended in ``KeyError: 'bogus'`` on ``--laws bogus``.
A count out of the range its ``--help`` states ended in a traceback, some after the builds and runs:
``leapfrog_paper.py --repeats 0`` in ``StatisticsError: no median for empty data``, ``path_scaling.py --n 2`` in
the child's CalledProcessError with its whole source.
"""

import re
import runpy
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import mol_shell
import mol_shell.runs.simulate

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def run(script, *args, cwd):
    return subprocess.run([sys.executable, str(BENCHMARKS / script), *args], capture_output=True, text=True,
                          cwd=cwd, timeout=120, check=False)


@pytest.mark.parametrize("script", ["engine.py", "performance.py", "rhs_side_by_side.py"])
@pytest.mark.parametrize("baseline", ["missing", "not-a-checkout"])
def test_a_baseline_that_is_no_checkout_is_refused(script, baseline, tmp_path):
    path = tmp_path / baseline
    if baseline == "not-a-checkout":
        path.mkdir()
    out = run(script, "--baseline", str(path), "--rounds", "1", cwd=tmp_path)
    assert out.returncode == 2 and not out.stdout, out
    assert out.stderr == f"benchmarks/{script}: --baseline {str(path)!r}: not a checkout of mol_shell " \
                         "(no mol_shell/__init__.py there)\n"


def test_an_unknown_law_is_refused_in_one_line_listing_the_laws(tmp_path):
    out = run("materials_cost.py", "--laws", "bogus", cwd=tmp_path)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "invalid choice: 'bogus'" in out.stderr and "'svk', 'svk-plane-stress', 'neo-hookean'" in out.stderr


#: every script (the two helpers aside)
SCRIPTS = sorted(p.name for p in BENCHMARKS.glob("*.py") if p.name not in ("arguments.py", "baselines.py"))
#: the options that take no number
WORDS = {"--json", "--baseline", "--targets", "--scenes", "--integrators", "--laws", "--xlarge"}


@pytest.mark.parametrize("script", SCRIPTS)
def test_every_option_says_its_default(script, monkeypatch, capsys):
    code, out, _ = in_process(script, ["--help"], monkeypatch, capsys)
    assert code == 0, out
    options = [o.strip() for o in re.split(r"\n  (?=-)", out.split("\noptions:\n", 1)[1])]
    silent = [o.split()[0] for o in options if not o.startswith("-h")
              and "default" not in " ".join(o.split()) and "--xlarge" not in o and not o.startswith("--baseline")]
    assert not silent, f"{script}: {silent} say no default"


def in_process(script, argv, monkeypatch, capsys):
    """``(exit code, stdout, stderr)`` of ``script`` run as ``__main__`` in this process (cheap: mol_shell imported
    once), with NumPy's error state and the warnings' filters restored after it."""
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    monkeypatch.setattr(sys, "argv", [str(BENCHMARKS / script), *argv])
    with np.errstate(), warnings.catch_warnings(), pytest.raises(SystemExit) as ended:
        runpy.run_path(str(BENCHMARKS / script), run_name="__main__")
    out = capsys.readouterr()
    return ended.value.code, out.out, out.err


def stated_ranges(script, monkeypatch, capsys):
    """``{option: range}`` of the options of ``script`` as its ``--help`` states them."""
    code, out, _ = in_process(script, ["--help"], monkeypatch, capsys)
    assert code == 0
    options = [" ".join(o.split()) for o in re.split(r"\n  (?=-)", out.split("\noptions:\n", 1)[1])]
    ranges = {}
    for option in options[1:]:  # -h first
        found = re.search(r"(an integer >= -?\d+|a number > 0)", option)
        name = option.split()[0].rstrip(",")
        assert found or name in WORDS, f"{script}: {name} states no range"
        if found:
            ranges[name] = found.group(1)
    return ranges


@pytest.mark.parametrize("script", SCRIPTS)
def test_every_number_out_of_its_stated_range_is_refused_in_one_line_before_any_work(script, monkeypatch, capsys,
                                                                                     tmp_path):
    ranges = stated_ranges(script, monkeypatch, capsys)
    assert ranges, script  # each script takes a count: its runs, rounds or grids
    for option, stated in ranges.items():
        low = int(stated.split()[-1]) if "integer" in stated else 0
        cases = {str(low - 1): f"{option} = {low - 1} is outside " +
                 (f"integers >= {low}" if "integer" in stated else "(0, inf) s"),
                 "abc": f"{option} = 'abc' is not " + (f"an integer; allowed: integers >= {low}" if "integer" in stated
                                                       else "a number; allowed: (0, inf) s")}
        if "integer" not in stated:
            cases["nan"] = f"{option} = nan is outside (0, inf) s"
        for value, said in cases.items():
            code, out, err = in_process(script, ["--baseline", str(tmp_path), option, value], monkeypatch, capsys) \
                if script in ("engine.py", "performance.py", "rhs_side_by_side.py") else \
                in_process(script, [option, value], monkeypatch, capsys)
            assert (code, out, err) == (2, "", f"benchmarks/{script}: error: {said}\n"), (option, value)


@pytest.mark.parametrize("script, argv, said", [
    ("leapfrog_paper.py", ["--repeats", "0"], "--repeats = 0 is outside integers >= 1"),
    ("cvode_settings.py", ["--repeats", "0"], "--repeats = 0 is outside integers >= 1"),
    ("sundials_overhead.py", ["--repeats", "-1"], "--repeats = -1 is outside integers >= 1"),
    ("path_scaling.py", ["--n", "41", "2"], "--n = 2 is outside integers >= 3"),
])
def test_the_probes_counts_are_refused_in_one_line(script, argv, said, monkeypatch, capsys):
    assert in_process(script, argv, monkeypatch, capsys) == (2, "", f"benchmarks/{script}: error: {said}\n")


class _Stop(Exception):
    pass


def test_leapfrog_paper_says_the_papers_law_warning_in_one_line(monkeypatch, capsys):
    # the paper's scene warns of SVK at nu = 0.49 (mol_shell.MaterialWarning); the run itself is left out here
    text = "material = \"svk\" at nu = 0.49: the inextensible director holds the thickness,\n  so the wall is stiffer"

    def resolve(scene):
        warnings.warn(text, mol_shell.MaterialWarning, stacklevel=2)
        raise _Stop

    monkeypatch.setattr(mol_shell.runs.simulate, "resolve", resolve)
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    monkeypatch.setattr(sys, "argv", [str(BENCHMARKS / "leapfrog_paper.py")])
    with np.errstate(), warnings.catch_warnings(), pytest.raises(_Stop):
        runpy.run_path(str(BENCHMARKS / "leapfrog_paper.py"), run_name="__main__")
    assert capsys.readouterr().err == f"benchmarks/leapfrog_paper.py: warning: {' '.join(text.split())}\n"


def test_sundials_overhead_times_one_rhs_as_leapfrog_paper_does_and_labels_seconds(monkeypatch):
    # the same call timed the same way in both (one batch alone read 28.72 us against 9.42 us); the callbacks'
    # columns and the rest are seconds of the run
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    names = runpy.run_path(str(BENCHMARKS / "sundials_overhead.py"), run_name="sundials_overhead_probe")
    assert names["rhs_cost"].__module__ == "leapfrog_paper"
    for column in ("in RHS", "in Jacobian", "in events", "SUNDIALS + wrappers"):
        assert f"{column} [s]" in names["COLUMNS"], column
