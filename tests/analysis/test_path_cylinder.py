"""A thin cylinder under axial compression, with edges given as the sets of fields they impose (``end1=z,theta``,
``end2=theta``): the axisymmetric bifurcation load of :func:`mol_shell.path` against the linear eigenvalue problem.

Derivation. Edges that impose ``theta = 0`` (the generator stays axial) and leave ``r`` free at both ends, ``z``
held at one end and loaded by the axial force ``F`` at the other, admit the uniform membrane state before buckling:
uniform axial stress resultant ``N = -F / (2 pi a)``, a uniform Poisson expansion, no bending. Linearising about it
(Donnell; Timoshenko & Gere sec. 11.4), an axisymmetric normal displacement ``w`` satisfies
``D w'''' + N w'' + (E t / a^2) w = 0``; the edges ask ``w' = 0`` (theta imposed) and ``D w''' = 0`` (no radial
force where r is free), which ``w = cos(k x)`` with ``k = m pi / L`` meets. So

    N_m = D k^2 + E t / (a^2 k^2),   D = E t^3 / (12 (1 - nu^2)),  t = 2h (h: mol_shell's half-thickness),

and the bifurcation load is the least over ``m``. ``L`` is chosen so that ``m = 8`` sits at the continuous
minimum ``k*^4 = E t / (D a^2)``, where ``N = E t^2 / (a sqrt(3 (1 - nu^2)))``. The model differs by the finite
strain before buckling, ``eps = N / (E t)`` (0.6 ``t/a``), and by transverse shear, ``N / (G t)``, both ``O(t/a)``:
within a few ``eps`` at each thickness, and the value extrapolated linearly in ``t/a`` to zero from two thicknesses
must be the classical one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mol_shell import Axisymmetric, path
from mol_shell.scenes.files import load_scene

E, NU, A, M = 1.0e6, 0.3, 1.0, 8


def classical(h):
    """``(L, F_cr)``: the length whose wave ``m = M`` is the optimum, and the least bifurcation force, N."""
    t = 2 * h
    D = E * t**3 / (12 * (1 - NU**2))
    k_star = (E * t / (D * A**2)) ** 0.25
    L = M * math.pi / k_star
    N = min(D * (m * math.pi / L) ** 2 + E * t / (A**2 * (m * math.pi / L) ** 2) for m in range(1, 200))
    assert N == pytest.approx(E * t**2 / (A * math.sqrt(3 * (1 - NU**2))), rel=1e-12)
    return L, 2 * math.pi * A * N


def cylinder(h, end2="theta"):
    L, _ = classical(h)
    return Axisymmetric(L=L, a=A, R=A, h=h, E=E, nu=NU, material="svk-plane-stress", end1="z,theta", end2=end2)


@pytest.fixture(scope="module")
def critical():
    out = {}
    for h in (0.01, 0.005):  # a/t = 50 and 100; n = 121: 15 nodes per half-wave
        _, F = classical(h)
        ds = path(cylinder(h), "end2_force", 0.0, -1.1 * F, n=121, steps=10, max_steps=20)
        assert ds.attrs["status"] == "complete" and ds.attrs["edge_sL"] == "theta"
        first = int(np.argmax(ds.point_parameter.values))  # the least compressive force
        out[h] = (ds, first, float(ds.point_parameter[first]) / -F)
    return out


@pytest.mark.parametrize("h", [0.01, 0.005])
def test_axisymmetric_bifurcation_of_the_compressed_cylinder(critical, h):
    ds, first, ratio = critical[h]
    assert ds.point_kind.values[first] == "bifurcation" and ds.point_located.values[first] == 1
    w = ds.point_mode_r.values[first]
    assert int(np.sum(np.diff(np.sign(w[1:-1])) != 0)) == M  # cos(8 pi x / L): eight zeros
    eps = (2 * h) / (A * math.sqrt(3 * (1 - NU**2)))  # N / (E t) at the classical load
    assert abs(ratio - 1) < 3 * eps
    before = ds.parameter.values > ds.point_parameter.values[first]
    assert np.all(ds.negative_eigenvalues.values[before] == 0)
    # the state before buckling is the uniform membrane state: r the same at every node
    r = ds.r.values[before]
    assert np.abs(r - r[:, :1]).max() <= 1e-10
    # the held edge's reaction at each critical point balances the applied end force (no other axial load). The
    # located states are equilibria to the locating Newton's residual, not to round-off: at the first point to 1e-7
    # (measured 7e-11 and 1e-14), at the later ones, where the solves are nearly singular on an unstable path,
    # to 1e-5 (measured up to 1.2e-6). The steps balance to round-off.
    imbalance = np.abs(ds.point_end1_reaction_force.values + ds.point_parameter.values)
    load = np.abs(ds.point_parameter.values)
    assert imbalance[first] <= 1e-7 * load[first] and np.all(imbalance <= 1e-5 * load)
    assert np.abs(ds.end1_reaction_force.values + ds.parameter.values).max() <= 1e-12 * load.max()


def test_the_critical_force_extrapolates_to_the_classical_value(critical):
    x = np.array([2 * 0.01 / A, 2 * 0.005 / A])
    ratio = np.array([critical[0.01][2], critical[0.005][2]])
    intercept = ratio[1] - (ratio[1] - ratio[0]) / (x[1] - x[0]) * x[1]
    assert abs(intercept - 1) < 0.005


def test_an_edge_is_the_set_of_fields_it_imposes_in_a_scene_file(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text('scene = "axisymmetric"\n[edges]\nend1 = "theta, z"\nend2 = "theta"\n')
    scene = load_scene(str(f))
    assert (scene.end1, scene.end2) == ("z,theta", "theta")


def test_displacement_control_gives_the_same_bifurcation_and_the_edge_reactions(critical):
    """The same cylinder with both edges imposing z and theta (``z,theta``), shortened by ``end2_dz``: the membrane
    state is that of the force-controlled path, so the reaction at the located bifurcation is its critical force
    (to 1e-3: the held z at the edge changes the mode's edge condition, 4.9e-5 measured); it lies between the two
    steps' reactions around the point; the two edges' reactions balance; the stored energy is the reaction's work
    ``int R d dz`` (trapezoidal rule over the steps)."""
    h = 0.01
    L, F = classical(h)
    eps = F / (2 * math.pi * A) / (E * 2 * h)  # axial strain at the classical load (uniaxial membrane stress)
    scene = cylinder(h, end2="z,theta")
    ds = path(scene, "end2_dz", 0.0, -1.3 * eps * L, n=121, steps=10, max_steps=20)
    assert ds.attrs["status"] == "complete" and ds.load_conjugate.attrs["units"] == "N"
    # the edge is where the parameter puts it, the other one stays
    assert np.abs(ds.end2_axial_displacement.values - ds.parameter.values).max() <= 1e-12
    assert np.all(ds.end1_axial_displacement.values == 0)
    r1, r2 = ds.end1_reaction_force.values, ds.end2_reaction_force.values
    assert np.abs(r1 + r2).max() <= 1e-9 * np.abs(r2).max()
    assert np.all(r2[1:] < 0)  # the support pushes the shortened edge back along -k: compression
    p = float(ds.point_parameter[0])
    assert ds.point_kind.values[0] == "bifurcation"
    # the reaction at the located point: between the two steps' around it, balanced by the other edge's
    reaction = float(ds.point_end2_reaction_force[0])
    k = int(ds.point_step[0])
    dz = ds.parameter.values
    assert min(dz[k], dz[k + 1]) <= p <= max(dz[k], dz[k + 1])
    assert min(r2[k], r2[k + 1]) <= reaction <= max(r2[k], r2[k + 1])
    assert abs(reaction + float(ds.point_end1_reaction_force[0])) <= 1e-7 * abs(reaction)
    assert ds.point_end2_reaction_force.attrs["units"] == "N"
    assert reaction / -F == pytest.approx(critical[h][2], rel=1e-3)
    stored = ds.stored_energy.values - ds.stored_energy.values[0]
    assert np.abs(stored - ds.load_work.values).max() <= 1e-3 * stored.max()


def test_a_displacement_of_a_free_field_is_refused_naming_the_option(tmp_path, capsys):
    from mol_shell.cli.main import main

    code = main(["path", "axisymmetric", "--param", "end2_dz=0:-0.01", "--set", "end2=theta", "--n", "11",
                 "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "--param" in err and "end1_dz" in err


def test_the_cli_says_the_reaction_at_each_critical_point_of_a_displacement_path(tmp_path, capsys):
    """``mol-shell path --param end2_dz=...``: each critical point's line names the reaction there (the quantity
    displacement control measures), as stored in ``point_end2_reaction_force``; a load path's lines do not."""
    from mol_shell.cli.main import main
    from mol_shell.results.dataset import read_netcdf

    sets = ["--set", "h=0.01", "--set", "L=1.955", "--set", "E=1e6", "--set", "nu=0.3", "--set", "R=1",
            "--set", "material=svk-plane-stress", "--set", "end1=z,theta", "--set", "end2=z,theta"]
    out = tmp_path / "dz.nc"
    assert main(["path", "axisymmetric", "--param", "end2_dz=0:-0.03", "--n", "41", *sets, "-o", str(out)]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "bifurcation at" in line]
    ds = read_netcdf(out)
    assert len(lines) == ds.sizes["point"] >= 1
    for line, reaction in zip(lines, ds.point_end2_reaction_force.values):
        assert f"reaction {reaction:.6g} N" in line and reaction < 0
