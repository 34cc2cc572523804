"""Benchmark: the paper's leap-frog run against the cost of one compiled RHS evaluation.

Runs the paper scene (n = 40, dt = 1e-6, t_end = 0.143) and reports
wall time / (steps x one compiled RHS evaluation), both measured in this process. The RHS evaluation is timed
as benchmarks/sundials_overhead.py times it (:func:`rhs_cost`). The scene is the paper's, its law SVK at
nu = 0.49, which mol_shell warns about: said in one line, as the command line says it.
Usage: python benchmarks/leapfrog_paper.py [--repeats 3]
"""

import json
import statistics
import time
import warnings

import numpy as np
from arguments import Parser, integer  # benchmarks/ is this script's folder

import mol_shell
from mol_shell.cli.outcome import one_line_warnings
from mol_shell.runs.simulate import build, resolve


def rhs_cost(compiled, y, calls=20000, batches=7):
    """Median over ``batches`` of ``calls`` evaluations: seconds per call of ``compiled.evaluator()`` at ``y``.

    That is the call the Python loops make (scikit-sundae's right-hand side callback, the explicit drivers): the
    Python call, the copy of ``y`` into a preallocated CasADi buffer, the compiled kernel. The call's share is
    well under 1 us, so this slightly overstates the kernel itself. benchmarks/sundials_overhead.py uses it too.
    """
    f = compiled.evaluator()
    f(y)
    per = []
    for _ in range(batches):
        start = time.perf_counter()
        for _ in range(calls):
            f(y)
        per.append((time.perf_counter() - start) / calls)
    return statistics.median(per)


def main():
    parser = Parser(__doc__)  # a value out of its range: one line naming the option, exit code 2
    parser.add_argument("--repeats", type=integer("--repeats", 1), default=3,
                        help="runs of the leap-frog; the median is reported (an integer >= 1, default: 3)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the numbers to this JSON file (default: none, the lines only)")
    args = parser.parse_args()
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    y0 = system.initial_state(scene)
    per_rhs = rhs_cost(compiled, y0)
    walls = []
    for _ in range(args.repeats):
        ds = mol_shell.simulate(scene, times=[0, 0.02, 0.07, 0.106, 0.143], dt=1e-6, progress=False)
        walls.append(ds.attrs["wall_time_s"])
    wall = statistics.median(walls)
    steps = ds.attrs["n_steps"]
    out = {
        "n": 40,
        "dt": 1e-6,
        "t_end": 0.143,
        "steps": steps,
        "rhs_instructions": ds.attrs["rhs_instructions"],
        "compiled_rhs_eval_us": per_rhs * 1e6,
        "wall_time_s": wall,
        "wall_per_step_us": wall / steps * 1e6,
        "ratio_wall_to_steps_x_rhs": wall / (steps * per_rhs),
        "energy_rel_drift": float(abs(ds.energy[-1] - ds.energy[0]) / ds.energy[0]),
    }
    for key, value in out.items():
        print(f"{key:28s} {value:.6g}" if isinstance(value, float) else f"{key:28s} {value}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    np.seterr(all="raise")
    with warnings.catch_warnings():
        one_line_warnings("benchmarks/leapfrog_paper.py")  # the paper's law at nu = 0.49: one line, not Python's
        main()
