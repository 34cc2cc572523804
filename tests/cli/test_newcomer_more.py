"""More of what a new user hit on the command line (and in Python): a template that runs as its header says, options
given twice or abbreviated, output that cannot be written, and refusals that list everything allowed."""

import re
import shlex

import pytest

from mol_shell.cli.main import main
from mol_shell.scenes import SCENES


def one_error(capsys):
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("mol-shell: error: ") and "Traceback" not in err, err
    return err.strip()


# -- a scene file printed by `scenes NAME --toml` runs with the command its header prints ----------------------
@pytest.mark.parametrize("name", sorted(SCENES))
def test_a_printed_scene_file_runs_with_the_command_of_its_header(name, tmp_path, monkeypatch, capsys):
    assert main(["scenes", name, "--toml"]) == 0
    text = capsys.readouterr().out
    command = re.search(r"mol-shell run THIS\.toml -o out\.nc", text.splitlines()[1]).group(0)
    (tmp_path / "THIS.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(shlex.split(command)[1:]) == 0, capsys.readouterr().err
    assert "wrote out.nc" in capsys.readouterr().out and (tmp_path / "out.nc").stat().st_size > 0
