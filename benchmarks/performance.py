"""Benchmark: the targets of issue 14 as ratios, each measured in one run, against a baseline tree (release 0.2.0).

  1. rhs     one compiled RHS evaluation, paper scene, n = 40: this tree / baseline (and lean / reference kernel)
  2. large   leap-frog per step at n = 10,240 (the paper scene's grid for its stability study): baseline, this
             tree's generic driver (around the compiled RHS) and its stencil (mol_shell.discretization.stencil,
             what the leap-frog runs for this scene), each on 1 thread and on all threads; projected to the run to
             t = 0.143 s at dt = 1.43 us. ``full`` (not in the default list) times that whole run once with this tree:
             ``mol_shell.simulate`` from the build to the Dataset
  3. peers   work-precision on the paper scene (n = 40, the paper's saved times): the fastest mol_shell
             configuration against the fastest scipy peer at errors 1e-6 and 1e-8, in one process
  4. study   100 cases of the paper scene (gamma varied) at n = 40 to t = 0.02 s: serial against 2 local
             workers (the default start, forked where that is safe, and spawned), the ratio of each round
             besides the fastest runs', and the gcc builds each run made (cache ``builds.log``)

Every measurement runs in its own process with ``PYTHONPATH`` set to its tree, baseline and this tree
alternating ``--rounds`` times; the minimum per configuration is reported (other load only adds time).
The load average is printed before and after: on a shared 2-core machine a busy second core slows the
threaded runs most. Usage:

    python benchmarks/performance.py --baseline /tmp/base020 [--targets rhs,large,peers,study] [--rounds 3]
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from arguments import MIN_NODES, Parser, integer, positive  # benchmarks/ is this script's folder
from baselines import refuse_baseline
from rhs_side_by_side import TIMED_EVALUATIONS

HERE = Path(__file__).resolve().parents[1]
TARGETS = ("rhs", "large", "full", "peers", "study")

RHS_PROBE = r"""
import json, sys, time
import numpy as np
import mol_shell
from mol_shell.runs.simulate import build, resolve
reference = sys.argv[1] == "reference"
scene = resolve(mol_shell.TwistedCylinder())
if reference:
    from mol_shell.discretization.compiled import CompiledRHS
    from mol_shell.discretization.system import ShellSystem
    system = ShellSystem(scene, 40, reference=True)
    compiled = CompiledRHS(system.rhs_mapped, system.limits)
else:
    system, compiled = build(scene, 40)
y = system.initial_state(scene)
y = y + 1e-3 * np.sin(np.arange(y.size))  # a deformed state (round-off at rest makes slow subnormals)
""" + TIMED_EVALUATIONS + r"""
print(json.dumps({"us": best * 1e6, "instructions": int(system.rhs.n_instructions())}))
"""

LARGE_PROBE = r"""
import json, sys, time
import numpy as np
import mol_shell
from mol_shell.runs.simulate import build, resolve
n, steps, threads, driver = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
scene = resolve(mol_shell.TwistedCylinder())
start = time.perf_counter()
system, compiled = build(scene, n)
build_s = time.perf_counter() - start
if hasattr(compiled, "set_threads"):
    compiled.set_threads(threads)
stepper = compiled  # "generic": the leap-frog driver around the compiled RHS (all that release 0.2.0 has)
if driver == "stencil":  # what Leapfrog.integrate runs for this scene (mol_shell.discretization.stencil)
    from mol_shell.discretization.stencil import StencilLeapfrog
    stepper = StencilLeapfrog(system, threads=threads)
y0 = system.initial_state(scene)
dt = 1.43e-6
f = compiled.evaluator()
ya, yb = y0.copy(), y0 + dt * f(y0)  # release 0.2.0: no time argument
import inspect
timed = "t" in inspect.signature(stepper.leapfrog).parameters
run = (lambda m: stepper.leapfrog(ya, yb, m, dt, dt)) if timed else (lambda m: stepper.leapfrog(ya, yb, m, dt))
run(5)  # warm-up (pages, threads)
best = float("inf")
for _ in range(3):
    start = time.perf_counter()
    run(steps)
    best = min(best, (time.perf_counter() - start) / steps)
