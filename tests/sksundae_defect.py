"""Repeated constrained solves of y' = -y/10 with scikit-sundae, to expose its constraints defect.

`python sksundae_defect.py {cvode|ida} {partial|full} SOLVES` prints the number of failed solves;
"full" lists every entry through mol_shell's workaround. Run it with MALLOC_PERTURB_ set and glibc
fills every fresh allocation with a byte pattern, so that uninitialised memory shows every time."""

import sys

import numpy as np
from sksundae.cvode import CVODE
from sksundae.ida import IDA

N, SOLVES = 200, 300


def _decay(t, y, yp):
    yp[:] = -0.1 * y


def _decay_residual(t, y, yp, res):
    res[:] = yp + 0.1 * y


def cvode(idx, types):
    return CVODE(_decay, rtol=1e-6, atol=1e-9, constraints_idx=idx, constraints_type=types)


def ida(idx, types):
    return IDA(_decay_residual, rtol=1e-6, atol=1e-9, constraints_idx=idx, constraints_type=types)


def solve_many(make, partial, dirt=(4,), solves=SOLVES, workaround=None):
    """Solves with a constraint on every 10th entry; the heap is dirtied before each one.

    `dirt` lists how many freed arrays of the solver's vector size precede a solve, cycled through:
    which layout hands the solver's constraints vector stale memory depends on the allocator's
    state, so a reproduction tries several. Without `partial`, `workaround(n, {index: type})` gives
    the full lists."""
    y0 = np.linspace(-1.0, 1.0, N)
    y0[1::10] = 1.0
    wanted = {i: 2 for i in range(1, N, 10)}
    failures = 0
    for k in range(solves):
        junk = [np.random.uniform(-5, 5, N) for _ in range(dirt[k % len(dirt)])]  # freed memory the solver may get back
        del junk
        idx, types = (list(wanted), list(wanted.values())) if partial else workaround(N, wanted)
        try:
            solver = make(idx, types)
            out = solver.solve([0.0, 1.0, 2.0], y0) if make is cvode else solver.solve([0.0, 1.0, 2.0], y0, -0.1 * y0)
            failures += not out.success
        except (RuntimeError, ValueError):
            failures += 1
    return failures


if __name__ == "__main__":
    make, mode, solves = {"cvode": cvode, "ida": ida}[sys.argv[1]], sys.argv[2], int(sys.argv[3])
    if mode == "partial":
        print(solve_many(make, partial=True, dirt=(1,), solves=solves))
    else:
        from mol_shell.integrators.sundials import full_constraints

        print(solve_many(make, partial=False, dirt=(1,), solves=solves, workaround=full_constraints))
