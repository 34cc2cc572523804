"""``cvode-bdf``, ``cvode-adams`` and ``ida``: SUNDIALS with the time loop in compiled code.

The same solvers, settings, events and constraints as scikit-sundae's route (:mod:`mol_shell.integrators.sundials`,
kept as ``sksundae-*``), driven by a generated C driver (:mod:`mol_shell.discretization.sundials_driver`) that calls
the compiled right-hand side (or IDA's residual), the compiled exact Jacobian written into a dense, banded or
sparse matrix, and the model's limits as root functions, with no Python per step. One C call advances to the
next saved time, or for at most :attr:`CHUNK_SECONDS` of wall time, so progress, saving and Ctrl-C are handled
between calls. Where the driver (or the right-hand side it calls) is neither in the cache nor built by a working gcc,
or cannot be loaded (libraries not found), the run takes scikit-sundae's route, with one line on stderr saying why.
"""

from __future__ import annotations

import ctypes
import dataclasses
import sys
from dataclasses import dataclass

import casadi as ca
import numpy as np

from mol_shell._core.errors import ModelLimitError, ParameterError
from mol_shell.discretization import kernel_cache
from mol_shell.discretization import sundials_driver as drv
from mol_shell.discretization.loading import drive_kinks
from mol_shell.integrators import buildable, sundials
from mol_shell.integrators.base import StepBudget
from mol_shell.integrators.explicit import failed
from mol_shell.integrators import loop
from mol_shell.integrators.loop import Option, choice, option

ILL_INPUT = sundials.ILL_INPUT
#: what SUNDIALS' failure flags mean (CVODE, IDA), for the run's message
FLAGS = {
    "cvode": {-1: "max_num_steps steps in one call", -2: "accuracy asked for is too high",
              -3: "error test failed repeatedly or with |h| = hmin",
              -4: "Newton iterations failed to converge repeatedly or with |h| = hmin",
              -5: "linear solver set-up failed", -6: "linear solve failed", -8: "right-hand side failed",
              -12: "root function failed", -15: "constraints could not be met", -22: ILL_INPUT},
    "ida": {-1: "max_num_steps steps in one call", -2: "accuracy asked for is too high",
            -3: "error test failed repeatedly or with |h| = hmin",
            -4: "Newton iterations failed to converge repeatedly",
            -5: "linear solver set-up failed", -6: "linear solve failed", -8: "residual failed",
            -10: "root function failed", -11: "constraints could not be met", -22: ILL_INPUT},
}


def _newton_iterations(v):
    return v is None or (isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 1 <= v <= 100)


def _fraction(v):
    return isinstance(v, (int, float, np.floating)) and not isinstance(v, bool) and 0 <= v < 1


_REPORTED = set()


def report_fallback(name, reason):
    """One line on stderr, once per process and reason: the run takes scikit-sundae's Python loop."""
    if reason not in _REPORTED:
        _REPORTED.add(reason)
        print(f"mol-shell: {name} runs scikit-sundae's Python loop: the compiled SUNDIALS driver is unavailable "
              f"({reason})", file=sys.stderr, flush=True)


