"""Stresses after a run: resultants against energy derivatives, statics, and the 3-D stress through the thickness.

Every expected value is computed here from :func:`mol_shell.model.material.shell_energy` /
``shell_dissipation`` (CasADi gradients), from a static state found by Newton's method on a
discrete energy assembled in this file, or from the 3-D stress integrated over the deformed
section by a 24-point Gauss rule with Nanson's formula; none of it uses the code under test.
"""

import math

import casadi as ca
import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.model.kinematics import deformation_gradient
from mol_shell.model.material import Thickness, centroidal_offset, effective_lame, lame, shell_dissipation, shell_energy
from mol_shell.results.stresses import RESULTANT_META, RESULTANTS, add_stresses, sample_stresses

EPS = np.finfo(float).eps
FIELDS = ("z", "r", "chi", "theta", "psi")


@pytest.fixture(scope="module")
def twisted():
    """The paper's scene on 8 nodes, saved over 10 us: at t = 0 the uniformly twisted cylinder at ``R``."""
    return mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False, stresses=False)


def run_dataset(Q, V, scene, s):
    """A run-like Dataset of one saved time from nodal fields ``Q`` and rates ``V`` (each ``5 x n``)."""
    data = {}
    for k, name in enumerate(FIELDS):
        data[name] = (("time", "s"), Q[k][None, :])
        data[name + "_t"] = (("time", "s"), V[k][None, :])
    attrs = {k: v for k, v in scene.params().items() if v is not None}
    attrs.update(zeta1_used=centroidal_offset(scene.h))
    return xr.Dataset(data, coords={"time": [0.0], "s": s}, attrs=attrs)


def energy_gradient(strains, scene, rates=None):
    """``dWhat/d(strains)`` (or, with ``rates``, ``dD/d(rates)``) by CasADi, at one sample."""
    lam, mu = effective_lame(scene.E, scene.nu, scene.material)
    thickness = Thickness(centroidal_offset(scene.h), scene.h, scene.n_quad)
    e, et = ca.SX.sym("e", 8), ca.SX.sym("et", 8)
    if rates is None:
        W = shell_energy(ca.vertsplit(e), lam, mu, thickness)
        return np.array(ca.Function("g", [e], [ca.gradient(W, e)])(strains)).ravel()
    eta = (scene.eta_lambda, scene.eta_mu)
    if scene.material == "svk-plane-stress":
        eta = (2 * eta[0] * eta[1] / (eta[0] + 2 * eta[1]), eta[1])
    D = shell_dissipation(ca.vertsplit(e), ca.vertsplit(et), *eta, thickness)
    return np.array(ca.Function("g", [e, et], [ca.gradient(D, et)])(strains, rates)).ravel()


@pytest.mark.parametrize("material", ["svk", "svk-plane-stress"])
def test_torque_and_force_of_the_twisted_cylinder_are_the_energy_derivatives(twisted, material):
    """At t = 0 every cell has ``z_s = 1, chi_s = gamma, r = R``: the axial torque through each section is
    ``2 pi r0 dWhat/dchi_s`` and the axial force ``2 pi r0 dWhat/dz_s`` (r0 = 1), both derivatives of
    ``shell_energy`` by ``casadi.gradient``. The run's strains are nodal differences, so they carry a
    rounding of ~``EPS |chi| / (gamma ds)`` relative; 1e-12 is allowed (the torque is ~2.6 kN m)."""
    ds = twisted.isel(time=[0]).assign_attrs(material=material)
    scene = mol_shell.TwistedCylinder(material=material)
    out = add_stresses(ds)
    grad = energy_gradient([1.0, 0.0, scene.gamma, 0.0, 0.0, float(ds.attrs["R"]), 0.0, 0.0], scene)
    torque, force = 2 * math.pi * grad[2], 2 * math.pi * grad[0]
    np.testing.assert_allclose(out.axial_torque.values, torque, rtol=1e-12)
    np.testing.assert_allclose(out.axial_force.values, force, rtol=1e-12, atol=1e-12 * abs(torque))
    assert torque > 2000 and out.axial_torque.attrs["units"] == "N m" and out.axial_force.attrs["units"] == "N"
    assert out.axial_torque.dims == ("time", "s_cell") and out.von_mises_stress.dims == ("time", "s_cell", "zeta")
    for name in out.data_vars:
        if name not in twisted:
            assert out[name].attrs["units"] and out[name].attrs["long_name"], name


