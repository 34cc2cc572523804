"""Every kind of file says the units of its global numbers (``units_<name>``) and has a global ``comment``
(docs/netcdf.md): modes files had no ``units_*`` at all, path files ``start``/``stop`` without units, ``zeta1_used``
lacked them in modes, path and path-study files, a compare file's ``reference_error`` had none, and path, compare,
stability, ring and modes files had no ``comment``."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mol_shell
from mol_shell.analysis.modes import modes
from mol_shell.analysis.path_study import path_study
from mol_shell.analysis.stability import Case, report
from mol_shell.analysis.workprecision import work_precision
from mol_shell.results.dataset import read_netcdf, write_netcdf
from mol_shell.scenes import Sphere, TwistedCylinder

#: units of the named numbers, written out here from their meaning (docs/scenes.md, docs/netcdf.md)
SCENE_UNITS = {"h": "m", "E": "Pa", "rho": "kg m-3", "pressure": "Pa", "zeta1": "m", "zeta1_used": "m", "nu": "1",
               "a": "m", "gravity": "m s-2", "end1_torque": "N m", "eta_mu": "Pa s"}


def _quiet(make):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return make()


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """One small file of each kind, written and read back."""
    folder = tmp_path_factory.mktemp("units")
    made = {
        "modes": lambda: modes("sphere", n=11, count=3),
        "path": lambda: mol_shell.path(Sphere(), "pressure", 0.0, -1000.0, n=11, max_steps=3),
        "path-study": lambda: path_study(Sphere(), {"nu": [0.3, 0.35]}, "pressure", 0.0, -1000.0, n=11, max_steps=2,
                                         scheduler="serial"),
        "compare": lambda: work_precision("twisted-cylinder", ["cvode-bdf"], n=11, times=[0, 0.005, 0.01],
                                          repeats=1, sweeps={"cvode-bdf": {"rtol": [1e-4]}}, log=lambda *a: None),
        "stability": lambda: report([Case("n=5", TwistedCylinder(), n=5, t_end=0.002)], bisect=False),
        "ring": lambda: mol_shell.simulate_ring(mol_shell.SpinningRing(), t_end=0.002),
    }
    out = {}
    for kind, make in made.items():
        write_netcdf(_quiet(make), folder / f"{kind}.nc")
        out[kind] = read_netcdf(folder / f"{kind}.nc")
    return out


@pytest.mark.parametrize("kind", ["modes", "path", "path-study", "compare", "stability", "ring"])
def test_every_file_has_a_comment(files, kind):
    assert str(files[kind].attrs.get("comment", "")).strip(), kind


@pytest.mark.parametrize("kind", ["modes", "path", "path-study", "compare", "ring"])
def test_the_scene_s_parameters_and_zeta1_used_carry_their_units(files, kind):
    attrs = files[kind].attrs
    named = [name for name in SCENE_UNITS if name in attrs and isinstance(attrs[name], (int, float, np.number))]
    if kind != "ring":
        assert "zeta1_used" in named or kind == "compare", (kind, named)
    assert len(named) >= 4, (kind, named)
    for name in named:
        assert attrs.get(f"units_{name}") == SCENE_UNITS[name], (kind, name, attrs.get(f"units_{name}"))


def test_a_path_s_range_is_in_the_units_of_its_parameter(files):
    attrs = files["path"].attrs
    assert attrs["parameter"] == "pressure"
    assert attrs["units_start"] == attrs["units_stop"] == "Pa"
    assert attrs["units_arclength_load_scale"] == "Pa" and attrs["units_arclength_displacement_scale"] == "1"


def test_a_comparison_s_reference_error_is_dimensionless_and_its_times_in_seconds(files):
    attrs = files["compare"].attrs
    assert attrs["units_reference_error"] == "1" and attrs["units_times"] == "s"


def test_a_modes_file_s_margin_is_dimensionless(files):
    attrs = files["modes"].attrs
    assert attrs["units_ellipticity_margin"] == "1" and attrs["units_R"] == "m"
