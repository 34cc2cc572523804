"""A small run file of the paper's scene for the views' tests, and the options that keep their figures small."""

import numpy as np

import mol_shell

#: animate's options for a small, quick animation
SMALL = ["--n-phi", "6", "--fibres", "2", "--width", "100"]


def paper_run_file(folder, n, saved):
    """``folder/run.nc``: the paper's scene on ``n`` nodes, ``saved`` times 1 us apart, without stresses."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=n, times=np.arange(saved) * 1e-6, progress=False,
                            stresses=False)
    path = folder / "run.nc"
    mol_shell.write_netcdf(ds, path)
    return path
