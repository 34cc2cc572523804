"""Stresses of the laws beyond SVK and of fibres (mol_shell.results.law_stresses): each shell stress resultant
against a central finite difference of the integrated energy (the model's own energy route,
``mol_shell.model.laws.scene_shell_energy``, not the stress code), and a balloon against membrane theory."""

import math
import os
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.model.hyperelastic import law_shell_dissipation
from mol_shell.model.kinematics import deformation_gradient
from mol_shell.model.laws import scene_shell_energy
from mol_shell.model.material import Thickness, effective_lame
from mol_shell.results.law_stresses import law_of_attrs, route_stress
from mol_shell.results.stresses import PARAMETERS, RESULTANT_META, add_stresses, kernel, route_elastic, sample_stresses
from mol_shell.scenes import Sphere

H = 0.01
#: a general sample with psi = 0 at the sample (psi_s is not 0): z_s, r_s, chi_s, theta_s, psi_s, r, theta, psi
STRAINS = (1.15, 0.05, 0.12, 0.08, 0.03, 1.25, 0.3, 0.0)
REF = (0.9, 0.25, 0.2, 1.01, 0.02)  # r0, theta0, theta0_s, beta1_0, beta2_0: a curved reference
CASES = {
    "neo-hookean": dict(material="neo-hookean", nu=0.3),
    "neo-hookean-log": dict(material="neo-hookean-log", nu=0.3),
    "neo-hookean-incompressible": dict(material="neo-hookean-incompressible"),
    "mooney-rivlin": dict(material="mooney-rivlin", c10=1.5e5, c01=4e4),
    "svk-plane-stress+fibres": dict(material="svk-plane-stress", nu=0.3, fibre_E=5e6, fibre_angle=0.6),
    "svk+2 fibre families": dict(material="svk", nu=0.3, fibre_E=5e6, fibre_angle=0.6, fibre_families=2),
    "mooney-rivlin+tension-only fibres": dict(material="mooney-rivlin", c01=4e4, fibre_E=5e6, fibre_angle=1.1,
                                              fibre_compression=False),
    "layers: rubber under SVK with fibres": dict(material="svk-plane-stress", nu=0.3, layers=(
        "0.012 neo-hookean-incompressible; 0.008 svk-plane-stress fibre_E=5e6 fibre_angle=0.6")),
    "layers: tension-only fibres in a layer": dict(material="svk-plane-stress", nu=0.3, layers=(
        "0.012 neo-hookean-incompressible fibre_E=5e6 fibre_angle=1.1 fibre_compression=false; "
        "0.008 svk-plane-stress fibre_E=5e6 fibre_angle=0.6 fibre_compression=true")),
}


def _scene(case):
    return Sphere(h=H, E=1e6, zeta1=-H, **CASES[case])  # the wall [-H, H] about the base surface, as below


def _resultants(scene):
    elastic, layers, _ = route_elastic(law_of_attrs(scene.params()), -H)
    out = sample_stresses([ca.SX(x) for x in STRAINS], None, [ca.SX(x) for x in REF], -H, H, 4, 0.0, 0.0,
                          elastic=elastic, layers=layers)
    return {k: float(v) for k, v in out["elastic"].items()}


def _energy_gradient(scene, step=1e-4):
    e = ca.SX.sym("e", 8)
    r0, theta0, theta0_s, beta1_0, beta2_0 = REF
    W = scene_shell_energy(scene, ca.vertsplit(e), Thickness(-H, H, 4), r0, theta0, theta0_s, beta1_0, beta2_0)
    f = ca.Function("W", [e], [W])
    grad = []
    for k in range(8):
        d = np.zeros(8)
        d[k] = step
        grad.append((float(f(np.add(STRAINS, d))) - float(f(np.subtract(STRAINS, d)))) / (2 * step))
    return grad


