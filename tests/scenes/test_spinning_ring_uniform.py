"""The spinning-ring scene is section 5's motion uniform in ``s``, and refuses by name what makes it depend on ``s``.

``mol-shell run spinning-ring --set gamma=0.1`` ran and exited 0 with ``r`` varying 6.1e-3 m along ``s`` (section 5:
no twisted motion is uniform in ``s``), while ``simulate_ring`` refused the same scene naming ``gamma``. A clamped
edge, a graded wall, an end torque or a spun end did the same: each acts at one place of the meridian.
"""

import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.runs.ring import simulate_ring


def test_the_command_line_refuses_a_twisted_spinning_ring_in_one_line_naming_gamma(tmp_path, capsys):
    out = tmp_path / "ring.nc"
    assert main(["run", "spinning-ring", "--set", "gamma=0.1", "--t-end", "0.01", "-o", str(out)]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if ": warning: " not in line]
    assert err == [("mol-shell: error: gamma = 0.1 is outside {0} for scene spinning-ring (section 5: twisted motions "
                    "are not uniform in s; scene twisted-cylinder runs them)")], err
    assert not out.exists()


@pytest.mark.parametrize("changes, named", [
    ({"gamma": -1e-3}, "gamma"),
    ({"end1": "clamped"}, "end1"), ({"end2": "free"}, "end2"), ({"end1": "r,theta"}, "end1"),
    ({"h_profile": "0.004+0.002*s"}, "h_profile"),
    ({"fibre_E": 1e7, "fibre_angle": 0.5}, "fibre_families"),  # one helical family: stretch couples to twist
    ({"gravity": 9.81}, "gravity"), ({"end1_force": 10.0}, "end1_force"), ({"end2_torque": 1.0}, "end2_torque"),
    ({"end1_spin": 1.0}, "end1_spin"), ({"end2_axial_speed": 0.1}, "end2_axial_speed"), ({"end1_dz": 0.01}, "end1_dz"),
    ({"end2_dchi": 0.1}, "end2_dchi"), ({"end_omega": 5.0}, "end_omega"),
])
def test_what_makes_the_motion_depend_on_s_is_refused_naming_it_and_twisted_cylinder(changes, named):
    with pytest.raises(mol_shell.ParameterError) as info:
        mol_shell.SpinningRing(**changes)
    text = str(info.value)
    assert info.value.name == named and "for scene spinning-ring" in text and "twisted-cylinder" in text, text
    assert "\n" not in text


@pytest.mark.parametrize("changes", [{"pressure": 100.0}, {"drag": 10.0}, {"end1": "magnet", "end2": "magnet"},
                                     {"fibre_E": 1e7, "fibre_angle": 0.5, "fibre_families": 2},
                                     {"fibre_E": 1e7, "fibre_angle": 0.0}])
def test_what_acts_alike_at_every_s_is_kept(changes):
    """Pressure and drag act alike at every ``s``, magnets hold the ends as a ring of any length, balanced or axial
    fibres couple no stretch to twist: the motion stays uniform (the ring ODE's tests compare it with the PDE)."""
    scene = mol_shell.SpinningRing(**changes)
    assert all(getattr(scene, key) == value for key, value in changes.items())


def test_the_ring_ode_refuses_one_helical_family_as_the_scene_does():
    """One helical family couples stretch to twist (the fibre's ``2 cos sin C_13``): the free ends twist and ``r``
    varies along ``s``, so the ring ODE, which takes a TwistedCylinder too, refuses it by name; two balanced families
    stay uniform and are taken."""
    with pytest.raises(ParameterError) as refused:
        simulate_ring(mol_shell.TwistedCylinder(gamma=0.0, fibre_E=1e7, fibre_angle=0.5, fibre_families=1), t_end=1e-3)
    assert refused.value.name == "fibre_families"
    ds = simulate_ring(mol_shell.TwistedCylinder(gamma=0.0, fibre_E=1e7, fibre_angle=0.5, fibre_families=2), t_end=1e-3)
    assert ds.attrs["integrator"].startswith("ring-ode")