class _Compiled:
    """What the compiled routes add to scikit-sundae's options (a mixin before :class:`sundials._Sundials`)."""

    #: wall time of one C call at most, s: the latency of progress lines and of Ctrl-C
    CHUNK_SECONDS = 0.2

    def __new__(cls, *args, **kwargs):
        # the options given, told apart from defaults: a Newton option given at its default (jac_every = 0, SUNDIALS'
        # 51 steps under Newton's) to a fixed-point iteration was taken silently, one given at another value refused
        self = super().__new__(cls)
        names = [f.name for f in dataclasses.fields(cls) if f.init]
        object.__setattr__(self, "_given", frozenset(names[:len(args)]) | frozenset(kwargs))
        return self

    def fixed_point(self):
        return getattr(self, "iteration", "newton") == "fixed-point"

    #: options of Newton's iteration and their defaults: a fixed-point iteration takes none of them (they were kept
    #: in the file and did nothing)
    NEWTON_ONLY = (("jac_every", 0), ("setup_every", 0), ("max_newton", None), ("newton_coef", 0.0),
                   ("jacobian", "auto"), ("linsolver", "auto"))
    #: options of the fixed-point iteration: Newton's takes none of them (``anderson`` was kept in the file beside
    #: iteration = 'newton' and did nothing)
    FIXED_POINT_ONLY = (("anderson", 0),)

    def __post_init__(self):
        super().__post_init__()
        iteration = getattr(self, "iteration", None)  # IDA has no choice of iteration
        if iteration is not None:
            default = next(f.default for f in dataclasses.fields(self) if f.name == "iteration")
            fixed = self.fixed_point()
            what, other = ("Newton's iteration", "newton") if fixed else ("the fixed-point iteration", "fixed-point")
            given = getattr(self, "_given", frozenset())
            for name, unused in self.NEWTON_ONLY if fixed else self.FIXED_POINT_ONLY:
                value = getattr(self, name, unused)
                # Newton's options given at all (their defaults are Newton's settings too); anderson's 0 is "none"
                if value != unused or (fixed and name in given):
                    raise ParameterError(name, value, f"its default ({unused}) with iteration = {iteration!r}",
                                         message=f"{name} = {value!r} is an option of {what}, which {self.name} runs "
                                         f"only with iteration = {other!r} (its iteration here is {iteration!r}, "
                                         f"{'the default' if iteration == default else 'as set'})")
            if not fixed and (self.jac_every or self.setup_every):  # the file records the count used
                object.__setattr__(self, "setup_every", min(self.setup_every or 20, self.jac_every or 51))
        if self.jacobian == "dq" and self.linsolver == "sparse" and not self.fixed_point():
            raise ParameterError("jacobian", "dq", "{compiled, vm} with linsolver='sparse' (SUNDIALS' difference "
                                 "quotients need a dense or banded matrix)")

    def choose_linsolver(self, size):
        """``"auto"``: dense up to 100 states, banded above (node-major order keeps a meridian's coupling in a band
        whatever ``n``; SuperLU_MT on request, ``linsolver="sparse"``)."""
        if self.linsolver != "auto":
            return self.linsolver
        return "dense" if size <= 100 else "band"

    def dense_matrices(self, size):
        """The N x N matrices a dense linear solver (``dense``, ``lapack-dense``) keeps at ``size`` unknowns: the
        Newton matrix, factorised in place, and CVODE's saved Jacobian beside it (IDA keeps none); 0 for a banded
        or sparse solver and for CVODE's fixed-point iteration."""
        if (self.fixed_point() and self.kind != "ida") or self.choose_linsolver(size) not in ("dense", "lapack-dense"):
            return 0
        return 1 if self.kind == "ida" else 2

    def jacobian_kind(self, size):
        """``"compiled"``, ``"vm"`` or ``"dq"``: ``"auto"`` is difference quotients for a dense or banded matrix (the
        driver's own for a banded one, SUNDIALS' for a dense one; measured cheaper than the compiled exact Jacobian:
        ml + mu + 1, about 30, right-hand sides against about 120 at n = 40 and 640, and nothing to compile), the
        compiled exact one for a sparse matrix."""
        if self.jacobian != "auto":
            return self.jacobian
        return "compiled" if self.choose_linsolver(size) == "sparse" else "dq"

    def parts(self, system):
        """The Jacobian's pieces (compiled, CasADi's VM, or its pattern only), or None for fixed-point iterations."""
        if self.fixed_point() and self.kind != "ida":
            return None
        kind = self.jacobian_kind(system.size)
        return sundials.pieces(system, self.kind, "pattern" if kind == "dq" else kind)

    def integrate(self, system, compiled, y0, times, *, progress=None):
        """Run from ``times[0]`` through ``times``; returns a :class:`Trajectory` of ``(q, p)`` states."""
        self.parts(system)  # built (and compiled) before the run is timed
        return loop.run(self, system, compiled, y0, times, progress=progress)

    def start(self, system, compiled, y0, times, monitor):
        try:
            drv.driver()
            if compiled.path is None:  # a cached driver, and the right-hand side neither cached nor built: in the VM
                problem = kernel_cache.gcc_problem() or compiled.vm_reason
                raise drv.DriverUnavailable(f"the compiled right-hand side is not in the cache and cannot be built "
                                            f"({problem})")
            residual = (self.parts(system) or {}).get("library")
            if residual is not None and residual.path is None:  # a cached driver, and a gcc that fails on the residual
                raise drv.DriverUnavailable(residual.vm_reason)
        except drv.DriverUnavailable as exc:
            report_fallback(self.name, str(exc))
            run = self.python_route().start(system, compiled, y0, times, monitor)
            run.route_reason = f"the compiled SUNDIALS driver is unavailable ({exc})"  # recorded, as said
            return run
        return _CompiledRun(self, system, compiled, self.parts(system), y0, times)

    def python_route(self):
        """The same solver through scikit-sundae's Python loop: the options both routes take (a Jacobian by difference
        quotients there from CasADi's virtual machine, LAPACK solvers as SUNDIALS' own)."""
        base = next(c for c in type(self).__mro__ if c.__module__ == sundials.__name__ and hasattr(c, "make_solver")
                    and "name" in c.__dict__)
        common = {f.name: getattr(self, f.name) for f in dataclasses.fields(base)}
        if self.jacobian in ("auto", "dq"):  # scikit-sundae's route has no difference quotients: the compiled
            # Jacobian where it can be had (cached, or built by a gcc that works), settled for the graph; the
            # driver's reason said, no second line
            common["jacobian"] = buildable.undecided(base.name, quiet=True)
        common["linsolver"] = common["linsolver"].replace("lapack-", "")
        return base(**common)

    def newton_settings(self):
        """``(max Newton iterations, nonlinear convergence coefficient, Jacobian every, set-up every, cj ratio)``."""
        default_newton = 4 if self.kind == "ida" else 3
        # a fixed-point iteration has neither (refused); setup_every is held at most jac_every in __post_init__ (a
        # fresh Jacobian is factorised: msbp above msbj would mean nothing)
        jac_every, setup_every = int(getattr(self, "jac_every", 0)), int(getattr(self, "setup_every", 0))
        return (self.max_newton or default_newton, float(self.newton_coef), jac_every, setup_every,
                float(getattr(self, "cj_ratio", 0.0)))


