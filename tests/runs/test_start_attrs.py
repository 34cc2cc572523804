"""A run's file records the initial data it started from: a cylinder's ``R = auto`` is the radius of its start (the
static equilibrium under loads included), and a start given as fields (a path's state, at rest) stands in for the
scene's ``omega``, ``gamma``, ... (the scene's values beside them as ``NAME_requested``)."""

import math
import re
import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.cli.main import main
from mol_shell.results.dataset import read_netcdf

#: one helical fibre family on a plane-stress SVK tube between magnets (axial strain 0, the shear free)
E, NU, H, FIBRE_E, ANGLE, A = 1e6, 0.3, 0.005, 1e7, 0.7854, 1.0
FIBRE_TUBE = {"gamma": 0.0, "material": "svk-plane-stress", "nu": NU, "h": H, "E": E, "fibre_E": FIBRE_E,
              "fibre_angle": ANGLE}


def lamination():
    """Classical lamination theory of the wall: ``A = t (Q + E_f v v^T)``, ``t = 2h``, ``Q`` plane stress,
    ``v = (c^2, s^2, c s)`` in (meridional, hoop, engineering shear)."""
    q = E / (1 - NU**2) * np.array([[1, NU, 0], [NU, 1, 0], [0, 0, (1 - NU) / 2]])
    c, s = math.cos(ANGLE), math.sin(ANGLE)
    v = np.array([c * c, s * s, c * s])
    return 2 * H * (q + FIBRE_E * np.outer(v, v))


def test_a_fibre_tubes_R_auto_is_the_radius_its_static_start_has(tmp_path, capsys):
    """Between magnets (e_11 = 0) under p with the shear resultant free (N_12 = 0): the hoop strain is
    p a / (A22 - A23^2/A33), the twist (engineering shear / a) -A23/A33 of it; the shear held, p a / A22 (the
    radial equilibrium R = auto computes, which the file and the summary reported as the start's radius)."""
    p = 1.0
    A_ = lamination()
    hoop = p * A / (A_[1, 1] - A_[1, 2] ** 2 / A_[2, 2])
    locked = p * A / A_[1, 1]
    assert hoop / locked > 2  # the two differ: the test tells them apart
    out = tmp_path / "c.nc"
    sets = [x for k, v in {**FIBRE_TUBE, "pressure": p}.items() for x in ("--set", f"{k}={v}")]
    assert main(["run", "twisted-cylinder", *sets, "--n", "11", "--t-end", "1e-5", "--no-stresses",
                 "-o", str(out)]) == 0
    said = capsys.readouterr().out
    ds = read_netcdf(out)
    r0, chi0, s = ds.r.isel(time=0).values, ds.chi.isel(time=0).values, ds.s.values
    R = float(ds.attrs["R"])
    assert ds.attrs["R_requested"] == "auto"
    np.testing.assert_allclose(r0, R, rtol=2e-9)  # attrs R is r(t = 0)
    assert (R - A) / A == pytest.approx(hoop, rel=1e-3)
    chi_s = np.polyfit(s, chi0, 1)[0]
    assert chi_s * A == pytest.approx(-A_[1, 2] / A_[2, 2] * hoop, rel=1e-3)
    assert f"R = {R:.10g} m (the start's" in said and "the static equilibrium under the loads" in said, said
    began = float(re.search(r"found from the radial equilibrium at r = (\S+) m", ds.attrs["initial_state"]).group(1))
    assert (began - A) / A == pytest.approx(locked, rel=1e-3)  # where the solve began: said, apart from R


def path_then_run(tmp_path, scene, sets, param, step=2):
    """``path SCENE --param PARAM`` (2 steps), then ``run --from`` its step: the run's file and stderr."""
    path, out = tmp_path / "p.nc", tmp_path / "r.nc"
    sets = [x for item in sets for x in ("--set", item)]
    assert main(["path", scene, *sets, "--param", param, "--n", "11", "--steps", "2", "-o", str(path)]) == 0
    assert main(["run", "--from", str(path), "--step", str(step), "--t-end", "1e-5", "--no-stresses",
                 "-o", str(out)]) == 0
    return read_netcdf(out), path


def test_a_run_from_a_spun_spheres_path_records_omega_0_beside_the_scenes(tmp_path, capsys):
    ds, _ = path_then_run(tmp_path, "sphere", ["omega=5"], "pressure=0:100")
    err = capsys.readouterr().err
    assert float(np.abs(ds.chi_t).max()) == 0.0  # the path's state at rest: it stays so
    assert ds.attrs["omega"] == 0.0 and ds.attrs["omega_requested"] == 5.0
    assert ds.attrs["units_omega_requested"] == "rad s-1"
    assert ds.attrs["gamma"] == 0.0 and "gamma_requested" not in ds.attrs  # the scene's 0, and the start's
    assert ds.attrs["R_requested"] == "auto" and "omega = 0 rad s-1 (the scene's 5 rad s-1)" in ds.attrs[
        "initial_data_note"]
    assert "mol-shell: note: " + ds.attrs["initial_data_note"] in err, err


