"""Ctrl-C during ``mol-shell export RUN -o X.xdmf`` ends it as for ``.pvd``: exit 130, one line, nothing left beside
the output. The signal used to raise ``KeyboardInterrupt`` inside ``WriteAside.seek``, which h5py calls from C (and
as its objects are released): "Exception ignored in: 'h5py._objects.ObjectID.__dealloc__'", a segmentation fault
(exit 139) in 5 of 11 tries, and the staged ``.e.xdmf.*.part/e.h5`` left behind.

The signal is sent at a fixed point of the HDF5 write (a patched ``WriteAside.seek``), in this process: the command
line's watch takes SIGINT while ``main`` runs."""

from __future__ import annotations

import gc
import signal
import sys

import pytest
from paper_run_file import paper_run_file

from mol_shell._core import write_aside
from mol_shell.cli.main import main
from mol_shell.views import export as exporting


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """The paper's scene on 5 nodes, 30 saved times."""
    return paper_run_file(tmp_path_factory.mktemp("xdmf_int"), 5, 30)


@pytest.mark.parametrize("at", [40, 400])
def test_ctrl_c_inside_the_hdf5_write_exits_130_in_one_line_and_leaves_nothing(run_file, tmp_path, capsys,
                                                                               monkeypatch, at):
    """Each seek of h5py into the HDF5 file from the ``at``-th on sends SIGINT (from the first steps' data, and from
    further on): also those h5py makes as it closes the file and releases its objects, where it calls Python from C."""
    real, calls = write_aside.WriteAside.seek, []

    def seek(self, *args):
        calls.append(1)
        if len(calls) >= at:  # Ctrl-C pressed again and again: also as h5py closes and releases its objects
            signal.raise_signal(signal.SIGINT)
        return real(self, *args)

    ignored = []
    monkeypatch.setattr(write_aside.WriteAside, "seek", seek)
    # every array compressed (chunked), as a large run's: HDF5 writes a chunk as h5py releases its dataset
    monkeypatch.setattr(exporting, "H5_COMPRESS_FROM", 0)
    monkeypatch.setattr(sys, "unraisablehook", ignored.append)
    out = tmp_path / "out" / "e.xdmf"
    code = main(["export", str(run_file), "--n-phi", "6", "-o", str(out)])
    gc.collect()  # h5py's objects of the export: released, and nothing raised at their release
    said = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mol-shell: warning: ")]
    assert len(calls) >= at  # the signal was sent inside the write
    assert (code, said, ignored) == (130, ["mol-shell: interrupted"], [])
    assert list(out.parent.iterdir()) == []  # no e.xdmf, no e.h5, no .e.xdmf.*.part
