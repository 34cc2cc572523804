"""Benchmark: the targets of issue 25 (SUNDIALS with the loop in compiled code) against a baseline tree (0.5.0).

  paper     the paper's scene, n = 40 to t = 0.143 s: cvode-adams of this tree (and with Newton iterations) and of the
            baseline, and this tree's dop853-c, each on a ladder of tolerances; times compared at equal error (the
            error of this tree's cvode-adams at rtol 1e-6 and 1e-8, log-log interpolation on each ladder)
  viscous   the viscous scene (eta_mu = 100, eta_lambda = 200), n = 640 (``--n-viscous``) to t = 0.01 s: cvode-bdf and
            ida of this tree and of the baseline, scipy-bdf and scipy-radau, on a ladder; compared at the error of this
            tree's cvode-bdf at rtol 1e-6. ``--xlarge``: also n = 10,240, at rtol 1e-6 only (minutes on the baseline)
  overhead  this tree's compiled routes: wall time against RHS evaluations x one RHS + Jacobians x one Jacobian +
            factorisations x one factorisation + linear solves x one solve + root evaluations x one evaluation,
            each cost measured in C at the run's final state

Every measurement runs in its own process (``python -c``) with ``PYTHONPATH`` set to its tree, through the public
``mol_shell.simulate``; in each process one warm-up run (the build, and the kernels from the disk cache), then the
minimum of ``--repeats`` runs of the integration's own wall time (``wall_time_s``). Trees alternate within each
round; the minimum over ``--rounds`` is reported (other load only adds time). The reference of each scene is this
tree's cvode-bdf at rtol 1e-11 with the exact compiled Jacobian; the error is the largest over r, theta, chi of
max |u - u_ref| / max |u_ref| at the final time. Usage:

    python benchmarks/engine.py --baseline /path/to/0.5.0 [--targets paper,viscous,overhead] [--rounds 2] [--xlarge]
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from arguments import MIN_NODES, Parser, integer  # benchmarks/ is this script's folder
from baselines import refuse_baseline

HERE = Path(__file__).resolve().parents[1]
TARGETS = ("paper", "viscous", "overhead", "xlarge")

RUN_PROBE = r"""
import json, sys, warnings
import numpy as np
import mol_shell
scene_name, n, t_end, name, rtol, repeats, opts = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], \
    float(sys.argv[5]), int(sys.argv[6]), json.loads(sys.argv[7])
scene = mol_shell.TwistedCylinder() if scene_name == "paper" else mol_shell.TwistedCylinder(eta_mu=100, eta_lambda=200)
warnings.simplefilter("ignore")
best, ds = float("inf"), None
for k in range(repeats + 1):  # the first: build, kernels from the cache, driver loaded
    ds = mol_shell.simulate(scene, name, n=n, times=[0.0, t_end], progress=False, rtol=rtol, atol=1e-3 * rtol, **opts)
    if k or not repeats:
        best = min(best, float(ds.attrs["wall_time_s"]))
final = {f: np.asarray(ds[f].values)[-1].tolist() for f in ("r", "theta", "chi")}
final["module"] = mol_shell.__file__
keys = ("n_steps", "n_rhs", "n_jac", "n_setups", "n_rhs_jacobian", "status")
print(json.dumps({"wall_s": best, "final": final, **{k: (ds.attrs[k] if isinstance(ds.attrs[k], str) else
                                                        int(ds.attrs[k])) for k in keys if k in ds.attrs}}))
"""

COST_PROBE = r"""
import json, sys, time
import numpy as np
import mol_shell
from mol_shell.integrators import INTEGRATORS
from mol_shell.runs.simulate import build, resolve
scene_name, n, t_end, name, rtol, opts = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], \
    float(sys.argv[5]), json.loads(sys.argv[6])
scene = resolve(mol_shell.TwistedCylinder() if scene_name == "paper" else
                mol_shell.TwistedCylinder(eta_mu=100, eta_lambda=200))
system, compiled = build(scene, n)
y0 = system.initial_state(scene)
method = INTEGRATORS[name](rtol=rtol, atol=1e-3 * rtol, **opts)
best = None
for k in range(3):
    method.parts(system)
    stepper = method.start(system, compiled, y0, [0.0, t_end], None)
    start = time.perf_counter()
    while stepper.t < t_end:
        stepper.advance(t_end)
    wall = time.perf_counter() - start
    if k and (best is None or wall < best[0]):
        best = (wall, stepper.stats(), stepper.solve.costs(20))
