"""Stability report on stiff and extreme cases of the paper scene (the same as `mol-shell stability`).

Cases (mol_shell.analysis.stability.default_cases): the paper scene; Kelvin-Voigt viscosity eta_mu = 0.01,
1, 100 Pa s (eta_lambda = 2 eta_mu); nu = 0.3 .. 0.4999, and with plane stress; thin shells
h = 1e-2 .. 1e-4 m; twists gamma = 0.5 .. 3 rad/m; a shear psi0 = 1.5 rad near the fold delta = 0;
fast spin omega = 50, 200 rad/s; grids n = 160 .. 10,240. For each: the spectrum of the exact
Jacobian at t = 0 (max |lambda|, fastest damping, stiffness ratio), the leap-frog bound
1/max|lambda| against the largest stable step found by bisection, and runs of leap-frog (at half
the bound), CVODE-BDF and IDA (rtol 1e-6): status, steps, failed steps, wall time, energy error
(with the dissipated energy added back for viscous shells). About 8 minutes, the Jacobians of the large
grids compiled on the way (docs/stability.md).
Writes OUT/stability.nc, .md and .png. ``main`` returns the report's Dataset.
Usage: python studies/stability_report.py [--max-n 10240] [--quick] [--out out] [--output FILE.nc]
(--max-n 640 is `mol-shell stability --quick`; --quick here: two cases on n = 40, the paper scene
and the stiff viscous eta_mu = 100 Pa s, in about 10 s.)
"""

import os

import mol_shell
from mol_shell._core.atomic import write_text
from mol_shell._core.paths import beside
from mol_shell.analysis.stability import default_cases, markdown_table, report
from mol_shell.cli.args import integer_arg
from mol_shell.cli.scripts import finished, output_file, output_folder, run_script, script_parser
from mol_shell.views.stability_plot import plot_report

QUICK_CASES = ("paper", "viscous eta_mu=100")
SMALLEST_GRID = 40  # the report's cases are on n = 40 .. 10,240: --max-n below it would leave none


def cases(max_n=None, quick=False):
    """The report's cases: all of them with grids up to ``max_n``, or the two of ``--quick``."""
    every = default_cases(mol_shell.TwistedCylinder())
    if quick:
        return [case for case in every if case.label in QUICK_CASES]
    return [case for case in every if max_n is None or case.n <= max_n]


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--max-n", type=integer_arg("--max-n", SMALLEST_GRID), default=None,
                        help=f"grid cases up to this n only, >= {SMALLEST_GRID} (default: all, to 10,240)")
    parser.add_argument("--quick", action="store_true", help="two cases: the paper scene and viscous eta_mu = 100 Pa s")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    parser.add_argument("--output", default=None, help="netCDF file (default: OUT/stability.nc)")
    args = parser.parse_args(argv)
    output = output_file(args.output) if args.output else os.path.join(output_folder(args.out), "stability.nc")
    ds = report(cases(args.max_n, args.quick))
    mol_shell.write_netcdf(ds, output)
    write_text(beside(output, ".md"), markdown_table(ds) + "\n")  # beside the name typed (a link's too)
    plot_report(ds, beside(output, ".png"))
    print(markdown_table(ds))
    return finished(ds, "stability report")  # Ctrl-C: the cases before it kept, exit 130


if __name__ == "__main__":
    run_script(main)