print(json.dumps({"per_step_s": best, "build_s": build_s, "finite": bool(np.all(np.isfinite(yb)))}))
"""

STUDY_PROBE = r"""
import json, sys, time
import numpy as np
import mol_shell
scheduler, workers, t_end = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
gammas = list(np.linspace(0.5, 1.5, 100) * mol_shell.TwistedCylinder().gamma)
start, epoch = time.perf_counter(), time.time()
ds = mol_shell.study(mol_shell.TwistedCylinder(), {"gamma": gammas}, n=40, t_end=t_end,
                     scheduler=None if scheduler == "local" else scheduler, workers=workers, progress=None)
wall = time.perf_counter() - start
busy = {}
for worker, case in zip(ds.worker.values, np.ravel(ds.case_wall_time_s.values)):
    busy[str(worker)] = busy.get(str(worker), 0.0) + float(case)
print(json.dumps({"wall_s": wall, "epoch": [epoch, epoch + wall], "complete": int((ds.status == "complete").sum()), "busy_s": busy,
                  "case_s": float(np.nanmean(ds.case_wall_time_s.values)), "start": ds.attrs.get("worker_start", "")}))
"""

#: the machine's own ceiling for two processes: half of the cases in each of two independent serial studies
#: started together (no scheduling, no shared table, no results sent between processes)
HALF_PROBE = STUDY_PROBE.replace("gammas = list(", "gammas = list(").replace(
    "* mol_shell.TwistedCylinder().gamma)", "* mol_shell.TwistedCylinder().gamma)[int(sys.argv[4])::2]")


def pair(tree, code, env, *args):
    """Two processes of ``code`` started together; the wall time of their studies, from the first one's start to
    the last one's end (as the other probes measure: the interpreters' start and imports are not in it)."""
    env = dict(os.environ, PYTHONPATH=str(tree), **env)
    start = time.perf_counter()
    procs = [subprocess.Popen([sys.executable, "-c", code, *map(str, args), str(k)], env=env, cwd=str(tree),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for k in (0, 1)]
    outs = [p.communicate() for p in procs]
    wall = time.perf_counter() - start
    for p, (_, err) in zip(procs, outs):
        if p.returncode:
            raise RuntimeError(f"probe failed in {tree}:\n{err[-3000:]}")
    halves = [json.loads(out.strip().splitlines()[-1]) for out, _ in outs]
    return {"wall_s": max(h["epoch"][1] for h in halves) - min(h["epoch"][0] for h in halves),
            "process_wall_s": wall, "halves": halves}


def probe(tree, code, *args, env=None):
    """``code`` run in a fresh interpreter on ``tree`` with ``args``; ``env`` adds variables (``None``: removed)."""
    env = {k: v for k, v in {**os.environ, "PYTHONPATH": str(tree), **(env or {})}.items() if v is not None}
    out = subprocess.run([sys.executable, "-c", code, *map(str, args)], env=env, capture_output=True, text=True,
                         cwd=str(tree))
    if out.returncode:
        raise RuntimeError(f"probe failed in {tree}:\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def load():
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def target_rhs(base, rounds):
    rows = {"baseline": [], "this tree": [], "this tree, reference kernel": []}
    for _ in range(rounds):
        rows["baseline"].append(probe(base, RHS_PROBE, "lean"))
        rows["this tree"].append(probe(HERE, RHS_PROBE, "lean"))
        rows["this tree, reference kernel"].append(probe(HERE, RHS_PROBE, "reference"))
    best = {k: min(r["us"] for r in v) for k, v in rows.items()}
    print("\n## 1. RHS cost, paper scene, n = 40 (one evaluation through a CasADi buffer)\n")
    print("| RHS | us per evaluation | graph instructions | ratio to baseline |")
    print("|---|---|---|---|")
    for k, v in rows.items():
        print(f"| {k} | {best[k]:.2f} | {v[0]['instructions']:,} | {best[k] / best['baseline']:.3f} |")
    return {"rhs_us": best, "ratio": best["this tree"] / best["baseline"]}


def target_large(base, rounds, n, steps, threads):
    configs = {"baseline": (base, 1, "generic"),
               "this tree, generic driver, 1 thread": (HERE, 1, "generic"),
               f"this tree, generic driver, {threads} threads": (HERE, threads, "generic"),
               "this tree, stencil, 1 thread": (HERE, 1, "stencil"),
               f"this tree, stencil, {threads} threads": (HERE, threads, "stencil")}
    rows = {k: [] for k in configs}
    for _ in range(rounds):
        for k, (tree, k_threads, driver) in configs.items():
            rows[k].append(probe(tree, LARGE_PROBE, n, steps, k_threads, driver))
    best = {k: min(r["per_step_s"] for r in v) for k, v in rows.items()}
    total = round(0.143 / 1.43e-6)
    print(f"\n## 2. Leap-frog at n = {n:,}, paper scene ({steps} steps timed, best of {rounds} processes x 3)\n")
    print(f"| configuration | ms per step | us per node and step | projected run to t = 0.143 s ({total:,} steps) "
          "| speed-up over baseline |")
    print("|---|---|---|---|---|")
    for k in rows:
        print(f"| {k} | {best[k] * 1e3:.3f} | {best[k] / n * 1e6:.3f} | {best[k] * total:.0f} s | "
              f"{best['baseline'] / best[k]:.2f} |")
    return {"per_step_s": best, "speedup": best["baseline"] / best[f"this tree, stencil, {threads} threads"]}


FULL_PROBE = r"""
import json, sys, time
import mol_shell
n, threads = int(sys.argv[1]), int(sys.argv[2])
start = time.perf_counter()
ds = mol_shell.simulate(mol_shell.TwistedCylinder(), "leapfrog", n=n, t_end=0.143, dt=1.43e-6, threads=threads,
                        progress=False, stresses=False)
