"""Values inside every range that put the motion at the edge of double precision (``E = 1e300``, ``rho = 1e-300``):
every integrator stops there as a failed run (exit 3, the saved time 0 kept), naming itself, the time and why; none
ends in an internal error (``ZeroDivisionError`` in the compiled pairs' starting step, SuperLU's "Factor is exactly
singular" in SciPy's implicit solvers).
"""

import re

import numpy as np
import pytest
from scipy.integrate._ivp.common import select_initial_step

import mol_shell
from mol_shell.cli.main import main
from mol_shell.integrators import explicit
from mol_shell.results.dataset import read_netcdf
from mol_shell.runs.building import build
from mol_shell.runs.simulate import starting_state

#: DOP853's error estimator order (SciPy's ``DOP853.error_estimator_order``)
ORDER = 7


def _constant(value):
    return lambda y, t: np.full_like(y, value)


def test_the_starting_step_beyond_the_squares_range_is_hairer_s():
    """``f = 1e300`` (constant), ``y0 = 2e-14``, ``atol = 1e-9``, ``rtol = 1e-6``: ``d1 = |f| / scale ~ 1e309`` has no
    double, and its square overflowed to inf (``h0 = 0``, then ``/ h0``: ZeroDivisionError). The estimate itself is
    finite: ``h0 = 0.01 d0 / d1 = 0.01 |y0| / |f| = 2e-316`` (the scale cancels), ``f(y0 + h0 f0) - f0 = 0`` so ``d2 = 0``
    and ``h1 = (0.01 / d1)^(1/8) ~ 1e-39``; the step is ``min(100 h0, h1) = |y0| / |f| = 2e-314`` s."""
    y0 = np.full(4, 2e-14)
    h = explicit.initial_step(_constant(1e300), y0, np.full(4, 1e300), ORDER, 1e-6, np.full(4, 1e-9), 0.01, 0.0)
    assert h == pytest.approx(2e-14 / 1e300, rel=1e-6)  # subnormal: about 11 digits


def test_a_starting_step_below_ten_ulp_of_zero_underflows():
    """``f = 1e308``: ``h0 = 0.01 |y0| / |f| = 2e-324``, below SciPy's minimum step at t = 0 (10 ulp(0) = 4.9e-323):
    the estimate underflows and ``initial_step`` says so by returning 0."""
    y0 = np.full(4, 2e-14)
    assert explicit.initial_step(_constant(1e308), y0, np.full(4, 1e308), ORDER, 1e-6, np.full(4, 1e-9), 0.01, 0.0) == 0


def test_an_ordinary_start_is_scipys():
    """Where nothing overflows the step is SciPy's ``select_initial_step`` to round-off (its RMS norm is
    ``norm(x) / sqrt(n)``, ours ``sqrt(mean(x^2))``, as before the logarithmic branch: they differ by about 1e-16)."""
    y0 = np.array([1.0, -0.5, 2.0])
    f = lambda t, y: np.array([y[1], -4.0 * y[0], 0.3 * y[2]])
    atol = np.full(3, 1e-9)
    ours = explicit.initial_step(lambda y, t: f(t, y), y0, f(0, y0), ORDER, 1e-6, atol, 1.0, 0.0)
    theirs = select_initial_step(f, 0.0, y0, 1.0, np.inf, f(0, y0), 1, ORDER, 1e-6, atol)
    assert ours == pytest.approx(theirs, rel=1e-14)


COMPILE_PROGRESS = re.compile(r"^mol-shell: (compiling|still compiling|compiled) ")


def _run(tmp_path, capsys, integrator, value):
    out = tmp_path / "x.nc"
    code = main(["run", "twisted-cylinder", "--n", "11", "--t-end", "0.01", "--set", value, "--integrator", integrator,
                 "-o", str(out)])
    # a gcc build that takes over 5 s (a cold kernel cache on a busy machine) says so in lines of its own
    lines = [line for line in capsys.readouterr().err.splitlines()
             if not line.startswith("mol-shell: warning: ") and not COMPILE_PROGRESS.match(line)]
    ds = read_netcdf(out)
    return code, lines, ds


