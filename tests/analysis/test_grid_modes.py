"""Grid modes among the natural modes: each mode's share in the node-to-node ``(-1)^i`` pattern, stored, marked and
warned about.

Membrane sphere (radius ``a``, plane stress): axisymmetric modes of Legendre degree ``k`` have
``Omega = omega a / c``, ``c = sqrt(E / (rho (1 - nu^2)))``, the roots of
``Omega^4 - Omega^2 (1 + 3 nu + k(k+1)) + (k(k+1) - 2)(1 - nu^2) = 0`` (the meridional and normal equations of
motion with ``u = U dP_k/dalpha``, ``w = W P_k``: their determinant); bending only raises them. The lowest is
``k = 2``'s lower root, 0.70096 for ``nu = 0.3``: 23.236 rad/s for ``E = 1e6`` Pa, ``rho = 1000`` kg m-3,
``a = 1`` m. Lamb's torsional modes: ``omega^2 = (k - 1)(k + 2) G / (rho a^2)``, 2 sqrt(G / rho) / a for ``k = 2``.
"""

import math

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell.analysis.grid_modes import GRID_MODE_SHARE, grid_mode_share, mark_grid_modes
from mol_shell.analysis.modes import modes
from mol_shell.cli.main import main

THIN = ["--set", "h=3e-4", "--set", "material=svk-plane-stress", "--set", "nu=0.3"]


def membrane_sphere_root(k, nu, E=1e6, rho=1000.0, a=1.0):
    """The lower root ``omega`` of the membrane sphere's degree-``k`` axisymmetric modes (module docstring)."""
    lam = k * (k + 1)
    b, c = 1 + 3 * nu + lam, (lam - 2) * (1 - nu**2)
    return math.sqrt((b - math.sqrt(b * b - 4 * c)) / 2) * math.sqrt(E / (rho * (1 - nu**2))) / a


def test_the_share_of_synthetic_shapes():
    """A ``(-1)^i`` pattern under a slow sign-changing envelope of ``k ds`` is grid mode but for the smoothing of the
    envelope, ``(1 + cos k ds) / 2`` (the mean of ``u (-1)^i`` over the meridian, ``grid_mode``'s global form, is
    0); a wave of ``k ds`` has ``(1 - cos k ds) / 2``: 0.5 at four
    nodes a wavelength, 0.012 at 20 (interior nodes, the ends excluded); fields weighted by their kinetic energy."""
    n = 41
    i = np.arange(n)
    envelope = np.sin(2 * np.pi * i / (n - 1))
    shapes = {"z": (-1.0) ** i * envelope, "r": np.cos(np.pi / 2 * i), "chi": np.cos(2 * np.pi / 20 * i),
              "theta": np.zeros(n), "psi": np.zeros(n)}
    fields = list(shapes)
    ds = xr.Dataset({name: (("mode", "s"), np.tile(shapes[name], (3, 1))) for name in fields}
                    | {"energy_fraction": (("mode", "field"), np.eye(5)[:3])}, coords={"field": fields})
    share = grid_mode_share(ds).values
    assert share == pytest.approx([(1 + math.cos(2 * math.pi / 40)) / 2, 0.5, (1 - math.cos(2 * math.pi / 20)) / 2], rel=1e-3)


@pytest.mark.filterwarnings("ignore::mol_shell.MaterialWarning")
def test_the_thin_spheres_lowest_modes_are_flagged_as_grid_modes(tmp_path, capsys):
    """``h = 3e-4``, plane stress, ``nu = 0.3`` on 41 nodes: the three lowest modes, 14.65 .. 15.18 rad/s, lie below
    the membrane sphere's lowest (23.236 rad/s): grid modes, flagged in the file, the printout and one warning."""
    out = tmp_path / "m.nc"
    assert main(["modes", "sphere", *THIN, "--n", "41", "--count", "3", "-o", str(out)]) == 0
    said = capsys.readouterr()
    ds = mol_shell.read_netcdf(out)
    lowest = membrane_sphere_root(2, 0.3)
    assert lowest == pytest.approx(23.236, abs=1e-3)
    assert (ds.frequency.values < 0.7 * lowest).all()  # the premise: far below every physical mode
    assert (ds.grid_mode_share.values >= 0.8).all()
    assert ds.grid_mode_share.attrs["units"] == "1" and "(-1)^i" in ds.grid_mode_share.attrs["long_name"]
    assert said.out.count("grid mode (-1)^i: 0.") == 3
    warning = [line for line in said.err.splitlines() if "grid mode" in line]
    assert len(warning) == 1 and "modes 1, 2, 3" in warning[0] and "refining n moves them up" in warning[0]
    assert ds.attrs["grid_mode_warning"] in warning[0]


def test_a_normal_spheres_modes_are_not_grid_modes(recwarn):
    """The paper's sphere (``h = 6.3e-3``, nu = 0.49) on 41 nodes: its ten lowest modes are resolved; among them
    Lamb's torsional mode (``chi`` only) at 2 sqrt(G / rho) / a = 36.6 rad/s; none is flagged, nothing said."""
    scene = mol_shell.Sphere()
    ds = modes(scene, n=41, count=10)
    assert (ds.grid_mode_share.values < GRID_MODE_SHARE).all() and "grid_mode_warning" not in ds.attrs
    torsion = int(np.flatnonzero(ds.energy_fraction.sel(field="chi").values > 0.99)[0])
    G = scene.E / (2 * (1 + scene.nu))
    assert float(ds.frequency[torsion]) == pytest.approx(2 * math.sqrt(G / scene.rho) / scene.a, rel=0.01)
    assert float(ds.grid_mode_share[torsion]) < 0.05
    assert not [w for w in recwarn if "grid mode" in str(w.message)]


@pytest.mark.parametrize(("frequency", "span"), [
    ([0.0, 0.0], "modes 1, 2 (at 0 rad/s: omega^2 zero to round-off) are grid modes"),
    ([0.0, 14.65, 15.18], "modes 1, 2, 3 (14.65 .. 15.18 rad/s; 1 at 0 rad/s: omega^2 zero to round-off) are"),
    ([14.65], "mode 1 (14.65 rad/s) is a grid mode"),
])
def test_the_warning_says_grid_modes_at_zero_apart_from_the_range(frequency, span):
    """Grid modes whose omega^2 is zero to round-off (listed at 0 rad/s: the natural sphere at h = 1e-8 m, n = 21) were
    said as ``modes 1, 2 (0 .. 0 rad/s)``: the zero ones are said apart, not as ends of a range of frequencies."""
    i = np.arange(21)
    count = len(frequency)
    fields = ["z", "r", "chi", "theta", "psi"]
    shapes = {name: np.tile((-1.0) ** i if name == "r" else np.zeros(21), (count, 1)) for name in fields}
    ds = xr.Dataset({name: (("mode", "s"), shapes[name]) for name in fields}
                    | {"energy_fraction": (("mode", "field"), np.tile(np.eye(5)[1], (count, 1))),
                       "frequency": (("mode",), frequency)}, coords={"field": fields})
    with pytest.warns(UserWarning, match="grid mode"):
        mark_grid_modes(ds)
    assert ds.attrs["grid_mode_warning"].startswith(span), ds.attrs["grid_mode_warning"]
