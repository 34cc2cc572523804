"""C source of the SUNDIALS driver: CVODE (BDF, Adams) and IDA time loops on compiled CasADi functions.

One generic driver, independent of the scene: it receives the addresses of the CasADi-generated functions (the
right-hand side or residual, the Jacobian, the model's limits) with their work sizes and the Jacobian's
compressed-column pattern, and runs SUNDIALS' one-step loop in C between two saved times (or until a wall-time
budget is spent, so that progress and Ctrl-C are handled between calls). It declares the few SUNDIALS 7.9
prototypes it uses itself (the wheel of scikit-sundae installs the libraries, not their headers; the types are
those of scikit-sundae's ``.pxd`` files: ``sunrealtype = double``, ``sunindextype = int``, ``SUNComm = int``),
and :func:`ms_check_index` verifies the index type against the libraries at load time.

The Jacobian is written into the solver's matrix here: dense (small systems), banded (node-major order keeps a
meridian's coupling in a band) or compressed sparse columns (SuperLU_MT). A Jacobian evaluated by a Python
callback (CasADi's virtual machine, no compiler) is also accepted: it is called a handful of times a run.
"""

from mol_shell.discretization.sundials_api import SUNDIALS_PROTOTYPES
from mol_shell.discretization.sundials_jacobians import JACOBIAN_SOURCE
from mol_shell.discretization.sundials_kinks import KINKS_SOURCE

#: steps in a row of at most 10 eps |t| before a solve stops (the driver's code 6, ``STALLED``)
STALL_STEPS = 100

_HEAD = r"""#define MS_ONE_STEP 2
#define MS_ROOT_RETURN 2
/* consecutive steps of at most 10 eps |t| (SUNDIALS warns of t + h == t and goes on; a state where the forces are
   not finite nearby took 1e6 such steps of IDA, minutes) before the solve stops (6) */
#define MS_STALL_STEPS @STALL_STEPS@

/* ---- a CasADi-generated function and its work arrays ---- */
typedef int (*ms_casadi_fn)(const double** arg, double** res, casadi_int* iw, double* w, int mem);
typedef int (*ms_py_jac)(double t, const double* y, const double* yp, double cj, double* out);
typedef struct {
  ms_casadi_fn f;
  const double** arg;
  double** res;
  casadi_int* iw;
  double* w;
} ms_fn;

static int ms_fn_init(ms_fn* fn, void* f, long long sz_arg, long long sz_res, long long sz_iw, long long sz_w) {
  fn->f = (ms_casadi_fn) f;
  fn->arg = (const double**) calloc((sz_arg > 4 ? sz_arg : 4) + 1, sizeof(double*)); /* ms_eval sets 4 */
  fn->res = (double**) calloc(sz_res + 1, sizeof(double*));
  fn->iw = (casadi_int*) malloc(sizeof(casadi_int) * (sz_iw + 1));
  fn->w = (double*) malloc(sizeof(double) * (sz_w + 1));
  return fn->arg && fn->res && fn->iw && fn->w ? 0 : -1;
}

static void ms_fn_free(ms_fn* fn) {
  free(fn->arg); free(fn->res); free(fn->iw); free(fn->w);
}

/* ---- one solve ---- */
typedef struct {
  int ida, n, linsolver, matrix, ml, mu, nnz, ng, nr; /* matrix: 0 dense, 1 band, 2 sparse */
  SUNContext ctx;
  void* mem;
  N_Vector y, yp, atol, cons;
  SUNMatrix a;
  SUNLinearSolver ls;
  SUNNonlinearSolver nls;
  ms_fn rhs, jac, lim;
  ms_py_jac py_jac;
  int* colind;
  int* row;
  double* jnz;
  double* g;
  const double* floor;
  int* r_idx;
  double r_floor, t, t_event, zero;
  int* roots;
  long long calls_in_step, max_calls, n_steps, n_dq;
  int dq, n_extra, reuse, since;      /* IDA: difference-quotient Jacobians reused over reuse set-ups */
  long ncf_seen;
  SUNMatrix jx, jxp;                  /* ... kept as dF/dx and dF/dx' */
  double rtol;
  int too_many_calls;
  double* kinks;                      /* times where a drive's rate has a kink, increasing: stop and restart there */
  int n_kinks, next_kink;
  long long base[9];                  /* SUNDIALS' counters before the last restart (a restart zeroes them) */
} ms_run;

static int ms_eval(ms_fn* fn, double t, const double* y, const double* yp, const double* cj, double* out) {
  fn->arg[0] = &t; fn->arg[1] = y; fn->arg[2] = yp; fn->arg[3] = cj;
  fn->res[0] = out;
  return fn->f(fn->arg, fn->res, fn->iw, fn->w, 0);
}

static int ms_count_call(ms_run* r, double t) {
  r->calls_in_step += 1;
  if (r->calls_in_step > r->max_calls || !isfinite(t)) { r->too_many_calls = 1; return -1; }
  return 0;
}

/* The time at which the right-hand side (or residual) is evaluated: t, but short of the next kink by one ulp at the
   kink itself, where the last step before it ends (the step stops there, and the drive's rate there is the new
   segment's: the old one's belongs to that step); after the restart at the kink, t itself */
static double ms_side(ms_run* r, double t) {
  return r->next_kink < r->n_kinks && t >= r->kinks[r->next_kink] ? nextafter(r->kinks[r->next_kink], -INFINITY) : t;
}

static int ms_limits(ms_run* r, const double* y, double* g) {
  int i;
  r->lim.arg[0] = y; /* limits(y): one input */
  r->lim.res[0] = r->g;
  if (r->lim.f(r->lim.arg, r->lim.res, r->lim.iw, r->lim.w, 0)) return -1;
  for (i = 0; i < r->ng; ++i) g[i] = r->g[i] - r->floor[i];
  return 0;
}

"""