@pytest.mark.parametrize("case", list(CASES))
def test_resultants_are_finite_differences_of_the_integrated_energy(case):
    """With ``psi = 0`` at the sample (``c1 = b1``, ``d = b2``, ``c3 = b3``) the virtual work of the resultants
    (``mol_shell.results.stresses``: ``r0 n^s = int T e1 c``, ``r0 m^s = d x int zeta T e1 c``, ``n^phi = int T e3
    a``) against the strains' variations gives, ``W`` the energy per unit reference area, ``N, Q, Ns, Nh, Mb, Mt``
    the membrane, transverse shear, membrane shear and hoop forces, the meridional bending and twisting moments:

        dW/dz_s = cos(theta) N - sin(theta) Q,    dW/dr_s = sin(theta) N + cos(theta) Q,
        dW/dchi_s = r Ns + cos(theta) Mt,         dW/dtheta_s = Mb,   dW/dpsi_s = Mt,   dW/dr = chi_s Ns + Nh / r0,

    and ``axial_force = 2 pi r0 dW/dz_s``, ``axial_torque = 2 pi r0 dW/dchi_s``. Central differences with step 1e-4 (round-off ~1e-15 W / step, truncation ~step^2):
    agreement to 1e-6 relative of each quantity's scale (the hoop bending moment: the closed form below)."""
    _check_virtual_work(_energy_gradient(_scene(case)), _resultants(_scene(case)))


def _check_virtual_work(g, R):
    """The relations of :func:`test_resultants_are_finite_differences_of_the_integrated_energy` between the
    resultants ``R`` and the gradient ``g`` of the energy (or of the Rayleigh function in the rates)."""
    _, _, chi_s, _, _, r, theta, _ = STRAINS
    r0 = REF[0]
    c, s = math.cos(theta), math.sin(theta)
    N, Q, Ns, Nh = (R[k] for k in ("membrane_force_meridional", "transverse_shear_force", "membrane_shear_force",
                                   "membrane_force_hoop"))
    Mb, Mt = R["bending_moment_meridional"], R["twisting_moment"]
    pairs = [(g[0], c * N - s * Q), (g[1], s * N + c * Q), (g[2], r * Ns + c * Mt), (g[3], Mb), (g[4], Mt),
             (g[5], chi_s * Ns + Nh / r0), (2 * math.pi * r0 * g[0], R["axial_force"]),
             (2 * math.pi * r0 * g[2], R["axial_torque"])]
    forces = max(abs(x) for x in (N, Q, Ns, Nh))
    for k, (fd, got) in enumerate(pairs):
        scale = forces * (2 * math.pi * r0 if k >= 6 else 1.0) if k not in (3, 4) else max(abs(Mb), abs(Mt))
        assert got == pytest.approx(fd, abs=1e-6 * scale), (k, fd, got)
    assert abs(Mt) > 1e-3 * abs(Mb) and abs(Q) > 1e-3 * forces and abs(Ns) > 1e-2 * forces  # nothing trivial


