"""Benchmark: cost of one compiled RHS evaluation per node, this tree against a baseline tree, side by side.

Each measurement runs in its own process (``PYTHONPATH`` set to the tree), alternating baseline and this
tree ``--rounds`` times, and the minimum per tree is reported (the machine's other load only adds time).
Also times curved meridians of this tree (sphere, cone, torus) per node against the paper's cylinder.

Usage: git worktree add /tmp/base020 <0.2.0 commit>; python benchmarks/rhs_side_by_side.py --baseline /tmp/base020
"""

import json
import os
import subprocess
import sys
from pathlib import Path

from arguments import MIN_NODES, Parser, integer  # benchmarks/ is this script's folder
from baselines import refuse_baseline

#: the end of a probe: the best of 9 rounds of 20,000 evaluations of ``compiled`` at ``y`` (microseconds in ``best``);
#: benchmarks/performance.py uses it too
TIMED_EVALUATIONS = r"""
f = compiled.evaluator()
f(y)
best = float("inf")
for _ in range(9):
    start = time.perf_counter()
    for _ in range(20000):
        f(y)
    best = min(best, (time.perf_counter() - start) / 20000)
"""

PROBE = r"""
import json, sys, time
import numpy as np
import mol_shell
from mol_shell.runs.simulate import build, resolve
name, n = sys.argv[1], int(sys.argv[2])
if name == "paper":
    scene = mol_shell.TwistedCylinder()
else:  # a deformed state: at the natural state at rest products of round-off make subnormal numbers, slow on x86
    from mol_shell.scenes import SCENES
    scene = SCENES[name](gamma=0.05, **({"R": 1.01} if name == "sphere" else {"dilation": 1.01}))
scene = resolve(scene)
system, compiled = build(scene, n)
y = system.initial_state(scene)
""" + TIMED_EVALUATIONS + r"""
print(json.dumps({"us": best * 1e6, "n": n, "instructions": int(system.rhs.n_instructions())}))
"""


def measure(tree, name, n):
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, "-c", PROBE, name, str(n)], env=env, capture_output=True, text=True,
                         check=True, cwd=str(tree))
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = Parser(__doc__.splitlines()[0])  # a value out of its range: one line naming the option, exit 2
    parser.add_argument("--baseline", required=True,
                        help="a checkout of the release to compare with, e.g. 0.2.0 (a folder holding mol_shell/)")
    parser.add_argument("--rounds", type=integer("--rounds", 1), default=3,
                        help="processes per tree and scene, baseline and this tree alternating; the fastest is "
                             "reported (an integer >= 1, default: 3)")
    parser.add_argument("--n", type=integer("--n", MIN_NODES), default=40, help="grid of every scene (an integer >= 3, default: 40)")
    args = parser.parse_args(argv)
    if refuse_baseline("benchmarks/rhs_side_by_side.py", args.baseline):
        return 2
    here = Path(__file__).resolve().parents[1]
    base, new = [], []
    for _ in range(args.rounds):
        base.append(measure(args.baseline, "paper", args.n))
        new.append(measure(here, "paper", args.n))
    b, c = min(x["us"] for x in base), min(x["us"] for x in new)
    print(f"paper scene, n = {args.n}: baseline {b:.2f} us ({base[0]['instructions']} instructions), "
          f"this tree {c:.2f} us ({new[0]['instructions']} instructions); ratio {c / b:.3f}")
    for name in ("sphere", "cone", "torus"):
        t = min(measure(here, name, args.n)["us"] for _ in range(args.rounds))
        print(f"{name:7s} n = {args.n}: {t:.2f} us, per node {t / args.n:.3f} us; ratio to the paper cylinder {t / c:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