LINSOLVER = option("auto", Option(
    "{auto, dense, band, sparse, lapack-dense, lapack-band} (auto: dense up to 100 states, banded above; sparse: "
    "SuperLU_MT; lapack-*: the wheel's OpenBLAS)",
    lambda v: v in ("auto", "dense", "band", "sparse", "lapack-dense", "lapack-band")))
JACOBIAN = option("auto", Option(
    "{auto, compiled, vm, dq} (CasADi's exact Jacobian as generated C or in its virtual machine, or SUNDIALS' "
    "difference quotients on the compiled right-hand side: ml + mu + 1 evaluations for a banded matrix; auto: dq "
    "for a dense or banded matrix, compiled for a sparse one)",
    lambda v: v in ("auto", "compiled", "vm", "dq")))
MAX_NEWTON = option(None, Option("integers in [1, 100], or None (SUNDIALS' 3 for CVODE, 4 for IDA)", _newton_iterations))
NEWTON_COEF = option(0.0, Option("[0, 1) (0: SUNDIALS' 0.1 for CVODE, 0.33 for IDA)", _fraction))


def _count(v):
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 0


#: the most steps between Jacobians or factorisations: SUNDIALS tests ``nst > nstlj + msbj`` (``>= nstlp + msbp``) in a
#: C ``long``, which a value near its top (2^63 - 1) overflows (undefined in C: a Jacobian at every step, in practice);
#: 2^31 - 1 steps are never reached, and keep that sum below 2^63 - 1 for any step count a run can make
FREQUENCY_MAX = 2**31 - 1


def _frequency(v):
    return _count(v) and v <= FREQUENCY_MAX


#: CVODE's steps between Jacobians and between factorisations: SUNDIALS' 51 and 20 (0). Longer reuse (200 and 100)
#: was 1.1-1.4x faster up to n = 640 and 1.35x to 2x slower at n = 2,560 and 10,240, where a stale Jacobian stalls
#: Newton's iteration and shortens the steps (benchmarks/cvode_settings.py, docs/integrators.md)
JAC_EVERY = option(0, Option(f"integers in [0, {FREQUENCY_MAX}] (0: SUNDIALS' 51)", _frequency, convert=int))
SETUP_EVERY = option(0, Option(f"integers in [0, {FREQUENCY_MAX}] (0: SUNDIALS' 20)", _frequency, convert=int))
ANDERSON = option(0, Option("integers in [0, 10]", lambda v: _count(v) and v <= 10))