wall, s, c = best
# difference quotients: in the Jacobian's measured cost (ours, banded), else counted as right-hand sides (SUNDIALS')
dq_rhs = s["n_rhs_jacobian"] if c["jacobian_s"] != c["jacobian_s"] else 0
# the driver's banded quotients: ml + mu + 1 evaluations each; IDA's jac_reuse evaluates them for a fraction of its
# set-ups (in two parts): count the evaluations made, in whole-Jacobian equivalents
n_jac = s["n_jac"]
if s["jacobian_kind"] == "dq" and c["jacobian_s"] == c["jacobian_s"]:  # measured: the driver's own quotients
    ml, mu = method.parts(system)["bw"]
    n_jac = s["n_rhs_jacobian"] / (ml + mu + 1)
terms = {"rhs": (s["n_rhs"] + dq_rhs, c["rhs_s"]), "jacobian": (n_jac, c["jacobian_s"]),
         "factorisation": (s["n_setups"], c["factorisation_s"]), "solve": (s["n_newton"], c["solve_s"]),
         "roots": (s["n_root_evals"], c["limits_s"])}
terms = {k: (round(m, 1), float(v) if v == v else 0.0) for k, (m, v) in terms.items()}
if s["linsolver"] == "none":
    terms["solve"] = (0, 0.0)  # fixed-point iterations: no linear algebra
print(json.dumps({"wall_s": wall, "terms": terms, "jacobian_kind": s["jacobian_kind"], "linsolver": s["linsolver"],
                  "n_steps": s["n_steps"]}))