print(json.dumps({"wall_s": time.perf_counter() - start, "steps": int(ds.attrs["n_steps"]),
                  "stepping_s": float(ds.attrs["wall_time_s"]), "complete": int(ds.attrs["complete"])}))
"""


def target_full(n, threads, baseline_per_step=None):
    out = probe(HERE, FULL_PROBE, n, threads)
    print(f"\n## 2b. The whole leap-frog run at n = {n:,} to t = 0.143 s (dt = 1.43 us), this tree, "
          f"{threads} threads\n")
    print(f"{out['steps']:,} steps; {out['stepping_s']:.1f} s stepping, {out['wall_s']:.1f} s from build to Dataset"
          + (f"; release 0.2.0 projected from its per-step time: {baseline_per_step * out['steps']:.0f} s "
             f"({baseline_per_step * out['steps'] / out['wall_s']:.1f}x)" if baseline_per_step else ""))
    return out


PEERS_PROBE = r"""
import json, sys
from mol_shell.analysis import workprecision as wp
names, repeats = sys.argv[1].split(","), int(sys.argv[2])
ds = wp.work_precision("twisted-cylinder", tuple(names), repeats=repeats, log=lambda line: print(line, file=sys.stderr))
out = {}
for target in (1e-6, 1e-8):
    row = {}
    for name in names:
        j = wp.best_at(ds, name, target)
        if j is not None:
            p = ds.sel(integrator=name).isel(level=j)
            row[name] = {"wall_s": float(p.wall_time_s), "error": float(p.error), "setting": float(p[wp.swept(name)]),
                         "n_rhs": int(p.n_rhs)}
    out[f"{target:g}"] = row
