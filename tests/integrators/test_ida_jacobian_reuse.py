"""IDA's difference-quotient Jacobian kept over several set-ups (``jac_reuse``): ``dF/dx`` and ``dF/dx'`` evaluated
afresh every ``jac_reuse``-th set-up and recombined with each set-up's ``cj`` in between."""

import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.analysis import workprecision as wp
from mol_shell.integrators import INTEGRATORS
from mol_shell.runs.simulate import build, resolve

TIMES = [0.0, 0.002, 0.004]


@pytest.fixture(scope="module")
def viscous():
    """The viscous scene on 16 nodes: 160 states, so a banded matrix and the driver's difference quotients."""
    scene = resolve(mol_shell.TwistedCylinder(eta_mu=100, eta_lambda=200))
    system, compiled = build(scene, 16)
    return system, compiled, system.initial_state(scene)


@pytest.fixture(scope="module")
def runs(viscous):
    system, compiled, y0 = viscous
    rtol = 1e-8
    out = {k: INTEGRATORS["ida"](rtol=rtol, atol=1e-3 * rtol, jac_reuse=k).integrate(system, compiled, y0, TIMES)
           for k in (1, 2, 1000)}
    out["cvode-bdf"] = INTEGRATORS["cvode-bdf"](rtol=rtol, atol=1e-3 * rtol).integrate(system, compiled, y0, TIMES)
    return out


def test_reused_jacobians_give_the_motion_to_the_tolerance(viscous, runs):
    system = viscous[0]
    assert all(r.status == "complete" for r in runs.values())
    assert all(runs[k].stats["linsolver"] == "band" and runs[k].stats["jacobian_kind"] == "dq" for k in (1, 2, 1000))
    fields = {k: wp.fields_of(system, r.y) for k, r in runs.items()}
    # each route within 10 rtol of the truth (test_integrators), so within 20 rtol of each other
    for k in (2, 1000):
        assert wp.relative_error(fields[k], fields[1]) < 20 * 1e-8
    assert wp.relative_error(fields[1000], fields["cvode-bdf"]) < 20 * 1e-8


def test_reuse_saves_the_evaluations_it_promises(runs):
    """One set-up in two evaluates both parts (2 x (ml + mu + 1) residuals) instead of the whole matrix (ml + mu + 1):
    as many residuals as before; over the whole run, the one pair of the first set-up (no Newton failure here)."""
    one, two, all_ = (runs[k].stats for k in (1, 2, 1000))
    width = one["n_rhs_jacobian"] / one["n_jac"]  # residuals per fresh Jacobian: ml + mu + 1
    assert width == int(width) and one["n_jac"] >= 5
    fresh_pairs = (two["n_jac"] + 1) // 2
    assert two["n_rhs_jacobian"] <= 2 * width * (fresh_pairs + two["n_failed_steps"])
    assert all_["n_rhs_jacobian"] <= 2 * width * (1 + all_["n_failed_steps"]) < one["n_rhs_jacobian"]


def test_the_recombined_matrix_is_the_newton_matrix(runs):
    """dF/dx + cj dF/dx' at each set-up's cj: Newton converges as on a fresh matrix (a wrong dF/dx' or cj would
    need more iterations per step, fail, or shorten the steps). The step counts themselves move with round-off
    (one failed step more or less sends IDA down another sequence: 287 and 321 for the same fresh-matrix run
    after a change of the residual's last bits), so only more steps are a defect."""
    one, two = runs[1].stats, runs[2].stats
    assert two["n_newton"] / two["n_steps"] <= 1.1 * one["n_newton"] / one["n_steps"]
    assert two["n_failed_steps"] <= one["n_failed_steps"] + 1
    assert two["n_steps"] <= 1.05 * one["n_steps"]


@pytest.mark.parametrize("bad", [0, 1001, 2.5, True, "3", None])
def test_jac_reuse_is_refused_outside_its_range(bad):
    with pytest.raises(ParameterError, match="jac_reuse"):
        INTEGRATORS["ida"](jac_reuse=bad)


def test_jac_reuse_is_ida_s_own():
    with pytest.raises((ParameterError, TypeError), match="jac_reuse"):
        INTEGRATORS["cvode-bdf"](jac_reuse=2)
    with pytest.raises((ParameterError, TypeError), match="jac_reuse"):
        INTEGRATORS["sksundae-ida"](jac_reuse=2)
