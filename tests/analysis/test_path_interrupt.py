"""Ctrl-C during a path: the steps traced so far are written, said interrupted, exit 130 (as a run keeps its saved
times). A path interrupted after about 150 steps wrote nothing and exited 130."""

from __future__ import annotations

import numpy as np
import pytest
from wrapped_interrupts import WRAPPED

from mol_shell import Sphere, path
from mol_shell.analysis import path as path_module
from mol_shell.analysis.path_record import PathRecord
from mol_shell.cli.main import main

SCENE = Sphere(nu=0.3, material="svk-plane-stress")


def _interrupt_after(monkeypatch, owner, name, calls, kind="keyboard"):
    """``owner.name`` raising KeyboardInterrupt (or, ``kind``, an error of a C call that wraps one: wrapped_interrupts)
    at its ``calls``-th call (the others as before)."""
    original, count = getattr(owner, name), [0]

    def wrapped(*args, **kwargs):
        count[0] += 1
        if count[0] == calls:
            raise WRAPPED[kind]() if kind in WRAPPED else KeyboardInterrupt
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, wrapped)


@pytest.mark.parametrize("kind", ["keyboard", "ctypes", "casadi"])  # ctypes, casadi: the interrupt in a C call
def test_an_interrupted_path_keeps_its_steps_and_exits_130(monkeypatch, tmp_path, capsys, kind):
    _interrupt_after(monkeypatch, path_module._Path, "correct", 6, kind)
    out = tmp_path / "p.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-300", "--set", "nu=0.3", "--set",
                 "material=svk-plane-stress", "--n", "10", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 130 and "path stopped: interrupted by the user at pressure = " in err, err
    from mol_shell.results.dataset import read_netcdf

    ds = read_netcdf(out)
    assert ds.attrs["status"] == "interrupted" and ds.sizes["step"] >= 2
    assert np.all(np.diff(ds.parameter.values) < 0)  # the steps traced, in order


def test_an_interruption_inside_a_steps_record_keeps_the_whole_steps(monkeypatch):
    """Ctrl-C between the lists one step appends to: every list is cut to the steps recorded whole."""
    whole = path(SCENE, "pressure", 0.0, -300.0, n=10)
    _interrupt_after(monkeypatch, PathRecord, "add", 4)  # the start and two steps recorded, the third not
    ds = path(SCENE, "pressure", 0.0, -300.0, n=10)
    assert ds.attrs["status"] == "interrupted" and ds.sizes["step"] == 3
    np.testing.assert_allclose(ds.parameter.values, whole.parameter.values[:3], rtol=1e-12)
    for name in ("r", "stored_energy"):
        if name in ds:
            assert ds[name].sizes["step"] == 3


def test_an_interruption_in_the_middle_of_a_step_append():
    """An interrupt inside :meth:`PathRecord.add` after some lists grew: :meth:`PathRecord.truncate` evens them."""
    record = PathRecord.__new__(PathRecord)
    record.qs, record.lams, record.tls, record.arcs, record.iterations = [1, 2], [1, 2], [1, 2], [1, 2], [1, 2]
    record.eigen, record.negative, record.det_sign = [1, 2], [1, 2], [1]
    record.stored, record.phi, record.volume, record.reactions, record.branches = [1], [1], [1], [1], [1, 2]
    record.points, record.locating = [{"step": 0}, {"step": 1}], False
    record.truncate()
    assert record.lams == [1] and record.qs == [1] and record.points == [{"step": 0}]


def test_an_interruption_while_a_steps_points_are_located_drops_that_steps_points():
    """Ctrl-C inside ``locate_between`` (after the step was recorded whole) kept the points located so far, two folds
    possibly both ``limit``: that step's points are dropped, the earlier ones kept."""
    record = PathRecord.__new__(PathRecord)
    lists = ("qs", "lams", "tls", "arcs", "iterations", "eigen", "negative", "det_sign", "stored", "phi", "volume",
             "reactions", "branches")
    for name in lists:
        setattr(record, name, [0, 1, 2, 3])
    record.points = [{"step": 0}, {"step": 2}, {"step": 2}]
    record.locating = True  # the points between steps 2 and 3 were being located
    record.truncate()
    assert record.points == [{"step": 0}] and record.lams == [0, 1, 2, 3]
    record.points, record.locating = [{"step": 0}, {"step": 2}], False
    record.truncate()
    assert record.points == [{"step": 0}, {"step": 2}]
