"""A Newton option given to a fixed-point CVODE is refused whatever its value: ``jac_every = 0`` (``--option
jac_every=0``, a scene file's ``[run]``) on ``cvode-adams``, whose iteration is a fixed point by default, was taken
silently, while ``jac_every = 10`` was refused by name. 0 is no "not used": under Newton's iteration it stands for
SUNDIALS' 51 steps (docs/integrators.md), a setting the fixed-point iteration has not got."""

from __future__ import annotations

import pickle

import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.sundials_c import _Compiled

ADAMS = INTEGRATORS["cvode-adams"]


@pytest.mark.parametrize("name,default", _Compiled.NEWTON_ONLY)
def test_a_newton_option_given_at_its_default_is_refused_under_a_fixed_point(name, default):
    said = (f"{name} = {default!r} is an option of Newton's iteration, which cvode-adams runs only with iteration = "
            "'newton' (its iteration here is 'fixed-point', the default)")
    with pytest.raises(ParameterError) as info:
        ADAMS(**{name: default})
    assert str(info.value) == said and info.value.name == name
    assert getattr(ADAMS(iteration="newton", **{name: default}), name) == default  # Newton's takes it


def test_what_is_not_given_is_not_refused():
    method = ADAMS()
    assert method.jac_every == 0 and method.fixed_point()
    assert pickle.loads(pickle.dumps(method)) == method  # a study's workers get it so
    assert INTEGRATORS["cvode-bdf"](anderson=0).anderson == 0  # anderson's 0 is "none" (documented): nothing to refuse


def test_jac_every_0_on_adams_is_refused_on_the_command_line_and_in_a_file(tmp_path, capsys):
    said = ("jac_every = 0 is an option of Newton's iteration, which cvode-adams runs only with iteration = 'newton' "
            "(its iteration here is 'fixed-point', the default)")
    argv = ["run", "twisted-cylinder", "--n", "9", "--t-end", "1e-4", "--integrator", "cvode-adams"]
    assert main([*argv, "--option", "jac_every=0", "-o", str(tmp_path / "x.nc")]) == 2
    assert capsys.readouterr().err.strip() == f"mol-shell: error: --option {said}"
    path = tmp_path / "f.toml"
    path.write_text('scene = "twisted-cylinder"\n[run]\nintegrator = "cvode-adams"\nt_end = 1e-4\nn = 9\njac_every = 0\n')
    assert main(["run", str(path), "-o", str(tmp_path / "x.nc")]) == 2
    assert capsys.readouterr().err.strip() == f"mol-shell: error: {path}: [run] {said}"
    assert not (tmp_path / "x.nc").exists()
