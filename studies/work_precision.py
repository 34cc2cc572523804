"""Work-precision on the paper scene: error against run time for every integrator.

The paper's scene (n = 40) to its last snapshot t = 0.143 s, saved at the paper's snapshot
times; a tolerance sweep per integrator (dt for leap-frog); error and reference as in
:mod:`mol_shell.workprecision`. Writes out/work_precision.nc, .png and .md, and prints the
table (the cheapest run of each integrator with error <= 1e-6, speed-up against the paper's
leap-frog at dt = 1e-6).
Usage: python studies/work_precision.py [--repeats 3] [--t-end 0.143] [--integrators a,b,...]
"""

import argparse
import os
import time

import numpy as np

import mol_shell
from mol_shell import workprecision as wp


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--t-end", type=float, default=None, help="default: the paper's snapshots up to 0.143 s")
    parser.add_argument("--integrators", default=",".join(wp.DEFAULT_INTEGRATORS))
    parser.add_argument("--output", default=os.path.join("out", "work_precision.nc"))
    args = parser.parse_args()
    times = wp.PAPER_TIMES if args.t_end is None else np.linspace(0.0, args.t_end, 5)
    os.makedirs(os.path.dirname(args.output) or ".", exist_ok=True)
    start = time.perf_counter()
    ds = wp.study(mol_shell.TwistedCylinder(), args.integrators.split(","), times=times, repeats=args.repeats)
    png, md = wp.write_outputs(ds, args.output)
    print(wp.markdown_table(ds))
    print(f"wrote {args.output}, {png}, {md} in {time.perf_counter() - start:.0f} s")
    return ds


if __name__ == "__main__":
    main()
