"""More of what a new user hit on the command line (and in Python): a template that runs as its header says, options
given twice or abbreviated, output that cannot be written, and refusals that list everything allowed."""

import argparse
import re
import shlex

import pytest

from mol_shell.cli.main import main, make_parser
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


# -- options are spelt in full ------------------------------------------
def subcommands():
    parser = make_parser()
    (sub,) = [action for action in parser._actions if isinstance(action, argparse._SubParsersAction)]
    return parser, sub.choices


def test_an_abbreviated_option_is_refused_naming_the_option_it_begins(tmp_path, capsys):
    """``--t-en 0.1`` was taken as ``--t-end`` and silently replaced the ``--t-end 0.001`` given before it."""
    out = tmp_path / "a.nc"
    assert main(["run", "sphere", "--n", "5", "--t-end", "0.001", "--t-en", "0.1", "-o", str(out)]) == 2
    assert one_error(capsys) == ("mol-shell: error: --t-en is not an option of mol-shell run; allowed: options spelt "
                                 "in full, as --t-end")
    assert not out.exists()
    assert main(["scenes", "sphere", "--tom"]) == 2
    assert one_error(capsys).endswith("allowed: options spelt in full, as --toml")
    parser, commands = subcommands()
    assert not parser.allow_abbrev and not any(p.allow_abbrev for p in commands.values())
