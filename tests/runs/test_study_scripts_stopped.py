"""A Ctrl-C stops a script of ``studies/`` that runs ``mol_shell.simulate`` (or the stability report): exit 130, one
line saying what stopped and what was written, what was saved kept. ``simulate`` returns a run that a Ctrl-C stopped
as data (``attrs["status"] = "interrupted"``), and the scripts read it as finished: ``ring_vs_pde.py --quick`` compared
a truncated run with the ODE and exited 0, ``stability_report.py --quick`` wrote the paper case alone and exited 0,
``paper_figures.py --quick`` took the paper's times past the run's end (``InvalidIndexError``, exit 1). And their
options are refused naming the option typed, not the saved ``times`` the script makes of it.

The SIGINT is real: sent from inside the run as the leap-frog loop checks the state it reached at ``t``."""

import ast
import signal
import sys

import numpy as np
import pytest
from study_scripts import STUDIES, load_script

import mol_shell
from mol_shell.analysis import stability
from mol_shell.cli.scripts import exit_code
from mol_shell.integrators.base import Monitor
from mol_shell.results.dataset import read_netcdf


def load(name):
    return load_script(name, "stopped")


@pytest.fixture
def script(monkeypatch):
    """``script(name, *argv)``: the script's exit code and the lines of its standard error, run as its program is."""
    def run(name, *argv):
        monkeypatch.setattr(sys, "argv", [str(STUDIES / f"{name}.py")])
        return exit_code(load(name).main, list(argv))

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # Python's, whatever the runner set
    yield run
    signal.signal(signal.SIGINT, previous)


def sigint_at(monkeypatch, t_stop, armed=(True,)):
    """SIGINT to this process once, as a run's loop checks its state at a time ``>= t_stop`` (once ``armed`` holds)."""
    check, sent = Monitor.check, []

    def checked(self, y, t):
        if t >= t_stop and armed and not sent:
            sent.append(t)
            signal.raise_signal(signal.SIGINT)
        return check(self, y, t)

    monkeypatch.setattr(Monitor, "check", checked)


def errors(capsys):
    """The lines of standard error but the scene's warnings (the ring's material, at nu = 0.49)."""
    return [line for line in capsys.readouterr().err.splitlines() if ": warning: material" not in line]


def test_ctrl_c_in_a_ring_vs_pde_run_stops_the_script_without_comparing_it(script, monkeypatch, tmp_path, capsys):
    """The first leap-frog run (dt = 8 us, 5 steps a saved time, 40 us) signalled at the saved time 0.2 ms stops at the
    end of the next 40 us: nothing compared, nothing written (was: exit 0, the discrepancy of the truncated run
    written and printed)."""
    sigint_at(monkeypatch, 2e-4)
    assert script("ring_vs_pde", "--quick", "--n", "3", "--t-end", "0.0004", "--out", str(tmp_path)) == 130
    assert errors(capsys) == ["ring_vs_pde.py: run stopped: interrupted by the user at t = 0.00024 s; nothing written"]
    assert not (tmp_path / "ring_vs_pde.nc").exists()


def test_ctrl_c_in_the_stability_reports_second_case_keeps_the_first_and_exits_130(script, monkeypatch, tmp_path,
                                                                                     capsys):
    """Two cases (n = 9, to 1 ms, no bisection); the signal in the second's leap-frog run: stability.nc, .md and .png
    hold the first case, said so, exit 130 (was: exit 0, as if the report were whole)."""
    module = load("stability_report")
    cheap = [stability.Case(label, mol_shell.TwistedCylinder(), n=9, t_end=1e-3) for label in ("first", "second")]
    monkeypatch.setattr(module, "cases", lambda max_n=None, quick=False: cheap)
    monkeypatch.setattr(module, "report", lambda cases: stability.report(cases, bisect=False))
    run_case, armed = stability.run_case, []
    sigint_at(monkeypatch, 5e-4, armed)

    def second_interrupted(case, **kwargs):
        if case.label == "second":
            armed.append(True)
        return run_case(case, **kwargs)

    monkeypatch.setattr(stability, "run_case", second_interrupted)
    monkeypatch.setattr(sys, "argv", [str(STUDIES / "stability_report.py")])
    assert exit_code(module.main, ["--quick", "--out", str(tmp_path)]) == 130
    files = [tmp_path / f"stability.{suffix}" for suffix in ("nc", "md", "png")]
    line = ("stability_report.py: stability report stopped: interrupted by the user at case 'second': the 1 case "
            f"before it measured, 1 not run; wrote {files[0]}, {files[1]} and {files[2]}")
    assert errors(capsys) == [line]
    ds = read_netcdf(files[0])
    assert list(ds.case.values) == ["first"] and ds.attrs["status"] == "interrupted"


