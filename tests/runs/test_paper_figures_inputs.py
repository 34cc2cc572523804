"""``studies/paper_figures.py``: its grids refused before any work, naming its own options; a Ctrl-C after its run's
end said truly.

``--check-n 2`` (its help: 0 skips) ran the whole paper run, wrote its files and only then said ``n = 2 is outside
integers >= 3``; ``--check-n 4000`` the same, ending ``times = '<7151 saved times>' is outside ...; save fewer times
(--times) or use fewer nodes (--n)``, options the script has not (its --n is the paper run's grid). A Ctrl-C in the
run's ellipticity check, after its end, said ``not drawn, their times not reached: , paper_psi.png (t = 0.143 s)``
and left paper_psi.png undrawn, its samples all there.
"""

import signal
import sys
from pathlib import Path

import pytest
from study_scripts import STUDIES, load_script

from mol_shell._core import interrupts
from mol_shell.cli.scripts import exit_code
from mol_shell.runs import resources
from mol_shell.runs import simulate as simulate_module

#: psi saved every 20 us from 0 to 0.143 s (the paper's times fall on them): 0.143 / 2e-5 + 1
SAVED_TIMES = 7151


@pytest.fixture
def paper(monkeypatch):
    """``paper(*argv)``: the script's exit code, run as its program is; ``paper.runs`` counts the runs it began."""
    module = load_script("paper_figures", "inputs")
    sampled = module._simulate_sampled

    def counted(*args, **kwargs):
        run.runs += 1
        return sampled(*args, **kwargs)

    def run(*argv):
        monkeypatch.setattr(sys, "argv", [str(STUDIES / "paper_figures.py")])
        return exit_code(module.main, list(argv))

    run.runs, run.module = 0, module
    monkeypatch.setattr(module, "_simulate_sampled", counted)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield run
    signal.signal(signal.SIGINT, previous)


def errors(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if ": warning: " not in line]


@pytest.mark.parametrize("value", ["1", "2", "-1"])
def test_a_check_grid_below_three_nodes_is_refused_before_any_work(value, paper, tmp_path, capsys):
    out = tmp_path / "pf"
    assert paper("--check-n", value, "--out", str(out)) == 2
    assert errors(capsys) == [(f"paper_figures.py: error: --check-n = {value} is outside 0 (no finer grid) or integers "
                               ">= 3")]
    assert paper.runs == 0 and not out.exists()


@pytest.mark.parametrize("argv, name", [(["--check-n", "4000"], "--check-n"), (["--n", "4000", "--quick"], "--n")])
def test_a_grid_too_large_for_memory_is_refused_before_any_work_naming_the_scripts_option(argv, name, paper, tmp_path,
                                                                                          capsys, monkeypatch):
    """With 1 GB available, 4,000 nodes x 7,151 saved times x 10 values x 8 bytes (2.3 GB of output) do not fit:
    refused naming the option, its range with the saved times the script takes (no option sets them), and no
    ``--times``."""
    monkeypatch.setenv(resources.MEMORY_ENV, "1G")
    out = tmp_path / "pf"
    assert paper(*argv, "--out", str(out)) == 2
    err = errors(capsys)
    assert len(err) == 1 and err[0].startswith(f"paper_figures.py: error: {name} = 4000 is outside "), err
    assert "integers 3.." in err[0] and f"on this machine with {SAVED_TIMES:,} saved times" in err[0], err
    assert f"use fewer nodes ({name})" in err[0] and "--times" not in err[0], err
    assert ("0 (no finer grid) or integers 3.." in err[0]) == (name == "--check-n"), err
    assert paper.runs == 0 and not out.exists()


def test_ctrl_c_after_the_runs_end_draws_every_figure_and_says_so(paper, monkeypatch, tmp_path, capsys):
    """The signal in the run's ellipticity check (after its last step; n = 9, dt = 0.1 ms, psi saved every 1 ms to keep
    it cheap, figures 4-8 stood in for): the run's data are whole, so fig4..fig8 and paper_psi.png are drawn and the
    line says so; the numbers are not printed; exit 130."""
    check = simulate_module.check_ellipticity
    module = paper.module
    monkeypatch.setattr(module, "PSI_STEP", 1e-3)

    def snapshots(ds, path):
        assert ds.sizes["time"] == 1
        Path(path).write_bytes(b"")
        interrupts.wrote(path)

    monkeypatch.setattr(module, "plot_snapshots", snapshots)

    def interrupted(*args, **kwargs):
        signal.raise_signal(signal.SIGINT)
        return check(*args, **kwargs)

    monkeypatch.setattr(simulate_module, "check_ellipticity", interrupted)
    assert paper("--quick", "--n", "9", "--dt", "1e-4", "--out", str(tmp_path)) == 130
    names = ["paper_figures.nc"] + [f"fig{k}.png" for k in range(4, 9)] + ["paper_psi.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names)
    assert (tmp_path / "paper_psi.png").read_bytes().startswith(b"\x89PNG")
    written = "7 files, the last " + ", ".join(str(tmp_path / name) for name in names[-3:-1])  # kept_files' form
    assert errors(capsys) == [(
        "paper_figures.py: run stopped: interrupted by the user after the run reached its end, t = 0.143 s, before its "
        "ellipticity check; every figure drawn from the whole run; its numbers not printed; "
        f"wrote {written} and {tmp_path / 'paper_psi.png'}")]
