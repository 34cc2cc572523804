"""Every parameter a user sets on a registered scene is named in the docstrings ``help()`` reads: the scene class's
own or a base class's (``L``, ``a``, ``R`` of the twisted cylinder, the cone's ``r1, r2, H``, ... were missing)."""

import dataclasses
import inspect
import re

import pytest

import mol_shell


def _own(cls):
    """The names in the numpydoc Parameters section of ``cls``'s own docstring (``a, b : float`` names both), and
    the histories named in double backticks in its entries (``pressure_history``)."""
    doc = inspect.cleandoc(cls.__dict__.get("__doc__") or "")
    if "Parameters\n----------" not in doc:
        return set()
    section = doc.split("Parameters\n----------", 1)[1].split("\n\n", 1)[0]
    names = set(re.findall(r"``(\w+_history)``", section))
    for line in section.splitlines():
        if line and not line[0].isspace() and " : " in line:
            names.update(n.strip() for n in line.split(" : ")[0].split(","))
    return names


def _documented(cls):
    """The names documented by ``cls`` or any of its bases."""
    return set().union(*(_own(base) for base in inspect.getmro(cls)))


@pytest.mark.parametrize("name", sorted(mol_shell.SCENES))
def test_every_field_is_documented_in_the_class_or_a_base(name):
    cls = mol_shell.SCENES[name]
    documented = _documented(cls)
    docs = " ".join(inspect.cleandoc(base.__dict__.get("__doc__") or "") for base in inspect.getmro(cls))
    missing = []
    for field in dataclasses.fields(cls):
        if field.name.startswith("_") or field.name in documented:
            continue
        base = field.name.removesuffix("_history")
        if field.name.endswith("_history") and base in documented and ("*_history" in docs or
                                                                       f"{base}_history" in docs):
            continue  # ``end1_force_history``: documented as the ``*_history`` of its load
        missing.append(field.name)
    assert not missing, f"{name}: not in the Parameters of {cls.__name__} or its bases: {missing}"


@pytest.mark.parametrize("name", sorted(mol_shell.SCENES))
def test_the_scene_documents_its_own_geometry_and_initial_data(name):
    """The fields a scene adds to :class:`ShellScene` (its geometry and initial data) are in its own docstring or
    a public base's, not only in a private one's, so ``help(mol_shell.Cone)`` shows them."""
    cls = mol_shell.SCENES[name]
    shared = {f.name for f in dataclasses.fields(mol_shell.ShellScene)}
    documented = set().union(*(_own(base) for base in inspect.getmro(cls) if not base.__name__.startswith("_")))
    own = [f.name for f in dataclasses.fields(cls) if f.name not in shared]
    assert set(own) <= documented, (name, sorted(set(own) - documented))


def test_sphere_says_one_thing_of_R_left_auto():
    doc = " ".join(inspect.cleandoc(mol_shell.Sphere.__doc__).split())
    assert "default ``a``" not in doc and mol_shell.Sphere().R is None
    assert doc.count("static equilibrium under the loads") >= 2


def test_a_documented_type_admits_what_the_signature_does():
    """``R : float`` where the field is ``float | None`` (the unshearable scene) said that auto was not taken."""
    for cls in set(mol_shell.SCENES.values()):
        doc = inspect.cleandoc(cls.__doc__)
        for field in dataclasses.fields(cls):
            typed = re.search(rf"^{field.name} : (.*)$", doc, re.MULTILINE)
            if typed and "None" in str(field.type):
                assert "None" in typed.group(1), (cls.__name__, field.name, typed.group(0))


def test_material_is_documented_with_a_law_of_ones_own():
    doc = inspect.getdoc(mol_shell.ShellScene)
    assert "mol_shell.Material" in doc and "package.module:attr" in doc
    material = inspect.getdoc(mol_shell.Material)
    assert "material=" in material and "package.module:attr" in material and "material_parameters" in material
