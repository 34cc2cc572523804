"""Scene axisymmetric has no chi or psi field: an edge given as a set naming either imposed nothing, silently
(``end1=chi`` ran), while ``end1_dchi`` was refused; its listing said R = auto was "the cylinder twisted by gamma"."""

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.scenes.descriptions import default_meaning


@pytest.mark.parametrize("edge, field", [("chi", "chi"), ("psi", "psi"), ("r,chi", "chi"), ("theta,psi", "psi")])
def test_an_edge_naming_a_field_the_scene_lacks_is_refused(edge, field):
    with pytest.raises(mol_shell.ParameterError, match=rf"^end2 = '{edge}' cannot be imposed: the scene has no "
                       rf"{field} field; allowed: an edge kind \(magnet, clamped, pinned, free, auto\) or a set of the "
                       "fields z, r, theta"):
        mol_shell.Axisymmetric(end2=edge)


@pytest.mark.parametrize("edge", ["r,theta", "z", "clamped", "pinned", "free", None])
def test_the_edges_of_its_fields_and_the_kinds_stay_allowed(edge):
    assert mol_shell.Axisymmetric(end1=edge).end1 == edge


def test_the_command_line_refuses_it_with_exit_2(tmp_path, capsys):
    assert main(["run", "axisymmetric", "--set", "end1=chi", "--n", "9", "--t-end", "1e-4",
                 "-o", str(tmp_path / "a.nc")]) == 2
    assert "end1 = 'chi' cannot be imposed: the scene has no chi field" in capsys.readouterr().err
    assert not (tmp_path / "a.nc").exists()


def test_its_r_auto_is_said_without_a_twist():
    said = default_meaning("R", mol_shell.Axisymmetric)
    assert "gamma" not in said and "twist" not in said and said.startswith("the radius of radial equilibrium")
