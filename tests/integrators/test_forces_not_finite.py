"""SUNDIALS' compiled loops where the forces stop being finite: a stop in seconds, not a million steps in minutes."""

import re
import textwrap
import warnings

import pytest

import mol_shell


def _sqrt_domain_law(tmp_path, monkeypatch):
    """A module on the path with ``law``: neo-Hookean plus ``1e-30 sqrt(I1 - 2.9)``, whose energy and forces are NaN
    where ``I1 < 2.9`` (director, ``C22 = 1``: equal stretches below sqrt(0.95) = 0.9747)."""
    (tmp_path / "sqrt_domain_laws.py").write_text(textwrap.dedent('''
        import casadi as ca
        import mol_shell

        def energy(C, p):
            J, I1 = ca.sqrt(ca.det(C)), ca.trace(C)
            return (p["mu"] / 2 * (I1 - 3) - p["mu"] * ca.log(J) + p["lam"] / 2 * ca.log(J) ** 2
                    + 1e-30 * ca.sqrt(I1 - 2.9))

        law = mol_shell.Material("sqrt_domain_laws", energy=energy, parameters={"mu": 3e5, "lam": 5e5},
                                 thickness="director")
    '''))
    monkeypatch.syspath_prepend(str(tmp_path))


@pytest.mark.parametrize("integrator", ["ida", "cvode-adams"])
def test_a_run_into_forces_that_are_not_finite_stops_where_its_step_underflows(tmp_path, monkeypatch, integrator):
    """A step of external pressure at 1 ms compresses the sphere until ``I1`` reaches 2.9, where the forces turn NaN.
    IDA then took steps of about 1e-21 s (SUNDIALS warns of t + h = t and goes on) until max_steps: 1e6 steps, five
    minutes at n = 8, and cvode-adams the same in seconds. A run whose steps stay within 10 eps |t| for 100 steps
    in a row stops there now (exit 3 from the command line), saying its step fell below round-off at t, after the
    pressure step, with the saved times before it kept."""
    _sqrt_domain_law(tmp_path, monkeypatch)
    scene = mol_shell.Sphere(h=0.01, material="sqrt_domain_laws:law", pressure=-2e5, pressure_history="step 0.001")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(scene, integrator, n=8, t_end=0.01, max_steps=20000, progress=False)
    message = ds.attrs["message"]
    assert ds.attrs["complete"] == 0 and "its step fell below round-off at t" in message, message
    assert "rtol = 1e-06, atol = 1e-09" in message
    assert float(re.search(r"failed at t = (\S+) s", message).group(1)) > 0.001  # after the pressure step
    assert ds.attrs["n_steps"] < 20000