def test_incompressible_viscous_stress_is_the_rayleigh_functions_derivative():
    """Kelvin-Voigt viscosity of an incompressible law (``eta_mu = 1000``, ``eta_lambda = 2000`` Pa s, which it cannot
    feel) through the run's stress kernel, at a general sample with made-up rates:

    - at each face ``S_v = J F_l^-1 sigma_v F_l^-T`` (``F_l`` the kinematic ``F`` with its director column times the
      thickness stretch ``sqrt(C_22)``, ``det C = 1``) has ``S_v,22 = 0`` and the stress power ``S_v : E_t = 2 D``,
      ``D = eta_mu E_t : E_t`` per unit volume with the thickness rate ``det C = 1`` sets: ``E(t)`` of the strains
      ``e + t e_t`` computed here in NumPy (``C_22 = (1 - N)/M``), ``E_t`` by central differences (step 1e-6: 1e-7
      relative allowed);
    - the viscous resultants are the rates' derivatives of the integrated Rayleigh function
      (:func:`~mol_shell.model.hyperelastic.law_shell_dissipation`, the kernels' route), as the elastic ones are the
      strains' derivatives of the energy (the same relations, 1e-6 of the scale).

    The code before condensed the pair as for plane stress: a power ``lambda* (tr E_t)^2 + 2 eta_mu E_t : E_t`` with
    the kinematic ``E_t`` (``E_t,22 = 0``)."""
    eta_mu, rates = 1000.0, (0.3, -0.2, 0.5, 0.4, -0.6, 0.25, 0.1, 0.2)
    scene = Sphere(h=H, E=1e6, zeta1=-H, material="neo-hookean-incompressible", eta_mu=eta_mu, eta_lambda=2000.0)
    assert PARAMETERS == ("zeta1", "h", "lam", "mu", "eta_lambda", "eta_mu", "plane_stress", "traction_inner",
                          "traction_outer")
    par = [-H, H, 0.0, 0.0, scene.eta_lambda, eta_mu, 1.0, 0.0, 0.0]
    out = kernel(4, True, law_of_attrs(scene.params()))(e=STRAINS, e_t=rates, ref=REF, par=par)
    sigma = np.array(out["sigma_viscous"]).ravel()

    def strain(e, zeta, incompressible):
        F = np.array(deformation_gradient(tuple(e), zeta, *REF), dtype=float)
        C = F.T @ F
        if incompressible:
            m = C[0, 0] * C[2, 2] - C[0, 2] ** 2
            C[1, 1] = 0.0
            C[1, 1] = (1.0 - np.linalg.det(C)) / m
        return F, C, (C - np.eye(3)) / 2

    step = 1e-6
    for face, zeta in enumerate((-H, H)):
        F, C, _ = strain(STRAINS, zeta, True)
        F_l = F.copy()
        F_l[:, 1] *= math.sqrt(C[1, 1])
        sig = np.empty((3, 3))
        for c, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
            sig[i, j] = sig[j, i] = sigma[6 * face + c]
        inverse = np.linalg.inv(F_l)
        S = np.linalg.det(F_l) * inverse @ sig @ inverse.T
        rate = {kind: (strain(np.add(STRAINS, step * np.array(rates)), zeta, kind)[2]
                       - strain(np.subtract(STRAINS, step * np.array(rates)), zeta, kind)[2]) / (2 * step)
                for kind in (False, True)}
        assert abs(S[1, 1]) < 1e-12 * np.abs(S).max()
        assert np.sum(S * rate[False]) == pytest.approx(2 * eta_mu * np.sum(rate[True] ** 2), rel=1e-7), face
    e, et = ca.SX.sym("e", 8), ca.SX.sym("et", 8)
    D = law_shell_dissipation(ca.vertsplit(e), ca.vertsplit(et), eta_mu, Thickness(-H, H, 4), *REF)
    g = np.array(ca.Function("g", [e, et], [ca.gradient(D, et)])(STRAINS, rates)).ravel()
    R = dict(zip(RESULTANT_META, np.array(out["resultants_viscous"]).ravel()))
    _check_virtual_work(g, R)


def test_generic_route_with_the_svk_energy_is_svks_kernel():
    """The automatic-differentiation route given the SVK energy (fibres of modulus 1e-300, so the route is taken)
    reproduces SVK's own stress kernel to round-off, resultants and face stresses, director and plane stress."""
    for material in ("svk", "svk-plane-stress"):
        scene = Sphere(h=H, nu=0.3, material=material, fibre_E=1e-300)
        got = sample_stresses([ca.SX(x) for x in STRAINS], None, [ca.SX(x) for x in REF], -H, H, 4, 0.0, 0.0,
                              elastic=route_stress(law_of_attrs(scene.params())))
        lam, mu = effective_lame(scene.E, scene.nu, material)
        ref = sample_stresses([ca.SX(x) for x in STRAINS], None, [ca.SX(x) for x in REF], -H, H, 4, lam, mu,
                              plane_stress=material == "svk-plane-stress")
        for k in RESULTANT_META:
            assert float(got["elastic"][k]) == pytest.approx(float(ref["elastic"][k]), rel=1e-11, abs=1e-9), k
        for face in range(2):
            a = np.array([[float(x) for x in row] for row in got["sigma_elastic"][face]])
            b = np.array([[float(x) for x in row] for row in ref["sigma_elastic"][face]])
            np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-11 * np.abs(b).max())


