"""Reference meridians: geometry, the natural state as an exact equilibrium, the balance laws on curved
meridians, meridians from a table of points, and which states ``modes`` accepts.

Closed forms used here (derived independently of ``mol_shell.model.geometry``): a meridian parametrised by
arc length has ``dz0/ds = cos(theta0)``, ``dr0/ds = sin(theta0)``, ``dtheta0/ds = theta0_s``.

* arc of radius ``a`` about ``(r, z) = (b, 0)`` traced from its lowest point upward, polar angle
  ``alpha = alpha1 + s/a``: ``r0 = b + a sin(alpha)``, ``z0 = -a cos(alpha)``, so ``(dz0, dr0)/ds =
  (sin alpha, cos alpha)``, i.e. ``theta0 = pi/2 - alpha`` and ``theta0_s = -1/a`` (a sphere: ``b = 0``);
* straight generator from ``(r1, 0)`` to ``(r2, H)``: ``theta0 = atan2(r2 - r1, H)``, ``r0 = r1 + s sin(theta0)``,
  ``z0 = s cos(theta0)``, ``theta0_s = 0``.
"""

import math

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.analysis.modes import modes
from mol_shell.discretization.system import ShellSystem
from mol_shell._core.errors import ParameterError
from mol_shell.model.balance import balance_laws, end_fluxes, euler_lagrange, virtual_power_projections
from mol_shell.model.kinematics import kinetic_energy_density
from mol_shell.model.material import Thickness, shell_energy
from mol_shell.scenes import Cone, MeridianShell, Sphere, Torus, TwistedCylinder

EPS = np.finfo(float).eps


def lame(E, nu):
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def sphere_table(count=41):
    """``count`` points of the unit sphere's meridian from the bottom pole to the top one (rows ``r z``)."""
    alpha = np.linspace(0.0, math.pi, count)
    table = np.column_stack([np.sin(alpha), -np.cos(alpha)])
    table[[0, -1], 0] = 0.0  # exactly on the axis
    return table


@pytest.fixture(scope="module")
def sphere_points(tmp_path_factory):
    path = tmp_path_factory.mktemp("meridians") / "sphere.txt"
    np.savetxt(path, sphere_table(), header="r z (m): unit sphere, 41 points")
    return str(path)


def builtin_scenes():
    return {
        "sphere": Sphere(),
        "cap-pinned": Sphere(alpha2=2.0, end2="pinned"),
        "zone-clamped-free": Sphere(alpha1=0.5, alpha2=2.5, end1="clamped", end2="free"),
        "cone": Cone(),
        "cone-free-clamped": Cone(r1=0.5, r2=1.5, H=0.7, end1="free", end2="clamped"),
        "torus": Torus(),
        "torus-free": Torus(end1="free", end2="free"),
        "torus-inner": Torus(a=0.3, b=1.0, alpha1=-2.5, alpha2=-0.5),
        "cylinder": TwistedCylinder(gamma=0.0, R=1.0),
    }


# ---------------------------------------------------------------------------------------
# geometry of the built-in meridians
# ---------------------------------------------------------------------------------------
def expected_geometry(scene, s):
    """``(r0, z0, theta0, theta0_s)`` from the closed forms of the module docstring."""
    if isinstance(scene, (Sphere, Torus)):
        a, b = scene.a, (0.0 if isinstance(scene, Sphere) else scene.b)
        alpha = scene.alpha1 + s / a
        return b + a * np.sin(alpha), -a * np.cos(alpha), math.pi / 2 - alpha, np.full_like(s, -1 / a)
    if isinstance(scene, Cone):
        t = math.atan2(scene.r2 - scene.r1, scene.H)
        return scene.r1 + s * math.sin(t), s * math.cos(t), np.full_like(s, t), np.zeros_like(s)
    return np.full_like(s, scene.a), s.copy(), np.zeros_like(s), np.zeros_like(s)