@dataclass(frozen=True)
class _CVODEOptions:
    """The options both CVODE methods take beyond scikit-sundae's route (:class:`mol_shell.integrators.sundials.CVODEBDF`):
    ``max_newton`` (Newton iterations per step), ``newton_coef`` (safety factor of the nonlinear convergence test),
    ``jac_every`` (steps between Jacobian evaluations, SUNDIALS' msbj; 0: 51), ``setup_every`` (steps between
    factorisations, msbp; 0: 20; held at most ``jac_every``, and holds the count used), ``iteration`` (``"newton"``, or
    ``"fixed-point"``: no Jacobian and no linear solver, for non-stiff motions) and ``anderson`` (Anderson acceleration
    depth of the fixed-point iteration; refused above 0 with Newton's)."""

    linsolver: str = LINSOLVER
    jacobian: str = JACOBIAN
    max_newton: int | None = MAX_NEWTON
    newton_coef: float = NEWTON_COEF
    jac_every: int = JAC_EVERY
    setup_every: int = SETUP_EVERY
    iteration: str = option("newton", choice("newton", "fixed-point"))
    anderson: int = ANDERSON


@dataclass(frozen=True)
class CVODEBDF(_CVODEOptions, _Compiled, sundials.CVODEBDF):
    """CVODE, variable-order BDF (1-5), Newton iterations on the exact Jacobian; loop in compiled C. Options: those of
    :class:`_CVODEOptions`."""

    name = "cvode-bdf"


@dataclass(frozen=True)
class CVODEAdams(_CVODEOptions, _Compiled, sundials.CVODEAdams):
    """CVODE, variable-order Adams-Moulton (1-12); loop in compiled C. Options as for :class:`CVODEBDF`, but
    ``iteration="fixed-point"`` by default (the non-stiff pairing SUNDIALS recommends; measured 1.4x-1.6x faster than
    Newton's on the paper's scene at equal error): ``iteration="newton"`` for scikit-sundae's route's iteration."""

    iteration: str = option("fixed-point", choice("newton", "fixed-point"))

    name = "cvode-adams"


@dataclass(frozen=True)
class IDA(_Compiled, sundials.IDA):
    """IDA on the linearly implicit residual; loop in compiled C. ``cj_ratio``: a new factorisation when ``cj`` changed
    by more than this fraction (0: SUNDIALS' 0.25). ``jac_reuse``: with the banded difference-quotient Jacobian (the
    default above 100 states), ``dF/dx`` and ``dF/dx'`` are evaluated afresh every ``jac_reuse``-th set-up and after a
    failed Newton iteration, and combined with each set-up's ``cj`` in between (IDA itself evaluates the whole
    matrix at every set-up)."""

    linsolver: str = LINSOLVER
    jacobian: str = JACOBIAN
    max_newton: int | None = MAX_NEWTON
    newton_coef: float = NEWTON_COEF
    cj_ratio: float = option(0.0, Option("[0, 1) (0: SUNDIALS' 0.25)", _fraction))
    jac_reuse: int = option(1, Option("integers in [1, 1000] (set-ups per difference-quotient Jacobian; 1: a fresh "
                                      "one at each set-up, as SUNDIALS)", lambda v: _count(v) and 1 <= v <= 1000))

    name = "ida"


def _sizes_of(lib_path, name):
    return drv.work_sizes(ca.external(name, str(lib_path)))