def test_natural_state_has_no_stress():
    """``gamma = 0, R = 1``: the reference state. Its cell samples equal the reference data from the same
    differences, so ``F = I`` up to one rounding of ``x (1/x)`` per entry: ``|S| <= (3 lambda + 2 mu) 2 EPS``,
    and every resultant is below that stress times ``2 pi x 2h`` (measured: 1e-61 N and below)."""
    scene = mol_shell.TwistedCylinder(gamma=0.0, R=1.0)
    ds = mol_shell.simulate(scene, n=8, t_end=1e-5, progress=False, stresses=False)
    out = add_stresses(ds)
    lam, mu = lame(scene.E, scene.nu)
    bound = (3 * lam + 2 * mu) * 2 * EPS
    for name in [*RESULTANTS, "von_mises_stress", "principal_stress_max", "principal_stress_min"]:
        scale = bound * (1 if "stress" in name else 2 * math.pi * 2 * scene.h * 2)
        assert float(abs(out[name].isel(time=0)).max()) <= scale, name


def test_axial_force_is_positive_in_tension():
    """Pull the natural cylinder to ``z_s = 1.01`` (nothing else changed): the part at larger ``s`` pulls
    the part at smaller ``s`` towards larger ``s``, i.e. along ``+k``: positive."""
    scene = mol_shell.TwistedCylinder(gamma=0.0, R=1.0)
    n, s = 6, np.linspace(0, scene.L, 6)
    Q = np.zeros((5, n))
    Q[0], Q[1] = 1.01 * s, 1.0
    out = add_stresses(run_dataset(Q, np.zeros((5, n)), scene, s))
    assert np.all(out.axial_force.values > 0) and np.all(out.membrane_force_meridional.values > 0)
    assert np.all(np.abs(out.axial_torque.values) < 1e-9)


def static_state(scene, n, r_end, twist):
    """Equilibrium of the interior nodes with all five fields held at both ends (``z = s``, ``r = r_end``,
    ``chi = -+twist/2``, ``theta = psi = 0``), by Newton's method on the discrete energy
    ``V = 2 pi sum_cells ds/2 [What(sample at psi_i) + What(sample at psi_{i+1})]`` assembled here."""
    lam, mu = effective_lame(scene.E, scene.nu, scene.material)
    thickness = Thickness(centroidal_offset(scene.h), scene.h, scene.n_quad)
    s = np.linspace(0.0, scene.L, n)
    ds = scene.L / (n - 1)
    x = ca.SX.sym("x", 5, n - 2)
    ends = [ca.DM([s[j], r_end, twist * (j / (n - 1) - 0.5), 0, 0]) for j in (0, n - 1)]
    Q = ca.horzcat(ends[0], x, ends[1])
    V = 0
    for i in range(n - 1):
        ql, qr = Q[:, i], Q[:, i + 1]
        grad, mid = (qr - ql) / ds, (qr + ql) / 2
        for psi in (ql[4], qr[4]):
            e = [grad[0], grad[1], grad[2], grad[3], grad[4], mid[1], mid[3], psi]
            V += 2 * math.pi * ds / 2 * shell_energy(e, lam, mu, thickness)
    g = ca.gradient(V, ca.vec(x))
    newton = ca.Function("newton", [ca.vec(x)], [g, ca.jacobian(g, ca.vec(x))])
    X0 = np.zeros((5, n - 2))
    X0[0], X0[1], X0[2] = s[1:-1], r_end, twist * (s[1:-1] / scene.L - 0.5)
    y = X0.T.ravel()  # vec is column-major: node by node
    for _ in range(30):
        res, jac = newton(y)
        step = np.linalg.solve(np.array(jac), np.array(res).ravel())
        y = y - step
        if np.abs(step).max() < 1e-15:
            break
    res = np.array(newton(y)[0]).ravel()
    Qn = np.array(ca.Function("Q", [ca.vec(x)], [Q])(y))
    return Qn, s, np.abs(res).max()


