"""``mol_shell.study(..., output=...)`` refuses an output that is one of its input files, as ``mol-shell study -o``
does: a meridian's table of points named ``shell.nc`` (the base scene's, or one ``vary`` gives) was replaced by the
study it described, where the command line refused it (mol_shell._core.atomic.keep_inputs)."""

import re

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.scenes import SCENES


@pytest.fixture
def table(tmp_path):
    """A quarter ellipse, 1 m across and 0.6 m high, as two columns r z, in a file that ends in .nc."""
    t = np.linspace(0.0, np.pi / 2, 12)
    path = tmp_path / "shell.nc"
    np.savetxt(path, np.c_[np.sin(t) + 0.1, 0.6 * np.cos(t)])
    return path


@pytest.mark.parametrize("given", ["scene", "vary", "case"])
def test_a_study_refuses_to_write_over_its_table_of_points(table, given, monkeypatch, tmp_path):
    before = table.read_bytes()
    monkeypatch.chdir(tmp_path)
    scene = SCENES["meridian"](points=str(table)) if given == "scene" else "meridian"
    vary = {"points": ["shell.nc"]} if given == "vary" else [{"points": "shell.nc"}] if given == "case" else {
        "h": [0.01]}
    label = {"scene": "scene.points", "vary": "vary['points'][0]", "case": "vary['points'][0]"}[given]
    with pytest.raises(mol_shell.ParameterError, match=rf"^output = 'shell.nc' is the input file {re.escape(label)} = "
                       r"'.*shell.nc': its data would be lost; allowed: an output that writes none of the command's "
                       r"input files \(give output another name\)$"):
        mol_shell.study(scene, vary, n=7, t_end=1e-6, scheduler="serial", output="shell.nc")
    assert table.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["shell.nc"]


def test_the_command_line_refuses_a_table_that_vary_gives(table, tmp_path, capsys):
    before = table.read_bytes()
    code = main(["study", "meridian", "--vary", f"points={table}", "--n", "7", "--t-end", "1e-6", "-o", str(table)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and err == [(f"mol-shell: error: -o = '{table}' is the input file --vary points (value 1) = "
                                  f"'{table}': its data would be lost; allowed: an output that writes none of the "
                                  "command's input files (give -o another name)")]
    assert table.read_bytes() == before

