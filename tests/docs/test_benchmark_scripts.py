"""The benchmarks' command lines refuse what they cannot measure in one line (exit code 2), and every option says
its default in ``--help``; no benchmark is run here.

rhs_side_by_side.py and performance.py ended in a FileNotFoundError traceback on a --baseline that does not
exist, and rhs_side_by_side.py measured whatever mol_shell was importable on a folder that is no checkout (and
printed a ratio of this tree to itself); materials_cost.py ended in ``KeyError: 'bogus'`` on ``--laws bogus``.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

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


@pytest.mark.parametrize("script", ["cvode_settings.py", "engine.py", "materials_cost.py", "path_scaling.py",
                                    "performance.py", "rhs_side_by_side.py"])
def test_every_option_says_its_default(script, tmp_path):
    out = run(script, "--help", cwd=tmp_path)
    assert out.returncode == 0, out
    options = [o.strip() for o in re.split(r"\n  (?=-)", out.stdout.split("\noptions:\n", 1)[1])]
    silent = [o.split()[0] for o in options if not o.startswith("-h")
              and "default" not in " ".join(o.split()) and "--xlarge" not in o and not o.startswith("--baseline")]
    assert not silent, f"{script}: {silent} say no default"