def test_torque_and_force_are_the_same_through_every_section_of_a_static_state():
    """A static state that is not uniform (``r`` held at 1.01 m at the twisted ends, ``R`` = 0.995 m inside):
    ``V`` depends on ``chi`` and ``z`` only through differences, so interior equilibrium says that the
    torque and the axial force are equal in neighbouring cells. Allowed: the Newton residual (the nodal
    force imbalance, ~1e-10 N) plus round-off of the torque (1e-12 relative)."""
    scene = mol_shell.TwistedCylinder()
    Q, s, residual = static_state(scene, 9, 1.01, scene.gamma * scene.L)
    assert residual < 1e-8
    out = add_stresses(run_dataset(Q, np.zeros_like(Q), scene, s))
    torque, force = out.axial_torque.values[0], out.axial_force.values[0]
    assert np.ptp(Q[1]) > 5e-3 and np.ptp(out.membrane_force_hoop.values) > 1.0  # really not uniform
    assert np.ptp(torque) <= 2 * residual + 1e-12 * abs(torque).max(), torque
    assert np.ptp(force) <= 2 * residual + 1e-12 * abs(torque).max(), force
    assert abs(torque).min() > 2000


def traction_integrals(strains, ref, scene, lam, mu):
    """The resultants from the 3-D Cauchy stress integrated over the deformed sections (24 Gauss points:
    exact to round-off for these smooth integrands over the width ``2h``; the package uses 4).

    Cauchy ``sigma = F S F^T / J`` with this file's St Venant-Kirchhoff law (at the faces of a plane-stress wall
    with the director column of ``F`` times the thickness stretch ``sqrt(1 + 2 E_22)``, ``E_22`` from the 3-D law's
    ``S_22 = 0``: the wall's thinning; the director's length is 1 in the kinematics); the force on a section element
    is ``sigma n da = J sigma F^-T N dA`` (Nanson) with the reference normals ``N = b0_1`` (the ``s``-section,
    ``dA = (r0 + zeta cos theta0) dzeta dphi``) and ``N = b0_3`` (the ``phi``-section,
    ``dA = (beta1_0 - zeta theta0_s) dzeta ds``); moments about the axis and about the base surface point.
    Components in the deformed ``b`` basis: ``k = (cos th, -sin th, 0)``, ``a2 = (sin th, cos th, 0)``,
    ``a3 = (0, 0, 1)``, ``d = (0, cos psi, sin psi)``, ``c1 = (1, 0, 0)``, ``c3 = c1 x d``.
    """
    r, th, psi = strains[5], strains[6], strains[7]
    r0, th0, th0_s, b10, b20 = ref
    k, a2, a3 = np.array([math.cos(th), -math.sin(th), 0]), np.array([math.sin(th), math.cos(th), 0]), np.array([0, 0, 1.0])
    d, c1 = np.array([0, math.cos(psi), math.sin(psi)]), np.array([1.0, 0, 0])
    c3 = np.cross(c1, d)

    def traction(zeta, column):
        F = np.array(deformation_gradient(strains, zeta, r0, th0, th0_s, b10, b20), dtype=float)
        E = 0.5 * (F.T @ F - np.eye(3))
        S = lam * np.trace(E) * np.eye(3) + 2 * mu * E
        if scene.material == "svk-plane-stress":
            S[1, 1] = 0.0
        J = np.linalg.det(F)
        sigma = F @ S @ F.T / J
        return J * sigma @ np.linalg.inv(F).T @ np.eye(3)[column], face_cauchy(F, S)

    def face_cauchy(F, S):  # the true stress: plane stress thins the wall, S_22 = lambda tr E + 2 mu E_22 = 0 in 3-D
        if scene.material == "svk-plane-stress":
            E = 0.5 * (F.T @ F - np.eye(3))
            lam3d, mu3d = lame(scene.E, scene.nu)
            F = F @ np.diag([1.0, math.sqrt(1 - 2 * lam3d / (lam3d + 2 * mu3d) * (E[0, 0] + E[2, 2])), 1.0])
            return F @ S @ F.T / np.linalg.det(F)
        # svk: the held director's reaction (a stress along the director d = F e2) makes the free face's normal
        # stress 0 (normal n along F^-T e2), not the law's lambda tr E
        sigma, d, n = F @ S @ F.T / np.linalg.det(F), F[:, 1], np.linalg.inv(F).T[:, 1]
        return sigma - (n @ sigma @ n) / (n @ d) ** 2 * np.outer(d, d)

    zeta1 = centroidal_offset(scene.h)
    x, w = np.polynomial.legendre.leggauss(24)

    def integral(fn):
        return scene.h * sum(wk * fn(zeta1 + scene.h * (1 + xk)) for xk, wk in zip(x, w))

    c = lambda z: r0 + z * math.cos(th0)  # noqa: E731
    a = lambda z: b10 - z * th0_s  # noqa: E731
    ts = lambda z: traction(z, 0)[0]  # noqa: E731
    tp = lambda z: traction(z, 2)[0]  # noqa: E731
    arm = lambda z: r * a2 + z * d  # noqa: E731  position relative to the axis point at the same height
    return {
        "axial_force": 2 * math.pi * integral(lambda z: ts(z) @ k * c(z)),
        "axial_torque": 2 * math.pi * integral(lambda z: np.cross(arm(z), ts(z)) @ k * c(z)),
        "membrane_force_meridional": integral(lambda z: ts(z) @ c1 * c(z)) / r0,
        "membrane_shear_force": integral(lambda z: ts(z) @ c3 * c(z)) / r0,
        "transverse_shear_force": integral(lambda z: ts(z) @ d * c(z)) / r0,
        "membrane_force_hoop": integral(lambda z: tp(z) @ c3 * a(z)),
        "bending_moment_meridional": integral(lambda z: np.cross(z * d, ts(z)) @ c3 * c(z)) / r0,
        "twisting_moment": integral(lambda z: np.cross(z * d, ts(z)) @ c1 * c(z)) / r0,
        "bending_moment_hoop": integral(lambda z: np.cross(z * d, tp(z)) @ c1 * a(z)),
    }, [traction(z, 0)[1] for z in (zeta1, zeta1 + 2 * scene.h)]


