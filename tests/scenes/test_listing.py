"""``mol-shell scenes NAME``: units only for numbers, the choices of a parameter that has a fixed set of them (from
the code's own registries), what ``auto`` and ``''`` stand for, the whole description of the scene, and a scene's own
words for a shared parameter (the vessel's ``a`` is no "tube radius (torus)")."""

import dataclasses

import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.model.edges import EDGES
from mol_shell.model.laws import MATERIALS
from mol_shell.scenes import UNITS, description
from mol_shell.scenes.descriptions import is_numeric


def listing(name, capsys):
    assert main(["scenes", name]) == 0
    lines = capsys.readouterr().out.splitlines()
    at = next(i for i, line in enumerate(lines) if line.split()[:2] == ["parameter", "default"])
    fields = dataclasses.fields(mol_shell.SCENES[name])
    header, rows = lines[at], lines[at + 1 : at + 1 + len(fields)]
    units_at, text_at = header.index("units"), header.index("what it is")
    table = {f.name: (row[units_at:text_at].strip(), row[text_at:]) for f, row in zip(fields, rows)}
    return lines[:at], table, " ".join(x.strip() for x in lines[at + 1 + len(fields) :] if x.strip())


@pytest.mark.parametrize("name", sorted(mol_shell.SCENES))
def test_units_are_shown_for_numbers_only(name, capsys):
    """``1`` (dimensionless) was shown for material, end1, the histories, the flags and the file of points."""
    _, table, _ = listing(name, capsys)
    for f in dataclasses.fields(mol_shell.SCENES[name]):
        units = table[f.name][0]
        if is_numeric(f):
            assert units == UNITS.get(f.name, "1"), (f.name, units)
        else:
            assert units == ("-" if UNITS.get(f.name, "1") == "1" else UNITS[f.name]), (f.name, units)
    for word in ("material", "end1", "end2", "pressure_history", "law_limit", "fibre_compression", "layers"):
        assert table[word][0] == "-", word
    assert table["nu"][0] == "1" and table["n_quad"][0] == "1" and table["h"][0] == "m"


@pytest.mark.parametrize("name", ["sphere", "meridian"])
def test_the_file_of_points_and_the_flags_have_no_units(name, capsys):
    _, table, _ = listing(name, capsys)
    assert table["ellipticity_limit"][0] == "-" and ("points" not in table or table["points"][0] == "-")


def test_parameters_with_a_fixed_set_of_values_list_them(capsys):
    _, table, _ = listing("torus", capsys)
    for end in ("end1", "end2"):
        assert all(kind in table[end][1] for kind in EDGES), table[end]
    assert all(law in table["material"][1] for law in MATERIALS) and "package.module:attr" in table["material"][1]
    for flag in ("fibre_compression", "law_limit", "ellipticity_limit"):
        assert table[flag][1].endswith("one of {true, false}"), table[flag]
    assert "one of" not in table["pressure_history"][1] and "one of" not in table["E"][1]


@pytest.mark.parametrize("name", sorted(mol_shell.SCENES))
def test_what_auto_and_empty_stand_for_is_said_under_the_table(name, capsys):
    _, _, note = listing(name, capsys)
    assert note.startswith("auto: left to the code") and "'': nothing given" in note
    for f in dataclasses.fields(mol_shell.SCENES[name]):
        if f.default is None or "None" in str(f.type):
            assert f" {f.name} = auto: " in note or f" {f.name}, " in note, (f.name, note)
        if f.default == "":
            assert f" {f.name} = '': " in note, (f.name, note)


def test_the_vessel_shows_its_whole_description_with_the_heads_defaults(capsys):
    head, _, note = listing("vessel", capsys)
    text = " ".join(x.strip() for x in head)
    assert text == "vessel: " + description(mol_shell.Vessel) and "..." not in text.replace("L, ...", "")
    assert "default (auto) 2a" in text and "0.2 a" in text
    assert all(len(x) <= 120 for x in head) and len(head) > 1
    assert "crown = auto: 2a" in note and "knuckle = auto: 0.2a" in note


def test_a_scene_says_what_its_own_shared_parameter_is(capsys):
    """``a`` was "natural radius (cylinder, sphere) or tube radius (torus)" in every scene, the vessel's too."""
    said = {name: listing(name, capsys)[1]["a"][1] for name in ("vessel", "torus", "sphere", "twisted-cylinder")}
    assert "vessel's cylinder" in said["vessel"] and "tube radius" in said["torus"]
    assert "sphere" in said["sphere"] and "cylinder" in said["twisted-cylinder"]
    assert not any("torus" in text or " or " in text for text in said.values()), said
    assert "equilibrium of the cylinder twisted by gamma" in listing("twisted-cylinder", capsys)[2]
    assert "R = auto: a, the radial equilibrium" in listing("unshearable", capsys)[2]
