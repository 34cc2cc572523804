"""Stability report on stiff and extreme cases of the paper scene (the same as `mol-shell stability`).

Cases (mol_shell.stability.default_cases): the paper scene; Kelvin-Voigt viscosity eta_mu = 0.01,
1, 100 Pa s (eta_lambda = 2 eta_mu); nu = 0.3 .. 0.4999, and with plane stress; thin shells
h = 1e-2 .. 1e-4 m; twists gamma = 0.5 .. 3 rad/m; a shear psi0 = 1.5 rad near the fold delta = 0;
fast spin omega = 50, 200 rad/s; grids n = 160 .. 10,240. For each: the spectrum of the exact
Jacobian at t = 0 (max |lambda|, fastest damping, stiffness ratio), the leap-frog bound
1/max|lambda| against the largest stable step found by bisection, and runs of leap-frog (at half
the bound), CVODE-BDF and IDA (rtol 1e-6): status, steps, failed steps, wall time, energy error
(with the dissipated energy added back for viscous shells). About 10 minutes on 2 cores.
Writes out/stability.nc, .md and .png.
Usage: python studies/stability_report.py [--quick] [--output out/stability.nc]
"""

import argparse
import os

import mol_shell
from mol_shell.stability import default_cases, markdown_table, report
from mol_shell.stability_plot import plot_report


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="grids up to n = 640 only")
    parser.add_argument("--output", default=os.path.join("out", "stability.nc"))
    args = parser.parse_args()
    os.makedirs(os.path.dirname(args.output) or ".", exist_ok=True)
    ds = report(default_cases(mol_shell.TwistedCylinder(), quick=args.quick))
    ds.to_netcdf(args.output)
    stem = args.output.rsplit(".", 1)[0]
    with open(stem + ".md", "w") as fh:
        fh.write(markdown_table(ds) + "\n")
    plot_report(ds, stem + ".png")
    print(markdown_table(ds))


if __name__ == "__main__":
    main()
