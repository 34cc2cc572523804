"""Moduli, viscosities and the density are 0 (where allowed) or normal doubles, one stated bound for all values.

``E = 1e-320`` was accepted and ran from R = 1 m (every other E gives 0.9948441944 m), with energy 0 and an
ellipticity margin of NaN; ``E = 1e-310`` was refused "outside about [3.491e-309, inf) Pa" while 1e-315 and 1e-320
passed, and ``E = 5e-324`` was refused with another bound: a subnormal modulus keeps a few digits, or none, in the
products it enters. Above the bound, svk-plane-stress's condensed ``2 lambda mu / (lambda + 2 mu)`` underflowed
from E ~ 1e-154 on (R off by 2e-3 at E = 1e-200), and the radius's Newton iteration ran out of iterations at
E = 3e-308 Pa while it converged at 2.3e-308."""

import dataclasses
import math
import sys

import pytest

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.model.equilibrium import equilibrium_radius
from mol_shell.results.dataset import read_netcdf

TINY = sys.float_info.min
SUBNORMAL = [math.nextafter(TINY, 0), 1e-310, 1e-315, 1e-320, 5e-324]
#: the parameters of the kind, and whether 0 is allowed
MODULI = {"E": False, "rho": False, "c10": False, "c01": True, "fibre_E": True, "eta_lambda": True, "eta_mu": True}


@pytest.mark.parametrize(("name", "zero"), MODULI.items())
def test_a_subnormal_modulus_is_refused_below_one_stated_bound(name, zero):
    base = mol_shell.TwistedCylinder()
    allowed = ("0 or " if zero else "") + "[2.2250738585072014e-308, inf)"
    assert getattr(dataclasses.replace(base, **{name: TINY}), name) == TINY
    for value in SUBNORMAL:
        with pytest.raises(ParameterError) as info:
            dataclasses.replace(base, **{name: value})
        assert info.value.name == name and f"is outside {allowed}" in str(info.value)
        assert "subnormal" in str(info.value) and value not in info.value.range
    assert (0.0 in info.value.range) == zero and TINY in info.value.range


def test_e_at_the_bound_runs_from_the_radius_of_every_other_e_and_below_it_is_refused(tmp_path, capsys):
    out = tmp_path / "E.nc"
    for E in ("1e-320", "1e-315", "1e-310"):
        assert main(["run", "twisted-cylinder", "--n", "6", "--t-end", "1e-5", "--set", f"E={E}", "-o", str(out)]) == 2
        said = (f"mol-shell: error: E = {E} is outside [2.2250738585072014e-308, inf) Pa (a subnormal number: the "
                "products it enters lose their digits or vanish)")
        assert capsys.readouterr().err.strip().splitlines() == [said]
    assert main(["run", "twisted-cylinder", "--n", "6", "--t-end", "1e-5", "--set", f"E={TINY!r}", "-o", str(out)]) == 0
    assert float(read_netcdf(out).attrs["R"]) == pytest.approx(0.9948441944, rel=1e-10)


def test_the_radius_does_not_depend_on_the_scale_of_the_moduli_down_to_the_bound():
    radius = equilibrium_radius(mol_shell.TwistedCylinder(material="svk-plane-stress"))
    for E in (1e-100, 1e-200, 1e-300, 1.1e-307, 5e-308, 4e-308, 3e-308, TINY):
        assert equilibrium_radius(mol_shell.TwistedCylinder(material="svk-plane-stress", E=E)) == pytest.approx(
            radius, rel=1e-11), E
