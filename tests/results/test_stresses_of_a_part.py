"""``add_stresses`` of a part of a run taken with ``isel(s=...)``: the part keeps the run's cells ``s_cell`` and
its stresses there, and the stresses of the part's own cells met them as a bare xarray ValueError ("conflicting
sizes for dimension 's_cell'"). Each cell's stresses are those of its two nodes: the part's cells are the run's
first cells, with their stresses. A variable on the old cells that is not a stress is refused naming ``ds``.
Nodes that are not neighbours (``isel(s=[0, 2, 5, 9])``, a stride) make no cells: their "cells" had stresses, wrong
and unsaid; they are refused naming ``ds``. Neighbours in the other order are cells: the run's, mirrored."""

import numpy as np
import pytest

import mol_shell
from mol_shell import ParameterError


@pytest.fixture(scope="module")
def run():
    return mol_shell.simulate(mol_shell.Sphere(R=1.01, material="svk-plane-stress", nu=0.3), n=21,
                              times=[0.0, 5e-4, 1e-3], progress=False)


def test_the_stresses_of_a_part_are_the_runs_on_its_cells(run):
    part = mol_shell.add_stresses(run.isel(s=slice(0, 10)))
    assert part.sizes["s_cell"] == 9
    np.testing.assert_array_equal(part.s_cell.values, run.s_cell.values[:9])
    for name in ("membrane_force_hoop", "bending_moment_meridional", "von_mises_stress"):
        np.testing.assert_allclose(part[name].values, run[name].values[:, :9], rtol=1e-12, atol=0, err_msg=name)
    again = mol_shell.add_stresses(run)  # a whole run's stresses computed again: the same
    np.testing.assert_array_equal(again.von_mises_stress.values, run.von_mises_stress.values)


@pytest.mark.parametrize("nodes", [[0, 2, 5, 9], slice(0, None, 2), [3, 4, 3], [2, 3, 5, 6]])
def test_nodes_that_are_not_neighbours_are_refused_naming_ds(run, nodes):
    spacing = np.pi / 20  # the unit sphere's meridian, from pole to pole, in 20 cells
    with pytest.raises(ParameterError, match=r"^ds = 'Dataset' holds nodes s that are not neighbours in the run \(its "
                                             rf"node spacing {spacing:.6g} m\); allowed: consecutive nodes of a run "
                                             r"\(stresses need neighbouring nodes: select with a slice, "
                                             r"isel\(s=slice\(i, j\)\)\)$"):
        mol_shell.add_stresses(run.isel(s=nodes))


def test_neighbours_in_the_other_order_are_the_runs_cells_mirrored(run):
    part = mol_shell.add_stresses(run.isel(s=slice(12, 3, -1)))
    assert part.sizes["s_cell"] == 8
    for name in ("membrane_force_hoop", "bending_moment_meridional", "von_mises_stress"):
        np.testing.assert_allclose(part[name].values[:, ::-1], run[name].values[:, 4:12], rtol=1e-12, atol=0)


def test_a_part_with_other_variables_on_the_runs_cells_is_refused_naming_ds():
    dae = mol_shell.simulate_unshearable(mol_shell.Unshearable(), n=8, t_end=1e-4, progress=False)
    with pytest.raises(ParameterError, match=r"^ds = 'Dataset' holds lambda_chi on 7 cells, not on the 4 cells of "
                                             r"its 5 nodes s") as err:
        mol_shell.add_stresses(dae.isel(s=slice(0, 5)))
    assert "\n" not in str(err.value)


def test_compiled_is_a_bool(run):
    with pytest.raises(ParameterError, match=r"^compiled = 'no' is not a bool; allowed: True or False$"):
        mol_shell.add_stresses(run, compiled="no")