@pytest.mark.parametrize("material", ["svk", "svk-plane-stress"])
def test_resultants_are_the_3d_stress_integrated_through_the_thickness(material):
    """A general sample (every strain non-zero) on a curved reference (``r0 = 0.9``, ``theta0 = 0.3``,
    ``theta0_s = 0.2``, ``beta1_0 = 1.01``, ``beta2_0 = 0.02``): each resultant equals the thickness
    integral of the 3-D traction (``traction_integrals``), and the face stresses equal the Cauchy stress
    there. The package uses 4 Gauss points; the integrands are smooth rational functions of ``zeta`` over
    a width ``2h = 0.0126`` m, so that rule is exact to ~(h/r0)^8: 1e-10 relative is allowed, with an
    absolute floor of 1e-10 of the largest resultant of its units (the moments are differences of
    nearly cancelling halves: measured 1e-13 .. 2e-12 relative, the forces 1e-16 .. 2e-15)."""
    scene = mol_shell.TwistedCylinder(material=material)
    lam, mu = effective_lame(scene.E, scene.nu, material)
    strains = (1.02, 0.03, 0.1, 0.05, 0.02, 0.93, 0.34, 0.03)
    ref = (0.9, 0.3, 0.2, 1.01, 0.02)
    out = sample_stresses([ca.SX(x) for x in strains], None, [ca.SX(x) for x in ref], centroidal_offset(scene.h),
                          scene.h, scene.n_quad, lam, mu, plane_stress=material == "svk-plane-stress")
    expected, faces = traction_integrals(strains, ref, scene, lam, mu)
    got = {k: float(v) for k, v in out["elastic"].items()}
    for units in ("N m-1", "N"):
        names = [k for k in got if RESULTANT_META[k][0] == units and k not in ("axial_force",)]
        floor = 1e-10 * max(abs(expected[k]) for k in names)
        for name in names:
            assert got[name] == pytest.approx(expected[name], rel=1e-10, abs=floor), name
    assert got["axial_force"] == pytest.approx(expected["axial_force"], rel=1e-10)
    assert got["axial_torque"] == pytest.approx(expected["axial_torque"], rel=1e-10)
    assert abs(expected["transverse_shear_force"]) > 1 and abs(expected["bending_moment_hoop"]) > 1e-3  # all non-trivial
    for face, sigma in enumerate(faces):
        np.testing.assert_allclose(np.array([[float(x) for x in row] for row in out["sigma_elastic"][face]]), sigma,
                                   rtol=1e-12, atol=1e-12 * np.abs(sigma).max())