def test_modes_from_a_spun_spheres_path_record_omega_0_beside_the_scenes(tmp_path, capsys):
    """``modes --from`` a path's step recorded the scene's ``omega = 5`` about a state at rest, as ``run`` did: it
    records what the modes are about, the scene's value beside it, and says so."""
    _, path = path_then_run(tmp_path, "sphere", ["omega=5"], "pressure=0:100")
    capsys.readouterr()
    out = tmp_path / "m.nc"
    assert main(["modes", "--from", str(path), "--step", "2", "--count", "2", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    ds = read_netcdf(out)
    assert ds.attrs["omega"] == 0.0 and ds.attrs["omega_requested"] == 5.0
    assert "omega = 0 rad s-1 (the scene's 5 rad s-1)" in ds.attrs["initial_data_note"]
    assert "mol-shell: note: " + ds.attrs["initial_data_note"] in err, err


def test_a_run_from_a_twisted_cylinders_path_records_the_twist_it_has(tmp_path, capsys):
    """The path let the scene's gamma = 0.1 unwind (magnets leave chi free): its states have chi = 0."""
    ds, _ = path_then_run(tmp_path, "twisted-cylinder", [], "pressure=0:100")
    capsys.readouterr()
    assert float(np.abs(ds.chi.isel(time=0)).max()) == 0.0
    assert ds.attrs["gamma"] == 0.0 and ds.attrs["gamma_requested"] == 0.1
    assert ds.attrs["psi0"] == 0.0 and "psi0_requested" not in ds.attrs
    assert ds.attrs["R_requested"] == "auto"
    np.testing.assert_allclose(ds.r.isel(time=0).values, float(ds.attrs["R"]), rtol=1e-9)


def test_a_start_given_as_the_scenes_own_fields_records_the_scenes_values():
    """Nothing stands in for anything: no NAME_requested (the twist read back by a fit to round-off)."""
    scene = mol_shell.TwistedCylinder(R=1.0, gamma=0.1, psi0=0.02)
    system, _ = mol_shell.runs.simulate.build(scene, 11)
    Q, _ = scene.initial_fields(system.s, system.reference)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.simulate(scene, n=11, t_end=1e-5, initial=Q, stresses=False, progress=False)
    assert (ds.attrs["R"], ds.attrs["gamma"], ds.attrs["psi0"], ds.attrs["omega"]) == (1.0, 0.1, 0.02, 0.0)
    assert not [k for k in ds.attrs if k.endswith("_requested") and k.startswith(("R", "gamma", "psi0", "omega"))]
    assert "initial_data_note" not in ds.attrs


def test_the_unshearable_scenes_R_auto_is_marked_as_computed():
    """``R = auto`` is its natural radius ``a``, the mean of its start ``r = R + dR cos(2 pi s / L)``; the file said
    ``R = 1`` as if given (no ``R_requested``)."""
    scene = mol_shell.Unshearable(R=None, a=1.2, dR=0.01)
    ds = mol_shell.simulate(scene, "leapfrog", n=11, t_end=1e-5, stresses=False, progress=False)
    assert ds.attrs["R"] == 1.2 and ds.attrs["R_requested"] == "auto"
    r0, s = ds.r.isel(time=0).values, ds.s.values
    assert np.sum((r0[1:] + r0[:-1]) / 2 * np.diff(s)) / (s[-1] - s[0]) == pytest.approx(1.2, rel=1e-12)


def test_a_spin_set_on_a_static_start_is_said_with_its_radius(tmp_path, capsys):
    """A cylinder under pressure with ``omega`` (the loaded cylinder of tests/cli/test_cli.py, spun): its start is the
    static equilibrium under the loads, then spun at ``chi_t = omega`` everywhere (the file's initial_state says so);
    the summary said only "the static equilibrium under the loads", as if it started at rest."""
    out = tmp_path / "c.nc"
    assert main(["run", "twisted-cylinder", "--set", "gamma=0", "--set", "end2=free", "--set", "pressure=10",
                 "--set", "material=svk-plane-stress", "--set", "nu=0.3", "--set", "omega=2", "--n", "11",
                 "--t-end", "1e-5", "--no-stresses", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    ds = read_netcdf(out)
    np.testing.assert_allclose(ds.chi_t.isel(time=0).values, 2.0, rtol=1e-14)  # spun, as asked
    moving = "then set moving at the scene's initial rates (omega, driven edges)"
    assert ds.attrs["initial_state"].startswith("static equilibrium under the loads") and moving in ds.attrs[
        "initial_state"]
    R = float(ds.attrs["R"])
    assert f"R = {R:.10g} m (the start's mean radius: the static equilibrium under the loads; {moving})" in said, said
