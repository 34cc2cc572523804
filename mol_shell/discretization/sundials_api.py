"""The SUNDIALS 7.9 C API that the compiled driver uses, declared by hand.

The wheel of scikit-sundae installs SUNDIALS' shared libraries but not their headers; the prototypes below are
those of the functions the driver calls (:mod:`mol_shell.discretization.sundials_source`), with the types of
scikit-sundae's ``.pxd`` files (``sunrealtype = double``, ``sunindextype = int``, ``SUNComm = int``), verified
against the libraries at load time (``ms_check_index``). Nothing of SUNDIALS' own source is copied.
"""

SUNDIALS_PROTOTYPES = r"""
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <float.h>

#define CASADI_SYMBOL_EXPORT __attribute__((visibility("default")))

typedef double sunrealtype;
typedef int sunindextype;
typedef long long casadi_int;
typedef struct _SUNContext* SUNContext;
typedef struct _generic_N_Vector* N_Vector;
typedef struct _generic_SUNMatrix* SUNMatrix;
typedef struct _generic_SUNLinearSolver* SUNLinearSolver;
typedef struct _generic_SUNNonlinearSolver* SUNNonlinearSolver;

/* the SUNDIALS 7.9 C API, as much of it as is used here */
int SUNContext_Create(int comm, SUNContext* ctx);
int SUNContext_Free(SUNContext* ctx);
int SUNContext_ClearErrHandlers(SUNContext ctx);
N_Vector N_VNew_Serial(sunindextype n, SUNContext ctx);
sunrealtype* N_VGetArrayPointer(N_Vector v);
void N_VDestroy(N_Vector v);
SUNMatrix SUNDenseMatrix(sunindextype m, sunindextype n, SUNContext ctx);
SUNMatrix SUNBandMatrix(sunindextype n, sunindextype mu, sunindextype ml, SUNContext ctx);
SUNMatrix SUNSparseMatrix(sunindextype m, sunindextype n, sunindextype nnz, int type, SUNContext ctx);
SUNMatrix SUNSparseFromDenseMatrix(SUNMatrix a, sunrealtype droptol, int type);
sunrealtype* SUNDenseMatrix_Column(SUNMatrix a, sunindextype j);
sunrealtype* SUNBandMatrix_Column(SUNMatrix a, sunindextype j);
sunrealtype* SUNSparseMatrix_Data(SUNMatrix a);
sunindextype* SUNSparseMatrix_IndexValues(SUNMatrix a);
sunindextype* SUNSparseMatrix_IndexPointers(SUNMatrix a);
sunindextype SUNSparseMatrix_NNZ(SUNMatrix a);
int SUNMatZero(SUNMatrix a);
int SUNMatScaleAddI(sunrealtype c, SUNMatrix a);
void SUNMatDestroy(SUNMatrix a);
SUNLinearSolver SUNLinSol_Dense(N_Vector y, SUNMatrix a, SUNContext ctx);
SUNLinearSolver SUNLinSol_Band(N_Vector y, SUNMatrix a, SUNContext ctx);
SUNLinearSolver SUNLinSol_SuperLUMT(N_Vector y, SUNMatrix a, int threads, SUNContext ctx);
SUNLinearSolver SUNLinSol_LapackDense(N_Vector y, SUNMatrix a, SUNContext ctx);
SUNLinearSolver SUNLinSol_LapackBand(N_Vector y, SUNMatrix a, SUNContext ctx);
int SUNLinSolSetup(SUNLinearSolver s, SUNMatrix a);
int SUNLinSolSolve(SUNLinearSolver s, SUNMatrix a, N_Vector x, N_Vector b, sunrealtype tol);
int SUNLinSolFree(SUNLinearSolver s);
SUNMatrix SUNMatClone(SUNMatrix a);
int SUNMatCopy(SUNMatrix a, SUNMatrix b);
int SUNMatScaleAdd(sunrealtype c, SUNMatrix a, SUNMatrix b);
N_Vector N_VClone(N_Vector v);
SUNNonlinearSolver SUNNonlinSol_FixedPoint(N_Vector y, int m, SUNContext ctx);
int SUNNonlinSolFree(SUNNonlinearSolver s);

typedef int (*CVRhsFn)(sunrealtype t, N_Vector y, N_Vector ydot, void* data);
typedef int (*CVRootFn)(sunrealtype t, N_Vector y, sunrealtype* g, void* data);
typedef int (*CVLsJacFn)(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* data, N_Vector t1,
                         N_Vector t2, N_Vector t3);
void* CVodeCreate(int lmm, SUNContext ctx);
int CVodeInit(void* mem, CVRhsFn f, sunrealtype t0, N_Vector y0);
int CVodeSVtolerances(void* mem, sunrealtype rtol, N_Vector atol);
int CVodeSetUserData(void* mem, void* data);
int CVodeSetLinearSolver(void* mem, SUNLinearSolver ls, SUNMatrix a);
int CVodeSetNonlinearSolver(void* mem, SUNNonlinearSolver nls);
int CVodeSetJacFn(void* mem, CVLsJacFn jac);
int CVodeSetMaxNonlinIters(void* mem, int maxcor);
int CVodeSetMaxConvFails(void* mem, int maxncf);
int CVodeSetNonlinConvCoef(void* mem, sunrealtype coef);
int CVodeSetJacEvalFrequency(void* mem, long int msbj);
int CVodeSetLSetupFrequency(void* mem, long int msbp);
int CVodeRootInit(void* mem, int nrtfn, CVRootFn g);
int CVodeSetRootDirection(void* mem, int* dir);
int CVodeSetInitStep(void* mem, sunrealtype h);
int CVodeSetMaxStep(void* mem, sunrealtype h);
int CVodeSetMaxOrd(void* mem, int order);
int CVodeSetMaxNumSteps(void* mem, long int mxsteps);
int CVodeSetConstraints(void* mem, N_Vector c);
int CVodeSetStopTime(void* mem, sunrealtype tstop);
int CVodeReInit(void* mem, sunrealtype t0, N_Vector y0);
int CVode(void* mem, sunrealtype tout, N_Vector yout, sunrealtype* tret, int itask);
int CVodeGetRootInfo(void* mem, int* rootsfound);
int CVodeGetNumSteps(void* mem, long int* n);
int CVodeGetNumRhsEvals(void* mem, long int* n);
int CVodeGetNumLinRhsEvals(void* mem, long int* n);
int CVodeGetNumJacEvals(void* mem, long int* n);
int CVodeGetNumLinSolvSetups(void* mem, long int* n);
int CVodeGetNumErrTestFails(void* mem, long int* n);
int CVodeGetNumNonlinSolvConvFails(void* mem, long int* n);
int CVodeGetNumNonlinSolvIters(void* mem, long int* n);
int CVodeGetNumGEvals(void* mem, long int* n);
void CVodeFree(void** mem);

typedef int (*IDAResFn)(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* data);
typedef int (*IDARootFn)(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype* g, void* data);
typedef int (*IDALsJacFn)(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix J,
                          void* data, N_Vector t1, N_Vector t2, N_Vector t3);
void* IDACreate(SUNContext ctx);
int IDAInit(void* mem, IDAResFn res, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDASVtolerances(void* mem, sunrealtype rtol, N_Vector atol);
int IDASetUserData(void* mem, void* data);
int IDASetLinearSolver(void* mem, SUNLinearSolver ls, SUNMatrix a);
int IDASetJacFn(void* mem, IDALsJacFn jac);
int IDASetMaxNonlinIters(void* mem, int maxcor);
int IDASetMaxConvFails(void* mem, int maxncf);
int IDASetNonlinConvCoef(void* mem, sunrealtype coef);
int IDASetDeltaCjLSetup(void* mem, sunrealtype dcj);
int IDARootInit(void* mem, int nrtfn, IDARootFn g);
int IDASetRootDirection(void* mem, int* dir);
int IDASetInitStep(void* mem, sunrealtype h);
int IDASetMaxStep(void* mem, sunrealtype h);
int IDASetMaxOrd(void* mem, int order);
int IDASetMaxNumSteps(void* mem, long int mxsteps);
int IDASetConstraints(void* mem, N_Vector c);
int IDASetStopTime(void* mem, sunrealtype tstop);
int IDAReInit(void* mem, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDASolve(void* mem, sunrealtype tout, sunrealtype* tret, N_Vector y, N_Vector yp, int itask);
int IDAGetRootInfo(void* mem, int* rootsfound);
int IDAGetNumSteps(void* mem, long int* n);
int IDAGetNumResEvals(void* mem, long int* n);
int IDAGetNumLinResEvals(void* mem, long int* n);
int IDAGetNumJacEvals(void* mem, long int* n);
int IDAGetNumLinSolvSetups(void* mem, long int* n);
int IDAGetNumErrTestFails(void* mem, long int* n);
int IDAGetNumNonlinSolvConvFails(void* mem, long int* n);
int IDAGetNumNonlinSolvIters(void* mem, long int* n);
int IDAGetNumGEvals(void* mem, long int* n);
void IDAFree(void** mem);

"""