_LOOP = r"""static int ms_cv_rhs(double t, N_Vector y, N_Vector ydot, void* data) {
  ms_run* r = (ms_run*) data;
  if (ms_count_call(r, t)) return -1;
  return ms_eval(&r->rhs, ms_side(r, t), N_VGetArrayPointer(y), 0, 0, N_VGetArrayPointer(ydot)) ? -1 : 0;
}

static int ms_cv_jac(double t, N_Vector y, N_Vector fy, SUNMatrix J, void* data, N_Vector t1, N_Vector t2,
                     N_Vector t3) {
  ms_run* r = (ms_run*) data;
  int flag;
  if (r->dq) return ms_dq_band(r, t, y, 0, 1.0, 0.0, 0.0, fy, J, t1, t2, 0);
  flag = r->py_jac ? r->py_jac(ms_side(r, t), N_VGetArrayPointer(y), 0, 0.0, r->jnz)
                   : ms_eval(&r->jac, ms_side(r, t), N_VGetArrayPointer(y), 0, 0, r->jnz);
  (void) fy; (void) t1; (void) t2; (void) t3;
  return flag ? -1 : ms_fill(r, J);
}

static int ms_cv_root(double t, N_Vector y, double* g, void* data) {
  (void) t;
  return ms_limits((ms_run*) data, N_VGetArrayPointer(y), g);
}

static int ms_ida_res(double t, N_Vector y, N_Vector yp, N_Vector res, void* data) {
  ms_run* r = (ms_run*) data;
  if (ms_count_call(r, t)) return -1;
  return ms_eval(&r->rhs, ms_side(r, t), N_VGetArrayPointer(y), N_VGetArrayPointer(yp), 0, N_VGetArrayPointer(res))
         ? -1 : 0;
}

static int ms_ida_jac(double t, double cj, N_Vector y, N_Vector yp, N_Vector res, SUNMatrix J, void* data,
                      N_Vector t1, N_Vector t2, N_Vector t3) {
  ms_run* r = (ms_run*) data;
  int flag;
  if (r->dq && r->reuse > 1) return ms_ida_dq_reused(r, t, cj, y, yp, res, J, t1, t2, t3);
  if (r->dq) return ms_dq_band(r, t, y, yp, 1.0, cj, 0.0, res, J, t1, t2, t3);
  flag = r->py_jac ? r->py_jac(ms_side(r, t), N_VGetArrayPointer(y), N_VGetArrayPointer(yp), cj, r->jnz)
                   : ms_eval(&r->jac, ms_side(r, t), N_VGetArrayPointer(y), N_VGetArrayPointer(yp), &cj, r->jnz);
  (void) res; (void) t1; (void) t2; (void) t3;
  return flag ? -1 : ms_fill(r, J);
}

static int ms_ida_root(double t, N_Vector y, N_Vector yp, double* g, void* data) {
  (void) t; (void) yp;
  return ms_limits((ms_run*) data, N_VGetArrayPointer(y), g);
}

/* 0 if the libraries' sunindextype is the int declared here: a sparse matrix made from a dense one holds the
   column pointers (0, 2, 3, 4) as ints */
CASADI_SYMBOL_EXPORT int ms_check_index(void) {
  SUNContext ctx;
  SUNMatrix d, s;
  sunindextype* p;
  int ok;
  if (SUNContext_Create(0, &ctx)) return -1;
  d = SUNDenseMatrix(3, 3, ctx);
  SUNDenseMatrix_Column(d, 0)[0] = 1.0; SUNDenseMatrix_Column(d, 0)[2] = 2.0;
  SUNDenseMatrix_Column(d, 1)[1] = 3.0; SUNDenseMatrix_Column(d, 2)[2] = 4.0;
  s = SUNSparseFromDenseMatrix(d, 0.0, 0);
  p = SUNSparseMatrix_IndexPointers(s);
  ok = p[0] == 0 && p[1] == 2 && p[2] == 3 && p[3] == 4 && SUNSparseMatrix_NNZ(s) == 4;
  SUNMatDestroy(s); SUNMatDestroy(d);
  SUNContext_Free(&ctx);
  return ok ? 0 : 1;
}

/* opts (doubles): rtol, first_step, max_step, r_floor, nonlinear convergence coefficient (0: default),
   IDA's cj ratio for a new factorisation (0: default).
   iopts (long long): ida, lmm (1 Adams, 2 BDF), linsolver (0 dense, 1 band, 2 sparse), ml, mu, max_order,
   max_newton, max_conv_fails, jac_every, setup_every, events, constraints, max_calls, threads (SuperLU_MT),
   fixed point (CVODE: 1 for fixed-point iterations, no Jacobian and no linear solver; 0 for Newton's),
   its Anderson acceleration depth, the number of accumulators at the end of the state (n_extra), IDA's set-ups
   per difference-quotient Jacobian (jac_reuse).
   Neither jac nor py_jac: difference quotients, ours for a banded matrix (ms_dq_band), SUNDIALS' for a dense one.
   Returns the run, or 0 with *err set to the step that failed. */
CASADI_SYMBOL_EXPORT ms_run* ms_create(const long long* iopts, const double* opts, int n, double t0,
                                       const double* y0, const double* yp0, const double* atol,
                                       void* rhs, const long long* rhs_sz, void* jac, const long long* jac_sz,
                                       ms_py_jac py_jac, const long long* colind, const long long* row, int nnz,
                                       void* lim, const long long* lim_sz, int ng, const double* floor,
                                       const int* r_idx, int nr, int* err) {
  ms_run* r = (ms_run*) calloc(1, sizeof(ms_run));
  int i, flag = 0, ida = (int) iopts[0];
  *err = 1;
  if (!r) return 0;
  r->ida = ida; r->n = n; r->linsolver = (int) iopts[2]; r->matrix = r->linsolver % 3 == 2 ? 2 : r->linsolver % 3; r->ml = (int) iopts[3]; r->mu = (int) iopts[4];
  r->nnz = nnz; r->ng = ng; r->nr = nr; r->floor = floor; r->r_floor = opts[3]; r->max_calls = iopts[12];
  r->py_jac = py_jac;
  r->t = t0;
  r->rtol = opts[0];
  r->n_extra = (int) iopts[16];
  r->reuse = (int) iopts[17];
  r->dq = !jac && !py_jac && r->matrix == 1;
  r->colind = (int*) malloc(sizeof(int) * (n + 1));
  r->row = (int*) malloc(sizeof(int) * (nnz + 1));
  r->jnz = (double*) calloc(nnz + 1, sizeof(double));
  r->g = (double*) calloc(ng + 1, sizeof(double));
  r->roots = (int*) calloc(ng + 1, sizeof(int));
  r->r_idx = (int*) malloc(sizeof(int) * (nr + 1));
  if (!r->colind || !r->row || !r->jnz || !r->g || !r->roots || !r->r_idx) return r;
  for (i = 0; i <= n; ++i) r->colind[i] = (int) colind[i];
  for (i = 0; i < nnz; ++i) r->row[i] = (int) row[i];
  for (i = 0; i < nr; ++i) r->r_idx[i] = r_idx[i];
  *err = 2;
  if (ms_fn_init(&r->rhs, rhs, rhs_sz[0], rhs_sz[1], rhs_sz[2], rhs_sz[3])) return r;
  if (jac && ms_fn_init(&r->jac, jac, jac_sz[0], jac_sz[1], jac_sz[2], jac_sz[3])) return r;
  if (ng > 0 && ms_fn_init(&r->lim, lim, lim_sz[0], lim_sz[1], lim_sz[2], lim_sz[3])) return r;
  *err = 3;
  if (SUNContext_Create(0, &r->ctx)) return r;
  SUNContext_ClearErrHandlers(r->ctx); /* failures are returned as flags and reported by the caller */
  r->y = N_VNew_Serial(n, r->ctx);
  r->atol = N_VNew_Serial(n, r->ctx);
  if (!r->y || !r->atol) return r;
  memcpy(N_VGetArrayPointer(r->y), y0, sizeof(double) * n);
  memcpy(N_VGetArrayPointer(r->atol), atol, sizeof(double) * n);
  if (ida) {
    r->yp = N_VNew_Serial(n, r->ctx);
    if (!r->yp) return r;
    memcpy(N_VGetArrayPointer(r->yp), yp0, sizeof(double) * n);
  }
  *err = 4;
  if (!ida && iopts[14]) {
    r->nls = SUNNonlinSol_FixedPoint(r->y, (int) iopts[15], r->ctx);
    if (!r->nls) return r;
  } else {
  if (r->matrix == 0) r->a = SUNDenseMatrix(n, n, r->ctx);
  else if (r->matrix == 1) r->a = SUNBandMatrix(n, r->mu, r->ml, r->ctx);
  else r->a = SUNSparseMatrix(n, n, nnz, 0, r->ctx);
  if (!r->a) return r;
  if (r->linsolver == 0) r->ls = SUNLinSol_Dense(r->y, r->a, r->ctx);
  else if (r->linsolver == 1) r->ls = SUNLinSol_Band(r->y, r->a, r->ctx);
  else if (r->linsolver == 3) r->ls = SUNLinSol_LapackDense(r->y, r->a, r->ctx);
  else if (r->linsolver == 4) r->ls = SUNLinSol_LapackBand(r->y, r->a, r->ctx);
  else r->ls = SUNLinSol_SuperLUMT(r->y, r->a, (int) iopts[13], r->ctx);
  if (!r->ls) return r;
  }
  *err = 5;
  if (ida) {
    r->mem = IDACreate(r->ctx);
    if (!r->mem) return r;
    flag |= IDAInit(r->mem, ms_ida_res, t0, r->y, r->yp);
    flag |= IDASVtolerances(r->mem, opts[0], r->atol);
    flag |= IDASetUserData(r->mem, r);
    flag |= IDASetLinearSolver(r->mem, r->ls, r->a);
    if (jac || py_jac || r->dq) flag |= IDASetJacFn(r->mem, ms_ida_jac); /* else SUNDIALS' difference quotients */
    flag |= IDASetMaxNonlinIters(r->mem, (int) iopts[6]);
    flag |= IDASetMaxConvFails(r->mem, (int) iopts[7]);
    if (opts[4] > 0) flag |= IDASetNonlinConvCoef(r->mem, opts[4]);
    if (opts[5] > 0) flag |= IDASetDeltaCjLSetup(r->mem, opts[5]);
    flag |= IDASetInitStep(r->mem, opts[1]);
    flag |= IDASetMaxStep(r->mem, opts[2]);
    flag |= IDASetMaxOrd(r->mem, (int) iopts[5]);
    flag |= IDASetMaxNumSteps(r->mem, 100000);
  } else {
    r->mem = CVodeCreate((int) iopts[1], r->ctx);
    if (!r->mem) return r;
    flag |= CVodeInit(r->mem, ms_cv_rhs, t0, r->y);
    flag |= CVodeSVtolerances(r->mem, opts[0], r->atol);
    flag |= CVodeSetUserData(r->mem, r);
    if (r->nls) {
      flag |= CVodeSetNonlinearSolver(r->mem, r->nls);
    } else {
      flag |= CVodeSetLinearSolver(r->mem, r->ls, r->a);
      if (jac || py_jac || r->dq) flag |= CVodeSetJacFn(r->mem, ms_cv_jac); /* else SUNDIALS' difference quotients */
    }
    flag |= CVodeSetMaxNonlinIters(r->mem, (int) iopts[6]);
    flag |= CVodeSetMaxConvFails(r->mem, (int) iopts[7]);
    if (opts[4] > 0) flag |= CVodeSetNonlinConvCoef(r->mem, opts[4]);
    if (iopts[8] > 0) flag |= CVodeSetJacEvalFrequency(r->mem, (long int) iopts[8]);
    if (iopts[9] > 0) flag |= CVodeSetLSetupFrequency(r->mem, (long int) iopts[9]);
    flag |= CVodeSetInitStep(r->mem, opts[1]);
    flag |= CVodeSetMaxStep(r->mem, opts[2]);
    flag |= CVodeSetMaxOrd(r->mem, (int) iopts[5]);
    flag |= CVodeSetMaxNumSteps(r->mem, 100000);
  }
  if (flag) return r;
  *err = 6;
  if (iopts[10] && ng > 0) {
    int* dir = (int*) malloc(sizeof(int) * ng);
    if (!dir) return r;
    for (i = 0; i < ng; ++i) dir[i] = -1;
    flag = ida ? IDARootInit(r->mem, ng, ms_ida_root) : CVodeRootInit(r->mem, ng, ms_cv_root);
    if (!flag) flag = ida ? IDASetRootDirection(r->mem, dir) : CVodeSetRootDirection(r->mem, dir);
    free(dir);
    if (flag) return r;
  }
  if (iopts[11] && nr > 0) {
    double* c;
    r->cons = N_VNew_Serial(n, r->ctx);
    if (!r->cons) return r;
    c = N_VGetArrayPointer(r->cons);
    for (i = 0; i < n; ++i) c[i] = 0.0;
    for (i = 0; i < nr; ++i) c[r_idx[i]] = 2.0; /* r > 0 */
    if (ida ? IDASetConstraints(r->mem, r->cons) : CVodeSetConstraints(r->mem, r->cons)) return r;
  } else {
    r->nr = 0; /* no constraint: no check of r after each step either */
  }
  *err = 0;
  return r;
}

static double ms_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Steps towards target (never past it; stopping and restarting at the kinks of a drive before it, ms_kinks; a kink
   within round-off of it stands for it, ms_target, and t_out is then target) until it is reached (0), a root of a
   limit is found (1: t_event and the
   roots), an accepted step leaves r <= r_floor on a constrained entry (2), max_steps steps were taken in all (3),
   the wall-time budget of this call is spent (4), MS_STALL_STEPS steps in a row are 10 eps |t| or less (6: the
   step below round-off at t), or SUNDIALS fails (its negative flag; 5 if a right-hand side or residual was called
   max_calls times within one step or at a non-finite time). y (and yp) hold the state at
   t (the last step's end). */
CASADI_SYMBOL_EXPORT int ms_advance(ms_run* r, double target, long long max_steps, double seconds, double* t_out,
                                    double* y, double* yp) {
  double start = ms_now(), tret = r->t, stop = target, asked = target;
  int flag = 0, code = 0, i, stalled = 0;
  target = ms_target(r, target); /* a kink within round-off of it instead */
  flag = ms_kinks(r, target, &stop);
  if (flag < 0) code = flag;
  while (!code && r->t < target) {
    r->calls_in_step = 0;
    flag = r->ida ? IDASolve(r->mem, stop, &tret, r->y, r->yp, MS_ONE_STEP)
                  : CVode(r->mem, stop, r->y, &tret, MS_ONE_STEP);
    r->n_steps += 1;
    if (flag == MS_ROOT_RETURN) {
      r->t_event = tret;
      if (r->ida) IDAGetRootInfo(r->mem, r->roots); else CVodeGetRootInfo(r->mem, r->roots);
      r->t = tret;
      code = 1;
      break;
    }
    if (flag < 0) {
      code = r->too_many_calls ? 5 : flag;
      if (isfinite(tret)) r->t = tret;
      break;
    }
    stalled = tret - r->t > 10 * DBL_EPSILON * fabs(tret) ? 0 : stalled + 1; /* a step of 10 eps |t| or less */
    r->t = tret;
    if (stalled >= MS_STALL_STEPS) { code = 6; break; }
    if (r->nr > 0) {
      const double* v = N_VGetArrayPointer(r->y);
      for (i = 0; i < r->nr; ++i) if (v[r->r_idx[i]] <= r->r_floor) { code = 2; break; }
      if (code) break;
    }
    if (r->n_steps >= max_steps) { code = 3; break; }
    if (stop < target && r->t >= stop) { /* at a kink: restart there */
      flag = ms_kinks(r, target, &stop);
      if (flag < 0) { code = flag; break; }
    }
    if (r->t < target && ms_now() - start > seconds) { code = 4; break; }
  }
  *t_out = code ? r->t : fmax(r->t, asked); /* reached: the saved time asked for, if at a kink just short of it */
  memcpy(y, N_VGetArrayPointer(r->y), sizeof(double) * r->n);
  if (r->ida) memcpy(yp, N_VGetArrayPointer(r->yp), sizeof(double) * r->n);
  return code;
}

/* steps, rhs (or residual) evaluations, Jacobians, linear solver set-ups (factorisations), error-test failures,
   nonlinear convergence failures, Newton iterations, root-function evaluations, the root found (index, or -1),
   one-step calls, right-hand side evaluations for difference-quotient Jacobians */
CASADI_SYMBOL_EXPORT void ms_stats(ms_run* r, long long* out) {
  long int v[9];
  int i;
  ms_counters(r, v); /* since the last restart at a kink; base holds those before it */
  for (i = 0; i < 8; ++i) out[i] = r->base[i] + v[i];
  out[8] = -1;
  for (i = 0; i < r->ng; ++i) if (r->roots[i]) { out[8] = i; break; }
  out[9] = r->n_steps;
  out[10] = r->base[8] + v[8] + r->n_dq;
}

/* The cost of each part of a step, s per call, at the run's current state (for the benchmark; after the run: it
   uses the solver's linear solver): right-hand side (or residual), Jacobian written into the matrix (-1 for
   difference quotients or none), copy and factorisation, one solve, the limits. */
CASADI_SYMBOL_EXPORT int ms_costs(ms_run* r, int reps, double* out) {
  N_Vector tmp = N_VClone(r->y), x = N_VClone(r->y);
  SUNMatrix J = r->a ? SUNMatClone(r->a) : 0, A = r->a ? SUNMatClone(r->a) : 0;
  double* yv = N_VGetArrayPointer(r->y);
  double* ypv = r->ida ? N_VGetArrayPointer(r->yp) : 0;
  double start, cj = 1.0;
  int k, j;
  for (k = 0; k < 5; ++k) out[k] = -1.0;
  start = ms_now();
  for (k = 0; k < reps; ++k) ms_eval(&r->rhs, r->t, yv, ypv, 0, N_VGetArrayPointer(tmp));
  out[0] = (ms_now() - start) / reps;
  if (J && (r->jac.f || r->py_jac || r->dq)) {
    long long before = r->n_dq;
    N_Vector y2 = N_VClone(r->y), yp2 = N_VClone(r->y);
    ms_eval(&r->rhs, r->t, yv, ypv, 0, N_VGetArrayPointer(x)); /* f0 of the difference quotients */
    start = ms_now();
    for (k = 0; k < reps; ++k) {
      if (r->dq) ms_dq_band(r, r->t, r->y, r->ida ? r->yp : 0, 1.0, cj, 0.0, x, J, tmp, y2, yp2);
      else if (r->ida) ms_ida_jac(r->t, cj, r->y, r->yp, tmp, J, r, 0, 0, 0);
      else ms_cv_jac(r->t, r->y, tmp, J, r, 0, 0, 0);
    }
    out[1] = (ms_now() - start) / reps;
    r->n_dq = before;
    N_VDestroy(y2); N_VDestroy(yp2);
  } else if (J && r->matrix != 2) { /* a diagonally dominant stand-in: the factorisation's cost depends on the shape */
    SUNMatZero(J);
    for (j = 0; j < r->n; ++j) (r->matrix == 1 ? SUNBandMatrix_Column(J, j) : SUNDenseMatrix_Column(J, j) + j)[0] = 1.0;
  }
  if (J) {
    double* b = N_VGetArrayPointer(tmp);
    for (j = 0; j < r->n; ++j) b[j] = 1.0;
    start = ms_now();
    /* CVODE factorises I - gamma J, not J (whose zero pivots, e.g. dq'/dq = 0, would end the LU early) */
    if (!r->ida) SUNMatScaleAddI(-1e-3, J);
    for (k = 0; k < reps; ++k) { SUNMatCopy(J, A); SUNLinSolSetup(r->ls, A); }
    out[2] = (ms_now() - start) / reps;
    start = ms_now();
    for (k = 0; k < reps; ++k) SUNLinSolSolve(r->ls, A, x, tmp, 0.0);
    out[3] = (ms_now() - start) / reps;
  }
  if (r->ng) {
    start = ms_now();
    for (k = 0; k < reps; ++k) ms_limits(r, yv, r->g);
    out[4] = (ms_now() - start) / reps;
  }
  if (J) { SUNMatDestroy(J); SUNMatDestroy(A); }
  N_VDestroy(tmp); N_VDestroy(x);
  return 0;
}

CASADI_SYMBOL_EXPORT double ms_event_time(ms_run* r) { return r->t_event; }

CASADI_SYMBOL_EXPORT void ms_free(ms_run* r) {
  if (!r) return;
  if (r->mem) { if (r->ida) IDAFree(&r->mem); else CVodeFree(&r->mem); }
  if (r->ls) SUNLinSolFree(r->ls);
  if (r->nls) SUNNonlinSolFree(r->nls);
  if (r->a) SUNMatDestroy(r->a);
  if (r->jx) SUNMatDestroy(r->jx);
  if (r->jxp) SUNMatDestroy(r->jxp);
  if (r->y) N_VDestroy(r->y);
  if (r->yp) N_VDestroy(r->yp);
  if (r->atol) N_VDestroy(r->atol);
  if (r->cons) N_VDestroy(r->cons);
  if (r->rhs.f) ms_fn_free(&r->rhs);
  if (r->jac.f) ms_fn_free(&r->jac);
  if (r->lim.f) ms_fn_free(&r->lim);
  if (r->ctx) SUNContext_Free(&r->ctx);
  free(r->colind); free(r->row); free(r->jnz); free(r->g); free(r->roots); free(r->r_idx); free(r->kinks);
  free(r);
}
"""

SUNDIALS_DRIVER = (SUNDIALS_PROTOTYPES + _HEAD.replace("@STALL_STEPS@", str(STALL_STEPS)) + JACOBIAN_SOURCE
                   + KINKS_SOURCE + _LOOP)
