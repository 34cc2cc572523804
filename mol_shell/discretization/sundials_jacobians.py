"""C source of the driver's Jacobians: the compiled or Python-evaluated non-zeros written into the solver's matrix,
banded difference quotients, and IDA's difference-quotient Jacobian reused over several set-ups.

Part of :data:`mol_shell.discretization.sundials_source.SUNDIALS_DRIVER` (after the run's struct ``ms_run``).
"""

JACOBIAN_SOURCE = r"""/* the Jacobian's non-zeros (compressed columns) into the solver's matrix */
static int ms_fill(ms_run* r, SUNMatrix J) {
  int j, k;
  if (r->matrix == 2) {
    sunindextype* ptr = SUNSparseMatrix_IndexPointers(J);
    sunindextype* idx = SUNSparseMatrix_IndexValues(J);
    double* data = SUNSparseMatrix_Data(J);
    if (SUNSparseMatrix_NNZ(J) < r->nnz) return -1;
    for (j = 0; j <= r->n; ++j) ptr[j] = r->colind[j];
    for (k = 0; k < r->nnz; ++k) { idx[k] = r->row[k]; data[k] = r->jnz[k]; }
    return 0;
  }
  SUNMatZero(J);
  for (j = 0; j < r->n; ++j) {
    double* col = r->matrix == 1 ? SUNBandMatrix_Column(J, j) : SUNDenseMatrix_Column(J, j);
    int shift = r->matrix == 1 ? j : 0;
    for (k = r->colind[j]; k < r->colind[j + 1]; ++k) col[r->row[k] - shift] = r->jnz[k];
  }
  return 0;
}

/* A banded Jacobian by difference quotients, ml + mu + 1 evaluations (columns j, j + w, j + 2w, ... perturbed
   together, w = ml + mu + 1): the rows of the last n_extra entries (accumulators of work and dissipation, which
   depend on every entry but feed back into none) keep their diagonal only, as in the Newton matrix of the exact
   route; a grouped quotient would add the derivatives of a whole group there. x moves by cx inc and x' by cxp inc:
   CVODE's df/dy (1, 0); IDA's dF/dx + cj dF/dx' (1, cj), dF/dx (1, 0), or dF/dx' (0, 1) with increments scaled
   by |x'| and by cj_scale atol (F is linear in x', so any increment gives its derivative). */
static int ms_dq_band(ms_run* r, double t, N_Vector yv, N_Vector ypv, double cx, double cxp, double cj_scale,
                      N_Vector f0v, SUNMatrix J, N_Vector fv, N_Vector yv2, N_Vector ypv2) {
  const double srur = 1.4901161193847656e-08; /* sqrt of the unit round-off */
  const double* y = N_VGetArrayPointer(yv);
  const double* yp = ypv ? N_VGetArrayPointer(ypv) : 0;
  const double* f0 = N_VGetArrayPointer(f0v);
  const double* atol = N_VGetArrayPointer(r->atol);
  double* f = N_VGetArrayPointer(fv);
  double* y2 = N_VGetArrayPointer(yv2);
  double* yp2 = ypv2 ? N_VGetArrayPointer(ypv2) : 0;
  int n = r->n, nm = r->n - r->n_extra, width = r->ml + r->mu + 1, g, j, i;
  memcpy(y2, y, sizeof(double) * n);
  if (r->ida) memcpy(yp2, yp, sizeof(double) * n);
  SUNMatZero(J);
  for (g = 0; g < width && g < n; ++g) {
    for (j = g; j < n; j += width) {
      double inc = cx != 0.0 ? srur * fmax(fabs(y[j]), atol[j] / fmax(r->rtol, srur))
                              : srur * fmax(fabs(yp[j]), cj_scale * atol[j] / fmax(r->rtol, srur));
      y2[j] = y[j] + cx * inc;
      if (r->ida) yp2[j] = yp[j] + cxp * inc;
    }
    if (ms_eval(&r->rhs, ms_side(r, t), y2, yp2, 0, f)) return -1;
    r->n_dq += 1;
    for (j = g; j < n; j += width) {
      double inc = cx != 0.0 ? (y2[j] - y[j]) / cx : (yp2[j] - yp[j]) / cxp;
      double* col = SUNBandMatrix_Column(J, j);
      int lo = j - r->mu > 0 ? j - r->mu : 0, hi = j + r->ml < nm - 1 ? j + r->ml : nm - 1;
      for (i = lo; i <= hi; ++i) col[i - j] = (f[i] - f0[i]) / inc;
      if (j >= nm) col[0] = (f[j] - f0[j]) / inc;
      y2[j] = y[j];
      if (r->ida) yp2[j] = yp[j];
    }
  }
  return 0;
}

/* IDA's Newton matrix dF/dx + cj dF/dx' from difference quotients kept over reuse set-ups: both parts evaluated
   afresh every reuse-th set-up and after a failed Newton iteration, combined with each set-up's cj in between (IDA
   itself evaluates the whole matrix at every set-up, which it makes whenever cj changes by a quarter). */
static int ms_ida_dq_reused(ms_run* r, double t, double cj, N_Vector y, N_Vector yp, N_Vector res, SUNMatrix J,
                            N_Vector t1, N_Vector t2, N_Vector t3) {
  long ncf = 0;
  IDAGetNumNonlinSolvConvFails(r->mem, &ncf);
  if (!r->jx) {
    r->jx = SUNMatClone(J);
    r->jxp = SUNMatClone(J);
    if (!r->jx || !r->jxp) return -1;
    r->since = r->reuse;
  }
  if (r->since >= r->reuse || ncf != r->ncf_seen) {
    if (ms_dq_band(r, t, y, yp, 1.0, 0.0, 0.0, res, r->jx, t1, t2, t3)) return -1;
    if (ms_dq_band(r, t, y, yp, 0.0, 1.0, cj, res, r->jxp, t1, t2, t3)) return -1;
    r->since = 0;
    r->ncf_seen = ncf;
  }
  r->since += 1;
  if (SUNMatCopy(r->jxp, J) || SUNMatScaleAdd(cj, J, r->jx)) return -1; /* J = cj dF/dx' + dF/dx */
  return 0;
}

"""
