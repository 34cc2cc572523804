"""``-o sub/../x.nc``: a ``..`` that goes back out of a directory resolves as the system resolves it.

Where ``sub`` exists the system reads ``sub/..`` as the current directory and the file is ``./x.nc``; where it does
not, the system refuses the path (``open("sub/../x.nc", "w")`` is ``FileNotFoundError``, as a shell's
``> sub/../x.nc`` is). The refusal said "cannot create directory 'sub/..' (File exists)"; it says now, in one line
naming ``-o``, that ``sub`` does not exist, and leaves nothing behind.
"""

from __future__ import annotations

import pytest

from mol_shell.cli.main import main

RUN = ["run", "twisted-cylinder", "--n", "11", "--times", "0,0.001"]


def test_what_the_system_does_with_an_up_through_a_missing_directory(tmp_path, monkeypatch):
    """The reference the command line follows: the system itself."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError):
        open("sub/../x.nc", "w")  # noqa: SIM115 - refused before a file exists
    (tmp_path / "afile").write_text("x")
    with pytest.raises(NotADirectoryError):
        open("afile/../x.nc", "w")  # noqa: SIM115
    (tmp_path / "sub").mkdir()
    with open("sub/../x.nc", "w"):
        pass
    assert (tmp_path / "x.nc").exists() and not any((tmp_path / "sub").iterdir())


@pytest.mark.parametrize(("command", "output", "missing", "why"), [
    (RUN, "sub/../x.nc", "sub", "does not exist"),
    (RUN, "new/sub/../x.nc", "new/sub", "does not exist"),
    (RUN, "afile/../x.nc", "afile", "is not a directory"),
    (["export", "run.nc"], "sub/../x.xdmf", "sub", "does not exist"),
])
def test_an_output_up_through_a_missing_directory_is_refused_naming_it(tmp_path, monkeypatch, capsys, command,
                                                                       output, missing, why):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("x")
    assert main([*command, "-o", output]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"mol-shell: error: -o = '{output}' cannot be written: '{missing}' "
                                               f"{why}, and the path goes back out of it with '..'"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]  # no directory made, no file written


def test_an_output_up_through_an_existing_directory_is_the_file_beside_it(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    assert main([*RUN, "-o", "sub/../x.nc"]) == 0
    assert (tmp_path / "x.nc").exists() and not any((tmp_path / "sub").iterdir())
    assert main(["export", "x.nc", "-o", "sub/../x.xdmf"]) == 0
    assert (tmp_path / "x.xdmf").exists() and (tmp_path / "x.h5").exists() and not any((tmp_path / "sub").iterdir())