"""


def load():
    return "load average (1, 5, 15 min): " + ", ".join(f"{x:.2f}" for x in os.getloadavg())


def probe(tree, code, *args, timeout=3600):
    env = dict(os.environ, PYTHONPATH=str(tree), OMP_NUM_THREADS="1")
    # run outside both trees: ``python -c`` puts the working directory first on sys.path, before PYTHONPATH
    out = subprocess.run([sys.executable, "-c", code, *map(str, args)], env=env, capture_output=True, text=True,
                         timeout=timeout, cwd=tempfile.gettempdir())
    if out.returncode:
        raise RuntimeError(f"probe failed in {tree}: {out.stderr[-1500:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def error(final, ref):
    """Largest over r, theta, chi of max |u - u_ref| / max |u_ref|."""
    return max(float(np.max(np.abs(np.subtract(final[f], ref[f])))) / float(np.max(np.abs(ref[f])))
               for f in ("r", "theta", "chi"))


def at_error(ladder, target):
    """Wall time at ``target`` error by log-log interpolation on ``[(error, wall), ...]`` (None outside)."""
    pts = sorted((e, w) for e, w in ladder if e > 0 and np.isfinite(e))
    if not pts or not pts[0][0] <= target <= pts[-1][0]:
        return None
    le, lw = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.exp(np.interp(np.log(target), le, lw)))


def ladders(configs, scene, n, t_end, rtols, rounds, repeats, ref):
    """``{label: [(rtol, error, wall, stats)]}``, minimum wall over rounds; configs: ``(label, tree, name, opts)``."""
    found = {}
    for _ in range(rounds):
        for rtol in rtols:
            for label, tree, name, opts in configs:
                r = probe(tree, RUN_PROBE, scene, n, t_end, name, rtol, repeats, json.dumps(opts))
                key = (label, rtol)
                if key not in found or r["wall_s"] < found[key]["wall_s"]:
                    found[key] = r
    for label, tree, _, _ in configs:
        module = next(r["final"]["module"] for (lb, _), r in found.items() if lb == label)
        print(f"{label}: {module}")
    table = {}
    for (label, rtol), r in found.items():
        table.setdefault(label, []).append((rtol, error(r["final"], ref), r["wall_s"], r))
    for rows in table.values():
        rows.sort()
    return table


def reference(scene, n, t_end):
    return probe(HERE, RUN_PROBE, scene, n, t_end, "cvode-bdf", 1e-11, 0, json.dumps({"jacobian": "compiled"}))["final"]


def report(table, anchor, targets, title):
    print(f"\n## {title}\n")
    print("| configuration | rtol | error | wall [s] | steps | RHS | Jacobians |")
    print("|---|---|---|---|---|---|---|")
    for label, rows in table.items():
        for rtol, err, wall, r in rows:
            print(f"| {label} | {rtol:g} | {err:.2g} | {wall:.4f} | {r.get('n_steps', '')} | {r.get('n_rhs', '')} | "
                  f"{r.get('n_jac', '')} |")
    out = {}
    for rtol in targets:
        err = next(e for t, e, _, _ in table[anchor] if t == rtol)
        walls = {label: at_error([(e, w) for _, e, w, _ in rows], err) for label, rows in table.items()}
        out[f"{rtol:g}"] = {"error": err, "wall_s": walls}
        print(f"\nAt the error of {anchor} at rtol {rtol:g} ({err:.2g}): wall [s] and ratio to {anchor}")
        for label, w in walls.items():
            ratio = "" if w is None or walls[anchor] is None else f"{w / walls[anchor]:.2f}"
            print(f"- {label}: {'outside its ladder' if w is None else f'{w:.4f}'} {ratio}")
    return out


def target_paper(baseline, rounds, repeats):
    ref = reference("paper", 40, 0.143)
    configs = [("cvode-adams", HERE, "cvode-adams", {}),
               ("cvode-adams newton", HERE, "cvode-adams", {"iteration": "newton"}),
               ("0.5.0 cvode-adams", baseline, "cvode-adams", {}),
               ("dop853-c", HERE, "dop853-c", {})]
    table = ladders(configs, "paper", 40, 0.143, [1e-5, 1e-6, 1e-7, 1e-8, 1e-9], rounds, repeats, ref)
    return report(table, "cvode-adams", [1e-6, 1e-8], "Paper scene, n = 40, t = 0.143 s")


def target_viscous(baseline, rounds, repeats, n, rtols=(1e-5, 1e-6, 1e-7)):
    ref = reference("viscous", n, 0.01)
    configs = [("cvode-bdf", HERE, "cvode-bdf", {}),
               ("cvode-bdf jac_every=200", HERE, "cvode-bdf", {"jac_every": 200, "setup_every": 100}),
               ("ida", HERE, "ida", {}), ("ida jac_reuse=1000", HERE, "ida", {"jac_reuse": 1000}),
               ("0.5.0 cvode-bdf", baseline, "cvode-bdf", {}), ("0.5.0 ida", baseline, "ida", {}),
               ("scipy-bdf", HERE, "scipy-bdf", {}), ("scipy-radau", HERE, "scipy-radau", {})]
    table = ladders(configs, "viscous", n, 0.01, list(rtols), rounds, repeats, ref)
    return report(table, "cvode-bdf", [1e-6], f"Viscous scene (eta_mu = 100, eta_lambda = 200), n = {n}, t = 0.01 s")


def target_xlarge(baseline, threads, n=10240):
    """One run each at rtol 1e-6 (no reference: its solve at rtol 1e-11 would take too long); same tolerance, the
    compiled right-hand side on ``threads`` threads in both trees (its OpenMP maps slow down several times when
    another process holds a core)."""
    print(f"\n## Viscous scene, n = {n}, t = 0.01 s, rtol 1e-6, {threads} thread(s) (one run each, same tolerance)\n")
    opts = json.dumps({"threads": threads})
    print("| configuration | wall [s] | steps | ratio to 0.5.0 |")
    print("|---|---|---|---|")
    out = {}
    for name in ("cvode-bdf", "ida"):
        ours = probe(HERE, RUN_PROBE, "viscous", n, 0.01, name, 1e-6, 0, opts)
        base = probe(baseline, RUN_PROBE, "viscous", n, 0.01, name, 1e-6, 0, opts)
        d = error(ours["final"], base["final"])
        out[name] = {"wall_s": ours["wall_s"], "baseline_wall_s": base["wall_s"], "difference": d}
        print(f"| {name} | {ours['wall_s']:.2f} | {ours.get('n_steps', '')} | {base['wall_s'] / ours['wall_s']:.2f} |")
        print(f"| 0.5.0 {name} | {base['wall_s']:.2f} | {base.get('n_steps', '')} | (difference of the final states "
              f"{d:.2g}) |")
        if name == "ida":  # the Jacobian kept over ten set-ups (docs/performance.md: it costs steps at this size)
            reuse = probe(HERE, RUN_PROBE, "viscous", n, 0.01, name, 1e-6, 0,
                          json.dumps({"threads": threads, "jac_reuse": 10}))
            out["ida jac_reuse=10"] = {"wall_s": reuse["wall_s"], "baseline_wall_s": base["wall_s"]}
            print(f"| ida jac_reuse=10 | {reuse['wall_s']:.2f} | {reuse.get('n_steps', '')} | "
                  f"{base['wall_s'] / reuse['wall_s']:.2f} |")
    return out


def target_overhead():
    cases = [("paper", 40, 0.143, "cvode-adams", {}), ("paper", 40, 0.143, "cvode-adams", {"iteration": "newton"}),
             ("paper", 40, 0.143, "cvode-bdf", {}), ("paper", 40, 0.143, "cvode-bdf", {"jacobian": "compiled"}),
             ("viscous", 640, 0.01, "cvode-bdf", {}), ("viscous", 640, 0.01, "ida", {}),
             ("viscous", 640, 0.01, "ida", {"jac_reuse": 1000})]
    print("\n## Overhead: wall against the sum of counts x costs (each cost measured in C), rtol 1e-6\n")
    print("| scene | n | integrator | options | wall [s] | RHS | Jacobian | factorisations | solves | roots | "
          "sum [s] | wall / sum |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    out = []
    for scene, n, t_end, name, opts in cases:
        r = probe(HERE, COST_PROBE, scene, n, t_end, name, 1e-6, json.dumps(opts))
        terms = r["terms"]
        total = sum(m * c for m, c in terms.values())
        cells = " | ".join(f"{m} x {c * 1e6:.1f} us" for m, c in terms.values())
        print(f"| {scene} | {n} | {name} | {opts or ''} | {r['wall_s']:.4f} | {cells} | {total:.4f} | "
              f"{r['wall_s'] / total:.2f} |")
        out.append({"scene": scene, "n": n, "integrator": name, "options": opts, **r, "sum_s": total})
    return out


def main(argv=None):
    parser = Parser(__doc__.splitlines()[0])  # a value out of its range: one line naming the option, exit 2
    parser.add_argument("--baseline", required=True, help="a checkout of release 0.5.0 (a folder holding mol_shell/)")
    parser.add_argument("--targets", default="paper,viscous,overhead",
                        help=f"comma-separated, any of {', '.join(TARGETS)} (default: paper,viscous,overhead)")
    parser.add_argument("--rounds", type=integer("--rounds", 1), default=2,
                        help="processes per configuration, baseline and this tree alternating; the fastest is "
                             "reported (an integer >= 1, default: 2)")
    parser.add_argument("--repeats", type=integer("--repeats", 0), default=2,
                        help="timed runs in each process, after one warm-up (an integer >= 0; 0: the warm-up alone is "
                             "timed; default: 2)")
    parser.add_argument("--n-viscous", type=integer("--n-viscous", MIN_NODES), default=640,
                        help="grid of the viscous target's scene (an integer >= 3, default: 640)")
    parser.add_argument("--xlarge", action="store_true", help="also the viscous scene at n = 10,240 (rtol 1e-6)")
    parser.add_argument("--threads", type=integer("--threads", 1), default=1,
                        help="threads of the right-hand side at n = 10,240 (an integer >= 1, default: 1)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the numbers to this JSON file (default: none, the tables only)")
    args = parser.parse_args(argv)
    unknown = [t for t in args.targets.split(",") if t not in TARGETS]
    if unknown:
        parser.error(f"--targets {args.targets!r}: unknown {', '.join(unknown)}; allowed: {', '.join(TARGETS)}")
    if refuse_baseline("benchmarks/engine.py", args.baseline):
        return 2
    start = time.perf_counter()
    out = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load_before": os.getloadavg()}
    print(load(), "(before)")
    targets = args.targets.split(",")
    if "paper" in targets:
        out["paper"] = target_paper(args.baseline, args.rounds, args.repeats)
    if "viscous" in targets:
        out["viscous"] = target_viscous(args.baseline, args.rounds, args.repeats, args.n_viscous)
    if args.xlarge or "xlarge" in targets:
        out["viscous_xlarge"] = target_xlarge(args.baseline, args.threads)
    if "overhead" in targets:
        out["overhead"] = target_overhead()
    out["load_after"] = os.getloadavg()
    print(f"\n{load()} (after); {time.perf_counter() - start:.0f} s in all")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
