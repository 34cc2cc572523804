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
                        times=[0.0, 0.003], repeats=1, log=lambda *a: None)
    for name in ("sksundae-cvode-bdf", "sksundae-ida"):
        error = ds.error.sel(integrator=name).values
        error = error[np.isfinite(error)]
        # tighter tolerances, smaller errors: over three decades of rtol, two at least (at t = 1 ms the errors, 1e-8 of the
        # fields' scale at rtol 1e-4 since the norm no longer magnifies theta's round-off, left no room for two)
        assert error.size >= 5 and error.min() < 1e-2 * error.max()


def test_the_default_set_on_a_loaded_scene_leaves_out_what_cannot_run_it_and_says_so(monkeypatch, tmp_path):
    """`compare examples/pressurised_sphere.toml` (no --integrators) exited 2: the default set holds casadi-idas,
    whose semi-explicit DAE takes no loads. The default set now leaves out the integrators that refuse the scene's
    loads, each said with its reason and kept in the attribute ``left_out``; named, such an integrator is still
    refused. (The runs themselves are not the point here: the first one stops the comparison.)"""
    import pytest

    from mol_shell._core.errors import ParameterError
    from mol_shell.analysis import workprecision as wp

    original, calls = wp.run_once, [0]

    def interrupted(*args, **kwargs):  # the two reference runs, then Ctrl-C in the first compared run
        calls[0] += 1
        traj = original(*args, **kwargs)
        if calls[0] % 3 == 0:
            traj.status = "interrupted"
        return traj

    monkeypatch.setattr(wp, "run_once", interrupted)
    said = []
    scene = mol_shell.Sphere(pressure=1e3)
    ds = work_precision(scene, None, n=6, times=[0.0, 1e-4], repeats=1, log=said.append)
    refusing = {name for name in DEFAULT_INTEGRATORS if getattr(INTEGRATORS[name], "refuses_loads", "")}
    assert refusing and refusing.isdisjoint(ds.integrator.values.tolist())
    assert set(ds.integrator.values.tolist()) == set(DEFAULT_INTEGRATORS) - refusing
    assert "Left out of the default set" in wp.markdown_table(ds)
    for name in refusing:
        assert name in ds.attrs["left_out"] and any(line.startswith(name) and "left out" in line for line in said)
    calls[0] = 0
    with pytest.raises(ParameterError, match="for a scene with loads"):
        work_precision(scene, sorted(refusing), n=6, times=[0.0, 1e-4], repeats=1, log=said.append)
    calls[0] = 0
    unloaded = work_precision(mol_shell.Sphere(), None, n=6, times=[0.0, 1e-4], repeats=1, log=said.append)
    assert unloaded.integrator.values.tolist() == list(DEFAULT_INTEGRATORS) and unloaded.attrs["left_out"] == ""
