"""Fibre reinforcement (mol_shell.model.fibres): the helical anisotropy of the paper's Figure 1c.

References independent of the code: classical lamination theory for the twist of an inflated tube, the reinforcing
model's uniaxial closed form, and the run's own energy accounting (conservation; dE/dt = -2D with viscosity).
"""

import hashlib
import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.errors import MaterialWarning, ParameterError
from mol_shell.cli.main import main
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.fibres import Fibres, fibre_energy, unused_fibres_warning
from mol_shell.runs.building import build
from mol_shell.runs.checks import initial_state
from mol_shell.runs.statics import newton
from mol_shell.scenes import Cone, Sphere, TwistedCylinder

E, NU, E_F, ALPHA, P, A, H = 1e6, 0.3, 1e7, 0.5, 1.0, 1.0, 0.005


def test_reinforcing_energy_uniaxial_closed_form():
    """A stretch ``lam`` along the fibre: ``a.E a = (lam^2 - 1)/2``, ``W = E_f/2 ((lam^2 - 1)/2)^2``; across it
    (``a.E a = 0``) nothing; tension only: nothing in compression, the same in tension."""
    alpha, lam = 0.4, 1.1
    c, s = math.cos(alpha), math.sin(alpha)
    # C = I + (lam^2 - 1) a a^T in the (meridian, thickness, circumference) basis, a = (c, 0, s)
    C = [[1 + (lam**2 - 1) * c * c, 0, (lam**2 - 1) * c * s], [0, 1, 0], [(lam**2 - 1) * c * s, 0, 1 + (lam**2 - 1) * s * s]]
    one = Fibres(E_F, alpha)
    assert fibre_energy(C, one) == pytest.approx(E_F / 2 * ((lam**2 - 1) / 2) ** 2, rel=1e-14)
    across = Fibres(E_F, alpha + math.pi / 2)
    assert abs(fibre_energy(C, across)) < 1e-12 * fibre_energy(C, one)
    squeezed = [[1 + (0.81 - 1) * c * c, 0, (0.81 - 1) * c * s], [0, 1, 0], [(0.81 - 1) * c * s, 0, 1 + (0.81 - 1) * s * s]]
    assert fibre_energy(squeezed, Fibres(E_F, alpha, compression=False)) == 0.0
    assert fibre_energy(squeezed, one) > 0
    assert fibre_energy(C, Fibres(E_F, alpha, compression=False)) == fibre_energy(C, one)


def _inflated_tube(families):
    """A closed-end tube (lids push the free end), chi free at both ends, at equilibrium under pressure P."""
    scene = Cone(r1=A, r2=A, H=2.0, h=H, material="svk-plane-stress", E=E, nu=NU, fibre_E=E_F, fibre_angle=ALPHA,
                 fibre_families=families, end1="magnet", end2="free", pressure=P, dilation=1.0)
    system, _ = build(scene, 9)
    y, _, res = newton(system, initial_state(scene, system), hold=())  # chi free: the twist is an unknown
    assert res < 1e-10
    Y = y[: system.ny * system.n].reshape(system.n, system.ny)
    mid = slice(2, 7)  # away from the ends
    return (np.mean(np.diff(Y[mid, 0]) / np.diff(system.s[mid])) - 1, np.mean(Y[mid, 1]) / A - 1,
            np.mean(np.diff(Y[mid, 2]) / np.diff(system.s[mid])))


