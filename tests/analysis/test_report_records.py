"""What the analyses' files record: every right-hand side evaluation a comparison's integrators spent, and the scene
a stability report ran."""

import mol_shell
from mol_shell.analysis.stability import Case
from mol_shell.analysis.workprecision import full_table, markdown_table, work_precision
from mol_shell.runs.simulate import build, resolve, simulate

TIMES = [0.0, 1e-3]


def test_a_comparison_counts_the_right_hand_sides_of_difference_quotient_jacobians():
    """`compare` showed cvode-bdf's RHS evals without the 1711 its difference-quotient Jacobians took (31 % of its
    work, against dop853-c's, which forms none). At n = 10 the states number 10 nodes x 5 fields x 2 = 100, the
    Jacobian is dense, and SUNDIALS' difference quotients take one evaluation per column: 100 per Jacobian. The
    column (and the file's n_rhs) is now every evaluation, a run's n_rhs + n_rhs_jacobian, its Jacobian share beside
    it; dop853-c's share is 0."""
    names = ["cvode-bdf", "ida", "dop853-c"]
    ds = work_precision(mol_shell.TwistedCylinder(), names, n=10, times=TIMES, repeats=1,
                        sweeps={name: {"rtol": (1e-6,)} for name in names}, log=lambda *a: None)
    size = build(resolve(mol_shell.TwistedCylinder()), 10)[0].size
    assert size == 10 * 5 * 2
    rows = {line.split(" | ")[0].strip("| "): line.split(" | ") for line in full_table(ds).splitlines()[2:]}
    for name in ("cvode-bdf", "ida"):
        run = simulate(mol_shell.TwistedCylinder(), name, n=10, times=TIMES, rtol=1e-6, atol=1e-9, progress=False)
        point = ds.sel(integrator=name).isel(level=0)
        assert run.attrs["jacobian_kind"] == "dq" and run.attrs["n_jac"] >= 1
        assert int(point.n_rhs_jacobian) == run.attrs["n_rhs_jacobian"] == size * run.attrs["n_jac"]
        assert int(point.n_rhs) == run.attrs["n_rhs"] + run.attrs["n_rhs_jacobian"]
        assert rows[name][5:7] == [str(int(point.n_rhs)), str(int(point.n_rhs_jacobian))]
    dop = ds.sel(integrator="dop853-c").isel(level=0)
    assert int(dop.n_rhs_jacobian) == 0 and rows["dop853-c"][6] == "0"
    assert "n_rhs + n_rhs_jacobian" in ds.n_rhs.attrs["long_name"]
    assert "difference-quotient Jacobians" in ds.n_rhs_jacobian.attrs["long_name"]
    header = markdown_table(ds).splitlines()[3]
    assert "| RHS evals (all) | of them in DQ Jacobians | Jacobian evals |" in header, header
    assert "a run file's n_rhs + n_rhs_jacobian" in markdown_table(ds)


def test_a_stability_file_records_the_scene_it_ran(monkeypatch, tmp_path):
    """`mol-shell stability twisted-cylinder --set E=2e6 --quick` wrote a file whose global attributes were only
    bisected, cases_not_measured, status and message: not the scene, its parameters, the package version or the CF
    header every other mol_shell file carries. It now has them, the base scene's parameters as its case used them
    (R as computed, beside R_requested = "auto"), as a compare or run file has them."""
    from mol_shell.cli.main import main

    seen = []

    def cases(scene, quick=False):  # the report's cases, cut to one small one on the scene as given
        seen.append(quick)
        return [Case("base", scene, n=8, t_end=1e-4)]

    monkeypatch.setattr("mol_shell.cli.analysis.default_cases", cases)
    out = tmp_path / "s.nc"
    assert main(["stability", "twisted-cylinder", "--set", "E=2e6", "--quick", "--no-bisect", "-o", str(out)]) == 0
    a = mol_shell.read_netcdf(out).attrs
    assert seen == [True] and a["quick"] == 1
    assert a["scene"] == "twisted-cylinder" and (a["E"], a["units_E"]) == (2e6, "Pa")
    assert a["nu"] == mol_shell.TwistedCylinder().nu and a["R_requested"] == "auto" and 0.9 < a["R"] < 1.0
    assert a["mol_shell_version"] == mol_shell.__version__ and a["Conventions"] == "CF-1.8"
    assert "created by mol_shell" in a["history"] and a["status"] == "complete"
