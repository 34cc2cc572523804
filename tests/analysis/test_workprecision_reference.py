"""``compare`` whose reference check does not complete: ``mol-shell compare examples/drum_spin_down.toml`` stopped
after 54 s, exit 3, nothing written, "the reference runs (cvode-adams and ida at rtol 1e-12) did not complete (ida
took max_steps = 1000000 steps ...)", though the reference itself (cvode-adams) had completed; only IDA's check
ran out of its step budget. Here IDA's budget is cut to a few steps on a cheap scene: the comparison keeps the
reference, records and says that its check did not complete, and estimates the reference's error by the check's
agreement up to where it stopped and by the reference's route at a 10x looser tolerance."""

import numpy as np

from mol_shell._core import progress
from mol_shell.analysis import workprecision as wp
from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS
from mol_shell.results.dataset import read_netcdf

ARGV = ["compare", "twisted-cylinder", "--integrators", "dop853-c", "--n", "8", "--t-end", "2e-3", "--repeats", "1"]


def _ida_on_a_small_budget(monkeypatch, max_steps=2000):  # of the 3774 it takes: stops after t = 1e-3 s
    original = wp.run_once

    def run_once(system, compiled, y0, times, name, value, **kw):
        if name != "ida":
            return original(system, compiled, y0, times, name, value, **kw)
        method = INTEGRATORS[name](**wp.options(name, value), max_steps=max_steps)
        return method.integrate(system, compiled, y0, np.asarray(times), **kw)

    monkeypatch.setattr(wp, "run_once", run_once)


def test_compare_whose_reference_check_runs_out_of_steps_keeps_the_reference_and_says_so(monkeypatch, tmp_path,
                                                                                          capsys):
    _ida_on_a_small_budget(monkeypatch)
    monkeypatch.setattr(progress, "LOG_INTERVAL_S", 0.0)  # a progress line at every update (stderr is no terminal)
    out = tmp_path / "c.nc"
    assert main([*ARGV, "-o", str(out)]) == 0
    captured = capsys.readouterr()
    ds = read_netcdf(out)
    attrs = ds.attrs
    assert attrs["reference"] == "cvode-adams rtol=1e-12" and attrs["reference_check"] == "ida rtol=1e-12"
    assert attrs["reference_check_status"] == "failed"
    assert attrs["reference_check_message"].startswith("ida took max_steps = 2000 steps by t = ")
    assert attrs["reference_check_t"] == 1e-3 and 0 < attrs["reference_check_error"] < 1e-6
    assert attrs["reference_self_check"] == "cvode-adams rtol=1e-11" and attrs["reference_self_check_status"] == "complete"
    assert attrs["reference_error"] == max(attrs["reference_check_error"], attrs["reference_self_error"]) < 1e-6
    assert ds.status.values.ravel()[0] == "complete" and np.isfinite(ds.error.values.ravel()[0])  # the sweep ran
    note = [line for line in captured.err.splitlines() if line.startswith("mol-shell: note: reference ")]
    assert len(note) == 1 and "its check ida rtol=1e-12 did not complete (ida took max_steps = 2000" in note[0], note
    assert "cvode-adams rtol=1e-11 (the same route 10x looser: an upper estimate) differs by" in note[0]
    assert "Not cross-checked: reference cvode-adams rtol=1e-12: error estimated as" in captured.out
    assert "stopped" not in captured.err
    for route in ("cvode-adams rtol=1e-12", "ida rtol=1e-12", "cvode-adams rtol=1e-11"):  # the long part, shown
        assert f"mol-shell: reference {route}: t = " in captured.err, captured.err


def test_compare_whose_reference_runs_both_fail_by_their_budgets_says_so_and_exits_3(monkeypatch, tmp_path, capsys):
    """Neither reference run completes: no error can be measured; one line naming both, exit 3 (as ``run`` exits
    for a run its integrator gave up), nothing written."""

    def run_once(system, compiled, y0, times, name, value, **kw):
        method = INTEGRATORS[name](**wp.options(name, value), max_steps=60)
        return method.integrate(system, compiled, y0, np.asarray(times), **kw)

    monkeypatch.setattr(wp, "run_once", run_once)
    out = tmp_path / "c.nc"
    assert main([*ARGV, "-o", str(out)]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("mol-shell: stopped: the reference runs (cvode-adams and ida at rtol 1e-12) did not "
                              "complete (cvode-adams took max_steps = 60 steps by t = "), err
    assert not out.exists()