def test_one_fibre_family_inflated_tube_twists_as_lamination_theory_says():
    """Classical lamination theory, derived here. Membrane strains ``eps = (e_x, e_theta, gamma)`` (``gamma`` the
    engineering shear; in the shell ``gamma = 2 E_13 = C_13 = r^2 chi_s / a``, so ``gamma = a chi_s`` at small
    strain). Energy per unit area ``t/2 eps^T Q eps + t E_f/2 (a.E a)^2`` with ``a.E a = c^2 e_x + s^2 e_theta +
    c s gamma`` (``c, s = cos, sin alpha``), so ``A = t (Q + E_f v v^T)``, ``v = (c^2, s^2, c s)``: the fibre's
    ``E_f c^4, E_f c^2 s^2, E_f c^3 s, E_f s^4, E_f c s^3`` terms; ``Q = E/(1 - nu^2) [[1, nu, 0], [nu, 1, 0],
    [0, 0, (1 - nu)/2]]`` (plane stress), ``t = 2h``. A closed-end tube: ``N = (p a/2, p a, 0)`` (lids, no torque).
    Solve ``A eps = N``: the twist rate ``chi_s = gamma / a``. At p = 1 Pa the strains are ~1e-4 (small strain)."""
    c, s = math.cos(ALPHA), math.sin(ALPHA)
    Q = E / (1 - NU**2) * np.array([[1, NU, 0], [NU, 1, 0], [0, 0, (1 - NU) / 2]])
    v = np.array([c * c, s * s, c * s])
    t = 2 * H
    ex, eth, gamma = np.linalg.solve(t * (Q + E_F * np.outer(v, v)), [P * A / 2, P * A, 0.0])
    axial, hoop, chi_s = _inflated_tube(1)
    assert chi_s == pytest.approx(gamma / A, rel=2e-3)  # measured 1.2e-4 (strain^2 and (h/a)^2 terms)
    assert hoop == pytest.approx(eth, rel=2e-3)
    assert axial == pytest.approx(ex, rel=2e-2)  # e_x is small beside the others (-2.3e-6)
    assert abs(chi_s) > 0.3 * abs(hoop)  # a real coupling: the twist is of the order of the hoop strain


def test_two_balanced_families_do_not_twist():
    """``+alpha`` and ``-alpha``: ``v`` has ``c s`` and ``-c s``, the coupling terms of ``A`` cancel, ``gamma = 0``."""
    _, hoop, chi_s = _inflated_tube(2)
    assert abs(chi_s) < 1e-6 * abs(hoop)


def test_without_fibre_modulus_the_graph_is_todays():
    """``fibre_E = 0``: the other fibre parameters leave the graph as it is (nothing of the fibres in it); the
    default scene's RHS serialises to the same bytes as before the fibres existed (checked against main once by
    hand, the hashes of three scenes equal); ``fibre_E > 0`` changes it."""
    def digest(scene):
        return hashlib.sha256(ShellSystem(scene, 6).rhs.serialize().encode()).hexdigest()

    base = TwistedCylinder()
    with pytest.warns(MaterialWarning, match="fibre_angle = 0.7, fibre_families = 2 is unused: fibre_E = 0"):
        ds = mol_shell.simulate(TwistedCylinder(fibre_angle=0.7, fibre_families=2), "leapfrog", n=6,
                                times=[0.0, 1e-4], progress=False)
    assert "is unused: fibre_E = 0" in ds.attrs["material_warning"]
    assert digest(TwistedCylinder(fibre_angle=0.7, fibre_families=2, fibre_compression=False)) == digest(base)
    assert digest(TwistedCylinder(fibre_E=1e5, fibre_angle=0.7)) != digest(base)
    assert unused_fibres_warning(base) is None


def test_energy_conserved_and_balanced_with_fibres():
    """Elastic (one helical family on SVK in plane stress): leap-frog keeps the energy to O(dt^2) (measured 9.9e-10
    relative) while the breathing sphere twists (chi moves: the coupling); viscous, tension-only fibres on
    incompressible neo-Hookean under pressure: ``E(t) - E(0) = work - dissipated`` (measured 7e-11)."""
    sc = Sphere(h=0.01, material="svk-plane-stress", nu=0.3, fibre_E=5e6, fibre_angle=0.6, R=1.05)
    ds = mol_shell.simulate(sc, "leapfrog", n=10, times=np.linspace(0, 0.02, 5), progress=False)
    energy = ds.energy.values
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-7
    assert np.ptp(ds.chi.values[:, 5]) > 1e-3
    assert "included" in ds.attrs["stresses"]  # with the fibres' stress (tests/results/test_law_stresses.py)
    sc = Sphere(h=0.01, material="neo-hookean-incompressible", fibre_E=5e6, fibre_angle=0.6, fibre_compression=False,
                eta_mu=50.0, pressure=1000.0, R=1.1)
    ds = mol_shell.simulate(sc, "dop853-c", n=10, times=np.linspace(0, 0.02, 5), rtol=1e-10, atol=1e-12,
                            progress=False)
    assert ds.attrs["energy_balance_error"] < 1e-7
    assert float(ds.dissipated.values[-1]) > 1e-3 * abs(float(ds.energy.values[0]))


