"""The modes are the undamped shell's (``K phi = omega^2 M phi``): a scene's drag and viscosity are said to be left
out, and the drag's first-order damping ratio of each mode, ``phi^T C phi / (2 omega phi^T M phi)``
(:mod:`mol_shell.analysis.mode_damping`), is checked against the eigenvalues of the package's own damped Jacobian."""

import warnings

import numpy as np
import pytest

from mol_shell import SceneWarning
from mol_shell.analysis.modes import modes
from mol_shell.discretization.system import ShellSystem
from mol_shell.scenes import Sphere

N = 11


def test_drag_is_said_left_out_and_its_damping_ratio_is_the_damped_jacobians():
    """``modes sphere --set drag=1e6`` printed the undamped frequencies, the same as without drag, with no word. Now a
    SceneWarning and ``attrs["damping_note"]`` say so, and ``drag_damping_ratio`` is, to first order in the drag, the
    ``-Re lambda / |lambda|`` of the eigenvalues of the exact Jacobian of the damped system (drag in ``dp/dt``)."""
    scene = Sphere(drag=2.0)
    with pytest.warns(SceneWarning, match=r"^modes are the undamped shell's: drag = 2 N s m-3 is left out \(it damps "
                      r"these modes; docs/shells.md\); the drag's damping ratio of each mode, to first order "
                      r"\(drag_damping_ratio\): "):
        ds = modes(scene, n=N, count=3)
    assert ds.attrs["damping_note"].startswith("modes are the undamped shell's: drag = 2 N s m-3 is left out")
    undamped = modes(Sphere(), n=N, count=3)
    np.testing.assert_array_equal(ds.frequency.values, undamped.frequency.values)  # the modes themselves: undamped
    assert "damping_note" not in undamped.attrs and "drag_damping_ratio" not in undamped
    # the damped system's eigenvalues on its free coordinates and momenta (drag: p_t = ... - C M^-1 p)
    system = ShellSystem(scene, N)
    J = np.array(system.jac(0, system.initial_state(scene)))
    fixed = system.fixed[:, list(system.active)]
    q = np.array([system.ny * i + k for i in range(system.n) for k in range(system.nf) if not fixed[i, k]])
    idx = np.concatenate([q, q + system.nf])
    lam = np.linalg.eigvals(J[np.ix_(idx, idx)])
    lam = lam[lam.imag > 1e-6 * np.abs(lam).max()]
    for omega, zeta in zip(ds.frequency.values, ds.drag_damping_ratio.values):
        near = lam[np.argmin(np.abs(np.abs(lam) - omega))]
        assert abs(abs(near) - omega) < 1e-6 * omega
        assert zeta == pytest.approx(-near.real / abs(near), rel=1e-3), (zeta, near)
    assert 0.001 < ds.drag_damping_ratio.values[0] < 0.1


def test_viscosity_is_said_left_out():
    """``eta_mu = 1e3``: the same frequencies as the elastic shell's, said, with no drag ratio."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        ds = modes(Sphere(eta_mu=1e3), n=N, count=2)
    note = ("modes are the undamped shell's: eta_mu = 1000 Pa s, eta_lambda = 0 Pa s are left out (they damp these "
            "modes; docs/shells.md)")
    assert [str(w.message) for w in said if w.category is SceneWarning] == [note]
    assert ds.attrs["damping_note"] == note and "drag_damping_ratio" not in ds
