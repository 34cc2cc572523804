"""A stability report or a comparison that a SIGTERM stopped says "terminated by SIGTERM", as a run, a study and a
path do (they said "interrupted by the user", a Ctrl-C's words, with exit 143). The work is stood in for: the report
and the sweep return what an interrupted one returns (their message as the analysis words it), the state of the
command line's watch says a SIGTERM stopped it."""

import xarray as xr

from mol_shell._core import interrupts
from mol_shell.cli import analysis
from mol_shell.cli.main import main


def _interrupted(message):
    return xr.Dataset(attrs={"status": "interrupted", "message": message})


def _stand_ins(monkeypatch, kept):
    monkeypatch.setattr(interrupts, "terminated", lambda: True)
    monkeypatch.setattr(analysis, "write_netcdf", lambda ds, path: kept.append(dict(ds.attrs)))
    monkeypatch.setattr(analysis, "write_text", lambda path, text: None)
    monkeypatch.setattr(analysis, "plot_report", lambda ds, path: None)
    monkeypatch.setattr(analysis, "stability_table", lambda ds: "")
    monkeypatch.setattr(analysis, "write_outputs", lambda ds, path, target: (kept.append(dict(ds.attrs)) or
                                                                            ("c.png", "c.md")))
    monkeypatch.setattr(analysis, "markdown_table", lambda ds, target: "")


def test_a_stability_report_stopped_by_sigterm_says_so(monkeypatch, tmp_path, capsys):
    kept = []
    _stand_ins(monkeypatch, kept)
    said = "at case 'n = 21': the 2 cases before it measured, 9 not run"
    monkeypatch.setattr(analysis, "report", lambda cases, bisect: _interrupted(f"interrupted by the user {said}"))
    code = main(["stability", "twisted-cylinder", "--quick", "--no-bisect", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 143
    assert kept[0]["message"] == f"terminated by SIGTERM {said}"  # the file's attrs
    assert f"mol-shell: stability report stopped: terminated by SIGTERM {said}; wrote " in err, err
    assert "by the user" not in err


def test_a_comparison_stopped_by_sigterm_says_so(monkeypatch, tmp_path, capsys):
    kept = []
    _stand_ins(monkeypatch, kept)
    said = "at rtol 1e-06: the points before it measured, the rest not run"
    monkeypatch.setattr(analysis, "work_precision", lambda *a, **k: _interrupted(f"interrupted by the user {said}"))
    code = main(["compare", "twisted-cylinder", "--n", "9", "-o", str(tmp_path / "c.nc")])
    err = capsys.readouterr().err
    assert code == 143
    assert kept[0]["message"] == f"terminated by SIGTERM {said}"
    assert f"mol-shell: comparison stopped: terminated by SIGTERM {said}; wrote " in err, err
    assert "by the user" not in err