@pytest.mark.parametrize("setting, line", [
    ("fibre_families=3", "fibre_families = 3 is outside {1, 2}"),
    ("fibre_E=-1", "fibre_E = -1.0 is outside 0 or [2.2250738585072014e-308, inf) Pa"),
    ("fibre_compression=maybe", "fibre_compression = 'maybe' is outside {true, false}"),
    ("fibre_compression=0", "fibre_compression = '0' is outside {true, false}"),  # as typed (it showed 0.0)
    ("fibre_compression=1", "fibre_compression = '1' is outside {true, false}"),
])
def test_bad_fibre_input_is_one_line_exit_2(capsys, tmp_path, setting, line):
    assert main(["run", "sphere", "--set", setting, "--n", "6", "--t-end", "1e-4", "-o", str(tmp_path / "unused.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and line in err[0], err
    name, value = setting.split("=")
    with pytest.raises(ParameterError, match=name):
        mol_shell.scenes.with_params(Sphere(), {name: value})


def test_scene_file_takes_the_fibres_in_material(tmp_path):
    from mol_shell.scenes.files import load_scene

    good = tmp_path / "wound.toml"
    good.write_text('scene = "cone"\n[geometry]\nr2 = 1.0\n[material]\nfibre_E = 2e7\nfibre_angle = 0.9\n'
                    'fibre_families = 2\nfibre_compression = false\n')
    scene = load_scene(good)
    assert (scene.fibre_E, scene.fibre_angle, scene.fibre_families, scene.fibre_compression) == (2e7, 0.9, 2, False)
    bad = tmp_path / "bad.toml"
    bad.write_text('scene = "cone"\n[material]\nfibre_families = 3\n')
    with pytest.raises(ParameterError, match=r"bad.toml: \[material\] fibre_families = 3 is outside \{1, 2\}"):
        load_scene(bad)


@pytest.mark.parametrize("table", ["material", "layer"])
@pytest.mark.parametrize("value", ["0", "1", '"false"'])
def test_a_scene_files_flag_is_a_toml_boolean_as_on_the_command_line(capsys, tmp_path, table, value):
    """One rule for true/false keys: a TOML boolean in a scene file, the words true/false on the command line. An
    integer 0 was accepted as false in [material] (the command line refuses it); in [[layer]] tables even true was
    refused. Refused in one line naming the file, the table and the key, with the value as written."""
    layer = '[[layer]]\nthickness = 0.02\nmaterial = "svk-plane-stress"\nfibre_E = 1e6\n'
    head = 'scene = "sphere"\n[material]\nh = 0.01\nfibre_E = 1e6\n'
    body = (head + f"fibre_compression = {value}\n") if table == "material" else (
        head + layer + f"fibre_compression = {value}\n")
    path = tmp_path / "flag.toml"
    path.write_text(body + "[run]\nn = 6\nt_end = 1e-4\n")
    assert main(["run", str(path), "-o", str(tmp_path / "unused.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    shown = {"0": "0", "1": "1", '"false"': "'false'"}[value]
    where = "[material]" if table == "material" else "[[layer]] 1 (from the lower face):"
    assert len(err) == 1 and f"flag.toml: {where} fibre_compression = {shown} is not a TOML boolean; allowed: " \
        "{true, false}" in err[0], err


@pytest.mark.parametrize(("angle", "same"), [(45.0, 45.0 - 14 * math.pi), (2.0, 2.0 - math.pi), (-1.6, -1.6 + math.pi)])
def test_a_fibre_angle_outside_minus_to_plus_half_pi_is_refused_with_what_it_may_mean(angle, same):
    """``fibre_angle = 45`` ran as 45 rad (the vessel's segments take degrees, so the slip is easy). Angles from the
    meridian cover every fibre direction in [-pi/2, pi/2] (alpha and alpha + pi are one fibre); beyond, refused
    with the same fibre in range and, for at most 90, the angle read as degrees."""
    with pytest.raises(mol_shell.ParameterError, match=r"^fibre_angle = .* is outside \[-pi/2, pi/2\] rad \(in rad: "
                       rf"the same fibre is {same:.6g} rad"):
        mol_shell.TwistedCylinder(fibre_E=1e7, fibre_angle=angle)
    for edge in (-math.pi / 2, math.pi / 2, 0.7, 1.5708, -1.571):  # pi/2 as typed is the hoop direction
        assert mol_shell.TwistedCylinder(fibre_E=1e7, fibre_angle=edge).fibre_angle == edge
