"""Two ``mol_shell.Material``s of one name are two laws: each scene runs the law it was made with.

A scene stored the law's name only, and the name was registered again for the second law: every scene ran the last
law made (and compared equal), the attrs said ``material = 'rubber'`` and ``material_parameters = ''`` for both,
and a study's workers received the last law too. The reference: the incompressible neo-Hookean energy
``mu/2 (tr C - 3)`` is linear in ``mu``, so on the same start (a sphere of radius 1.05 on a natural radius of 1)
the stored energy of ``mu = 2e5`` is half that of ``mu = 4e5``, and about ``mu/2 (2 l^2 + l^-4 - 3)`` times the
wall's volume ``4 pi a^2 2h`` (``l = 1.05``; the thin-shell value, to O(h/a) = 1 %).
"""

import math

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.model import laws
from mol_shell.runs.study import carried_materials, restore_materials

MUS = (2e5, 4e5)
STRETCH, H = 1.05, 0.01


def neo_hookean(C, p):
    return p["mu"] / 2 * (ca.trace(C) - 3)


def sphere(name, mu):
    law = mol_shell.Material(name, neo_hookean, {"mu": mu}, "incompressible")
    return mol_shell.Sphere(h=H, R=STRETCH, material=law)


def stored(scene):
    ds = mol_shell.simulate(scene, "leapfrog", n=21, times=[0.0, 1e-5], progress=False, stresses=False)
    return float(ds.stored_energy[0]), ds.attrs


def thin_shell_energy(mu):
    return mu / 2 * (2 * STRETCH**2 + STRETCH**-4 - 3) * 4 * math.pi * 2 * H


@pytest.mark.parametrize("order", [(0, 1), (1, 0)], ids=["soft-first", "stiff-first"])
def test_each_scene_runs_the_law_it_was_made_with_in_either_order_and_with_a_warm_cache(order):
    name = f"same-name-rubber-{order[0]}"
    first = sphere(name, MUS[order[0]])
    warm, _ = stored(first)  # its graphs built and cached before the second law exists
    second = sphere(name, MUS[order[1]])
    energies = {order[0]: warm, order[1]: stored(second)[0]}
    again, attrs = stored(first)
    assert again == warm
    assert first != second and first.material == name and second.material.startswith(name + "@")
    np.testing.assert_allclose(energies[1] / energies[0], 2.0, rtol=1e-12)  # linear in mu
    np.testing.assert_allclose(energies[0], thin_shell_energy(MUS[0]), rtol=1e-2)
    assert attrs["material_laws"].startswith(f"{name}: incompressible, mu={MUS[order[0]]!r}, fingerprint ")


def test_the_same_law_made_again_is_the_same_scene_and_a_name_is_the_first_law_of_it():
    """A cell run again unchanged makes an equal law: the same key, equal scenes (and the caches shared)."""
    one, two = sphere("same-name-again", 2e5), sphere("same-name-again", 2e5)
    assert one == two and one.material == "same-name-again"
    other = sphere("same-name-again", 4e5)
    assert mol_shell.Sphere(h=H, R=STRETCH, material="same-name-again") == one  # the name: the first law
    assert mol_shell.Sphere(h=H, R=STRETCH, material=other.material) == other  # its key: the second


def test_a_study_over_two_laws_of_one_name_and_its_workers_get_each_its_own():
    soft_law = mol_shell.Material("same-name-study", neo_hookean, {"mu": MUS[0]}, "incompressible")
    stiff_law = mol_shell.Material("same-name-study", neo_hookean, {"mu": MUS[1]}, "incompressible")
    soft = mol_shell.Sphere(h=H, R=STRETCH, material=soft_law)
    out = mol_shell.study(soft, {"material": [soft_law, stiff_law]}, "leapfrog", n=21, times=[0.0, 1e-5],
                          scheduler="serial", progress=False)
    energy = out.stored_energy.isel(time=0).values
    np.testing.assert_allclose(energy[1] / energy[0], 2.0, rtol=1e-12)
    assert list(out.material.values) == [soft.material, mol_shell.Sphere(material=stiff_law).material]
    # a worker process (its registry empty) restores each case's law under the key its scene stores
    stiff = mol_shell.Sphere(h=H, R=STRETCH, material=stiff_law)
    carried = carried_materials(stiff) + carried_materials(soft)
    saved = dict(laws.REGISTRY)
    try:
        laws.REGISTRY.clear()
        restore_materials(carried)
        assert laws.REGISTRY[stiff.material].parameters == {"mu": MUS[1]}
        assert laws.REGISTRY[soft.material].parameters == {"mu": MUS[0]}
    finally:
        laws.REGISTRY.clear()
        laws.REGISTRY.update(saved)
