"""The ``meridian`` scene's table of points: ends on the axis by the poles' rule are poles, and sizes the model
cannot compute are refused naming ``points``.

* A unit sphere sampled as ``(sin a, -cos a)`` has ``sin(pi) = 1.22e-16``, not 0, at its top: an end that the
  poles' rule (``|r| <= 1e-12`` of the size) calls a pole must be one, i.e. the same meridian as the table with
  ``0`` written there: the tangent perpendicular to the axis (``theta0 = -pi/2``, ``dr0/ds = sin(theta0) = -1``,
  ``dz0/ds = 0``) and the shell mirror-symmetric about ``z = 0`` (``r0(L - s) = r0(s)``, ``z0(L - s) = -z0(s)``,
  ``theta0(L - s) = -theta0(s)``), as the sampled curve is.
* The spin inertia of a node, ``mA r^2``, is a part of the shell's moment of inertia about the axis; for a cylinder
  of radius ``S`` and length ``S`` (wall ``2h``) that is ``4 pi rho h S^4``, and it must stay finite.
"""

import math
import sys

import numpy as np
import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.analysis.modes import modes
from mol_shell.discretization.system import ShellSystem
from mol_shell.runs import checks
from mol_shell.scenes import MeridianShell


def sphere_rows(exact_poles):
    a = np.linspace(0.0, math.pi, 23)
    table = np.column_stack([np.sin(a), -np.cos(a)])
    if exact_poles:
        table[[0, -1], 0] = 0.0
    return table


@pytest.fixture(scope="module")
def sphere_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("poles")
    out = {}
    for name, exact in (("sin", False), ("zero", True)):
        np.savetxt(folder / f"{name}.txt", sphere_rows(exact))
        out[name] = str(folder / f"{name}.txt")
    return out


def test_an_end_within_round_off_of_the_axis_is_a_pole_with_a_horizontal_tangent(sphere_files):
    """``sin(pi) = 1.22e-16`` at the top: a pole put on the axis, the tangent perpendicular to it (was -1.5295 rad,
    a cone tip of 2.4 degrees), the same reference geometry as the table with 0 written, and mirror-symmetric."""
    assert sphere_rows(False)[-1, 0] != 0.0  # the case: a tiny but nonzero radius
    sampled = MeridianShell(points=sphere_files["sin"]).meridian()
    exact = MeridianShell(points=sphere_files["zero"]).meridian()
    assert sampled.poles == exact.poles == (True, True)
    L = sampled.length
    r0, z0, th0, _ = sampled.at(np.array([0.0, L]))
    assert r0 == pytest.approx([0.0, 0.0], abs=1e-15)
    assert th0 == pytest.approx([math.pi / 2, -math.pi / 2], abs=1e-14)
    s = np.linspace(0.0, L, 21)
    for got, want in zip(sampled.at(s), exact.at(s)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    r0, z0, th0, k0 = sampled.at(s)
    r1, z1, th1, k1 = sampled.at(L - s)
    np.testing.assert_allclose(r1, r0, atol=1e-12)
    np.testing.assert_allclose(z1, -z0, atol=1e-12)
    np.testing.assert_allclose(th1, -th0, atol=1e-12)
    np.testing.assert_allclose(k1, k0, atol=1e-9)


def test_the_sampled_sphere_with_sin_pi_vibrates_as_with_an_exact_pole(sphere_files):
    """The same shell, so the same lowest modes (n = 15) as the table with 0 written, to the eigen-solver's round-off
    (were 5e-6 apart at n = 40: the lopsided tip)."""
    sampled = modes(MeridianShell(points=sphere_files["sin"]), n=15, count=4)
    exact = modes(MeridianShell(points=sphere_files["zero"]), n=15, count=4)
    assert sampled.attrs["edge_s0"] == sampled.attrs["edge_sL"] == "pole"
    np.testing.assert_allclose(sampled.frequency.values, exact.frequency.values, rtol=1e-9)


def cylinder_table(path, size):
    np.savetxt(path, np.column_stack([size * np.ones(5), size * np.linspace(0.0, 1.0, 5)]))
    return str(path)


def test_a_table_too_large_for_the_inertia_is_refused_naming_points(tmp_path):
    """1e90 m, inside the points' 1e100 m, was refused as ``scene = 'meridian' has the right-hand side at t = 0 is not
    finite``. Now one line naming the file and the size that fits: the cylinder's axial inertia ``4 pi rho h S^4``
    times 2 for the wall's and curvature's factors (bounded by 2 each way), kept 100 times below the largest
    double, ``S = (0.01 DBL_MAX / (8 pi rho h))^(1/4)`` = 1.03e76 m with the defaults."""
    path = cylinder_table(tmp_path / "big.txt", 1e90)
    with pytest.raises(ParameterError) as info:
        MeridianShell(points=path)
    scene = MeridianShell()
    fits = (0.01 * sys.float_info.max / (8 * math.pi * scene.rho * scene.h)) ** 0.25
    message = str(info.value)
    assert info.value.name == "points" and "\n" not in message
    assert message.startswith(f"points = '{path}' has coordinates up to 1e+90 m")
    assert f"allowed: a table with coordinates up to about {fits:.2g} m" in message
    # inside the stated size the model's numbers are finite
    inside = MeridianShell(points=cylinder_table(tmp_path / "inside.txt", 0.9 * fits))
    system = ShellSystem(inside, 5)
    assert checks.problem(system, system.initial_state(inside)) is None


def test_the_generic_refusal_names_a_text_parameter_and_reads(sphere_files):
    """When no number was changed, the refusal of non-finite numbers names the text parameter that, set back to its
    default, makes them finite (was ``scene = 'meridian' has the right-hand side ... is not finite``)."""
    scene = MeridianShell(points=sphere_files["zero"])
    reason = "the right-hand side at t = 0 is not finite in double precision"
    error = checks._diagnose(scene, reason, bad=lambda sc: sc.points != "")
    assert error.name == "points"
    assert str(error) == (f"points = '{sphere_files['zero']}' leaves the model's numbers outside double precision: "
                          f"{reason}; allowed: values whose discretised numbers are finite in double precision "
                          "(they are with points = '', the default)")
