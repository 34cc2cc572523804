"""C source of the embedded Runge-Kutta driver appended to the compiled right-hand side.

An explicit embedded pair whose tableau is passed in at run time (SciPy's ``RK45`` and ``DOP853``
coefficients), with SciPy's step-size control and error norms, so a whole run between two saved times
is one C call: no Python per step (:class:`mol_shell.integrators.explicit.RungeKuttaC`). It uses the
leap-frog driver's ``ms_call`` and ``ms_limits_call`` (:mod:`mol_shell.discretization.compiled`), and checks the
model's limits after every accepted step: a step whose end left them is kept (its start, stages and end) for the
search of the crossing inside it (:mod:`mol_shell.integrators.rk_dense`), and ``ms_limits`` evaluates the limits there.
"""

RK_DRIVER = r"""
/* ---- mol_shell embedded Runge-Kutta driver (SciPy's RK45 / DOP853 step control) ---- */
static void ms_axpy(int n, casadi_real a, const casadi_real* x, casadi_real* y) {
  int i;
  if (a == 0.0) return;
  for (i = 0; i < n; ++i) y[i] += a * x[i];
}
/* Advances (t, y, f = f(t, y)) towards t_end, landing on it. The tableau: s stages, A (s x s, row-major),
   B (s), C (s), E (s + 1) and, for DOP853's error estimate, E3 (s + 1; dop853 != 0). h: the proposed step,
   updated. work: (s + 4) N doubles. stats: accepted steps, rejected steps, RHS evaluations (added to).
   Returns 0 at t_end, 1 after an accepted step whose end left a limit (t, y, f then hold the step's start, h the
   time at its end, work its stages K (s N) followed by y and f at its end, g the limits there: its dense output
   locates the crossing), 2 after max_steps accepted steps, -1 if the RHS failed, -2 if the step fell below SciPy's
   minimum. */
CASADI_SYMBOL_EXPORT int ms_rk(casadi_real* t, casadi_real* y, casadi_real* f, casadi_real* h,
                               casadi_real t_end, casadi_real rtol, const casadi_real* atol, casadi_real max_step,
                               int s, const casadi_real* A, const casadi_real* B, const casadi_real* C,
                               const casadi_real* E, const casadi_real* E3, int dop853, casadi_real exponent,
                               casadi_real* work, casadi_real* g, long long max_steps, long long* stats) {
  const int N = MS_N;
  casadi_real *K = work, *ynew = work + (long long) s * N, *ytmp = ynew + N, *err5 = ytmp + N, *err3 = err5 + N;
  long long taken = 0;
  int i, j, m;
  for (i = 0; i < N; ++i) K[i] = f[i];
  while (*t < t_end) {
    casadi_real min_step = 10.0 * fabs(nextafter(*t, INFINITY) - *t);
    casadi_real h_abs = *h, t_new = *t, hh = 0.0;
    int accepted = 0, rejected = 0, clipped = 0;
    if (taken >= max_steps) return 2;
    if (max_step > 0 && h_abs > max_step) h_abs = max_step;
    if (h_abs < min_step) h_abs = min_step;
    while (!accepted) {
      casadi_real e5 = 0.0, e3 = 0.0, err;
      if (h_abs < min_step) { *h = h_abs; return -2; }
      t_new = *t + h_abs;
      clipped = t_new > t_end;
      if (clipped) t_new = t_end;
      hh = t_new - *t;
      /* stage j at y + hh sum_m A[j][m] K[m]: whole-vector updates, zero coefficients skipped */
      for (j = 1; j < s; ++j) {
        casadi_real* Kj = K + (long long) j * N;
        for (i = 0; i < N; ++i) Kj[i] = 0.0;
        for (m = 0; m < j; ++m) ms_axpy(N, A[j * s + m], K + (long long) m * N, Kj);
        for (i = 0; i < N; ++i) ytmp[i] = y[i] + hh * Kj[i];
        if (ms_call({name}, *t + C[j] * hh, ytmp, Kj)) return -1;
        stats[2] += 1;
      }
      for (i = 0; i < N; ++i) ytmp[i] = 0.0;
      for (m = 0; m < s; ++m) ms_axpy(N, B[m], K + (long long) m * N, ytmp);
      for (i = 0; i < N; ++i) ynew[i] = y[i] + hh * ytmp[i];
      /* the last row of K is f at the step's end (first same as last), kept in ytmp */
      if (ms_call({name}, t_new, ynew, ytmp)) return -1;
      stats[2] += 1;
      for (i = 0; i < N; ++i) err5[i] = E[s] * ytmp[i];
      for (m = 0; m < s; ++m) ms_axpy(N, E[m], K + (long long) m * N, err5);
      if (dop853) {
        for (i = 0; i < N; ++i) err3[i] = E3[s] * ytmp[i];
        for (m = 0; m < s; ++m) ms_axpy(N, E3[m], K + (long long) m * N, err3);
      }
      for (i = 0; i < N; ++i) {
        casadi_real scale = atol[i] + fmax(fabs(y[i]), fabs(ynew[i])) * rtol, a = err5[i] / scale;
        e5 += a * a;
        if (dop853) { a = err3[i] / scale; e3 += a * a; }
      }
      if (dop853)
        err = (e5 == 0.0 && e3 == 0.0) ? 0.0 : hh * e5 / sqrt((e5 + 0.01 * e3) * N);
      else
        err = hh * sqrt(e5 / N);
      if (err < 1.0) {
        casadi_real factor = err == 0.0 ? 10.0 : fmin(10.0, 0.9 * pow(err, exponent));
        if (rejected) factor = fmin(1.0, factor);
        /* a step shortened to land on t_end keeps the proposal it was shortened from */
        *h = clipped ? fmax(h_abs, hh * factor) : hh * factor;
        accepted = 1;
      } else {
        h_abs = hh * fmax(0.2, 0.9 * pow(err, exponent));
        rejected = 1;
        stats[1] += 1;
      }
    }
    stats[0] += 1;
    taken += 1;
    if (MS_NG > 0) {
      /* a step whose end left a limit is kept whole for the search of the crossing inside it: (t, y, f) its start,
         h the time at its end, K its stages, ynew and ytmp the state and f at its end, g the limits there */
      if (ms_limits_call(ynew, g)) return -1;
      for (i = 0; i < MS_NG; ++i) if (!(g[i] > 0)) { *h = t_new; return 1; }
    }
    *t = t_new;
    for (i = 0; i < N; ++i) { y[i] = ynew[i]; f[i] = ytmp[i]; K[i] = ytmp[i]; }
  }
  return 0;
}
/* The model's limits at y (g: MS_NG values), for the search of a crossing inside the step that crossed it. */
CASADI_SYMBOL_EXPORT int ms_limits(const casadi_real* y, casadi_real* g) { return ms_limits_call(y, g); }
"""