@pytest.mark.parametrize("name", list(builtin_scenes()))
def test_builtin_meridians_are_the_closed_forms(name):
    """``meridian.at(s)`` equals the closed forms (to 1e-14), the length is the arc's, poles where ``r0 = 0``."""
    scene = builtin_scenes()[name]
    mer = scene.meridian()
    s = np.linspace(0.0, mer.length, 57)
    for got, want in zip(mer.at(s), expected_geometry(scene, s)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    if isinstance(scene, (Sphere, Torus)):
        assert mer.length == pytest.approx(scene.a * (scene.alpha2 - scene.alpha1), rel=1e-15)
    if isinstance(scene, Sphere):
        assert mer.poles == (scene.alpha1 == 0.0, scene.alpha2 == math.pi)
    else:
        assert mer.poles == (False, False)


def test_points_meridian_is_parametrised_by_arc_length(sphere_points):
    """The spline through the sampled unit sphere: ``dz0/ds = cos theta0``, ``dr0/ds = sin theta0``,
    ``dtheta0/ds = theta0_s``, and it is the unit sphere.

    Interpolation error of a cubic spline with spacing ``d = pi/40`` (chord-length parameter): ``~(5/384)
    d^4 = 4.9e-7`` in position, ``~d^3/24 = 2e-5`` in the tangent angle, ``~d^2/8 = 8e-4`` in the curvature;
    the arc-length identities hold to the accuracy of the 4th-order differences used to check them
    (step ``k = 1e-3``: ``k^4/30 x`` the 5th derivative, plus round-off ``EPS/k``), asserted at 1e-8 for
    ``z0, r0``; Newton's inversion of the arc length is converged to 1e-14. ``theta0`` is smooth only
    within a spline segment: its second derivative (the spline's third) jumps at the knots, so a stencil
    straddling a knot errs by ``~k x`` that jump (``O(d)``; measured 1.3e-5): asserted at 1e-4.
    """
    mer = MeridianShell(points=sphere_points).meridian()
    assert mer.poles == (True, True)
    assert mer.length == pytest.approx(math.pi, rel=1e-6)
    s = np.linspace(0.05, mer.length - 0.05, 41)
    k = 1e-3
    r0, z0, th0, th0s = mer.at(s)
    stencil = [mer.at(s + j * k) for j in (-2, -1, 1, 2)]
    d = [(stencil[0][i] - 8 * stencil[1][i] + 8 * stencil[2][i] - stencil[3][i]) / (12 * k) for i in range(3)]
    np.testing.assert_allclose(d[0], np.sin(th0), atol=1e-8)
    np.testing.assert_allclose(d[1], np.cos(th0), atol=1e-8)
    np.testing.assert_allclose(d[2], th0s, atol=1e-4)
    # the unit sphere, outward director (theta0 = pi/2 - s/a with a = 1)
    r_exact, z_exact, th_exact, ths_exact = expected_geometry(Sphere(), s)
    np.testing.assert_allclose(np.hypot(r0, z0), 1.0, atol=1e-6)
    np.testing.assert_allclose(th0, np.pi / 2 - np.arctan2(r0, -z0), atol=5e-5)
    np.testing.assert_allclose(th0s, -1.0, atol=3e-3)


# ---------------------------------------------------------------------------------------
# 7. the natural state at rest is an exact equilibrium
# ---------------------------------------------------------------------------------------
def unit_strain_force(scene, system):
    """Force of a unit membrane strain through a whole parallel circle: ``2 pi max(r0) (lambda + 2 mu) 2h`` (N)."""
    lam, mu = lame(scene.E, scene.nu)
    return 2 * math.pi * float(system.reference[1].max()) * (lam + 2 * mu) * 2 * scene.h


@pytest.mark.parametrize("n", [21, 41])
def test_natural_state_is_an_exact_equilibrium_on_every_meridian(n, sphere_points):
    """``rhs(0, y0)`` at the natural state: rates exactly 0, forces below ``20 EPS`` of a unit strain's.

    The discrete reference is the nodal one: the cell kernel gets exactly the numbers it was built from, so
    ``F = G G0^-1`` is the identity up to the rounding of a few operations (``x * (1/x)``, the sums in
    ``beta1``), ``|F - I| <= ~5 EPS``, hence strains ``<= ~5 EPS`` and each cell's forces on its nodes
    ``<= 5 EPS`` of the force of a unit strain; a node collects two cells: ``10 EPS``, and we allow 20.
    (The ``r`` force is an integral over the cell, the others are fluxes: both are bounded by the same
    unit-strain force times ``ds <= 1`` or 1.) Measured: at most 1.9 EPS. Built-ins with every edge kind
    (pole, magnet, pinned, clamped, free) and the sampled sphere.
    """
    scenes = dict(builtin_scenes(), points=MeridianShell(points=sphere_points))
    for name, scene in scenes.items():
        system = ShellSystem(scene, n)
        y0 = system.initial_state(scene)
        Q = system.unpack(y0)
        np.testing.assert_array_equal(Q[[0, 1, 3]], system.reference)
        rhs = np.array(system.rhs(0, y0)).ravel().reshape(n, 10)
        assert np.all(rhs[:, :5] == 0.0), name
        force = np.abs(rhs[:, 5:]).max()
        assert force <= 20 * EPS * unit_strain_force(scene, system), (name, force / unit_strain_force(scene, system))


@pytest.mark.parametrize("name", ["sphere", "cone", "torus-free", "points"])
def test_natural_state_stays_at_rest_under_leapfrog(name, sphere_points):
    """Leap-frog from the natural state, ``n = 41``, ``dt = 1e-5``, 500 steps: nothing moves beyond round-off.

    A residual force ``f`` on a coordinate of mass ``m`` displaces it by at most ``f T^2/(2m)`` (a
    constant force on an oscillator gives ``(f/K)(1 - cos wt) <= f t^2/(2m)``; rounding per step adds
    forces of the same size). With ``f <= 20 EPS`` of the unit-strain force (previous test) and ``m`` the
    smallest nodal ``z, r`` mass (the pole's half cell), ``|q - q0| <= f T^2/(2 m)`` and ``|q_t| <= f T/m``
    (measured: ``z, r`` move by <= 4e-17 m, rates <= 1e-12 m/s, against bounds 1e-13 .. 1e-12 m and
    5e-11 .. 5e-10 m/s; ``chi, psi`` stay exactly 0). The angular fields' masses are ``rhoJ``-sized
    (``h^2/3`` smaller), so we bound them by the same force over the smallest ``rhoJ`` node mass.
    """
    scene = {"sphere": Sphere(), "cone": Cone(), "torus-free": Torus(end1="free", end2="free"),
             "points": MeridianShell(points=sphere_points)}[name]
    n, dt, T = 41, 1e-5, 0.005
    run = mol_shell.simulate(scene, "leapfrog", n=n, times=np.linspace(0.0, T, 6), dt=dt, progress=False)
    assert run.attrs["complete"] == 1
    system, _ = mol_shell.build(scene, n)
    f = 20 * EPS * unit_strain_force(scene, system)
    m_lin, m_rot = float(system.inertia[0].min()), float(system.inertia[2].min())
    for field, ref in (("z", run.z0), ("r", run.r0), ("theta", run.theta0)):
        m = m_rot if field == "theta" else m_lin
        assert float(np.abs(run[field] - ref).max()) <= f * T**2 / (2 * m) + 4 * EPS, field
        assert float(np.abs(run[field + "_t"]).max()) <= f * T / m, field
    for field in ("chi", "psi"):
        assert float(np.abs(run[field]).max()) <= f * T**2 / (2 * m_rot), field
    # the energy of strains <= 20 EPS over the whole wall: (lambda + 2 mu) (20 EPS)^2 x volume (measured ~1e-23 J)
    assert float(np.abs(run.energy).max()) <= unit_strain_force(scene, system) * system.L * (20 * EPS) ** 2


# ---------------------------------------------------------------------------------------
# 7. balance laws on curved meridians
# ---------------------------------------------------------------------------------------
S, T = ca.SX.sym("s"), ca.SX.sym("t")


def reference(kind):
    """``(r0, z0, theta0, theta0_s)`` as CasADi expressions of ``s``, from the module docstring's closed forms."""
    if kind == "sphere":  # a = 1.3 from the bottom pole
        a, alpha = 1.3, S / 1.3
        return a * ca.sin(alpha), -a * ca.cos(alpha), math.pi / 2 - alpha, -1 / a + 0 * S
    if kind == "cone":  # r1 = 1, half-angle 0.4 (widening)
        return 1.0 + S * math.sin(0.4), S * math.cos(0.4), 0.4 + 0 * S, 0 * S
    if kind == "torus":  # tube radius 0.6 about b = 1.2, from alpha1 = -0.7 (through the outer equator)
        alpha = -0.7 + S / 0.6
        return 1.2 + 0.6 * ca.sin(alpha), -0.6 * ca.cos(alpha), math.pi / 2 - alpha, -1 / 0.6 + 0 * S
    raise ValueError(kind)


MERIDIAN_SCENES = {"sphere": Sphere(a=1.3), "cone": Cone(r1=1.0, r2=1.0 + 2 * math.sin(0.4), H=2 * math.cos(0.4)),
                   "torus": Torus(a=0.6, b=1.2, alpha1=-0.7, alpha2=2.0)}


AMPLITUDE = ca.SX.sym("e")


def motion(r0, z0, th0, e=AMPLITUDE):
    """Smooth fields near the reference: twist, breathing, shear, bending all present (``e = 0``: at rest)."""
    return (z0 + e * 0.03 * ca.sin(1.1 * S + 0.6 * T),
            r0 * (1 + e * 0.03 * ca.cos(0.7 * S - 1.3 * T)) + e * 0.02 * S * T,
            e * (0.1 * (S - 0.5) + 0.15 * ca.sin(0.9 * T + 0.4 * S)),
            th0 + e * (0.12 * ca.sin(0.8 * S + 1.2 * T) + 0.05),
            e * (0.1 * ca.cos(1.3 * S - 0.5 * T) + 0.08 * T))


def both_routes(kind, lam=2.0, mu=1.0, rho=1.0, h=0.1, zeta1=-0.07, n_quad=4):
    """Route 1 (Euler-Lagrange of ``2 pi r0 (T - What)``) and route 2 (``balance_laws``): a Function of ``(s, t, e)``.

    The inertias per unit reference area are written out here (eq. 7.8): ``rho{A,I,J} = (1/r0) int rho
    zeta^k (1 - zeta theta0_s)(r0 + zeta cos theta0) dzeta``, by the thickness rule (exact: a polynomial of
    degree <= 4 in ``zeta``). ``zeta1 = -0.07`` with ``h = 0.1`` leaves ``rhoI != 0``, so its terms are checked.
    """
    r0, z0, th0, th0s = reference(kind)
    thickness = Thickness(zeta1, h, n_quad)
    rho_k = [0, 0, 0]
    for zeta, w in zip(*thickness.nodes_weights):
        factor = (1 - zeta * th0s) * (r0 + zeta * ca.cos(th0)) / r0
        for k in range(3):
            rho_k[k] = rho_k[k] + rho * w * factor * zeta**k
    fields = motion(r0, z0, th0)
    laws = balance_laws(fields, S, T, lam, mu, rho, thickness, r0, th0, th0s)

    def stored(q, q_s, q_t):
        return -2 * math.pi * r0 * shell_energy((*q_s, q[1], q[3], q[4]), lam, mu, thickness, r0, th0, th0s)

    def kinetic(q, q_s, q_t):
        return 2 * math.pi * r0 * kinetic_energy_density(q, q_t, *rho_k)

    el_elastic, flux = euler_lagrange(stored, fields, S, T)
    el_inertia, _ = euler_lagrange(kinetic, fields, S, T)
    r = fields[1]
    outputs = {
        "el_elastic": el_elastic,
        "proj_elastic": -2 * math.pi * virtual_power_projections(laws["elastic_lin"], laws["elastic_ang"], laws, r),
        "el_inertia": el_inertia,
        "proj_inertia": 2 * math.pi * virtual_power_projections(laws["inertia_lin"], laws["inertia_ang"], laws, r),
        "flux_lagrange": flux,
        "flux_balance": -2 * math.pi * end_fluxes(laws, r, r0),
        "rho_i": rho_k[1],
    }
    return ca.Function("routes", [S, T, AMPLITUDE], list(outputs.values()), ["s", "t", "e"], list(outputs))


POINTS = [(0.15, 0.1), (0.6, 0.45), (1.05, 0.9), (1.5, 0.25), (1.9, 0.7)]


def evaluate(f, amplitude=1.0):
    values = [f(s=s, t=t, e=amplitude) for s, t in POINTS]
    return {key: np.array([np.array(v[key]).ravel() for v in values]) for key in f.name_out()}


@pytest.mark.parametrize("kind", ["sphere", "cone", "torus"])
def test_reference_expressions_are_the_package_meridians(kind):
    """The CasADi references used below are the package's meridians (``Sphere(a=1.3)``, a cone, a torus)."""
    mer = MERIDIAN_SCENES[kind].meridian()
    f = ca.Function("ref", [S], list(reference(kind)))
    for s, _ in POINTS:
        mine = [float(x) for x in f(s)]
        np.testing.assert_allclose(mine, [float(x) for x in mer.at(np.array(s))], rtol=0, atol=1e-14)


@pytest.mark.parametrize("kind", ["sphere", "cone", "torus"])
def test_balance_laws_equal_euler_lagrange_on_curved_meridians(kind):
    """``EL_j = -2 pi <(R_lin, R_ang), (delta r, omega)_j>`` with ``r0(s), theta0(s), theta0_s(s)`` of the meridian.

    As ``tests/test_balance_laws.py`` on the cylinder: two exact continuum routes evaluated on smooth
    explicit fields, so they agree to rounding. With ``r0`` depending on ``s`` the Euler-Lagrange flux
    ``d_s(dl/dq_s)`` differentiates ``r0(s)`` too, and the reference factors ``1 - zeta theta0_s`` (curved)
    and ``r0 + zeta cos theta0`` (sloped) enter both ``F`` and the volume element. Elastic, inertial parts
    and the natural boundary terms separately, relative to each equation's size over the points; bound
    1e-11 as there (~100 roundings per term, times the cancellation of membrane stresses in the moments).
    Measured: <= 1e-14. Every equation is exercised (nonzero), ``rhoI != 0``.
    """
    out = evaluate(both_routes(kind))
    assert np.abs(out["rho_i"]).min() > 1e-4
    for lagrange, balance in (("el_elastic", "proj_elastic"), ("el_inertia", "proj_inertia"),
                              ("flux_lagrange", "flux_balance")):
        size = np.abs(out[lagrange]).max(axis=0)
        assert np.all(size > 0), (lagrange, size)
        err = np.abs(out[balance] - out[lagrange]).max(axis=0) / size
        assert err.max() < 1e-11, (lagrange, err)


@pytest.mark.parametrize("kind", ["sphere", "cone", "torus"])
def test_natural_state_of_a_curved_meridian_is_stress_free(kind):
    """At the reference fields, at rest, ``F = I``: both routes give zero forces, fluxes and inertia (to 1e-14).

    This checks the reference factors against the geometry: ``F11 = (beta1 - zeta theta_s)/(1 - zeta theta0_s)``
    and ``F33 = (r + zeta cos theta)/(r0 + zeta cos theta0)`` are 1 only if ``dz0/ds = cos theta0``,
    ``dr0/ds = sin theta0`` and ``theta0_s`` is the curvature.
    """
    out = evaluate(both_routes(kind), amplitude=0.0)
    for key in ("el_elastic", "proj_elastic", "el_inertia", "proj_inertia", "flux_lagrange", "flux_balance"):
        assert np.abs(out[key]).max() < 1e-14, (key, np.abs(out[key]).max())


# ---------------------------------------------------------------------------------------
# 8. meridians from points
# ---------------------------------------------------------------------------------------
def test_sampled_sphere_has_the_spheres_frequencies(sphere_points):
    """41 points of the unit sphere (poles at the ends) vs ``Sphere()``, ``n = 21``: the lowest 12 frequencies agree.

    The spline reproduces the sphere to ``~(5/384) d^4 = 4.9e-7`` in position (``d = pi/40``, see above), the
    curvature to ``~d^2``, but the frequencies depend on the geometry through integrals over cells, so
    their relative change is of the order of the position error: asserted < 5e-6 (measured 5e-8, the
    same for all modes: mostly the length, ``|L/pi - 1| ~ 5e-8``). The two are the same grid and kind of
    shell (2 rigid motions, pole edges), and the same base surface ``zeta1`` (to the spline's accuracy).
    """
    builtin = modes(Sphere(), n=21, count=12)
    sampled = modes(MeridianShell(points=sphere_points), n=21, count=12)
    assert sampled.attrs["zero_modes"] == builtin.attrs["zero_modes"] == 2
    assert sampled.attrs["edge_s0"] == sampled.attrs["edge_sL"] == "pole"
    assert sampled.attrs["zeta1_used"] == pytest.approx(builtin.attrs["zeta1_used"], rel=1e-6)
    np.testing.assert_allclose(sampled.frequency.values, builtin.frequency.values, rtol=5e-6)
    np.testing.assert_array_equal(sampled.energy_fraction.values.argmax(axis=1),
                                  builtin.energy_fraction.values.argmax(axis=1))


@pytest.fixture(scope="module")
def reversed_tables(tmp_path_factory):
    """The sampled sphere top to bottom, and a straight frustum (the default ``Cone()``) both ways."""
    folder = tmp_path_factory.mktemp("reversed")
    frustum = np.column_stack([np.linspace(1.0, 0.5, 5), np.linspace(0.0, 1.0, 5)])
    tables = {"sphere-down": sphere_table()[::-1], "cone-up": frustum, "cone-down": frustum[::-1]}
    for name, table in tables.items():
        np.savetxt(folder / f"{name}.txt", table)
    return {name: str(folder / f"{name}.txt") for name in tables}


def test_the_direction_of_the_director_does_not_matter(sphere_points, reversed_tables):
    """A table read in the other order turns the director over (outward -> inward); the physics must not change.

    Rows ordered by decreasing ``z`` give ``d0`` pointing inward, so ``zeta`` counts the other way and the
    centroidal base surface is found at the opposite offset: mid-surface offset ``zeta1 + h`` changes sign
    (the base surface is the same physical surface, ``~2h^2/(3a) = 2.6e-5`` m outside the mid-surface of a
    sphere). The frequencies (n = 21, lowest 12) are the same: the spline is the same curve (its end
    conditions are symmetric), so they agree to the eigen-solver's round-off, ``EPS (omega_max/omega)^2 ~ 1e-11``
    relative; asserted 1e-9 (measured 6e-12). The straight table is ``Cone()`` exactly (a cubic spline
    through collinear points is the line), both ways, to the same bound.
    """
    h = Sphere().h
    forward = modes(MeridianShell(points=sphere_points), n=21, count=12)
    backward = modes(MeridianShell(points=reversed_tables["sphere-down"]), n=21, count=12)
    offset_forward, offset_backward = forward.attrs["zeta1_used"] + h, backward.attrs["zeta1_used"] + h
    assert offset_forward == pytest.approx(-2 * h * h / 3, rel=0.01)
    assert offset_backward == pytest.approx(-offset_forward, rel=1e-6)
    np.testing.assert_allclose(backward.frequency.values, forward.frequency.values, rtol=1e-9)
    cone = modes(Cone(), n=21, count=12)
    for name in ("cone-up", "cone-down"):
        sampled = modes(MeridianShell(points=reversed_tables[name]), n=21, count=12)
        np.testing.assert_allclose(sampled.frequency.values, cone.frequency.values, rtol=1e-9, err_msg=name)


BAD_TABLES = {
    "negative r": ([[0.5, 0.0], [1.0, 0.5], [-0.2, 1.0], [0.5, 1.5], [0.7, 2.0]], "r = -0.2 < 0"),
    "self-crossing": ([[1.0, 0.0], [2.0, 1.0], [2.0, 0.0], [1.0, 1.0], [1.0, 2.0]], "crosses itself"),
    "three points": ([[1.0, 0.0], [1.2, 0.5], [1.0, 1.0]], "4 or more"),
    "axis mid-way": ([[1.0, 0.0], [0.0, 1.0], [1.0, 2.0], [1.0, 3.0]], "touches the axis between its ends"),
    # were refused naming h (the thickness off the axis), and as "repeats a point" of two distinct points
    "doubling back": ([[1.0, 0.0], [1.0, 1.0], [1.0, 0.5], [1.0, 2.0]], "doubles back on itself at line 2"),
    "1e300 m": ([[1.0, 0.0], [1.0, 1.0], [1.0, 2.0], [1.0, 1e300]], "has a coordinate beyond 1e+100 m on line 4"),
    "1e50 m": ([[1.0, 0.0], [1.0, 1.0], [1.0, 2.0], [1.0, 1e50]], "points 1 m apart on line 1 and line 2, closer than"),
}


@pytest.mark.parametrize("case", list(BAD_TABLES))
def test_bad_point_tables_are_refused_naming_points(case, tmp_path):
    """``r < 0``, a self-crossing curve, fewer than 4 points, ``r = 0`` between the ends: refused naming ``points``."""
    table, phrase = BAD_TABLES[case]
    path = tmp_path / f"{case.replace(' ', '_')}.txt"
    np.savetxt(path, np.array(table))
    with pytest.raises(ParameterError, match=r"^points = ") as info:
        MeridianShell(points=str(path))
    assert info.value.name == "points"
    assert phrase in str(info.value)


# ---------------------------------------------------------------------------------------
# 9. which states modes() accepts
# ---------------------------------------------------------------------------------------
def test_modes_refuse_the_twisted_cylinder_between_magnets():
    """The paper's twisted cylinder (``gamma = 0.1``, magnet ends) is not an equilibrium: its twist has no
    torque to hold it at the ends (``n.a3 = 0`` there), so the end nodes' ``chi`` forces are a unit twist's
    ``mu int (1 + zeta)^3`` times 0.1 -- refused, naming the scene and the residual."""
    with pytest.raises(ParameterError, match="equilibrium") as info:
        modes(TwistedCylinder(), n=21, count=4)
    assert info.value.name == "scene"
    assert "chi" in str(info.value)


def test_modes_accept_the_clamped_twisted_cylinder_at_its_equilibrium_radius():
    """Clamped ends hold ``z, r, chi, theta, psi``: the uniform twist at the equilibrium radius is an equilibrium.

    No rigid motion is left (0 zero modes), every frequency is positive. Reflection ``phi -> -phi``
    (``chi, psi -> -chi, -psi``) maps the shell twisted by ``gamma`` onto the one twisted by ``-gamma``, so
    the frequencies are even in ``gamma`` and move from the untwisted clamped cylinder's by ``O(gamma^2)``:
    halving ``gamma`` (0.1 -> 0.05) divides the shift of the two lowest modes (torsion ``k = 1`` and the
    first ``z, r`` mode) by 4 (ratio in [3.8, 4.2]; measured 3.97, 4.02; modes 3-4, near a crossing of a
    torsional and a ``z, r`` branch, converge more slowly and are not used).
    """
    base = modes(TwistedCylinder(gamma=0.0, R=1.0, end1="clamped", end2="clamped"), n=21, count=6)
    shifts = {}
    for gamma in (0.1, 0.05):
        ds = modes(TwistedCylinder(gamma=gamma, end1="clamped", end2="clamped"), n=21, count=6)
        assert ds.attrs["zero_modes"] == 0
        assert np.all(ds.frequency.values > 0)
        assert 0.99 < ds.attrs["R"] < 1.0
        shifts[gamma] = ds.frequency.values[:2] / base.frequency.values[:2] - 1
    ratio = shifts[0.1] / shifts[0.05]
    assert np.all((3.8 <= ratio) & (ratio <= 4.2)), ratio