def test_inflated_rubber_sphere_stresses_are_membrane_theorys():
    """An incompressible neo-Hookean sphere (``a = 1``, ``h/a = 0.01``) dilated uniformly to ``lam = 1.2``: membrane
    theory gives the nominal membrane force per unit reference length ``2 h mu (lam - lam^-5)`` in both tangent
    directions and the Cauchy stress ``mu (lam^2 - lam^-4)``, zero through the thickness (von Mises = that stress;
    the thickness stretch ``lam^-2`` is in ``F``). At the equator of the exact sphere (its strains at one sample)
    to the shell's thickness corrections, O((h/a)^2) (measured 1.2e-4 and -5.7e-5; allowed 3e-4). In a run on
    12 nodes the hoop force is per unit of the discrete meridian, whose cell length is the chord: the same times
    ``beta1_0 = sin(ds/2)/(ds/2)`` (allowed 3e-4); the face stresses 1e-3."""
    scene = Sphere(h=H, material="neo-hookean-incompressible", R=1.2)
    mu, lam = scene.E / 3, 1.2
    membrane, sigma = 2 * H * mu * (lam - lam**-5), mu * (lam**2 - lam**-4)
    exact = sample_stresses([ca.SX(x) for x in (lam, 0, 0, 1.0, 0, lam, 0, 0)], None,
                            [ca.SX(x) for x in (1.0, 0.0, 1.0, 1.0, 0.0)], scene.zeta1_used(), H, 4, 0.0, 0.0,
                            elastic=route_stress(law_of_attrs(scene.params())))["elastic"]
    assert float(exact["membrane_force_hoop"]) == pytest.approx(membrane, rel=3e-4)
    assert float(exact["membrane_force_meridional"]) == pytest.approx(membrane, rel=3e-4)
    ds = mol_shell.simulate(scene, "leapfrog", n=12, times=[0.0, 1e-5], progress=False)
    assert "included" in ds.attrs["stresses"]
    mid, cell = ds.sizes["s_cell"] // 2, math.pi / 11
    assert float(ds.membrane_force_hoop[0, mid]) == pytest.approx(membrane * math.sin(cell / 2) / (cell / 2), rel=3e-4)
    assert float(ds.von_mises_stress[0, mid].mean()) == pytest.approx(sigma, rel=1e-3)
    assert float(ds.principal_stress_max[0, mid].mean()) == pytest.approx(sigma, rel=1e-3)
    assert float(ds.principal_stress_min[0, mid].mean()) == pytest.approx(0.0, abs=1e-3 * sigma)


