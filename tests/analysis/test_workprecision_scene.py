"""A comparison's file and table say which scene it ran: `compare twisted-cylinder --set nu=0.3 --set gamma=0.05`
recorded neither nu nor gamma, in the .nc or the .md."""

import mol_shell
from mol_shell.analysis.workprecision import markdown_table, parameters_line, work_precision


def test_a_comparison_records_the_scene_parameters_as_used():
    ds = work_precision(mol_shell.TwistedCylinder(nu=0.3, gamma=0.05), ["dop853-c"], n=6, times=[0.0, 1e-4],
                        repeats=1, sweeps={"dop853-c": {"rtol": (1e-5,)}}, log=lambda *a: None)
    a = ds.attrs
    assert (a["nu"], a["units_nu"], a["gamma"], a["units_gamma"]) == (0.3, "1", 0.05, "rad m-1")
    assert a["R_requested"] == "auto" and 0.99 < a["R"] < 1.0 and a["units_R"] == "m"  # as used, as a run file has it
    assert a["end1"] == "magnet" and a["end1_requested"] == "auto" and a["units_h"] == "m"
    table = markdown_table(ds).splitlines()
    assert table[1] == ("Scene parameters: nu = 0.3, gamma = 0.05 rad m-1; the others the scene's defaults (each as "
                        "used in the .nc's attributes).")
    defaults = ds.copy()
    defaults.attrs.update(nu=mol_shell.TwistedCylinder().nu, gamma=mol_shell.TwistedCylinder().gamma)
    assert parameters_line(defaults).startswith("Scene parameters: the scene's defaults")