@pytest.mark.parametrize("integrator", ["rk45-c", "dop853-c"])
def test_the_compiled_pairs_stop_when_the_starting_step_underflows(tmp_path, capsys, integrator):
    """``rho = 1e-300``: the rates of the start are ``p / m`` and forces over a mass ~ rho, ``|f| / atol ~ 1e314`` per
    second, so ``h0 = 0.01 |y| / |f|`` underflows; a failed run at t = 0, time 0 kept (it was an internal error)."""
    code, lines, ds = _run(tmp_path, capsys, integrator, "rho=1e-300")
    assert code == 3 and len(lines) == 1, lines
    assert lines[0].startswith(f"mol-shell: run stopped: {integrator} failed at t = 0 s: its initial step underflows "
                               "(below 4.9e-323 s, 10 ulp(0)): the right-hand side at the start is 1e+"), lines
    assert ds.attrs["complete"] == 0 and ds.attrs["status"] == "failed" and ds.sizes["time"] == 1


@pytest.mark.parametrize("integrator, value", [("scipy-radau", "E=1e200"), ("scipy-bdf", "rho=1e-300")])
def test_scipy_s_implicit_solvers_stop_at_a_singular_newton_matrix(tmp_path, capsys, integrator, value):
    """``E = 1e200`` or ``rho = 1e-300``: SciPy's starting step underflows to 0 (``|f|`` beyond 1e300), so it steps at its
    minimum, 10 ulp(0) = 4.94e-323 s; ``I / (c h) - J`` (Radau: 1 / 4.94e-323 overflows) or ``I - c h J`` (BDF, with
    a Jacobian whose entries ~ E / rho overflow) holds inf and NaN, and SuperLU calls it singular. A failed run at t = 0,
    time 0 kept (it was an internal error, SuperLU's RuntimeError)."""
    code, lines, ds = _run(tmp_path, capsys, integrator, value)
    assert code == 3 and len(lines) == 1, lines
    assert lines[0].startswith(f"mol-shell: run stopped: {integrator} failed at t = 0 s: its Newton matrix is singular "
                               "in double precision (SuperLU: Factor is exactly singular) at SciPy's minimum step "
                               "4.94e-323 s (10 ulp(t); its step estimate, 0 s, underflowed below it), with the "
                               "Jacobian's entries up to "), lines
    assert ds.attrs["complete"] == 0 and ds.attrs["status"] == "failed" and ds.sizes["time"] == 1


def test_idas_invalid_input_at_extreme_moduli_is_said_in_words():
    """At E = 1e300 the compiled IDA stops at t = 0 with SUNDIALS' IDA_ILL_INPUT (-22): the run's message said only
    "SUNDIALS error (status -22)"; it says what SUNDIALS found invalid."""
    with pytest.warns(RuntimeWarning, match="run incomplete"):
        ds = mol_shell.simulate(mol_shell.get_scene("twisted-cylinder", E=1e300), "ida", n=11, t_end=0.01,
                                progress=False)
    assert "status -22" in ds.attrs["message"] and "input of the step invalid" in ds.attrs["message"], ds.attrs["message"]


def test_casadis_cached_tolerance_scale_follows_rtol():
    """The accumulators' absolute tolerance is ``rtol`` times the start's energies, so CasADi's scaled state may not
    be cached by ``atol`` alone: a run at rtol 1e-8 after one at 1e-4 on the same system took the 1e-4 scale
    (10,000 times too loose for the work and dissipation totals)."""
    scene = mol_shell.Sphere(R=1.0, pressure=1e3)
    system, _ = build(scene, 10)
    y0, _ = starting_state(scene, system, 10)
    loose, tight = (mol_shell.INTEGRATORS["casadi-cvodes-c"](rtol=rtol) for rtol in (1e-4, 1e-8))
    loose._scale(system, y0)
    expected = tight.atol_vector(system, y0, momenta=True) / tight.field_atol().min()
    np.testing.assert_array_equal(tight._scale(system, y0), expected)
    assert expected[-1] == pytest.approx(loose._scale(system, y0)[-1] * 1e-4)
