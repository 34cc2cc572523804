"""docs/python.md said a run's attrs hold ``n_jac`` and ``n_failed_steps``: leap-frog and dop853-c have neither
(dop853-c has ``n_rejected``), scipy-rk45 and the casadi routes have no ``n_failed_steps``. It now says which counts
each family records; checked here on one integrator of three families (n = 9, 0.1 ms)."""

from pathlib import Path

import pytest

import mol_shell

DOC = " ".join((Path(__file__).resolve().parents[2] / "docs" / "python.md").read_text().split())
#: integrator, the counts the doc says it records, counts it says it does not (forms no Jacobian, rejects no step)
FAMILIES = [("leapfrog", {"n_steps", "n_rhs", "n_restarts"}, {"n_jac", "n_failed_steps", "n_rejected"}),
            ("dop853-c", {"n_steps", "n_rhs", "n_rejected"}, {"n_jac", "n_failed_steps"}),
            ("cvode-adams", {"n_steps", "n_rhs", "n_jac", "n_failed_steps", "n_newton", "n_rhs_jacobian"},
             {"n_rejected"})]


def test_python_md_says_which_counts_each_family_records():
    assert "`n_rejected` (rejected steps) from `dop853-c` and `rk45-c`, which form no Jacobian" in DOC
    assert "`n_restarts` from `leapfrog`, which forms no Jacobian and rejects no step" in DOC
    assert "`n_failed_steps` (error-test plus nonlinear failures) from `cvode-bdf`, `cvode-adams`, `ida`" in DOC
    assert "not recorded, which is not 0" in DOC


@pytest.mark.parametrize(("integrator", "present", "absent"), FAMILIES)
def test_each_family_records_the_counts_python_md_names(integrator, present, absent):
    options = {"dt": 1e-5} if integrator == "leapfrog" else {}
    attrs = mol_shell.simulate("twisted-cylinder", integrator, n=9, t_end=1e-4, **options).attrs
    assert present <= set(attrs) and not absent & set(attrs)
