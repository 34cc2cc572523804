"""C source of the SUNDIALS driver's restarts at the kinks of a drive's history, and its counters across them.

A driven edge's rate that follows a ramp or a table has kinks: there the driven node's acceleration, and with it the
driver's power in the ``work`` accumulator, jumps. The driver (:mod:`mol_shell.discretization.sundials_source`)
stops at each kink (a stop time), evaluates the step that ends there on the old segment (``ms_side``: one ulp short
of the kink, since the history's rate at the kink itself is the new segment's) and restarts the solver from the
state there (``CVodeReInit``, ``IDAReInit``: order 1, a new first step, a fresh Jacobian), so that no step and no
multistep history spans the jump. SUNDIALS zeroes its counters at a restart; the run's are kept across them.

A saved time within :data:`CLOSE` ``eps max(|t|, |kink|)`` of a kink (``numpy.linspace(0, 0.01, 11)[9]`` is one ulp
after a table's point 0.009) is the kink's time (``ms_target``): the solve stops at the kink, and the state there is
the saved time's (they differ by round-off). SUNDIALS refuses a first step, after a start or a restart, towards a
time closer than ``2 uround max(|t0|, |tout|)`` ("tout too close to t0", CVODE -27, IDA -60), and takes a stop
time within ``100 uround (|t| + |h|)`` as reached: a kink one ulp before a saved time, or before the end, failed.
Kinks as close (two drives') are one restart, at the last of them: the step before ends at the first, on every
drive's old segment; the steps after start from the last, on every drive's new one.
"""

import math
import sys

#: times within ``CLOSE * DBL_EPSILON * max(|a|, |b|)`` are one time (SUNDIALS' ``2 uround``, times 100: its fuzz)
CLOSE = 200


def one_time(a, b):
    """Whether the finite times ``a`` and ``b`` are one for SUNDIALS (``ms_close`` of the C source, for the loops in
    Python): within ``CLOSE * eps * max(|a|, |b|)``."""
    bound = CLOSE * sys.float_info.epsilon * max(abs(a), abs(b))
    return math.isfinite(bound) and abs(a - b) <= bound


KINKS_SOURCE = r"""#define MS_CLOSE @CLOSE@.0

/* SUNDIALS' counters since the last restart: steps, rhs (or residual) evaluations, Jacobians, set-ups, error-test
   failures, nonlinear convergence failures, Newton iterations, root-function evaluations, rhs evaluations of its
   difference-quotient Jacobians */
static void ms_counters(ms_run* r, long int* v) {
  int i;
  for (i = 0; i < 9; ++i) v[i] = 0;
  if (r->ida) {
    IDAGetNumSteps(r->mem, v); IDAGetNumResEvals(r->mem, v + 1); IDAGetNumJacEvals(r->mem, v + 2);
    IDAGetNumLinSolvSetups(r->mem, v + 3); IDAGetNumErrTestFails(r->mem, v + 4);
    IDAGetNumNonlinSolvConvFails(r->mem, v + 5); IDAGetNumNonlinSolvIters(r->mem, v + 6);
    if (r->ng) IDAGetNumGEvals(r->mem, v + 7);
    if (r->ls) IDAGetNumLinResEvals(r->mem, v + 8);
  } else {
    CVodeGetNumSteps(r->mem, v); CVodeGetNumRhsEvals(r->mem, v + 1); CVodeGetNumJacEvals(r->mem, v + 2);
    CVodeGetNumLinSolvSetups(r->mem, v + 3); CVodeGetNumErrTestFails(r->mem, v + 4);
    CVodeGetNumNonlinSolvConvFails(r->mem, v + 5); CVodeGetNumNonlinSolvIters(r->mem, v + 6);
    if (r->ng) CVodeGetNumGEvals(r->mem, v + 7);
    if (r->ls) CVodeGetNumLinRhsEvals(r->mem, v + 8);
  }
}

/* The times where a drive's rate has a kink (increasing, > t0): the solve stops at each and starts afresh there, so
   that no step and no multistep history spans the jump of the driven node's acceleration. 0, or -1 (no memory). */
CASADI_SYMBOL_EXPORT int ms_set_kinks(ms_run* r, const double* kinks, int n) {
  r->kinks = (double*) malloc(sizeof(double) * (n + 1));
  if (!r->kinks) return -1;
  memcpy(r->kinks, kinks, sizeof(double) * n);
  r->n_kinks = n; r->next_kink = 0;
  return 0;
}

/* Whether two times are one for SUNDIALS (closer than its first step may go, with a margin: MS_CLOSE) */
static int ms_close(double a, double b) {
  return fabs(a - b) <= MS_CLOSE * DBL_EPSILON * fmax(fabs(a), fabs(b));
}

/* Where the solve stops for the saved time target: a kink as close to it (the one r->t may stand at, or one ahead)
   is the target, else target itself */
static double ms_target(ms_run* r, double target) {
  int i;
  for (i = r->next_kink > 0 ? r->next_kink - 1 : 0; i < r->n_kinks; ++i) {
    if (ms_close(r->kinks[i], target)) return r->kinks[i];
    if (r->kinks[i] > target) break;
  }
  return target;
}

/* At a kink (r->t): the solver restarted from the state there (order 1, a new first step, a fresh Jacobian; IDA
   from the rates it holds there, the left limit: making them consistent with IDACalcIC changed the balance by
   nothing measurable), its counters kept in base. Then the stop time: the next kink before target, or target.
   Returns SUNDIALS' flag of the restart (0 if none). */
static int ms_kinks(ms_run* r, double target, double* stop) {
  int flag = 0, i;
  if (r->next_kink < r->n_kinks && r->kinks[r->next_kink] <= r->t) {
    long int v[9];
    /* with the kinks within round-off after it (another drive's): one restart, at the last of them */
    while (r->next_kink < r->n_kinks && (r->kinks[r->next_kink] <= r->t || ms_close(r->kinks[r->next_kink], r->t))) {
      r->t = fmax(r->t, r->kinks[r->next_kink]);
      r->next_kink += 1;
    }
    ms_counters(r, v);
    for (i = 0; i < 9; ++i) r->base[i] += v[i];
    if (r->ida) {
      flag = IDAReInit(r->mem, r->t, r->y, r->yp);
      r->since = r->reuse; r->ncf_seen = 0; /* a fresh Jacobian: IDA's failure count starts again at 0 */
    } else {
      flag = CVodeReInit(r->mem, r->t, r->y);
    }
  }
  *stop = r->next_kink < r->n_kinks && r->kinks[r->next_kink] < target ? r->kinks[r->next_kink] : target;
  if (r->ida) IDASetStopTime(r->mem, *stop); else CVodeSetStopTime(r->mem, *stop);
  return flag;
}

""".replace("@CLOSE@", str(CLOSE))