def test_viscous_part_is_the_dissipation_derivative_and_is_added():
    """Kelvin-Voigt (eta_mu = 1000, eta_lambda = 2000 Pa s) with made-up smooth rates on the twisted
    cylinder: the viscous axial torque of each cell is the mean over its two samples of
    ``2 pi dD/d(chi_s rate)`` (``shell_dissipation``), the total is elastic + viscous, and an elastic
    run of the same state has no ``*_viscous`` variables. Allowed: 1e-12 relative."""
    scene = mol_shell.TwistedCylinder(eta_mu=1000.0, eta_lambda=2000.0, R=0.995)
    n, s = 7, np.linspace(0, scene.L, 7)
    Q = np.array([s, 0.995 + 0.003 * np.sin(s), scene.gamma * (s - 2), 0.01 * np.sin(s), 0.002 * np.cos(s)])
    Q[3, [0, -1]] = 0.0
    V = np.array([0.01 * np.sin(s), 0.02 * np.cos(s), 0.5 * np.sin(2 * s), 0.1 * np.cos(s), 0.3 * np.sin(3 * s)])
    out = add_stresses(run_dataset(Q, V, scene, s))
    elastic = add_stresses(run_dataset(Q, V, mol_shell.TwistedCylinder(R=0.995), s))
    assert "axial_torque_viscous" not in elastic and "von_mises_stress_viscous" in out
    ds = s[1] - s[0]
    for i in range(n - 1):
        grad, mid, rate, rmid = (Q[:, i + 1] - Q[:, i]) / ds, (Q[:, i + 1] + Q[:, i]) / 2, (V[:, i + 1] - V[:, i]) / ds, (V[:, i + 1] + V[:, i]) / 2
        torque_v = torque_e = 0.0
        for j in (i, i + 1):
            e = [*grad, mid[1], mid[3], Q[4, j]]
            et = [*rate, rmid[1], rmid[3], V[4, j]]
            torque_v += math.pi * energy_gradient(e, scene, et)[2]
            torque_e += math.pi * energy_gradient(e, scene)[2]
        assert float(out.axial_torque_viscous[0, i]) == pytest.approx(torque_v, rel=1e-12)
        assert float(elastic.axial_torque[0, i]) == pytest.approx(torque_e, rel=1e-12)
        assert float(out.axial_torque[0, i]) == pytest.approx(torque_e + torque_v, rel=1e-12)
    assert float(abs(out.axial_torque_viscous).min()) > 1e-3 * float(abs(out.axial_torque).max())


def test_large_runs_are_skipped_with_a_note_and_non_runs_refused(twisted):
    out = add_stresses(twisted, limit=10)
    assert "axial_torque" not in out and out.attrs["stresses"].startswith("skipped: 154 cell samples")
    assert "axial_torque" in add_stresses(twisted, limit=None)
    with pytest.raises(ParameterError, match="is not a mol_shell run"):
        add_stresses(twisted[["r", "chi"]])


def test_run_writes_the_stresses_unless_told_not_to(tmp_path):
    """``mol-shell run`` adds the stresses by default and leaves them out with ``--no-stresses``."""
    from mol_shell.cli.main import main

    base = ["run", "twisted-cylinder", "--n", "8", "--t-end", "1e-5", "-o"]
    assert main([*base, str(tmp_path / "a.nc")]) == 0
    assert main([*base, str(tmp_path / "b.nc"), "--no-stresses"]) == 0
    a, b = mol_shell.read_netcdf(tmp_path / "a.nc"), mol_shell.read_netcdf(tmp_path / "b.nc")
    assert a.axial_torque.dims == ("time", "s_cell") and a.attrs["stresses"].startswith("included")
    assert "axial_torque" not in b and "s_cell" not in b.dims


