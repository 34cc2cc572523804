"""The README's Python example runs verbatim, and what it computes holds.

The ```python block(s) of README.md are executed as written (as a script would run them:
``__name__ == "__main__"``) in a temporary working directory; then the variables they leave
and the file they write are checked against expectations derived here, independently of the
package (closed forms, symmetry, round-off bounds). The block reassigns ``ds``; the leap-frog
run of the paper's scene is read back from the ``run.nc`` it writes.
"""

import math
import os
import re
from pathlib import Path

import numpy as np
import pytest

import mol_shell
import reference_ring as ref

EPS = np.finfo(float).eps
README = Path(__file__).resolve().parents[2] / "README.md"
PAPER = mol_shell.TwistedCylinder()
PAPER_TIMES = [0, 0.02, 0.07, 0.106, 0.143]
#: the README's example runs the paper's 143,000 steps, a viscous IDA run at n = 160 and a study: ~20 s
pytestmark = pytest.mark.slow


def python_blocks(text):
    """The contents of the README's ```python fenced blocks, in order."""
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def membrane_radius(gamma, nu):
    """The uniformly twisted membrane in radial equilibrium (derivation in tests/runs/test_studies.py):
    ``r^2 = (lambda (1 + gamma^2) + 2 mu) / ((lambda + 2 mu)(1 + gamma^2)^2)``; the shell's ``1 - R``
    differs by a relative ``O(h^2)`` (``h^2 = 3.9e-5``), for which ``3 h^2`` is allowed below."""
    lam, mu = ref.lame(PAPER.E, nu)
    g2 = gamma**2
    return math.sqrt((lam * (1 + g2) + 2 * mu) / ((lam + 2 * mu) * (1 + g2) ** 2))


@pytest.fixture(scope="module")
def readme_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("readme")
    blocks = python_blocks(README.read_text())
    assert len(blocks) == 1, "one Python example in the README"
    namespace = {"__name__": "__main__"}
    cwd = Path.cwd()
    try:
        os.chdir(folder)  # the block writes run.nc where it runs
        exec(compile(blocks[0], str(README), "exec"), namespace)
    finally:
        os.chdir(cwd)
    return namespace, folder


def test_the_paper_run_conserves_energy_and_angular_momentum_at_the_equilibrium_radius(readme_run):
    """Leap-frog, N = 40, dt = 1e-6 s, saved at the paper's times (read back from run.nc).

    * ``R`` is the twisted membrane's equilibrium radius up to the O(h^2) thickness correction.
    * A fixed step: 0.143 s / 1e-6 s = 143,000 steps, and the saved times are the ones asked for.
    * Energy: leap-frog's error is ``C dt^2`` without drift; the README claims < 1e-9 relative.
    * The shell starts at rest, so its axial angular momentum is 0; the scheme conserves
      ``sum p_chi`` exactly, so it stays 0 up to round-off accumulated over the steps, at worst
      ``EPS`` of the momentum scale ``2 pi rho 2h R^2 L max|chi_t|`` per step: we allow that.
    """
    _, folder = readme_run
    run = mol_shell.read_netcdf(folder / "run.nc")
    assert run.attrs["status"] == "complete" and run.attrs["integrator"] == "leapfrog"
    np.testing.assert_array_equal(run.time.values, PAPER_TIMES)
    assert run.sizes["s"] == 40 and int(run.attrs["n_steps"]) == 143000
    R = float(run.attrs["R"])
    assert abs((1 - R) / (1 - membrane_radius(PAPER.gamma, PAPER.nu)) - 1) <= 3 * PAPER.h**2, R
    e = run.energy.values
    assert 0 < np.abs(e - e[0]).max() / e[0] <= 1e-9
    scale = 2 * math.pi * PAPER.rho * 2 * PAPER.h * R**2 * PAPER.L * float(abs(run.chi_t).max())
    assert float(abs(run.angular_momentum).max()) <= 143000 * EPS * scale


def test_the_viscous_ida_run_dissipates(readme_run):
    """Kelvin-Voigt (eta_mu = 1000, eta_lambda = 2000 Pa s) on n = 160 with IDA to 10 ms.

    The dissipation ``eta_lambda/2 (tr E_t)^2 + eta_mu |E_t|^2`` is nonnegative, so the energy
    never grows (up to IDA's tolerance, rtol 1e-6 by default: we allow 1e-5 of E(0) per saved
    time), and the motion released at the free ends strains the shell, so it falls.
    """
    ns, _ = readme_run
    ds = ns["ds"]
    assert ds.attrs["status"] == "complete" and ds.attrs["integrator"] == "ida"
    assert ds.sizes["s"] == 160 and float(ds.attrs["eta_mu"]) == 1000.0
    e = ds.energy.values
    assert np.all(np.diff(e) <= 1e-5 * e[0]), np.diff(e)
    assert e[-1] < e[0]


def test_the_ring_ode_conserves_energy_and_angular_momentum(readme_run):
    """The reduced ODE of section 5 (DOP853, rtol = atol = 1e-12): both invariants to ~1e-10.

    A global error of a few hundred times the tolerance over 0.01 s (a few breathing periods)
    bounds the change of either invariant; we allow 1e-9 relative.
    """
    ring = readme_run[0]["ring"]
    for name in ("energy", "angular_momentum"):
        x = ring[name].values
        assert np.abs(x - x[0]).max() <= 1e-9 * abs(x[0]), name
    assert ring.time.values[-1] == 0.01


def test_the_unshearable_dae_keeps_its_constraints(readme_run):
    """Unshearable shell, omega = 20 rad/s, IDA to 0.1 s: chi_s and psi at round-off; energy conserved.

    The constraints are linear and IDA's Newton iteration has their exact rows, so ``chi_s``
    is the round-off of differences of ``chi`` (``|chi| <= omega t = 2`` rad) over ``ds``; we
    allow 100x ``EPS max|chi| / ds``. The multipliers do no work (``G v = 0``): the energy is
    conserved to IDA's accuracy (rtol 1e-8); we allow 100 rtol.
    """
    dae = readme_run[0]["dae"]
    assert dae.attrs["status"] == "complete"
    ds_grid = float(dae.s[1] - dae.s[0])
    assert float(dae.chi_s_max.max()) <= 100 * EPS * float(abs(dae.chi).max()) / ds_grid
    assert float(dae.psi_max.max()) <= 100 * EPS
    e = dae.energy.values
    assert np.abs(e - e[0]).max() / e[0] <= 100 * dae.attrs["rtol"]
    assert float(abs(dae.lambda_chi).max()) > 0  # the spin needs the constraint torque


def test_the_study_has_one_dimension_per_parameter_and_each_case_its_radius(readme_run):
    """gamma x nu = 2 x 2 cases to 0.02 s: all complete, 20,000 leap-frog steps each, and each
    case's R the membrane radius of its own gamma and nu (to the O(h^2) thickness correction)."""
    st = readme_run[0]["st"]
    assert st.status.dims == ("gamma", "nu") and (st.status.values == "complete").all()
    assert np.all(st.n_steps.values == 20000)
    for gamma in st.gamma.values:
        for nu in st.nu.values:
            R = float(st.R.sel(gamma=gamma, nu=nu))
            assert abs((1 - R) / (1 - membrane_radius(gamma, nu)) - 1) <= 3 * PAPER.h**2, (gamma, nu, R)