def test_ctrl_c_in_the_paper_run_keeps_it_and_draws_the_figures_of_the_times_it_reached(script, monkeypatch, tmp_path,
                                                                                         capsys):
    """Stopped at t = 0.06 s (dt = 5 us, n = 9; saved every 20 us): paper_figures.nc every 1 ms to 0.06 s and at the
    paper's times 0 and 0.02 s, each time once; fig4.png (t = 0) and fig5.png (0.02 s) drawn, fig6-8 (0.07, 0.106,
    0.143 s) and paper_psi.png (its t = 0.143 s panel) not, said so; exit 130 (was: exit 1, InvalidIndexError, the
    file with 0.06 s three times over)."""
    sigint_at(monkeypatch, 0.06)
    assert script("paper_figures", "--quick", "--n", "9", "--dt", "5e-6", "--out", str(tmp_path)) == 130
    ds = read_netcdf(tmp_path / "paper_figures.nc")
    np.testing.assert_allclose(ds.time.values, np.arange(61) * 1e-3, rtol=0, atol=1e-12)
    assert sorted(p.name for p in tmp_path.glob("*.png")) == ["fig4.png", "fig5.png"]
    written = ", ".join(str(tmp_path / name) for name in ("paper_figures.nc", "fig4.png"))
    line = ("paper_figures.py: run stopped: interrupted by the user at t = 0.06 s; not drawn, their times not reached: "
            "fig6.png (t = 0.07 s), fig7.png (t = 0.106 s), fig8.png (t = 0.143 s), paper_psi.png (t = 0.143 s); "
            f"wrote {written} and {tmp_path / 'fig5.png'}")
    assert errors(capsys) == [line]


def test_ctrl_c_in_an_unshearable_run_stops_unshearable_vs_free(script, monkeypatch, tmp_path, capsys):
    """simulate_unshearable keeps a run a Ctrl-C stopped as data: the script went on with it (compared, wrote, ran the
    study); now it stops there, nothing written, exit 130 (n = 5, saved every 1 ms to 2 ms, signalled at 1 ms)."""
    sigint_at(monkeypatch, 1e-3)
    assert script("unshearable_vs_free", "--n", "5", "--t-end", "0.002", "--dt", "2e-6", "--scheduler", "serial",
                  "--out", str(tmp_path)) == 130
    line = "unshearable_vs_free.py: run stopped: interrupted by the user at t = 0.001 s; nothing written"
    assert errors(capsys) == [line]
    assert not list(tmp_path.iterdir())


#: the mol_shell functions that return a run (report, comparison) a Ctrl-C stopped as data, ``attrs["status"] =
#: "interrupted"``, for the caller to check (``simulate_ring`` raises today: checked as every run is)
RUN_FUNCTIONS = {"simulate", "simulate_unshearable", "simulate_ring", "path", "path_study", "modes", "report",
                 "run_case", "work_precision"}


def unchecked_runs(source):
    """The calls in ``source`` of a :data:`RUN_FUNCTIONS` of mol_shell (by name or through a module) but the wrappers
    of :mod:`mol_shell.cli.scripts`, whose run no ``finished(...)`` checks: neither ``finished(f(...))`` nor ``x =
    f(...)`` with a ``finished(x, ...)`` in the script."""
    tree = ast.parse(source)
    origin = {}  # a name bound by an import -> the module it came from (a module imported: its own name)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            origin.update({alias.asname or alias.name: node.module for alias in node.names})
        elif isinstance(node, ast.Import):
            origin.update({alias.asname or alias.name: alias.name for alias in node.names})
    parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    checked = {ast.unparse(node.args[0]) for node in ast.walk(tree) if isinstance(node, ast.Call)
               and ast.unparse(node.func) == "finished" and node.args}
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        base, name = node.func, ast.unparse(node.func).rsplit(".", 1)[-1]
        while isinstance(base, ast.Attribute):
            base = base.value
        module = origin.get(getattr(base, "id", None), "")
        if name not in RUN_FUNCTIONS or not module.startswith("mol_shell") or module == "mol_shell.cli.scripts":
            continue
        parent = parents[node]
        wrapped = ast.unparse(parent.func) == "finished" if isinstance(parent, ast.Call) else (
            isinstance(parent, ast.Assign) and any(ast.unparse(target) in checked for target in parent.targets))
        if not wrapped:
            found.append(ast.unparse(node.func))
    return found


