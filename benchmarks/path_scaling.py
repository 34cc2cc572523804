"""Benchmark: time and memory per step of an equilibrium path against n (a closed sphere through its first
critical point), with the counts of factorisations and of evaluations per step.

The sphere of tests/analysis/test_path.py (``a = 1 m``, ``a/t = 39.9``, ``E = 1 MPa``, ``nu = 0.3``, plane-stress
SVK), whose first critical point is the axisymmetric bifurcation into ``P_11`` at 0.97 of the classical pressure:
each ``n`` runs ``mol_shell.path`` from 0 to ``-0.975 p_cl`` (a first step of a tenth; the next critical point, at 0.98, is left out) in a fresh process, and reports

* wall time, per step (build of the graphs apart),
* peak resident memory of the process (``ru_maxrss``) and the Python-side peak of the path (``tracemalloc``,
  which sees NumPy's arrays but not SuperLU's or ARPACK's own allocations),
* per step: sparse LU factorisations (``splu``: correctors, tangents, eigen solves, determinants, the location of
  critical points), evaluations of ``F`` with its Jacobian, of ``F`` alone, and of the mass matrix (each one
  evaluation of the dynamics' full Jacobian, whose block ``dq_t/dp`` is ``M^-1``).

Usage: python benchmarks/path_scaling.py [--n 641 2561 10241] [--json out.json]
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

from arguments import MIN_NODES, Parser, integer  # benchmarks/ is this script's folder

CHILD = r'''
import json, math, resource, sys, time, tracemalloc
import scipy.sparse.linalg
import mol_shell
from mol_shell.analysis import equilibria
n = int(sys.argv[1])
E, NU, A = 1.0e6, 0.3, 1.0
h = A / (2 * 11 * 12 / math.sqrt(12 * (1 - NU**2)))
p_cl = 2 * E * (2 * h) ** 2 / (A**2 * math.sqrt(3 * (1 - NU**2)))
counts = {"splu": 0, "jacobian": 0, "residual": 0, "mass": 0}
splu = scipy.sparse.linalg.splu
def counted_splu(*args, **kwargs):
    counts["splu"] += 1
    return splu(*args, **kwargs)
scipy.sparse.linalg.splu = counted_splu
evaluate, residual = equilibria.EquilibriumEquations.evaluate, equilibria.EquilibriumEquations.residual
def counted_evaluate(self, *args):
    counts["jacobian"] += 1
    return evaluate(self, *args)
def counted_residual(self, *args):
    counts["residual"] += 1
    return residual(self, *args)
mass = equilibria.EquilibriumEquations.mass
def counted_mass(self, *args):
    counts["mass"] += 1
    return mass(self, *args)
equilibria.EquilibriumEquations.mass = counted_mass
equilibria.EquilibriumEquations.evaluate = counted_evaluate
equilibria.EquilibriumEquations.residual = counted_residual
sphere = mol_shell.Sphere(a=A, h=h, E=E, nu=NU, material="svk-plane-stress")
start = time.perf_counter()
eq = equilibria.EquilibriumEquations(sphere, "pressure", n)
eq.evaluate(eq.unknowns(eq.y_ref), 0.0)
build = time.perf_counter() - start
for k in counts:
    counts[k] = 0
tracemalloc.start()
start = time.perf_counter()
ds = mol_shell.path(sphere, "pressure", 0.0, -0.975 * p_cl, n=n, steps=10)
wall = time.perf_counter() - start
traced = tracemalloc.get_traced_memory()[1]
steps = ds.sizes["step"] - 1
first = float(ds.point_parameter.values.max()) / -p_cl if ds.sizes["point"] else float("nan")
print(json.dumps({"n": n, "steps": steps, "status": ds.attrs["status"], "points": int(ds.sizes["point"]),
                  "first_critical_over_p_cl": first, "build_s": build, "wall_s": wall - build,
                  "per_step_s": (wall - build) / steps, "maxrss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3,
                  "traced_peak_MB": traced / 1e6, **{k + "_per_step": v / steps for k, v in counts.items()}}))
'''


def main():
    parser = Parser(__doc__)  # a value out of its range: one line naming the option, exit code 2
    parser.add_argument("--n", type=integer("--n", MIN_NODES), nargs="+", default=[641, 2561, 10241],
                        help="grids, each an integer >= 3 (default: 641 2561 10241); on coarse grids (n = 41, not 61) "
                             "the first critical point lies beyond the path's end, -0.975 p_cl, and the row says so")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the rows to this JSON file (default: none, the table only)")
    args = parser.parse_args()
    rows = []
    for n in args.n:
        out = subprocess.run([sys.executable, "-c", CHILD, str(n)], capture_output=True, text=True, check=False)
        if out.returncode:  # the child's last line (its error), not its whole source from CalledProcessError
            said = (out.stderr.strip().splitlines() or [f"exit code {out.returncode}"])[-1]
            sys.exit(f"{parser.prog}: n = {n}: the path's process failed: {said}")
        row = json.loads(out.stdout.strip().splitlines()[-1])
        if not row["points"]:
            row["note"] = (f"n = {n}: no critical point by -0.975 p_cl, where the path stops: the grid is too coarse "
                           "to reach the first critical point (0.97 p_cl on fine grids; a coarse grid is stiffer and "
                           "puts it beyond the path's end), so this row times a path without one")
        rows.append(row)
        print(json.dumps(row), flush=True)
    print("| n | steps | first critical / p_cl | s per step | LU per step | F+J per step | F per step | M per step | "
          "peak RSS (MB) | Python peak (MB) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        first = f"{r['first_critical_over_p_cl']:.5f}" if r["points"] else "none by 0.975 (grid too coarse)"
        print(f"| {r['n']} | {r['steps']} | {first} | {r['per_step_s']:.3g} | "
              f"{r['splu_per_step']:.1f} | {r['jacobian_per_step']:.1f} | {r['residual_per_step']:.1f} | "
              f"{r['mass_per_step']:.1f} | "
              f"{r['maxrss_MB']:.0f} | {r['traced_peak_MB']:.0f} |")
    for r in rows:
        if "note" in r:
            print(r["note"])
    if len(rows) > 1:
        a, b = rows[0], rows[-1]
        slope = math.log(b["per_step_s"] / a["per_step_s"]) / math.log(b["n"] / a["n"])
        print(f"time per step grows like n^{slope:.2f} from n = {a['n']} to {b['n']} "
              f"(n log n would be n^{1 + math.log(math.log(b['n']) / math.log(a['n'])) / math.log(b['n'] / a['n']):.2f})")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
