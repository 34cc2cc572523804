"""The loads a path is offered are the ones it can follow: a load with a net force along a rigid motion that no
edge stops has no equilibrium, so it is neither listed as allowed nor accepted.

Independent reasoning (statics of a free body): gravity's net axial force is the shell's weight and an end force's
is itself, never zero; an end torque's net moment about the axis is itself. A closed sphere (two poles) is held
neither axially nor in spin, so of the loads only pressure (whose net force on a closed surface vanishes) is left;
a cylinder whose edges fix ``z`` but leave ``chi`` free (magnet edges) keeps gravity and loses its end torques.
"""

from __future__ import annotations

import pytest

from mol_shell import Sphere, TwistedCylinder, path
from mol_shell._core.errors import ParameterError
from mol_shell.analysis.equilibria import allowed_parameters, rigid_motions
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem


def test_a_closed_sphere_is_offered_pressure_only():
    system = ShellSystem(Sphere(), 10)
    assert set(rigid_motions(system)) == {"axial translation", "spin about the axis"}
    assert allowed_parameters(system) == ("pressure",)


@pytest.mark.parametrize("load, motion", [("gravity", "axial translation"), ("end1_force", "axial translation")])
def test_a_load_no_edge_holds_is_refused_with_the_allowed_set_and_the_reason(load, motion):
    with pytest.raises(ParameterError) as info:
        path(Sphere(), load, 0.0, 1.0, n=10, steps=2)
    message = str(info.value)
    assert "is outside {pressure}" in message and f"no edge stops the shell's {motion}" in message, message


def test_a_cylinder_held_axially_but_free_in_spin_keeps_gravity_and_loses_its_end_torques():
    system = ShellSystem(TwistedCylinder(), 10)
    assert set(rigid_motions(system)) == {"spin about the axis"}
    allowed = allowed_parameters(system)
    assert "gravity" in allowed and not {"end1_torque", "end2_torque"} & set(allowed)


def test_the_command_names_the_allowed_set(tmp_path, capsys):
    code = main(["path", "sphere", "--param", "gravity=0:1", "--n", "10", "-o", str(tmp_path / "p.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert "outside {pressure}" in err and "no equilibrium" in err, err
