"""``load_scene(path, with_run=True)`` checked the ``[run]`` table's integrator options against each other, not
whether the integrator takes ``rtol``, ``atol``, ``dt`` or ``max_step``: ``integrator = "leapfrog"`` with ``rtol``
came back as options that ``simulate`` then refused without naming the file. It refuses them as ``mol-shell run``
does: the same line, the file and ``[run]`` first."""

from __future__ import annotations

import dataclasses

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.runs.simulate import integrator_options
from mol_shell.runs.unshearable import DAE_OPTIONS
from mol_shell.scenes.unshearable import UNSHEARABLE_DAE_OPTIONS


def fields(integrator):
    return ", ".join(sorted(f.name for f in dataclasses.fields(mol_shell.INTEGRATORS[integrator])))


CASES = [  # (scene, integrator, option, value, the integrator's options: its dataclass's fields)
    ("sphere", "leapfrog", "rtol", "1e-6", fields("leapfrog")),
    ("sphere", "cvode-bdf", "dt", "1e-6", fields("cvode-bdf")),
    ("unshearable", "ida", "dt", "1e-6", "atol, max_step, rtol"),  # the constrained DAE's own three
    ("unshearable", "leapfrog", "max_step", "1e-3", fields("leapfrog")),
]


@pytest.mark.parametrize(("scene", "integrator", "option", "value", "options"), CASES)
def test_an_option_the_integrator_does_not_take_is_refused_by_the_file(tmp_path, capsys, scene, integrator, option,
                                                                     value, options):
    path = tmp_path / "d.toml"
    path.write_text(f'scene = "{scene}"\n[run]\nintegrator = "{integrator}"\n{option} = {value}\n')
    said = f"{path}: [run] {option} is not an option of {integrator} (its options: {options})"
    with pytest.raises(mol_shell.ParameterError) as refused:
        mol_shell.load_scene(path, with_run=True)
    assert str(refused.value) == said and refused.value.name == option
    assert main(["run", str(path), "-o", str(tmp_path / "d.nc")]) == 2  # the command line's line, the same
    assert capsys.readouterr().err.strip() == f"mol-shell: error: {said}"
    # together=False: the caller checks, after its own options replace the file's (the command line's --integrator)
    assert mol_shell.load_scene(path, with_run=True, together=False)[1][option] == float(value)


def test_the_unshearable_scene_takes_ida_or_leapfrog(tmp_path):
    path = tmp_path / "u.toml"
    path.write_text('scene = "unshearable"\n[run]\nintegrator = "cvode-bdf"\n')
    with pytest.raises(mol_shell.ParameterError, match=rf"^{path}: \[run\] integrator = 'cvode-bdf' is outside "
                       r"\{ida, leapfrog\}"):
        mol_shell.load_scene(path, with_run=True)


def test_options_the_integrator_takes_pass(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text('scene = "unshearable"\n[run]\nintegrator = "ida"\nrtol = 1e-6\natol = 1e-9\nmax_step = 0.01\n')
    assert mol_shell.load_scene(path, with_run=True)[1] == {"integrator": "ida", "rtol": 1e-6, "atol": 1e-9,
                                                            "max_step": 0.01}


def test_the_files_options_are_simulates():
    """The scene layer's names of the unshearable DAE's options are those the run layer takes."""
    assert set(UNSHEARABLE_DAE_OPTIONS) == set(DAE_OPTIONS) == integrator_options(mol_shell.Unshearable(), "ida")
