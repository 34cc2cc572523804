"""A ring ODE's file broadcast onto a grid (``simulate_ring(..., n=21)``) written back as a scene file was refused as
"the run's scene is refused by this version (0.6.0.dev1 wrote it): integrator = 'ring-ode/DOP853' is outside
{leapfrog, ...}" by the version that wrote it; the file without s said what it holds. Both say it now."""

import pytest

import mol_shell
from mol_shell.cli.main import main


@pytest.mark.parametrize("n, tail", [(21, ")"), (None, ", without s)")])
def test_scenes_toml_of_a_ring_ode_file_says_it_holds_the_ring_odes_run(tmp_path, capsys, n, tail):
    path = tmp_path / "ring.nc"
    mol_shell.write_netcdf(mol_shell.simulate_ring(mol_shell.SpinningRing(), t_end=1e-3, n=n), path)
    assert main(["scenes", str(path), "--toml"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"mol-shell: error: FILE = '{path}' is not a mol_shell run or path file; allowed: a netCDF file "
                   "written by mol-shell run or mol-shell path (it holds the reduced ring ODE's run (simulate_ring)"
                   + tail), err
