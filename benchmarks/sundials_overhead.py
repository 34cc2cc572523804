"""Benchmark: where the time of a SUNDIALS run through scikit-sundae's Python loop goes (the ``sksundae-*`` routes,
release 0.5.0's), against one compiled RHS evaluation. The compiled routes: benchmarks/engine.py.

Paper scene (n = 40) to t = 0.143 s at rtol = 1e-6 (atol = 1e-9). For CVODE-BDF, CVODE-Adams and
IDA it times the callbacks SUNDIALS makes into Python (right-hand side or residual, Jacobian,
events) and attributes the rest of the wall time to SUNDIALS itself plus scikit-sundae's
wrappers; it also compares stepping with ``onestep`` (exact step counts) against ``normal``
(one call per saved time), and the Jacobian compiled against CasADi's virtual machine.

The columns "in RHS", "in Jacobian", "in events" are seconds spent inside those callbacks over the run, "SUNDIALS +
wrappers" the rest of the wall time (the four add up to wall [s]). "One RHS evaluation" is one call of
``compiled.evaluator()``, the call scikit-sundae's right-hand side callback makes (Python call, copy of y into the
CasADi buffer, compiled kernel), timed as benchmarks/leapfrog_paper.py times it (the median of 7 batches of
20,000; one batch alone, as this script took it before, follows the machine's load: 28.72 us against
leapfrog_paper.py's 9.42 us for the same call in one probe, 12-15 us in both in one process).
Usage: python benchmarks/sundials_overhead.py [--repeats 3] [--json FILE]
"""

import json
import statistics
import time

import numpy as np
from arguments import Parser, integer  # benchmarks/ is this script's folder
from leapfrog_paper import rhs_cost

import mol_shell
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.sundials import _Run, pieces
from mol_shell.runs.simulate import build, resolve

TIMES = np.array([0.0, 0.02, 0.07, 0.106, 0.143])
#: the table's columns: "in RHS" ... "SUNDIALS + wrappers" are seconds of the run (they add up to its wall time)
COLUMNS = ("integrator", "stepping", "wall [s]", "steps", "RHS evals", "Jacobian evals", "us/step", "in RHS [s]",
           "in Jacobian [s]", "in events [s]", "SUNDIALS + wrappers [s]", "SUNDIALS + wrappers per step / one RHS")


def per_call(f, *args, calls=2000):
    f(*args)
    start = time.perf_counter()
    for _ in range(calls):
        f(*args)
    return (time.perf_counter() - start) / calls


def timed_run(method, system, compiled, y0, stepping):
    """One run with timed callbacks; returns (wall, callback seconds by kind, steps, nfev, njev)."""
    spent = {"rhs": 0.0, "jac": 0.0, "events": 0.0}
    run = _Run(method, system, compiled, pieces(system, method.kind, method.jacobian), y0)

    def wrap(fn, key):
        def inner(*a):
            t0 = time.perf_counter()
            fn(*a)
            spent[key] += time.perf_counter() - t0
        return inner

    f, j, e = wrap(run.resfn if run.ida else run.rhsfn, "rhs"), wrap(run.jacfn, "jac"), wrap(run.eventsfn, "events")
    if run.ida:
        run.resfn = lambda t, x, xp, r: f(t, x, xp, r)
        run.jacfn = lambda t, x, xp, r, cj, JJ: j(t, x, xp, r, cj, JJ)
        run.eventsfn = lambda t, x, xp, g: e(t, x, xp, g)
    else:
        run.rhsfn = lambda t, y, yp: f(t, y, yp)
        run.jacfn = lambda t, y, yp, JJ: j(t, y, yp, JJ)
        run.eventsfn = lambda t, y, g: e(t, y, g)
    run.eventsfn.terminal = [True] * run.n_events
    run.eventsfn.direction = [-1] * run.n_events
    start = time.perf_counter()
    solver = method.make_solver(system, run.parts, y0, run)
    if run.ida:
        solver.init_step(0.0, *run.parts["dae"].consistent_rates(y0))
    else:
        solver.init_step(0.0, y0)
    steps, t = 0, 0.0
    for target in TIMES[1:]:
        if stepping == "normal":
            res = solver.step(float(target), tstop=float(target))
        else:
            while t < target:
                res = solver.step(float(target), method="onestep", tstop=float(target))
                steps += 1
                t = float(res.t)
    return time.perf_counter() - start, spent, steps, res.nfev, res.njev


def main():
    parser = Parser(__doc__)  # a value out of its range: one line naming the option, exit code 2
    parser.add_argument("--repeats", type=integer("--repeats", 1), default=3,
                        help="timed runs of each integrator and stepping; the median is reported (an integer >= 1, "
                             "default: 3)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the numbers to this JSON file (default: none, the table only)")
    args = parser.parse_args()
    scene = resolve(mol_shell.TwistedCylinder())
    system, compiled = build(scene, 40)
    y0 = system.initial_state(scene)
    rhs_s = rhs_cost(compiled, y0)  # the callback's call: compiled.evaluator()(y), median of 7 x 20,000
    out = {"compiled_rhs_eval_us": rhs_s * 1e6}
    for kind, name in (("cvode", "cvode-bdf"), ("ida", "ida")):
        for backend in ("compiled", "vm"):
            parts = pieces(system, kind, backend)
            args_ = (0.0, y0) if kind == "cvode" else (0.0, *parts["dae"].consistent_rates(y0), 1e3)
            out[f"{kind}_jacobian_{backend}_us"] = per_call(parts["jac"], *args_, calls=50) * 1e6
    out["events_eval_us"] = per_call(pieces(system, "cvode")["events"], y0, calls=20000) * 1e6
    print(f"one RHS evaluation as the callback calls it (compiled.evaluator()(y): Python call, copy into the CasADi "
          f"buffer, compiled kernel; median of 7 x 20,000 calls): {out['compiled_rhs_eval_us']:.2f} us")
    print("| " + " | ".join(COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    for name in ("sksundae-cvode-adams", "sksundae-cvode-bdf", "sksundae-ida"):  # scikit-sundae's Python loop
        method = INTEGRATORS[name](rtol=1e-6, atol=1e-9)
        counted = 0
        for stepping in ("onestep", "normal"):
            timed_run(method, system, compiled, y0, stepping)
            runs = [timed_run(method, system, compiled, y0, stepping) for _ in range(args.repeats)]
            wall = statistics.median(r[0] for r in runs)
            _, spent, steps, nfev, njev = min(runs, key=lambda r: abs(r[0] - wall))
            steps = steps or counted  # normal mode: the step count of the one-step runs (same steps)
            counted = steps
            rest = wall - sum(spent.values())
            n = steps if steps else float("nan")
            key = f"{name}_{stepping}"
            out[key] = {"wall_s": wall, "steps": steps, "nfev": int(nfev), "njev": int(njev), **spent, "rest_s": rest}
            print(f"| {name} | {stepping} | {wall:.4f} | {steps or ''} | {nfev} | {njev} | "
                  f"{wall / n * 1e6 if steps else float('nan'):.1f} | {spent['rhs']:.4f} | {spent['jac']:.4f} | "
                  f"{spent['events']:.4f} | {rest:.4f} | {(rest / n) / rhs_s if steps else float('nan'):.2f} |")
    for key, value in out.items():
        if not isinstance(value, dict):
            print(f"{key:32s} {value:.4g}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
