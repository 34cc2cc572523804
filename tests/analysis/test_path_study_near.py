"""A study of paths gathers what each path records of its critical modes: the grid-mode share of every critical point
(``point_grid_mode_share``) and the near-critical points (dim ``near``), with units and long names, as a single path
file has them (they were left out: a study said nothing of an imperfect bifurcation its cases passed).

The cases: the cylinder of tests/analysis/test_path_critical_modes.py shortened by its end (``end2_dz``), with the
wall 0.1 % thicker over its middle half-wave (an imperfect bifurcation: one near-critical point, no crossing) and
without (the perfect bifurcation: one critical point, no near-critical point). Its mode ``m = 2`` spans five cells a
half-wavelength at n = 11: a grid-mode share of ``(1 - cos(pi / 5)) / 2 = 0.0955``."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from mol_shell import TwistedCylinder
from mol_shell.analysis.path_study import path_study

E, NU, A, H, L = 1.0e6, 0.3, 1.0, 0.005, 0.35
EPS_CL = 2 * H / (A * math.sqrt(3 * (1 - NU**2)))
BUMP = f"table 0:{H} {L / 4}:{H} {L / 2}:{H * 1.001} {3 * L / 4}:{H} {L}:{H}"
SHARE = (1 - math.cos(math.pi / 5)) / 2


def test_a_study_gathers_near_critical_points_and_grid_mode_shares(tmp_path):
    scene = TwistedCylinder(gamma=0.0, L=L, a=A, h=H, E=E, nu=NU, material="svk-plane-stress", end1="z,theta",
                            end2="z,theta")
    out = tmp_path / "s.nc"
    ds = path_study(scene, [{"h_profile": BUMP}, {"h_profile": ""}], "end2_dz", 0.0, -1.01 * EPS_CL * L, n=11,
                    steps=10, scheduler="serial", output=out, progress=False)
    assert ds.near_parameter.dims == ("case", "near") and ds.sizes["near"] == 1
    bumped, perfect = 0, 1
    assert ds.near_parameter.values[bumped, 0] == pytest.approx(-0.99642 * EPS_CL * L, rel=1e-4)
    assert ds.near_located.values[bumped, 0] == 1 and ds.near_family.values[bumped, 0] == "axisymmetric"
    assert 0 < ds.near_eigenvalue_share.values[bumped, 0] < 0.01 and ds.near_eigenvalue.values[bumped, 0] > 0
    assert ds.near_grid_mode_share.values[bumped, 0] == pytest.approx(SHARE, abs=0.01)
    assert np.isnan(ds.near_parameter.values[perfect, 0]) and ds.near_family.values[perfect, 0] == ""
    assert ds.point_grid_mode_share.dims == ("case", "point")
    assert ds.point_grid_mode_share.values[perfect, 0] == pytest.approx(SHARE, abs=0.01)
    assert np.isnan(ds.point_grid_mode_share.values[bumped]).all()  # the bumped case met no critical point
    for name in ("near_parameter", "near_eigenvalue", "near_eigenvalue_share", "near_grid_mode_share",
                 "near_located", "point_grid_mode_share"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    assert ds.near_parameter.attrs["units"] == "m" and ds.near_eigenvalue.attrs["units"] == "s-2"
    with xr.open_dataset(out, mask_and_scale=False) as raw:  # a case without near-critical points: -1, declared
        assert raw.near_located.values.tolist() == [[1], [-1]] and raw.near_located.attrs["_FillValue"] == -1
