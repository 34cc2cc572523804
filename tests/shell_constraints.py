"""Repeated constrained solves of the shell with mol_shell's own CVODE and IDA set-up, to check the
workaround for scikit-sundae 1.2.0's constraints defect where the package uses it.

`python shell_constraints.py {full|partial} SOLVES INTEGRATOR [INTEGRATOR ...]` runs SOLVES solves of
the twisted cylinder (n = 10, 100 states, `r > 0` constrained at each of the 10 nodes, root-finding
events on) to t = 4 ms with each integrator (cvode-bdf, cvode-adams, ida) and prints one line per
integrator: `name failures solves spread`, where spread is the largest difference between the final
state of a successful solve and that of the first one (0.0: bit-identical repeats). "full" is the
package as it is (every entry listed, :func:`mol_shell.integrators.sundials.full_constraints`);
"partial" swaps in the list the defect needs (the constrained entries only), to show that this
harness detects the defect.

Run it with glibc's MALLOC_PERTURB_ set (every allocation is filled with a byte pattern, e.g. 0x5a..
= 1.4e127 as a double) and GLIBC_TUNABLES=glibc.malloc.tcache_count=0 (blocks recycled through the
per-thread cache skip that fill and could hand back old, valid constraint values): memory the solver
reads without initialising it is then garbage in every solve, whatever state the heap is in.
"""

import sys
import warnings

import numpy as np

import mol_shell
from mol_shell.integrators import INTEGRATORS, sundials
from mol_shell.runs.simulate import build, resolve

TIMES = [0.0, 0.002, 0.004]


def partial_constraints(size, entries):
    """The list scikit-sundae 1.2.0 mishandles: only the constrained entries."""
    return list(entries), list(entries.values())


def solve_many(name, solves):
    """``(failures, spread)`` of ``solves`` shell solves with ``name``."""
    scene = resolve(mol_shell.TwistedCylinder(omega=2.0))
    system, compiled = build(scene, 10)
    y0 = system.initial_state(scene)
    method = INTEGRATORS[name](rtol=1e-6, atol=1e-9, jacobian="vm", constraints=True, events=True)
    failures, finals = 0, []
    for _ in range(solves):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                run = method.integrate(system, compiled, y0, TIMES)
        except (RuntimeError, ValueError):  # "could not start", or scikit-sundae refusing the options
            failures += 1
            continue
        if run.status == "complete" and len(run.t) == len(TIMES) and np.all(np.isfinite(run.y)):
            finals.append(run.y[-1])
        else:
            failures += 1
    spread = max((float(np.abs(f - finals[0]).max()) for f in finals), default=float("nan"))
    return failures, spread


if __name__ == "__main__":
    mode, solves, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    if mode == "partial":
        sundials.full_constraints = partial_constraints  # solver_options looks it up at every solve
    elif mode != "full":
        raise SystemExit(f"mode {mode!r} is not one of full, partial")
    for name in names:
        failures, spread = solve_many(name, solves)
        print(name, failures, solves, repr(spread), flush=True)
