"""Work-precision on the paper scene: error against run time for every integrator.

The paper's scene (n = 40) to its last snapshot t = 0.143 s, saved at the paper's snapshot
times; a tolerance sweep per integrator (dt for leap-frog); error and reference as in
:mod:`mol_shell.analysis.workprecision`. Writes OUT/work_precision.nc, .png and .md, and prints the
table (the cheapest run of each integrator with error <= 1e-6, speed-up against the paper's
leap-frog at dt = 1e-6). ``main`` returns the Dataset.
Usage: python studies/work_precision.py [--repeats 3] [--t-end 0.143] [--integrators a,b,...] [--quick] [--out out]
(--quick: leap-frog at dt = 1e-5, 5e-6 s and CVODE-Adams at rtol = 1e-5, 1e-7, to t = 0.02 s,
one repeat; about 10 s.)
"""

import os
import time

import numpy as np

import mol_shell
from mol_shell.analysis import workprecision as wp
from mol_shell.cli.args import integer_arg, number_arg
from mol_shell.cli.scripts import finished, output_file, output_folder, run_script, script_parser
from mol_shell.views.workprecision import write_outputs

QUICK = {"t_end": 0.02, "repeats": 1, "integrators": "leapfrog,cvode-adams",
         "sweeps": {"leapfrog": {"dt": (1e-5, 5e-6)}, "cvode-adams": {"rtol": (1e-5, 1e-7)}}}


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--repeats", type=integer_arg("--repeats", 1, wp.MAX_REPEATS), default=None, help="timed repeats per point (default 3)")
    parser.add_argument("--t-end", type=number_arg("--t-end", unit="s"), default=None, help="default: the paper's snapshots up to 0.143 s")
    parser.add_argument("--integrators", default=None, help="default: all")
    parser.add_argument("--quick", action="store_true", help="a tiny sweep of two integrators to t = 0.02 s")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    parser.add_argument("--output", default=None, help="netCDF file (default: OUT/work_precision.nc)")
    args = parser.parse_args(argv)
    quick = QUICK if args.quick else {}
    repeats = args.repeats if args.repeats is not None else quick.get("repeats", 3)
    t_end = args.t_end if args.t_end is not None else quick.get("t_end")
    integrators = args.integrators or quick.get("integrators") or ",".join(wp.DEFAULT_INTEGRATORS)
    output = output_file(args.output) if args.output else os.path.join(output_folder(args.out), "work_precision.nc")
    times = wp.PAPER_TIMES if t_end is None else [float(f"{t:.12g}") for t in np.linspace(0.0, t_end, 5)]
    start = time.perf_counter()
    ds = wp.work_precision(mol_shell.TwistedCylinder(), integrators.split(","), times=times, repeats=repeats,
                  sweeps=quick.get("sweeps"))
    png, md = write_outputs(ds, output)
    print(wp.markdown_table(ds))
    print(f"wrote {output}, {png}, {md} in {time.perf_counter() - start:.0f} s")
    return finished(ds, "work-precision comparison")  # Ctrl-C: the points before it kept, exit 130


if __name__ == "__main__":
    run_script(main)
