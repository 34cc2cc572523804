"""``mol-shell run --help`` states the tolerances' defaults, and that atol is absolute, in the state's units."""

import re

from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS


def test_run_help_states_the_default_tolerances(capsys):
    assert main(["run", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    rtol = re.search(r"--rtol RTOL (.*?) --atol ATOL (.*?) --max-step", text)
    assert rtol, text
    method = INTEGRATORS["cvode-bdf"]()  # every adaptive integrator's defaults are these
    assert f"default {method.rtol:g}" in rtol.group(1)
    assert f"default {method.atol:g}" in rtol.group(2) and method.atol == 1e-9
    assert "absolute, in the state's units (m for z and r, rad for chi, theta and psi" in rtol.group(2)
