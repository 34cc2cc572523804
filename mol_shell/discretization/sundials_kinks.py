"""C source of the SUNDIALS driver's restarts at the kinks of a drive's history, and its counters across them.

A driven edge's rate that follows a ramp or a table has kinks: there the driven node's acceleration, and with it the
driver's power in the ``work`` accumulator, jumps. The driver (:mod:`mol_shell.discretization.sundials_source`)
stops at each kink (a stop time), evaluates the step that ends there on the old segment (``ms_side``: one ulp short
of the kink, since the history's rate at the kink itself is the new segment's) and restarts the solver from the
state there (``CVodeReInit``, ``IDAReInit``: order 1, a new first step, a fresh Jacobian), so that no step and no
multistep history spans the jump. SUNDIALS zeroes its counters at a restart; the run's are kept across them.
"""

KINKS_SOURCE = r"""/* SUNDIALS' counters since the last restart: steps, rhs (or residual) evaluations, Jacobians, set-ups, error-test
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

/* At a kink (r->t): the solver restarted from the state there (order 1, a new first step, a fresh Jacobian; IDA
   from the rates it holds there, the left limit: making them consistent with IDACalcIC changed the balance by
   nothing measurable), its counters kept in base. Then the stop time: the next kink before target, or target.
   Returns SUNDIALS' flag of the restart (0 if none). */
static int ms_kinks(ms_run* r, double target, double* stop) {
  int flag = 0, i;
  if (r->next_kink < r->n_kinks && r->kinks[r->next_kink] <= r->t) {
    long int v[9];
    while (r->next_kink < r->n_kinks && r->kinks[r->next_kink] <= r->t) r->next_kink += 1;
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

"""