def test_the_check_finds_a_run_left_unchecked():
    assert unchecked_runs("from mol_shell.runs.unshearable import simulate_unshearable\nds = simulate_unshearable(s)") \
        == ["simulate_unshearable"]
    assert unchecked_runs("import mol_shell\nds = mol_shell.simulate(s)") == ["mol_shell.simulate"]
    assert unchecked_runs("from mol_shell.analysis import workprecision as wp\nds = wp.work_precision(s)\n"
                          "finished(ds)") == []
    assert unchecked_runs("from mol_shell.cli.scripts import simulate\nds = simulate(s)") == []


@pytest.mark.parametrize("path", sorted(STUDIES.glob("*.py")), ids=lambda p: p.stem)
def test_every_script_runs_simulate_through_the_scripts_entry(path):
    """``mol_shell.cli.scripts.simulate`` (and ``finished``) stops a script whose run was interrupted: none calls a run
    function of mol_shell unchecked (``mol_shell.simulate``'s interrupted run plane_stress.py, ellipticity.py and
    implicit_scaling.py took as finished, or as a bug; unshearable_vs_free.py its ``simulate_unshearable``'s, and
    work_precision.py wrote and printed an interrupted comparison, exit 0)."""
    assert unchecked_runs(path.read_text()) == []


@pytest.mark.parametrize(("name", "argv", "said"), [
    ("ring_vs_pde", ["--t-end", "0.0001"], "--t-end = 0.0001 is outside multiples of 4e-05 s"),
    ("ring_vs_pde", ["--t-end", "1e-9"], "--t-end = 1e-9 is outside multiples of 4e-05 s"),
    ("paper_figures", ["--dt", "1"], "--dt = 1 is outside (0, 0.001] s"),
])
def test_options_the_script_makes_times_of_are_refused_naming_the_option(name, argv, said, script, tmp_path, capsys):
    """Each was refused by simulate naming ``times`` (``times = 3.3333e-05 is outside multiples of dt = 8e-06 s``,
    ``times = [0.0] is outside increasing finite times starting at 0``): ring_vs_pde saves every 40 us at most, which
    every step it runs (8, 4, 2, 1 us) divides only for a t_end of whole 40 us; paper_figures saves its fields every
    1 ms at the leap-frog step nearest."""
    assert script(name, "--quick", *argv, "--out", str(tmp_path)) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"{name}.py: error: {said}"), err


def test_paper_figures_says_leapfrogs_bound_of_its_dt_naming_dt(script, tmp_path, capsys):
    """Past leap-frog's bound (n = 9: about 1/5,290 s, the transverse-shear mode's, as at n = 40) simulate refused
    ``dt = ...``; the script says ``--dt``."""
    assert script("paper_figures", "--quick", "--n", "9", "--dt", "5e-4", "--out", str(tmp_path)) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("paper_figures.py: error: --dt = 0.0005 is outside (0, "), err


def test_ctrl_c_before_the_stability_reports_first_case_finished_is_one_line_and_130(script, monkeypatch, tmp_path,
                                                                                     capsys):
    """A report with no case measured has nothing to keep: the interrupt goes on (``report`` raises it again), and
    the script says so in one line, nothing written, exit 130."""
    module = load("stability_report")
    cheap = [stability.Case(label, mol_shell.TwistedCylinder(), n=9, t_end=1e-3) for label in ("first", "second")]
    monkeypatch.setattr(module, "cases", lambda max_n=None, quick=False: cheap)

    def interrupted(case, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(stability, "run_case", interrupted)
    assert script("stability_report", "--quick", "--out", str(tmp_path)) == 130
    assert errors(capsys) == ["stability_report.py: interrupted"]
    assert not list(tmp_path.iterdir())
