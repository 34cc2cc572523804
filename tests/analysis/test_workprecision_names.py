"""Every integrator name can be compared: `compare --integrators sksundae-cvode-bdf,sksundae-ida` (0.5.0's
scikit-sundae routes, listed as valid names) ended in an internal KeyError, having no sweep of tolerances."""

import numpy as np

import mol_shell
from mol_shell.analysis.workprecision import DEFAULT_INTEGRATORS, SWEEPS, work_precision
from mol_shell.integrators import INTEGRATORS


def test_every_integrator_has_a_sweep_and_the_default_leaves_out_only_the_slow_python_routes():
    assert set(INTEGRATORS) == set(SWEEPS)
    assert set(INTEGRATORS) - set(DEFAULT_INTEGRATORS) == {"sksundae-cvode-bdf", "sksundae-ida"}


def test_scikit_sundae_s_bdf_and_ida_are_compared_and_converge():
    ds = work_precision(mol_shell.TwistedCylinder(), ["sksundae-cvode-bdf", "sksundae-ida"], n=6,
                        times=[0.0, 0.001], repeats=1, log=lambda *a: None)
    for name in ("sksundae-cvode-bdf", "sksundae-ida"):
        error = ds.error.sel(integrator=name).values
        error = error[np.isfinite(error)]
        assert error.size >= 5 and error.min() < 1e-2 * error[0]  # tighter tolerances, smaller errors