@pytest.mark.parametrize("case", ["svk-plane-stress", "neo-hookean-incompressible"])
def test_hoop_bending_moment_of_a_dilated_cylinder_is_the_closed_forms_integral(case):
    """A cylinder (``a = 1``, wall ``[-h, h]``, ``h = 0.05``) dilated to ``r = 1.2 a`` with the meridian unstretched
    and no twist: at depth ``zeta`` the hoop stretch is ``l(zeta) = (r + zeta)/(a + zeta)`` and the meridional one 1.
    The hoop resultants are ``n^phi = int T33 dzeta`` and ``m^phi . c1 = int zeta T33 dzeta`` with the first
    Piola-Kirchhoff hoop stress ``T33`` of the law in that uniaxial-strain state in closed form: plane-stress SVK
    ``T33 = l E/(1 - nu^2) (l^2 - 1)/2``; incompressible neo-Hookean (thickness stretch ``1/l``, ``S22 = 0``)
    ``T33 = mu (l - 1/l^3)``. Integrated here by scipy's adaptive quadrature; the model's Gauss rule (4 points)
    agrees to 1e-9 relative (the only resultant the energy's finite differences above do not reach)."""
    from scipy.integrate import quad

    h, a, r, E, nu = 0.05, 1.0, 1.2, 1e6, 0.3
    strains = [ca.SX(x) for x in (1.0, 0.0, 0.0, 0.0, 0.0, r, 0.0, 0.0)]
    ref = [ca.SX(x) for x in (a, 0.0, 0.0, 1.0, 0.0)]
    if case == "svk-plane-stress":
        lam, mu = effective_lame(E, nu, "svk-plane-stress")
        out = sample_stresses(strains, None, ref, -h, h, 4, lam, mu, plane_stress=True)

        def t33(stretch):
            return stretch * E / (1 - nu**2) * (stretch**2 - 1) / 2
    else:
        scene = Sphere(h=h, E=E, zeta1=-h, material=case)
        elastic, _, _ = route_elastic(law_of_attrs(scene.params()), -h)
        out = sample_stresses(strains, None, ref, -h, h, 4, 0.0, 0.0, elastic=elastic)

        def t33(stretch):
            return E / 3 * (stretch - stretch**-3)

    def hoop(zeta):
        return t33((r + zeta) / (a + zeta))

    got = {k: float(v) for k, v in out["elastic"].items()}
    force = quad(hoop, -h, h, epsabs=0, epsrel=1e-12)[0]
    moment = quad(lambda zeta: zeta * hoop(zeta), -h, h, epsabs=0, epsrel=1e-12)[0]
    assert got["membrane_force_hoop"] == pytest.approx(force, rel=1e-9)
    assert got["bending_moment_hoop"] == pytest.approx(moment, rel=1e-9)
    assert moment < -1e-3 * h * force  # the inner fibres stretch more: a moment that is not round-off


def _dilated_meridional_force(R, layer):
    """The meridional membrane force at t = 0 of the unit sphere dilated to radius R, its wall one layer ``layer``."""
    scene = Sphere(h=0.01, R=R, layers=f"0.02 svk-plane-stress nu=0.3 {layer}")
    ds = mol_shell.simulate(scene, n=8, times=[0.0, 1e-6], stresses=True)
    return ds["membrane_force_meridional"].values[0]


def test_tension_only_fibres_of_a_layer_carry_tension_and_no_compression():
    """A layer's fibre_compression=false reached the stresses as the text 'false', which they could not read (the run
    was lost). Fibres along the meridian of a uniformly dilated sphere are stretched everywhere through the wall
    for R > 1 and shortened everywhere for R < 1: tension-only fibres then give the stresses of fibres that carry
    compression, and of no fibres, respectively (and these differ)."""
    fibres = "fibre_E=5e6 fibre_angle=0"
    for R, same, other in ((1.05, f"{fibres} fibre_compression=true", ""),
                           (0.95, "", f"{fibres} fibre_compression=true")):
        tension_only = _dilated_meridional_force(R, f"{fibres} fibre_compression=false")
        np.testing.assert_allclose(tension_only, _dilated_meridional_force(R, same), rtol=1e-12, atol=0)
        assert np.all(np.abs(tension_only - _dilated_meridional_force(R, other)) > 1e-3 * np.abs(tension_only))


def test_a_file_written_before_layers_were_stored_canonically_is_read():
    """Files of the development code before December 6 hold a layer's flag and count as typed (1/0, 2.0)."""
    from mol_shell.results.law_stresses import law_of_attrs

    attrs = {"material": "svk-plane-stress", "E": 1e6, "nu": 0.3, "h": 0.01,
             "layers": "0.02 svk-plane-stress fibre_compression=0 fibre_families=2.0 fibre_E=1e6"}
    (_, ((_, route),), _) = law_of_attrs(attrs)
    fibres = route[2]
    assert fibres.families == 2 and fibres.compression is False


