"""A start computed as a static equilibrium (``R = auto``) past a critical load is said to be unstable.

Expected values, derived apart from the code under test: a closed sphere of radius ``a`` and wall ``t = 2h`` buckles
under external pressure near Zoelly's ``p_cl = 2 E t^2 / (a^2 sqrt(3 (1 - nu^2)))``: below it the membrane state is
stable, beyond it unstable. The number of unstable directions is checked against a second route: the natural modes
about the same state (``mol_shell.analysis.modes``: the dense generalised eigenproblem ``K phi = omega^2 M phi``
with the rigid motions removed), whose modes with ``omega^2 < 0`` are as many as the negative eigenvalues of ``K``
(Sylvester's law of inertia); the run's check counts those of the banded ``K`` scaled to a unit diagonal.
"""

from __future__ import annotations

import math
import warnings

import pytest

from mol_shell import Sphere, simulate
from mol_shell.analysis.modes import modes
from mol_shell.cli.main import main
from mol_shell.runs import simulate as simulate_module

E, NU, A = 1.0e6, 0.3, 1.0
H = A / 80  # a/t = 40
P_CL = 2 * E * (2 * H) ** 2 / (A**2 * math.sqrt(3 * (1 - NU**2)))


def sphere(factor):
    return Sphere(a=A, h=H, E=E, nu=NU, material="svk-plane-stress", pressure=-factor * P_CL)


def run(factor):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = simulate(sphere(factor), n=40, times=[0.0, 1e-4], stresses=False)
    return ds, [str(w.message) for w in caught if "unstable" in str(w.message)]


def test_below_the_critical_pressure_the_start_is_not_flagged():
    ds, said = run(0.9)
    assert not said and "stability_warning" not in ds.attrs


@pytest.mark.parametrize("factor", [1.1, 1.5])
def test_past_it_the_start_is_flagged_with_as_many_directions_as_the_modes_find(factor):
    ds, said = run(factor)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        unstable = int(modes(sphere(factor), n=40).attrs["unstable_modes"])
    assert unstable > 0
    assert len(said) == 1 and said[0] == ds.attrs["stability_warning"]
    assert f"has {unstable} negative eigenvalues" in said[0], said[0]


def test_the_command_says_it_in_one_line_and_runs(tmp_path, capsys):
    code = main(["run", "sphere", "--n", "40", "--times", "0,1e-4", "--set", f"a={A}", "--set", f"h={H}", "--set",
                 f"E={E}", "--set", f"nu={NU}", "--set", "material=svk-plane-stress", "--set",
                 f"pressure={-1.5 * P_CL}", "-o", str(tmp_path / "s.nc")])
    err = capsys.readouterr().err
    assert code == 0
    lines = [line for line in err.splitlines() if "unstable" in line]
    assert len(lines) == 1 and lines[0].startswith("mol-shell: warning: the start computed"), err


@pytest.mark.parametrize("loads, named", [
    (["gravity=9.81", "pressure=10"], "gravity = 9.81"),  # named pressure, with Newton's failure
    (["gravity=9.81"], "gravity = 9.81"),
    (["end1_force=5"], "end1_force = 5.0"),
])
def test_loads_a_free_shell_cannot_hold_are_refused_naming_the_load(loads, named, tmp_path, capsys):
    """A closed sphere (two poles) under gravity, or one end force, has a net axial force: it falls, no
    equilibrium (statics of a free body). The run's static start said Newton failed and named the pressure."""
    extra = [arg for load in loads for arg in ("--set", load)]
    code = main(["run", "sphere", "--n", "10", "--t-end", "0.001", *extra, "-o", str(tmp_path / "e.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert err[-1].startswith(f"mol-shell: error: {named} is outside loads whose net force along the axis is zero")
    assert "no equilibrium" in err[-1] and "Newton" not in err[-1], err


def test_balanced_end_forces_on_a_free_shell_are_not_refused(tmp_path):
    """Equal and opposite end forces (net zero) leave the sphere an equilibrium: the check is on the net."""
    ds = simulate(Sphere(end1_force=5.0, end2_force=-5.0), n=10, times=[0.0, 1e-4], stresses=False)
    assert ds.attrs["initial_state"].startswith("static equilibrium")


def test_a_start_whose_stability_cannot_be_checked_says_so_in_the_file(monkeypatch):
    """``unstable_directions`` gives None for a stiffness it cannot read as a band of positive diagonal: the run
    passed over it in silence; the file says the check was not made (no warning: nothing is known to be wrong)."""
    monkeypatch.setattr(simulate_module, "unstable_directions", lambda system, y: None)
    ds, said = run(1.5)
    assert not said and ds.attrs["stability_warning"].startswith("the stability of the start computed as a static "
                                                                 "equilibrium was not checked")
