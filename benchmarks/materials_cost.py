"""Benchmark: the cost of one compiled RHS evaluation of each material law relative to SVK (issue 24).

For each law (and two fibre-reinforced ones) on the closed sphere (``h = 0.01``, ``n_quad = 4``, one thread):
build the system, compile its RHS (gcc; cached on disk afterwards), and time the compiled evaluator on a
deformed state (``R = 1.1 a``, so nothing sits at a special point of a law): the fastest of ``--rounds``
interleaved batches of about 0.1 s each (the laws take turns, so other load on the machine hits them alike).
Public tools only: mol_shell's ``build`` and the compiled evaluator. Also reports the cell kernel's operation
count (CasADi instructions of one cell's forces), which does not depend on the machine.

Usage: python benchmarks/materials_cost.py [--n 40 2560] [--json out.json]
"""

import json
import statistics
import time

from arguments import MIN_NODES, Parser, integer  # benchmarks/ is this script's folder

import mol_shell
from mol_shell.runs.building import build
from mol_shell.runs.checks import initial_state

CASES = {
    "svk": dict(material="svk"),
    "svk-plane-stress": dict(material="svk-plane-stress"),
    "neo-hookean": dict(material="neo-hookean", nu=0.45),
    "neo-hookean-log": dict(material="neo-hookean-log", nu=0.45),
    "neo-hookean-incompressible": dict(material="neo-hookean-incompressible"),
    "mooney-rivlin": dict(material="mooney-rivlin", c01=3e4),
    "svk-plane-stress + 1 fibre family": dict(material="svk-plane-stress", fibre_E=5e6, fibre_angle=0.6),
    "neo-hookean + 1 fibre family": dict(material="neo-hookean", nu=0.45, fibre_E=5e6, fibre_angle=0.6),
}


def batch_cost(f, y, seconds=0.1):
    """Seconds per evaluation of ``f(y)`` over one batch of about ``seconds`` (Python's call overhead included)."""
    start, calls = time.perf_counter(), 0
    while time.perf_counter() - start < 0.02:
        f(y)
        calls += 1
    per_batch = max(3, int(calls * seconds / 0.02))
    start = time.perf_counter()
    for _ in range(per_batch):
        f(y)
    return (time.perf_counter() - start) / per_batch


def prepare(name, params, n):
    """``(evaluator, state, row)`` of one law on ``n`` nodes (built and compiled here)."""
    scene = mol_shell.Sphere(h=0.01, R=1.1, **params)
    start = time.perf_counter()
    system, compiled = build(scene, n)
    built = time.perf_counter() - start
    compiled.set_threads(1)
    y = initial_state(scene, system)
    f = compiled.evaluator()
    f(y)
    kernel = system.cell_forces_shared_kernel()
    return f, y, {"law": name, "n": n, "cell_kernel_ops": kernel.n_instructions(), "build_and_compile_s": built}


def main():
    parser = Parser(__doc__)  # a value out of its range: one line naming the option, exit code 2
    parser.add_argument("--n", type=integer("--n", MIN_NODES), nargs="+", default=[40, 2560],
                        help="grids to time, each an integer >= 3 (default: 40 2560)")
    parser.add_argument("--laws", nargs="+", default=list(CASES), choices=list(CASES), metavar="LAW",
                        help="laws to time (quote the names with spaces), any of: " + ", ".join(map(repr, CASES))
                             + " (default: all; the column 'x SVK' needs svk among them)")
    parser.add_argument("--rounds", type=integer("--rounds", 1), default=15,
                        help="interleaved batches of about 0.1 s per law; the fastest is reported (an integer >= 1, "
                             "default: 15)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the numbers to this JSON file (default: none, the lines only)")
    args = parser.parse_args()
    rows = []
    for n in args.n:
        prepared = {name: prepare(name, CASES[name], n) for name in args.laws}
        samples = {name: [] for name in args.laws}
        for _ in range(args.rounds):  # interleaved rounds, the fastest of each: robust to other load on the machine
            for name, (f, y, _) in prepared.items():
                samples[name].append(batch_cost(f, y))
        base = min(samples["svk"]) if "svk" in samples else float("nan")
        for name, (_, _, row) in prepared.items():
            row["rhs_us"] = min(samples[name]) * 1e6
            row["rhs_us_median"] = statistics.median(samples[name]) * 1e6
            row["vs_svk"] = row["rhs_us"] / (base * 1e6)
            rows.append(row)
            print(f"n = {n:5d}  {name:36s} {row['rhs_us']:10.1f} us  {row['vs_svk']:6.2f}x SVK  "
                  f"(median {row['rhs_us_median']:.1f} us)  cell kernel {row['cell_kernel_ops']:6d} ops", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