@pytest.mark.parametrize("version", ["0.5.0", "0.6.0.dev0"])
def test_a_neo_hookean_file_of_a_version_before_the_rename_gets_the_law_it_ran(version):
    """Until 0.6.0.dev1 ``neo-hookean`` was the ``(ln J)^2`` law (now ``neo-hookean-log``): a file of those versions
    gets that law's stresses, which it ran with (3.4 % off in the membrane forces with the other law), also for
    a layer; a file of this version keeps ``neo-hookean``."""
    ds = mol_shell.simulate(Sphere(h=0.01, material="neo-hookean-log", nu=0.3, R=1.2), "leapfrog", n=8,
                            times=[0.0, 1e-4], progress=False)
    old = ds.drop_vars([v for v in ds.data_vars if "s_cell" in ds[v].dims]).assign_attrs(
        material="neo-hookean", mol_shell_version=version)
    again = add_stresses(old)
    np.testing.assert_allclose(again.membrane_force_hoop.values, ds.membrane_force_hoop.values, rtol=1e-12)
    assert law_of_attrs({**old.attrs, "mol_shell_version": mol_shell.__version__})[0] == "neo-hookean"
    layered = {**old.attrs, "material": "svk", "layers": "0.02 neo-hookean"}
    assert law_of_attrs(layered)[1][0][1][0] == "neo-hookean-log"
    assert law_of_attrs({**layered, "mol_shell_version": mol_shell.__version__})[1][0][1][0] == "neo-hookean"


def test_a_law_this_process_cannot_import_is_said_so_not_called_unknown(tmp_path, monkeypatch):
    """A run of `material = MODULE:NAME` read where MODULE cannot be imported (another folder, another session): its
    stresses were skipped as "not computed for material = ... (the built-in laws only)", silently, and with
    limit=None refused as a law that is not built in. Both now say that the law cannot be loaded here, and why."""
    import subprocess
    import sys
    import textwrap

    (tmp_path / "gone_laws.py").write_text(
        "import casadi as ca\nimport mol_shell\n"
        "rubber = mol_shell.Material('gone-rubber', energy=lambda C, p: p['mu'] / 2 * (ca.trace(C) - 3) "
        "- p['mu'] * ca.log(ca.sqrt(ca.det(C))) + p['lam'] / 2 * ca.log(ca.sqrt(ca.det(C))) ** 2, "
        "parameters={'mu': 3e5, 'lam': 1e6})\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    ds = mol_shell.simulate(mol_shell.Sphere(material="gone_laws:rubber", R=1.1, h=0.01), n=8, t_end=1e-3,
                            stresses=False, progress=False)
    mol_shell.write_netcdf(ds, tmp_path / "run.nc")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    script = textwrap.dedent("""
        import warnings, mol_shell
        ds = mol_shell.read_netcdf("../run.nc")
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            print(mol_shell.add_stresses(ds).attrs["stresses"])
        print(*[str(w.message) for w in said], sep="\\n")
        try:
            mol_shell.add_stresses(ds, limit=None)
        except mol_shell.ParameterError as exc:
            print("refused:", exc)
    """)
    root = str(Path(mol_shell.__file__).parents[1])
    done = subprocess.run([sys.executable, "-c", script], cwd=elsewhere, capture_output=True, text=True, timeout=120,
                          check=False, env={**os.environ, "PYTHONPATH": root})
    lines = done.stdout.splitlines()
    assert done.returncode == 0 and len(lines) == 3, done.stderr
    assert lines[0].startswith("skipped: material = gone_laws:rubber cannot be loaded in this process") and \
        "No module named 'gone_laws'" in lines[0], lines[0]
    assert lines[1].startswith("stresses not computed: material = gone_laws:rubber cannot be loaded"), lines[1]
    assert lines[2].startswith("refused: material = 'gone_laws:rubber' cannot be loaded in this process, and the "
                               "stresses need its energy: ") and "No module named 'gone_laws'" in lines[2], lines[2]