print(json.dumps(out))
"""
#: scipy's solvers (the peers) and mol_shell's own configurations (leap-frog, SUNDIALS, the C Runge-Kutta pairs)
SCIPY = ("scipy-rk45", "scipy-dop853", "scipy-radau", "scipy-bdf")
OURS = ("leapfrog", "cvode-bdf", "cvode-adams", "ida", "casadi-cvodes-c", "dop853-c", "rk45-c")


def target_peers(rounds):
    found = probe(HERE, PEERS_PROBE, ",".join(OURS + SCIPY), max(3, rounds))
    print("\n## 3. Ahead of every peer: paper scene, n = 40, the paper's saved times (median of repeats)\n")
    print("| error at most | fastest mol_shell | wall [s] | fastest scipy peer | wall [s] | ratio |")
    print("|---|---|---|---|---|---|")
    ratios = {}
    for target, row in found.items():
        ours = min((k for k in row if k in OURS), key=lambda k: row[k]["wall_s"])
        peer = min((k for k in row if k in SCIPY), key=lambda k: row[k]["wall_s"])
        ratios[target] = row[peer]["wall_s"] / row[ours]["wall_s"]
        print(f"| {target} | {ours} (rtol {row[ours]['setting']:g}, error {row[ours]['error']:.2g}) | "
              f"{row[ours]['wall_s']:.4f} | {peer} (rtol {row[peer]['setting']:g}, error {row[peer]['error']:.2g}) | "
              f"{row[peer]['wall_s']:.4f} | {ratios[target]:.2f} |")
    return {"found": found, "ratio": ratios}


def target_study(rounds, t_end=0.02):
    with tempfile.TemporaryDirectory() as cache:
        env = {"MOL_SHELL_CACHE": cache}
        log = Path(cache, "builds.log")
        runs = {"serial": [], "2 local workers": [], "2 local workers, spawned": [], "two independent halves": []}
        probe(HERE, STUDY_PROBE, "serial", 1, 1e-4, env=env)  # builds the kernels: no timed run compiles
        builds = [len(log.read_text().splitlines()) if log.exists() else 0]
        for k in range(rounds):
            asked = {"2 local workers": None, "2 local workers, spawned": "spawn"}  # None: the default start
            for name in sorted(asked, reverse=bool(k % 2)):  # the two starts take turns to go first
                runs[name].append(probe(HERE, STUDY_PROBE, "local", 2, t_end,
                                        env=dict(env, MOL_SHELL_START_METHOD=asked[name])))
                builds.append(len(log.read_text().splitlines()) if log.exists() else 0)
            runs["serial"].append(probe(HERE, STUDY_PROBE, "serial", 1, t_end, env=env))
            builds.append(len(log.read_text().splitlines()) if log.exists() else 0)
            runs["two independent halves"].append(pair(HERE, HALF_PROBE, env, "serial", 1, t_end))
    best = {k: min(r["wall_s"] for r in v) for k, v in runs.items()}
    local = min(runs["2 local workers"], key=lambda r: r["wall_s"])
    serial = min(runs["serial"], key=lambda r: r["wall_s"])
    halves = min(runs["two independent halves"], key=lambda r: r["wall_s"])
    ceiling = best["serial"] / best["two independent halves"]
    utilisation = sum(local["busy_s"].values()) / (2 * local["wall_s"])
    slowdown = local["case_s"] / serial["case_s"]
    half_slowdown = np.mean([h["case_s"] for h in halves["halves"]]) / serial["case_s"]
    print(f"\n## 4. Study: 100 cases of the paper scene (gamma varied), n = 40, t = {t_end:g} s, fresh compile cache\n")
    print("| scheduler | wall [s] | cases per second | complete | throughput ratio |")
    print("|---|---|---|---|---|")
    for k, v in runs.items():
        complete = v[0]["complete"] if "complete" in v[0] else sum(h["complete"] for h in v[0]["halves"])
        print(f"| {k} | {best[k]:.2f} | {100 / best[k]:.2f} | {complete} | {best['serial'] / best[k]:.2f} |")
    print(f"\ngcc builds in the cache's builds.log after an untimed first study to 0.1 ms and after each run: {builds} "
          "(a build is never repeated: every later run and every other case found the objects on disk)")
    starts = sorted({r["start"] for r in runs["2 local workers"]})
    print(f"\nThe default start of the workers here: {', '.join(starts)}.")
    per_round = {k: [a["wall_s"] / b["wall_s"] for a, b in zip(runs["serial"], runs[k])]
                 for k in ("2 local workers", "2 local workers, spawned")}
    print("Throughput ratio of each round (serial over parallel, run one after the other): " + "; ".join(
        f"{k} {', '.join(f'{r:.2f}' for r in v)} (lowest {min(v):.2f}, median {np.median(v):.2f})"
        for k, v in per_round.items()))
    print("\nWhere the time goes (fastest run of each):\n")
    print(f"* the machine's ceiling, two independent serial halves started together: {ceiling:.2f}x "
          f"(each case {half_slowdown:.2f}x as long as alone; their studies' wall, from the first start to the last "
          f"end, without the interpreters' start and imports, which the other rows leave out too: "
          f"{halves['process_wall_s']:.2f} s with them)")
    print(f"* 2 local processes: each case {slowdown:.2f}x as long as in the serial study; the processes busy "
          f"{100 * utilisation:.1f} % of the wall time (the rest: the worker's start, the last case's tail, results)")
    print(f"* the study's share of the ceiling: {best['serial'] / best['2 local workers'] / ceiling:.3f}")
    return {"wall_s": best, "ratio": best["serial"] / best["2 local workers"], "builds": builds, "ceiling": ceiling,
            "start": starts, "per_round": per_round,
            "utilisation": utilisation, "case_slowdown": slowdown, "half_case_slowdown": half_slowdown}


def main(argv=None):
    parser = Parser(__doc__.splitlines()[0])  # a value out of its range: one line naming the option, exit 2
    parser.add_argument("--baseline", required=True, help="a checkout of release 0.2.0 (a folder holding mol_shell/)")
    parser.add_argument("--targets", default="rhs,large,peers,study",
                        help=f"comma-separated, any of {', '.join(TARGETS)} (default: rhs,large,peers,study; "
                             "full: the whole large run once, after large)")
    parser.add_argument("--rounds", type=integer("--rounds", 1), default=3,
                        help="processes per configuration, baseline and this tree alternating; the fastest is "
                             "reported (an integer >= 1, default: 3; the study target runs one fewer)")
    parser.add_argument("--n-large", type=integer("--n-large", MIN_NODES), default=10240,
                        help="grid of the large and full targets (an integer >= 3, default: 10240)")
    parser.add_argument("--steps", type=integer("--steps", 1), default=40,
                        help="leap-frog steps timed at the large n (an integer >= 1, default: 40)")
    parser.add_argument("--threads", type=integer("--threads", 1), default=os.cpu_count() or 1,
                        help="threads of the multi-threaded runs of the large and full targets (an integer >= 1, "
                             f"default: the machine's cores, {os.cpu_count() or 1} here)")
    parser.add_argument("--study-t-end", type=positive("--study-t-end", "s"), default=0.02,
                        help="simulated time of each study case, s (a number > 0, default: 0.02)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the numbers to this JSON file (default: none, the tables only)")
    args = parser.parse_args(argv)
    unknown = [t for t in args.targets.split(",") if t not in TARGETS]
    if unknown:
        parser.error(f"--targets {args.targets!r}: unknown {', '.join(unknown)}; allowed: {', '.join(TARGETS)}")
    if refuse_baseline("benchmarks/performance.py", args.baseline):
        return 2
    out = {"load_before": os.getloadavg()}
    print(load(), "(before)")
    targets = args.targets.split(",")
    if "rhs" in targets:
        out["rhs"] = target_rhs(args.baseline, args.rounds)
    if "large" in targets:
        out["large"] = target_large(args.baseline, args.rounds, args.n_large, args.steps, args.threads)
    if "full" in targets:
        base = out.get("large", {}).get("per_step_s", {}).get("baseline")
        out["full"] = target_full(args.n_large, args.threads, base)
    if "peers" in targets:
        out["peers"] = target_peers(args.rounds)
    if "study" in targets:
        out["study"] = target_study(max(1, args.rounds - 1), args.study_t_end)
    print()
    print(load(), "(after)")
    summary = []
    if "rhs" in out:
        summary.append(f"1. RHS cost ratio to baseline {out['rhs']['ratio']:.3f} (target <= 0.5)")
    if "large" in out:
        summary.append(f"2. n = {args.n_large} leap-frog speed-up over baseline {out['large']['speedup']:.2f}x "
                       "(target >= 8)")
    if "peers" in out:
        summary.append("3. fastest mol_shell over fastest scipy peer: " + ", ".join(
            f"{r:.2f}x at error {t}" for t, r in out["peers"]["ratio"].items()) + " (target >= 1.5)")
    if "study" in out:
        summary.append(f"4. study throughput ratio {out['study']['ratio']:.2f} (target >= 1.8; the machine's ceiling "
                       f"for two processes {out['study']['ceiling']:.2f})")
    print("\n".join(summary))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