class _CompiledRun:
    """One solve in the driver: a stepper of the run loop."""

    def __init__(self, method, system, compiled, parts, y0, times):
        self.method, self.system, self.parts = method, system, parts
        self.ida = method.kind == "ida"
        self.names = system.limit_names()
        self.y0 = np.array(y0, dtype=float)
        size = system.size
        linsolver = method.choose_linsolver(size)
        self.linsolver = linsolver
        r_entries = system.ny * system.radial_nodes + list(system.active).index(1)
        self.r_entries = r_entries
        r_floor = float(method.field_atol()[1])
        n_events = len(self.names)
        floor = np.zeros(n_events)
        first_r = system.samples_per_cell * (system.n - 1)  # the deltas come first, then r per node
        floor[first_r: first_r + len(system.radial_nodes)] = r_floor  # r events sit at r = atol_r

        fixed_point = method.fixed_point() and not self.ida
        if fixed_point:  # no Jacobian, no linear solver
            parts = self.parts = {"sparsity": ca.Sparsity(size, size), "bw": (0, 0), "build_time_s": 0.0}
            linsolver = self.linsolver = "none"
        # the functions: the right-hand side and limits from the compiled RHS, the Jacobian (and IDA's residual)
        rhs_lib = compiled._lib
        kind = "none" if fixed_point else method.jacobian_kind(size)
        library = parts.get("library")
        if self.ida:
            x0, xp0 = parts["dae"].consistent_rates(self.y0)
            if library is None:  # jacobian="vm": the residual compiled alone, the Jacobian from CasADi's VM
                library = sundials.CompiledFunctions([parts["dae"].residual])
            funcs = ctypes.CDLL(str(library.path))
            rhs = (drv.address(funcs, "dae_residual"), drv.work_sizes(library.functions["dae_residual"]))
        else:
            x0, xp0 = self.y0, self.y0
            funcs = ctypes.CDLL(str(library.path)) if library is not None else None
            rhs = (drv.address(rhs_lib, compiled.function.name()), drv.work_sizes(compiled.function))
        self._libs = (rhs_lib, funcs)
        pattern = parts["sparsity"]
        jac, py_jac = None, None
        if kind == "compiled":
            name = "dae_jacobian" if self.ida else "ode_jacobian"
            jac = (drv.address(funcs, name), drv.work_sizes(library.functions[name]))
        elif kind == "vm":
            py_jac = self._python_jacobian(parts["jac"], size, int(pattern.nnz()))
        self.jacobian = kind
        limits = None
        if method.events and compiled.n_limits:
            limits = (drv.address(rhs_lib, "limits"), _sizes_of(compiled.path, "limits"))
        max_newton, coef, jac_every, setup_every, cj_ratio = method.newton_settings()
        lmm = 1 if getattr(method, "method", "BDF") == "Adams" else 2
        max_order = method.max_order if method.max_order is not None else (12 if lmm == 1 and not self.ida else 5)
        ml, mu = parts["bw"]
        iopts = [int(self.ida), lmm, drv.LINSOLVERS.get(linsolver, 0), ml, mu, int(max_order), int(max_newton), 10,
                 jac_every, setup_every, int(limits is not None), int(bool(method.constraints)),
                 sundials._Run.MAX_CALLS_PER_STEP, 1, int(fixed_point), int(getattr(method, "anderson", 0)),
                 int(system.n_extra), int(getattr(method, "jac_reuse", 1))]
        opts = [float(method.rtol), float(method.first_step), float(method.max_step), r_floor, coef, cj_ratio]
        atol = method.atol_vector(system, self.y0, momenta=not self.ida)
        self.py_error = None
        self.solve = drv.Solve(self.ida, iopts, opts, x0, xp0, atol, rhs, jac, py_jac, pattern, limits, floor,
                               r_entries if method.constraints else np.zeros(0, dtype=np.int32),
                               kinks=[t for t in drive_kinks(system) if t <= float(times[-1])])
        self.t = 0.0
        self.t_end = float(times[-1])
        self.budget = StepBudget(method.name, self.t_end, method.max_steps, method.tolerance_text())

    def _python_jacobian(self, jac, size, nnz):
        """The Jacobian's non-zeros from CasADi's virtual machine (``jacobian="vm"``: no compiler for it)."""
        ida = self.ida

        def evaluate(t, y, yp, cj, out):
            try:
                yv = np.ctypeslib.as_array(y, (size,))
                vals = jac(t, yv, np.ctypeslib.as_array(yp, (size,)), cj) if ida else jac(t, yv)
                np.ctypeslib.as_array(out, (nnz,))[:] = vals
                return 0
            except BaseException as exc:  # noqa: BLE001 - Ctrl-C included: re-raised after the C call returns
                self.py_error = exc
                return -1

        return evaluate

    def advance(self, target):
        method, solve = self.method, self.solve
        code = solve.advance(target, method.max_steps, method.CHUNK_SECONDS)
        if self.py_error is not None:
            raise self.py_error
        t = solve.t
        if code == drv.ROOT:
            raise self._event_error()
        if code == drv.R_FLOOR:
            raise self._constraint_limit(t)
        if code == drv.MAX_STEPS:
            raise failed(f"{method.name} took max_steps = {method.max_steps} steps by t = {t:.9g} s"
                         + self._stiff_steps(), t)
        if code == drv.CALLS:
            raise failed(f"{method.name} evaluated the right-hand side {sundials._Run.MAX_CALLS_PER_STEP} times without "
                         f"completing a step after t = {self.t:.9g} s (its step size underflowed): the motion is too "
                         "fast for double precision", self.t)
        if code == drv.STALLED:
            raise failed(f"{method.name} failed at t = {t:.9g} s: its step fell below round-off at t (at most 10 eps |t| "
                         f"for {drv.STALL_STEPS} steps in a row): {method.tolerance_text()} cannot be met there in double "
                         "precision (a looser tolerance goes on), or the right-hand side is not finite near this "
                         "state", t)
        if code < 0:
            raise self._failure(code, t)
        self.budget.project(solve.stats()["n_steps"], t)  # the steps still needed, from the mean of the last ones
        self.t = t

    def _stiff_steps(self):
        """Why the steps were short, when a fixed-point iteration failed to converge in 10 % of them or more (the
        wall is stiff: :mod:`mol_shell.runs.step_limits`), else ''."""
        s = self.solve.stats()
        if not (self.method.fixed_point() and not self.ida and s["n_convergence_fails"] >= 0.1 * max(s["n_steps"], 1)):
            return ""
        return (f": its fixed-point iteration failed to converge {s['n_convergence_fails']:,} times in {s['n_steps']:,} "
                "steps, which the stiffness of the wall (its viscous damping) holds short, not the tolerance; use "
                'iteration="newton" (--option iteration=newton), cvode-bdf or ida (implicit, for stiff walls)')

    def to_hamiltonian(self, state, t):
        if not self.ida:
            return np.array(state, dtype=float)
        return np.array(self.parts["dae"].to_momenta(state, float(t))).ravel()

    def state(self, target):
        return self.to_hamiltonian(self.solve.y, self.t)

    def stats(self):
        s = self.solve.stats()
        return {"n_steps": s["n_steps"], "n_rhs": s["n_rhs"], "n_jac": s["n_jac"],
                "n_failed_steps": s["n_error_test_fails"] + s["n_convergence_fails"],
                "n_convergence_fails": s["n_convergence_fails"],
                "n_setups": s["n_setups"], "n_newton": s["n_newton"], "n_root_evals": s["n_root_evals"],
                "n_rhs_jacobian": s["n_rhs_jacobian"],
                "linsolver": self.linsolver, "jacobian_kind": self.jacobian, "route": "compiled C",
                "jacobian_build_s": float(self.parts.get("build_time_s", 0.0))}

    def _event_error(self):
        t = self.solve.event_time()
        limit, where = self.names[self.solve.stats()["root"]]
        if limit.startswith("r reached"):
            limit += " (to within atol)"  # the event sits at r = atol_r: r > 0 is also a constraint
        return ModelLimitError(f"{limit} at t = {t:.9g} s, {where}: a limit of the model "
                               f"(root found by {self.method.name})", t, where)

    def _constraint_limit(self, t):
        r = self.solve.y[self.r_entries]
        i = int(self.system.radial_nodes[np.argmin(r)])
        where = f"s = {self.system.s[i]:.6g} m"
        return ModelLimitError(
            f"r reached 0 (to within atol; r > 0 is a constraint of the model, held by {self.method.name}, "
            f"r = {r.min():.3g} m) at t = {t:.9g} s, {where}", t, where)

    def _failure(self, flag, t):
        kind = self.method.kind
        if flag == drv.CONSTRAINT_FAIL[kind]:
            r = self.system.unpack(self.to_hamiltonian(self.solve.y, t))[1][self.system.radial_nodes]
            i = int(self.system.radial_nodes[np.argmin(r)])
            where = f"s = {self.system.s[i]:.6g} m"
            return ModelLimitError(
                f"r -> 0 (r > 0 is a constraint of the model; {self.method.name} could not keep it, "
                f"r = {r.min():.3g} m) at t = {t:.9g} s, {where}", t, where)
        what = FLAGS[kind].get(flag, "SUNDIALS error")
        return failed(f"{self.method.name} failed at t = {t:.9g} s: {what} (status {flag})", t)


COMPILED = {cls.name: cls for cls in (CVODEBDF, CVODEAdams, IDA)}
