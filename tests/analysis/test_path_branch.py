"""Branch switching (``path(..., branch=K)``, ``mol-shell path --branch K``) at the first bifurcation of a closed
sphere under external pressure.

What is expected, independently of a run. The sphere of tests/analysis/test_path.py with ``a/t = 39.9`` buckles
first into the Legendre mode ``P_11`` (odd: antisymmetric about the equator). Before that point every state is
symmetric about the equator (``r(s) = r(L - s)``); the discrete sphere keeps this symmetry exactly, so the point is
a symmetric pitchfork and the branch leaving it carries the antisymmetric mode: on it ``r(s) - r(L - s)`` is not
zero, and near the point it is along the mode's own antisymmetric part. The axisymmetric post-buckling of a
sphere under pressure is unstable (Koiter 1969; Hutchinson 1967): the branch is subcritical, its pressure falls
below the critical one, and by the exchange of stability at a simple pitchfork whose primary path was stable
before it carries exactly one unstable direction near the point.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from reference_cap import cap_params, p_classical

import mol_shell
from mol_shell import Sphere, path
from mol_shell.cli.main import main

E, NU, A = 1.0e6, 0.3, 1.0
H11 = A / (2 * 11 * 12 / math.sqrt(12 * (1 - NU**2)))
P_CL = 2 * E * (2 * H11) ** 2 / (A**2 * math.sqrt(3 * (1 - NU**2)))


@pytest.fixture(scope="module")
def switched():
    sphere = Sphere(a=A, h=H11, E=E, nu=NU, material="svk-plane-stress")
    return path(sphere, "pressure", 0.0, -1.02 * P_CL, n=60, steps=10, max_steps=16, branch=0)


def antisymmetric(r):
    return r - r[..., ::-1]


def test_the_path_switches_at_the_first_bifurcation(switched):
    ds = switched
    branch = ds.branch.values
    first = int(np.argmax(branch == 1))
    assert first > 0 and np.all(branch[:first] == 0) and np.all(branch[first:] == 1)
    assert ds.attrs["branch_point"] == 0 and ds.point_kind.values[0] == "bifurcation"
    p_c = float(ds.point_parameter[0])
    # the branch starts next to the point
    assert abs(float(ds.parameter[first]) / p_c - 1) < 0.01
    # symmetric before it, antisymmetric part on the branch growing away from the point
    asym = np.abs(antisymmetric(ds.r.values)).max(axis=1)
    assert np.all(asym[:first] < 1e-12)
    assert np.all(asym[first:] > 1e-5) and np.all(np.diff(asym[first:]) > 0)


def test_the_branch_leaves_along_the_critical_mode(switched):
    ds = switched
    first = int(np.argmax(ds.branch.values == 1))
    a = antisymmetric(ds.r.values[first])
    m = antisymmetric(ds.point_mode_r.values[0])
    assert abs(np.dot(a, m)) / (np.linalg.norm(a) * np.linalg.norm(m)) > 0.99


def test_the_branch_is_subcritical_and_unstable(switched):
    ds = switched
    on = ds.branch.values == 1
    p = -ds.parameter.values[on]
    assert np.all(p < -float(ds.point_parameter[0])) and np.all(np.diff(p) < 0)
    assert np.all(ds.negative_eigenvalues.values[on][:3] == 1)


def test_branch_at_a_limit_point_keeps_the_path_and_says_why_there_is_no_switch(tmp_path, capsys):
    """No branch leaves a limit point. ``--branch 0`` there exited 2 after the whole path was traced, writing
    nothing; the path is now written, followed on past the point without a switch, and the note says why (as for
    a point the path did not reach)."""
    argv = ["path", "sphere", "--param", f"pressure=0:{-0.7 * p_classical():.6g}", "--n", "21", "--branch", "0"]
    for k, v in cap_params(5.0).items():
        argv += ["--set", f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"]
    out = tmp_path / "b.nc"
    assert main(argv + ["-o", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    notes = [line for line in err if line.startswith("mol-shell: note: --branch 0: ")]
    assert len(notes) == 1 and "critical point 0 is a limit point" in notes[0]
    assert "no bifurcation point was found up to it" in notes[0]
    ds = mol_shell.read_netcdf(out)
    assert str(ds.point_kind.values[0]) == "limit" and np.all(ds.branch.values == 0)
    assert "; no switch: critical point 0 is a limit point" in ds.attrs["message"]


def test_a_branch_that_closes_into_a_loop_ends_where_it_left_the_path():
    """The vessel's two heads are equal, so the antisymmetric branch (one head buckling first) is a loop: the heads
    snap in turn, the branch passes through the mirror image of each state it left (``r(s) - r(L - s)`` of both
    signs, each limit load found twice, once per head), and it comes back to the bifurcation it left. It went round
    the loop until ``max_steps``; it now ends there, said ``returned``."""
    ds = path(mol_shell.Vessel(), "pressure", 0.0, -2000.0, n=13, branch=0, max_steps=300, progress=False)
    assert ds.attrs["status"] == "returned", ds.attrs["message"]
    assert "the branch closed: it came back to critical point 0" in ds.attrs["message"]
    on = ds.branch.values == 1
    half = ds.sizes["s"] // 2
    lopsided = antisymmetric(ds.r.values[on])[:, :half].sum(axis=1)
    assert lopsided.min() < -0.5 * np.abs(lopsided).max() and lopsided.max() > 0.5 * np.abs(lopsided).max()
    away = np.abs(ds.r.values[on] - ds.point_r.values[0]).max(axis=1)
    assert away[-1] < 0.2 * away.max()  # back at the bifurcation, within a step
    kinds, loads = ds.point_kind.values, ds.point_parameter.values
    on_branch = np.sort(loads[(kinds == "limit") & (ds.point_step.values > ds.point_step.values[0] + 1)])
    assert len(on_branch) >= 4 and len(on_branch) % 2 == 0, loads
    np.testing.assert_allclose(on_branch[0::2], on_branch[1::2], rtol=1e-5)  # each head's fold, once each