def sphere_dataset(Q_extra, n=7, a=1.0):
    """A run-like Dataset on a spherical zone ``s in [0.3, 2.8]`` (``r0 = a sin(s/a)``, ``z0 = a cos(s/a)``,
    ``theta0 = pi/2 + s/a``; MODEL_NOTES), carrying the reference meridian as the geometry work will, with
    fields = reference + ``Q_extra`` (a function of ``s`` giving ``5 x n``)."""
    scene = mol_shell.TwistedCylinder()
    s = np.linspace(0.3, 2.8, n)
    ref = np.array([a * np.cos(s / a), a * np.sin(s / a), 0 * s, np.pi / 2 + s / a, 0 * s])
    ds = run_dataset(ref + Q_extra(s), np.zeros((5, n)), scene, s)
    return ds.assign(r0=("s", ref[1]), z0=("s", ref[0]), theta0=("s", ref[3])), scene, s, ref


def test_a_curved_reference_is_stress_free_and_its_torque_is_the_energy_derivative():
    """With ``r0, z0, theta0`` in the run (a spherical zone), the natural state has no stress (to the rounding
    of ``F = I``: NumPy's and C's cosines may differ by an ulp), and a twist ``chi = 0.1 (s - 1.55)`` transmits
    in each cell the mean over its two samples of ``2 pi r0 dWhat/dchi_s`` with the cell's reference data
    from the difference formulas (``theta0, r0`` at the midpoint, ``theta0_s`` and
    ``(beta1_0, beta2_0) = ((dz0 cos + dr0 sin), (-dz0 sin + dr0 cos))(theta0_mid) / ds``), evaluated here
    with ``shell_energy``. Allowed: 1e-12 relative."""
    natural, scene, s, ref = sphere_dataset(lambda s: 0 * s[None, :] * np.ones((5, 1)))
    out = add_stresses(natural)
    lam, mu = lame(scene.E, scene.nu)
    for name in ("axial_force", "axial_torque", "membrane_force_hoop", "von_mises_stress"):
        scale = (3 * lam + 2 * mu) * 8 * EPS * (1 if "stress" in name else 2 * math.pi * 2 * scene.h * 2)
        assert float(abs(out[name]).max()) <= scale, name

    def twist(s):
        extra = np.zeros((5, len(s)))
        extra[2] = 0.1 * (s - 1.55)
        return extra

    twisted, scene, s, ref = sphere_dataset(twist)
    out = add_stresses(twisted)
    lam, mu = effective_lame(scene.E, scene.nu)
    thickness = Thickness(centroidal_offset(scene.h), scene.h, scene.n_quad)
    e, refs = ca.SX.sym("e", 8), ca.SX.sym("ref", 5)
    W = shell_energy(ca.vertsplit(e), lam, mu, thickness, *ca.vertsplit(refs))
    grad = ca.Function("g", [e, refs], [ca.gradient(W, e)])
    Q = np.array([twisted[f].values[0] for f in FIELDS])
    ds = (s[-1] - s[0]) / (len(s) - 1)
    for i in range(len(s) - 1):
        th = (ref[3, i] + ref[3, i + 1]) / 2
        dz0, dr0 = ref[0, i + 1] - ref[0, i], ref[1, i + 1] - ref[1, i]
        cell_ref = [(ref[1, i] + ref[1, i + 1]) / 2, th, (ref[3, i + 1] - ref[3, i]) / ds,
                    (dz0 * math.cos(th) + dr0 * math.sin(th)) / ds, (-dz0 * math.sin(th) + dr0 * math.cos(th)) / ds]
        d, mid = (Q[:, i + 1] - Q[:, i]) / ds, (Q[:, i + 1] + Q[:, i]) / 2
        torque = np.mean([2 * math.pi * cell_ref[0] * float(grad([*d, mid[1], mid[3], Q[4, j]], cell_ref)[2])
                          for j in (i, i + 1)])
        assert float(out.axial_torque[0, i]) == pytest.approx(torque, rel=1e-12)
    assert float(abs(out.axial_torque).min()) > 100


def test_simulate_adds_the_stresses_unless_told_not_to(twisted):
    with_default = mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, progress=False)
    assert "axial_torque" in with_default and "axial_torque" not in twisted
    np.testing.assert_array_equal(with_default.axial_torque, add_stresses(twisted).axial_torque)
    with pytest.raises(ParameterError, match="stresses"):
        mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, t_end=1e-5, stresses="yes")
