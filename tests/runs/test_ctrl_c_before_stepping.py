"""A Ctrl-C in ``simulate`` before the run steps (its graphs, the kernel's compilation: each new ``nu`` compiles one)
raises ``KeyboardInterrupt``; once it steps the run returns its Dataset, ``status`` ``interrupted``. docs/python.md
said Ctrl-C inside ``simulate`` does not raise, and built its loop of runs on that alone."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest
import xarray as xr

import mol_shell
import mol_shell.runs.simulate as simulate_module

DOC = (Path(__file__).resolve().parents[2] / "docs" / "python.md").read_text()


def _loop_idiom():
    """The docs' loop of runs over ``nu`` (the block that stops on an interrupted run)."""
    blocks = re.findall(r"```python\n(.*?)```", DOC, flags=re.DOTALL)
    loops = [b for b in blocks if b.startswith("for nu in") and "interrupted" in b]
    assert len(loops) == 1, loops
    return loops[0]


def _names():
    """What the docs' block reads: ``mol_shell``, ``replace`` and a ``scene``."""
    return {"mol_shell": mol_shell, "replace": replace, "scene": mol_shell.TwistedCylinder()}


def _ctrl_c_in_build(scene, n):
    raise KeyboardInterrupt


def test_a_ctrl_c_in_the_build_raises_keyboard_interrupt(monkeypatch):
    monkeypatch.setattr(simulate_module, "build", _ctrl_c_in_build)
    with pytest.raises(KeyboardInterrupt):
        mol_shell.simulate(mol_shell.TwistedCylinder(nu=0.3), "cvode-bdf", n=9, t_end=0.01)


def test_the_docs_say_so():
    said = " ".join(DOC.split())
    assert "Ctrl-C inside `simulate` does not raise:" not in said  # unqualified, as it was
    assert "Before it steps" in said and "raises `KeyboardInterrupt`" in said
    doc = " ".join(mol_shell.simulate.__doc__.split())
    assert "KeyboardInterrupt A Ctrl-C before the run steps" in doc


def test_the_docs_loop_stops_on_a_ctrl_c_in_the_build(monkeypatch):
    calls = []

    def build(scene, n):
        calls.append(scene.nu)
        raise KeyboardInterrupt

    monkeypatch.setattr(simulate_module, "build", build)
    with pytest.raises(KeyboardInterrupt):
        exec(_loop_idiom(), _names())  # noqa: S102 - the docs' own block
    assert calls == [0.3]  # the first case's build: the loop went no further


def test_the_docs_loop_stops_on_an_interrupted_run(monkeypatch):
    calls = []

    def simulate(scene, integrator, **kwargs):  # the run Ctrl-C stopped as it stepped: its Dataset, interrupted
        calls.append(scene.nu)
        return xr.Dataset(attrs={"status": "interrupted", "complete": 0})

    monkeypatch.setattr(mol_shell, "simulate", simulate)
    exec(_loop_idiom(), _names())  # noqa: S102 - the docs' own block
    assert calls == [0.3]
