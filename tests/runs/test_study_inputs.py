"""A stored study case is reused only when everything it read is the same: the parameters, and the files and laws
they name. A meridian's points file edited between two runs of a study (same path) made the second reuse the
first's cases, geometry and all, silently; so did an edited energy of a law of one's own under the same name.
Independent check: a plain run of the edited file (its reference radii ``r0``) against the study's."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell import ParameterError
from mol_shell.runs.study import case_inputs, design, study

NARROW = "0 0\n0.5 0.1\n1 0.5\n0.5 0.9\n0 1\n"
WIDE = "0 0\n0.8 0.1\n1.6 0.5\n0.8 0.9\n0 1\n"


def _study(points, output):
    return study(mol_shell.MeridianShell(points=str(points)), {"h": [0.005, 0.006]}, "leapfrog", n=10,
                 t_end=1e-3, scheduler="serial", output=output, progress=False)


def test_an_edited_points_file_is_another_case(tmp_path):
    points, output = tmp_path / "points.txt", tmp_path / "study.nc"
    points.write_text(NARROW)
    first = _study(points, output)
    points.write_text(WIDE)
    second = _study(points, output)
    assert (second.attrs["n_executed"], second.attrs["n_reused"]) == (2, 0)
    plain = mol_shell.simulate(mol_shell.MeridianShell(points=str(points), h=0.005), n=10, t_end=1e-3,
                               stresses=False)
    assert np.allclose(second.r0.sel(h=0.005).values, plain.r0.values, rtol=1e-12, atol=0)
    assert abs(float(first.r0.sel(h=0.005).max()) / float(plain.r0.max()) - 1) > 0.3  # the narrow shell
    third = _study(points, output)  # unchanged since: reused
    assert (third.attrs["n_executed"], third.attrs["n_reused"]) == (0, 2)


def neo_hookean_like(scale):
    def energy(C, p):
        return scale * p["mu"] / 2 * (ca.trace(C) - 3)
    return energy


def test_a_law_of_ones_own_is_keyed_by_what_it_computes():
    one = mol_shell.Material("study-key-law", energy=neo_hookean_like(1.0), parameters={"mu": 1e5},
                             thickness="incompressible")
    same = mol_shell.Material("study-key-law", energy=neo_hookean_like(1.0), parameters={"mu": 1e5},
                              thickness="incompressible")
    edited = mol_shell.Material("study-key-law", energy=neo_hookean_like(2.0), parameters={"mu": 1e5},
                                thickness="incompressible")
    assert one.fingerprint() == same.fingerprint() != edited.fingerprint()
    before = case_inputs(mol_shell.Sphere(material=one))
    after = case_inputs(mol_shell.Sphere(material=edited))
    assert before["law study-key-law"] == one.fingerprint() and after["law study-key-law"] == edited.fingerprint()


def test_in_one_process_an_edited_points_file_is_another_shell(tmp_path):
    """The in-process caches (the meridian read, the built graphs) were keyed by the file's name and time: a run
    after an edit (the same name, within one tick of the file system's clock) was the old shell's."""
    points = tmp_path / "points.txt"
    points.write_text(NARROW)
    narrow = mol_shell.simulate(mol_shell.MeridianShell(points=str(points)), n=10, t_end=1e-4, stresses=False)
    points.write_text(WIDE)
    wide = mol_shell.simulate(mol_shell.MeridianShell(points=str(points)), n=10, t_end=1e-4, stresses=False)
    assert float(narrow.r0.max()) < 1.0 and float(wide.r0.max()) > 1.4  # the tables' largest r: 1 and 1.6


def test_a_case_that_leaves_out_a_laws_parameter_has_the_laws_value():
    """``[{"material.mu": 2e5}, {"E": 2e6}]`` refused the second case ("no value of material.mu to record")."""
    rubber = mol_shell.Material("study-default-law", energy=neo_hookean_like(1.0), parameters={"mu": 3e5},
                                thickness="incompressible")
    _, coords, _ = design(mol_shell.Sphere(material=rubber), [{"material.mu": 2e5}, {"E": 2e6}], "leapfrog")
    assert coords["material.mu"] == [2e5, 3e5]
    scene = mol_shell.Sphere(material=rubber, material_parameters="mu=4e5")  # the scene's own value wins
    assert design(scene, [{"material.mu": 2e5}, {"E": 2e6}], "leapfrog")[1]["material.mu"] == [2e5, 4e5]


def test_a_law_made_in_a_function_reaches_the_worker_processes_of_a_study_and_of_a_path_study(monkeypatch):
    """A script's ``Material`` made under ``if __name__ == "__main__":`` (here: in a function, with a closure for its
    energy) is registered in this process only: the spawned worker knew no law by that name and refused its cases
    (``material = 'study-worker-law' is outside {svk, ...}``) while this process ran its own. Each case now carries
    the law, and the worker's cases equal the serial study's. (Workers spawned here: a forked one has the law.)"""
    from mol_shell.analysis.path_study import path_study

    monkeypatch.setenv("MOL_SHELL_START_METHOD", "spawn")

    rubber = mol_shell.Material("study-worker-law", energy=neo_hookean_like(1.0), parameters={"mu": 3e5},
                                thickness="incompressible")
    scene = mol_shell.Sphere(h=0.01, material=rubber, R=1.2)
    vary = {"material.mu": [2e5, 2.5e5, 3e5, 3.5e5]}
    local = study(scene, vary, "leapfrog", n=8, t_end=1e-3, workers=2, progress=False)
    serial = study(scene, vary, "leapfrog", n=8, t_end=1e-3, scheduler="serial", progress=False)
    assert list(local.status.values) == ["complete"] * 4, list(local.message.values)
    assert len(set(local.worker.values)) == 2  # both processes ran cases
    np.testing.assert_array_equal(local.r.values, serial.r.values)
    paths = path_study(mol_shell.Sphere(h=0.01, material=rubber), {"h": [0.01, 0.011, 0.012, 0.013]}, "pressure",
                       0.0, 100.0, n=8, workers=2, progress=False)
    assert list(paths.status.values) == ["complete"] * 4, list(paths.message.values)


def test_a_law_that_cannot_be_carried_is_refused_naming_material_where_it_is_unknown():
    from mol_shell.runs.study import restore_materials

    with pytest.raises(ParameterError, match="material = 'nowhere-law' could not be sent to the study's worker "
                                             "processes.*PicklingError: no"):
        restore_materials((("nowhere-law", "PicklingError: no"),))
    here = mol_shell.Material("study-law-made-here", energy=neo_hookean_like(1.0), parameters={"mu": 1e5},
                              thickness="incompressible")
    mol_shell.Sphere(material=here)  # registered in this process: its own cases run
    restore_materials((("study-law-made-here", "PicklingError: no"),))


def test_a_carried_law_is_restored_once_per_process(monkeypatch):
    """Each case carries its laws; a process that has restored one (a worker's first case, or this process) finds
    it registered as it was and neither unpickles nor compares it again for the study's later cases."""
    from mol_shell.runs import study as study_module

    law = mol_shell.Material("study-restored-once", energy=neo_hookean_like(1.0), parameters={"mu": 1e5},
                             thickness="incompressible")
    carried = study_module.carried_materials(mol_shell.Sphere(material=law))
    real, loads = study_module.pickle.loads, []
    monkeypatch.setattr(study_module.pickle, "loads", lambda data: loads.append(1) or real(data))
    for _ in range(5):
        study_module.restore_materials(carried)
    assert len(loads) == 1 and study_module.REGISTRY["study-restored-once"] is law
