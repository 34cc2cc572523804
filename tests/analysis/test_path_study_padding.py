"""A study of paths whose cases met different numbers of critical points pads the shorter cases' ``point_located``
with -1, declared as its ``_FillValue`` (docs/netcdf.md: an integer with no value for a case): it was padded with 0,
which already means "not located", so a case that met no critical point read as points met and not located."""

from __future__ import annotations

import numpy as np
import xarray as xr

from mol_shell import Sphere, write_netcdf
from mol_shell.analysis.path_study import _gather


def _path(located):
    """A path file's variables as the study gathers them: two states, one critical point per entry of ``located``."""
    m = len(located)
    return xr.Dataset({"parameter": ("step", [0.0, -500.0]),
                       "point_kind": ("point", np.array(["limit"] * m, dtype=object).astype(str)),
                       "point_family": ("point", np.array(["axisymmetric"] * m, dtype=object).astype(str)),
                       "point_parameter": ("point", -100.0 * (1.0 + np.arange(m))),
                       "point_located": ("point", np.array(located, dtype=np.int8))})


def test_a_case_without_critical_points_reads_as_none_not_as_points_not_located(tmp_path):
    info = {"status": "complete", "message": "", "case_wall_time_s": 0.1}
    cases = [((0,), {"h": 0.0125}), ((1,), {"h": 0.02})]
    results = {(0,): (_path([1, 0, 1]), info), (1,): (_path([]), info)}
    ds = _gather(Sphere(), ["h"], {"h": [0.0125, 0.02]}, cases, results, "pressure")
    write_netcdf(ds, tmp_path / "s.nc")
    with xr.open_dataset(tmp_path / "s.nc", mask_and_scale=False) as raw:  # as stored
        assert raw.point_located.values.tolist() == [[1, 0, 1], [-1, -1, -1]]
        assert raw.point_located.attrs["_FillValue"] == -1
    with xr.open_dataset(tmp_path / "s.nc") as read:  # xarray: NaN where the case has no point
        located = read.point_located.values
        assert located[0].tolist() == [1.0, 0.0, 1.0] and np.isnan(located[1]).all()
