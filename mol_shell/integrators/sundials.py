"""SUNDIALS CVODE (BDF and Adams) and IDA through scikit-sundae's Python loop, fed by the CasADi graphs.

These are the routes of release 0.5.0 under the names ``sksundae-cvode-bdf``, ``sksundae-cvode-adams`` and
``sksundae-ida``: every right-hand side, Jacobian and event evaluation is a Python call. The names ``cvode-bdf``,
``cvode-adams`` and ``ida`` run the same solvers with the loop in compiled code
(:mod:`mol_shell.integrators.sundials_c`), and fall back to these where that cannot be built.

* CVODE integrates the Hamiltonian ODE ``y_t = f(y)`` of :class:`~mol_shell.discretization.system.ShellSystem`;
  IDA the linearly implicit residual of :class:`~mol_shell.discretization.dae.ShellDAE` in ``x = (q, v)``
  (the mass matrix is never inverted). Saved states are returned as ``y = (q, p)`` either way.
* The exact Jacobian comes from CasADi (``dF/dx + cj dF/dxp`` for IDA), compiled to C once per graph
  and cached on disk (:class:`~mol_shell.discretization.compiled.CompiledFunctions`); dense, banded or sparse
  linear algebra by size (``linsolver="auto"``).
* Model limits: ``r > 0`` is a SUNDIALS inequality constraint on the ``r`` entries; ``delta > 0``
  (per cell) and ``|psi| < pi/2`` (per node) are root-finding events. A breach ends the run with
  status ``"limit"``, a message naming time, place and limit, and the saved times reached.
* scikit-sundae 1.2.0 leaves the constraint entries that ``constraints_idx`` does not list
  uninitialised (malloc garbage: "Illegal values in constraints vector", or spurious sign
  constraints on other entries). Types must be in ``{-2, -1, 1, 2}``, so "no constraint" (0)
  cannot be listed. Workaround: list *every* entry; unconstrained ones get :data:`UNCONSTRAINED`,
  which passes the type check (it compares equal to 1) and is stored as 0.0 (its ``__float__``).
  ``tests/test_constraints.py`` reproduces the defect and checks the workaround over many solves.
* At each kink of a driven edge's rate (:func:`~mol_shell.discretization.loading.drive_kinks`) the solver stops
  (``tstop``), evaluates the step that ends there one ulp short of it (the old segment's rate) and restarts there
  (``init_step``: SUNDIALS' ``ReInit``), as the compiled route does (docs/loads.md); a saved time within round-off
  of a kink is taken there (:func:`~mol_shell.discretization.sundials_kinks.one_time`).
* Statistics: ``n_steps`` counts ``onestep`` calls; ``n_rhs``/``n_jac`` are SUNDIALS' counters;
  scikit-sundae exposes no failure counters, so ``n_failed_steps`` (error-test plus nonlinear
  failures together) is inferred from the trial times of the right-hand side calls: a step attempt
  followed by one at an earlier time was rejected.
"""

from __future__ import annotations

import time
import warnings
import weakref
from dataclasses import dataclass

import casadi as ca  # noqa: E402
import numpy as np  # noqa: E402

from mol_shell._core.constants import DENSE_MAX_STATES, MIN_STEP, stated_up
from mol_shell._core.errors import ModelLimitError, ParameterError  # noqa: E402
from mol_shell.discretization.compiled import CompiledFunctions, CompilerError, CompilerMissing, buffered
from mol_shell.discretization.dae import ShellDAE
from mol_shell.discretization.loading import drive_kinks
from mol_shell.discretization.sundials_kinks import one_time
from mol_shell.discretization.threads import OMP_NUM_THREADS_GIVEN  # noqa: F401  (sets OMP_NUM_THREADS = 1 unless set)
from mol_shell.integrators import loop  # noqa: E402
from mol_shell.integrators.base import StepBudget  # noqa: E402
from mol_shell.integrators.buildable import JACOBIAN_DEFAULT, Undecided, resolve_jacobian
from mol_shell.integrators.loop import BOOL, Option, choice, integers, option, zero_or_at_least  # noqa: E402
from mol_shell.integrators.sksundae_workarounds import UNCONSTRAINED, unlisted_status
from mol_shell.integrators.tolerances import Tolerances  # noqa: E402

#: the scikit-sundae version whose constraint defect the workaround targets (and that passes the tests)
SKSUNDAE_TESTED = "1.2.0"
ROOT_RETURN, CONSTRAINT_FAIL = 2, {"cvode": -15, "ida": -11}
#: CV_ILL_INPUT / IDA_ILL_INPUT in a step: an input SUNDIALS checks is not valid there (the step, the time or the
#: error weights: a state or a tolerance's scale that is not finite, e.g. E = 1e300 or rho = 1e-300)
ILL_INPUT_FLAG = -22
ILL_INPUT = ("SUNDIALS found an input of the step invalid (a step, time or error weight that is not finite in double "
             "precision: the motion's scales are beyond it)")
#: the least first step other than 0 (s): :data:`~mol_shell._core.constants.MIN_STEP` (its square underflows below
#: it: IDA stopped with status -22 at 1e-320 s, CVODE's BDF failed its Newton iteration at t = 0 from 1e-290 s),
#: rounded up to the digits its range states
FIRST_STEP_MIN = stated_up(MIN_STEP)


def full_constraints(size, entries):
    """``(constraints_idx, constraints_type)`` listing all ``size`` entries; ``entries`` maps index -> type."""
    return list(range(size)), [entries.get(i, UNCONSTRAINED) for i in range(size)]


# -- per-system pieces, built once (compiled code cached on disk) ------------------------------
_PIECES = weakref.WeakKeyDictionary()


def pieces(system, kind, jacobian="compiled"):
    """Compiled Jacobian (and for IDA the residual) plus the events function of ``system``; cached. ``jacobian``
    :class:`~mol_shell.integrators.buildable.Undecided` (the default without a working gcc) is settled here, for this
    graph: the compiled Jacobian where its library is in the cache, else CasADi's virtual machine (one line)."""
    store = _PIECES.setdefault(system, {})
    undecided = isinstance(jacobian, Undecided)
    key = (kind, "default" if undecided else jacobian)
    if key not in store:
        start = time.perf_counter()
        store[key] = _build_pieces(system, kind, jacobian)
        store[key]["build_time_s"] = time.perf_counter() - start
    elif undecided:  # settled for this graph before: recorded (and said) for this integrator too
        jacobian.settle(store[key]["unavailable"])
    return store[key]


def _build_pieces(system, kind, jacobian):
    out = {"events": buffered(system.limits)}
    if kind == "ida":
        dae = ShellDAE(system)
        funcs = [dae.residual, dae.jacobian]
        out["dae"] = dae
    else:
        t, y = system.rhs_mapped.mx_in()
        funcs = [ca.Function("ode_jacobian", [t, y], [ca.jacobian(system.rhs_newton_mapped(t, y), y)])]
    jac = funcs[-1]
    generated = None
    if isinstance(jacobian, Undecided):  # compiled where its library is cached (or gcc builds it), else the VM's
        generated = CompiledFunctions.generate(funcs)
        out["unavailable"] = CompiledFunctions.unavailable(generated)
        jacobian = jacobian.settle(out["unavailable"])
        generated = generated if jacobian == "compiled" else None
    if jacobian == "compiled":
        try:
            lib = CompiledFunctions(funcs, generated=generated)
        except CompilerError as exc:  # given: the default is the VM's without a working gcc (buildable)
            why = "gcc not found on PATH" if isinstance(exc, CompilerMissing) else str(exc)
            allowed = "'vm' (CasADi's virtual machine) where gcc cannot build the Jacobian"
            raise ParameterError("jacobian", jacobian, allowed, message=f"jacobian = 'compiled' cannot be built: "
                                 f"{why}; allowed: {allowed}") from None
        out["library"] = lib  # the compiled route calls its C functions directly
        out["jac"] = lib.evaluator(jac.name())
        out["residual"] = lib.evaluator(funcs[0].name()) if kind == "ida" else None
    elif jacobian == "vm":
        out["jac"] = buffered(system.jac if kind != "ida" else jac)
        out["residual"] = buffered(funcs[0]) if kind == "ida" else None
    elif jacobian == "pattern":  # the compiled route's difference quotients: the pattern, and IDA's residual compiled
        out["jac"] = out["residual"] = None
        if kind == "ida":  # without gcc the driver is unavailable and the Python route builds its own (vm)
            out["library"] = CompiledFunctions(funcs[:1], vm_without_gcc=True)
    else:
        raise ParameterError("jacobian", jacobian, "{compiled, vm}")
    import scipy.sparse as sp

    pattern = (system.jac if (kind != "ida" and jacobian == "vm") else jac).sparsity_out(0)
    rows, cols = (np.asarray(a) for a in pattern.get_triplet())
    out["pattern"] = sp.csc_matrix((np.ones(len(rows)), (rows, cols)), shape=pattern.shape)
    out["rows"], out["cols"] = rows, cols
    out["bw"] = (int(pattern.bw_lower()), int(pattern.bw_upper()))
    out["sparsity"] = pattern
    return out


# -- the integrators ---------------------------------------------------------------------------
@dataclass(frozen=True)
class _Sundials(Tolerances):
    """Options of CVODE and IDA: the tolerances (:class:`~mol_shell.integrators.tolerances.Tolerances`) and

    Parameters
    ----------
    linsolver : str
        ``"auto"`` (dense up to 100 states, banded up to DENSE_MAX_STATES, sparse above), ``"dense"``,
        ``"band"`` or ``"sparse"``.
    jacobian : str
        ``"compiled"`` (generated C, cached) or ``"vm"`` (CasADi's virtual machine, no compiler); the default,
        ``"compiled"``, is ``"vm"`` where its library is neither in the cache nor built by a working gcc
        (:mod:`mol_shell.integrators.buildable`).
    constraints, events : bool
        Enforce ``r > 0`` (SUNDIALS constraints) and ``delta > 0``, ``|psi| < pi/2`` (events).
    max_order : int or None
        Largest order (BDF and IDA <= 5, Adams <= 12).
    first_step : float
        First step, s (0: SUNDIALS estimates it); at least :data:`FIRST_STEP_MIN`.
    max_steps : int
        Steps after which the run stops with status ``"failed"`` (scikit-sundae's ``max_num_steps``
        counts per call, and in one-step mode every call is one step).
    """

    linsolver: str = option("auto", choice("auto", "dense", "band", "sparse"))
    jacobian: str = option(JACOBIAN_DEFAULT, choice("compiled", "vm"))
    constraints: bool = option(True, BOOL)
    events: bool = option(True, BOOL)
    max_order: int | None = option(None, Option("integers in [1, 12] (Adams), [1, 5] (BDF, IDA), or None",
                                                lambda v: v is None or (isinstance(v, (int, np.integer))
                                                                        and not isinstance(v, bool) and 1 <= v <= 12)))
    first_step: float = option(0.0, zero_or_at_least(FIRST_STEP_MIN, " s", " (SUNDIALS estimates it)"))
    max_steps: int = option(1_000_000, integers(1))

    order = None  # variable order: tests check that the tolerance is reached instead
    kind = "cvode"

    def __post_init__(self):
        super().__post_init__()
        top = 12 if getattr(self, "method", "BDF") == "Adams" and self.kind != "ida" else 5
        if self.max_order is not None and self.max_order > top:  # the declared range holds both methods' orders
            raise ParameterError("max_order", self.max_order, f"integers in [1, {top}], or None",
                                 hint=f"{self.name} is {'Adams' if top == 12 else 'BDF'}: orders up to {top}")

    def settings(self):
        import sksundae  # imported when used: with scipy.optimize it is 0.28 s of every process's start

        return {**self.tolerances(), "linsolver_option": self.linsolver, "jacobian": self.jacobian_used(),
                "sksundae_version": sksundae.__version__}

    def choose_linsolver(self, size):
        if self.linsolver != "auto":
            return self.linsolver
        return "dense" if size <= 100 else "band" if size <= DENSE_MAX_STATES else "sparse"

    def dense_matrices(self, size):
        """The N x N matrices a dense linear solver keeps at ``size`` unknowns (the memory estimate's,
        :func:`mol_shell.runs.resources.solver_bytes`): SUNDIALS' matrix (factorised in place), CVODE's saved
        Jacobian and the array scikit-sundae's Jacobian callback fills; for ``linsolver="band"`` that array alone
        (scikit-sundae hands a banded solver's callback a full N x N array: 26.8 GiB at n = 6,000 was a MemoryError
        after the build; ``auto`` bands only up to DENSE_MAX_STATES, where the estimate counts the array anyway);
        0 for a sparse solver."""
        chosen = self.choose_linsolver(size)
        if chosen == "dense":
            return 2 if self.kind == "ida" else 3
        return 1 if self.linsolver == "band" else 0

    # -- running -----------------------------------------------------------------------------
    def jacobian_used(self):
        """``jacobian`` as this run uses it: the default follows what gcc can build (:func:`resolve_jacobian`)."""
        return resolve_jacobian(self.name, self.jacobian)

    def integrate(self, system, compiled, y0, times, *, progress=None):
        """Run from ``times[0]`` through ``times``; returns a :class:`Trajectory` of ``(q, p)`` states."""
        pieces(system, self.kind, self.jacobian_used())  # built (and compiled) before the run is timed
        return loop.run(self, system, compiled, y0, times, progress=progress)

    def start(self, system, compiled, y0, times, monitor):
        return _Run(self, system, compiled, pieces(system, self.kind, self.jacobian_used()), y0).begin(times)

    def solver_options(self, system, parts, y0, run):
        size = system.size
        linsolver = self.choose_linsolver(size)
        opts = {"rtol": self.rtol, "atol": self.atol_vector(system, y0, momenta=self.kind == "cvode"),
                "max_step": float(self.max_step), "first_step": float(self.first_step),
                "linsolver": linsolver, "max_num_steps": 100000, "jacfn": run.jacfn}
        if linsolver == "band":
            opts["lband"], opts["uband"] = parts["bw"]
        elif linsolver == "sparse":
            opts["sparsity"] = parts["pattern"]
        if self.max_order is not None:
            opts["max_order"] = int(self.max_order)
        if self.constraints:
            r = list(system.active).index(1)
            opts["constraints_idx"], opts["constraints_type"] = full_constraints(
                size, {system.ny * i + r: 2 for i in system.radial_nodes}
            )
        if self.events:
            run.eventsfn.terminal = [True] * run.n_events
            run.eventsfn.direction = [-1] * run.n_events
            opts["eventsfn"], opts["num_events"] = run.eventsfn, run.n_events
        return opts


@dataclass(frozen=True)
class CVODEBDF(_Sundials):
    """CVODE, variable-order BDF (1-5) with Newton iterations on the exact Jacobian (scikit-sundae's Python loop)."""

    name = "sksundae-cvode-bdf"
    method = "BDF"

    def make_solver(self, system, parts, y0, run):
        from sksundae.cvode import CVODE

        with warnings.catch_warnings():  # 'sparse' needs the pattern; scikit-sundae warns it is not used for DQ
            warnings.filterwarnings("ignore", "Custom sparse Jacobian approximation")
            return CVODE(run.rhsfn, method=self.method, **self.solver_options(system, parts, y0, run))


@dataclass(frozen=True)
class CVODEAdams(CVODEBDF):
    """CVODE, variable-order Adams-Moulton (1-12) with Newton iterations on the exact Jacobian (Python loop)."""

    name = "sksundae-cvode-adams"
    method = "Adams"


@dataclass(frozen=True)
class IDA(_Sundials):
    """IDA, variable-order BDF on the linearly implicit residual (no inverse of the mass matrix; Python loop)."""

    name = "sksundae-ida"
    kind = "ida"

    def make_solver(self, system, parts, y0, run):
        from sksundae.ida import IDA as _IDA

        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "Custom sparse Jacobian approximation")
            return _IDA(run.resfn, **self.solver_options(system, parts, y0, run))


class _Run:
    """One solve: the callbacks SUNDIALS calls, trial-time bookkeeping, and its steps (a stepper of the run loop)."""

    #: why a compiled route's name runs this loop (its stats' ``route_reason``); "" where the name asked for it
    route_reason = ""

    def __init__(self, method, system, compiled, parts, y0):
        self.method, self.system, self.parts = method, system, parts
        self.ida = method.kind == "ida"
        self.y0 = np.array(y0, dtype=float)
        self.names = system.limit_names()
        self.n_events = len(self.names)
        self.last_t, self.failures, self.counting, self.calls_in_step, self.t_reached = -np.inf, 0, False, 0, 0.0
        rows, cols, size = parts["rows"], parts["cols"], system.size
        jac, events = parts["jac"], parts["events"]
        sparse = method.choose_linsolver(size) == "sparse"
        # the next kink of a drive's rate and the time one ulp short of it: the step that ends there is evaluated
        # there (the history's rate at its corner is the new segment's; the old one's belongs to that step)
        self.kink, self.left = np.inf, np.inf
        if self.ida:
            res = parts["residual"]

            def resfn(t, x, xp, out):
                self._trial(t)
                out[:] = res(t if t < self.kink else self.left, x, xp)

            def jacfn(t, x, xp, res_, cj, JJ):
                t = t if t < self.kink else self.left
                if sparse:
                    JJ[:] = jac(t, x, xp, cj)
                else:
                    JJ[rows, cols] = jac(t, x, xp, cj)

            self.resfn, self.jacfn = resfn, jacfn
        else:
            f = compiled.evaluator()

            def rhsfn(t, y, yp):
                self._trial(t)
                yp[:] = f(y, t if t < self.kink else self.left)

            def jacfn(t, y, yp, JJ):
                t = t if t < self.kink else self.left
                if sparse:
                    JJ[:] = jac(t, y)
                else:
                    JJ[rows, cols] = jac(t, y)

            self.rhsfn, self.jacfn = rhsfn, jacfn

        floor = np.zeros(self.n_events)
        first_r = system.samples_per_cell * (system.n - 1)  # the deltas come first, then r per node
        floor[first_r : first_r + len(system.radial_nodes)] = method.field_atol()[1]  # r events sit at r = atol_r
        # the r entries (same places in y and x): with the constraint alone, SUNDIALS cuts a step that
        # would cross r = 0 back to r ~ 2e-10 m and then crawls along the axis (~4e-12 s a step) until
        # max_steps; IDA may also return an accepted state a little below 0. A step that ends with
        # r <= atol_r has reached the limit to the accuracy asked for: stop there.
        self.r_entries = system.ny * system.radial_nodes + list(system.active).index(1)
        self.r_floor = float(method.field_atol()[1])

        if self.ida:
            def eventsfn(t, x, xp, g):
                g[:] = events(x) - floor
        else:
            def eventsfn(t, y, g):
                g[:] = events(y) - floor

        self.eventsfn = eventsfn

    #: right-hand side (or residual) evaluations within one ``onestep`` call after which the step is given up:
    #: a step takes a few, a few hundred with failed attempts; SUNDIALS can loop forever on a step size that
    #: underflowed to 0 ("t + h = t") when the model's motions are too fast for double precision
    MAX_CALLS_PER_STEP = 20_000

    def _trial(self, t):
        self.calls_in_step += 1
        if self.calls_in_step > self.MAX_CALLS_PER_STEP or not np.isfinite(t):
            what = (f"asked for the right-hand side at t = {t}" if not np.isfinite(t) else
                    f"evaluated the right-hand side {self.MAX_CALLS_PER_STEP} times without completing a step")
            err = ModelLimitError(f"{self.method.name} {what} after t = {self.t_reached:.9g} s (its step size "
                                  "underflowed): the motion is too fast for double precision", self.t_reached,
                                  "whole shell")
            err.status = "failed"
            raise err
        if t != self.last_t:
            if t < self.last_t and self.counting:
                self.failures += 1
            self.last_t = t

    def to_hamiltonian(self, state, t=0.0):
        if not self.ida:
            return np.array(state, dtype=float)
        return np.array(self.parts["dae"].to_momenta(state, float(np.ravel(t)[0]))).ravel()

    def begin(self, times):
        """Make the solver and take its first step (a consistent start for IDA)."""
        method = self.method
        self.solver = method.make_solver(self.system, self.parts, self.y0, self)
        if self.ida:
            x0, xp0 = self.parts["dae"].consistent_rates(self.y0)
            init = self.solver.init_step(0.0, x0, xp0)
        else:
            init = self.solver.init_step(0.0, self.y0)
        if not init.success:
            raise RuntimeError(f"{method.name} could not start: {init.message}")
        self.t, self.t_reached, self.n_steps, self.res = 0.0, 0.0, 0, init
        self.budget = StepBudget(method.name, times[-1], method.max_steps, method.tolerance_text())
        #: the kinks of a drive's rate still ahead (increasing, up to the last saved time): a stop and a restart at each
        self.kinks = [k for k in drive_kinks(self.system) if k <= float(times[-1])]
        self.before = (0, 0)  # SUNDIALS' counts (rhs, Jacobians) before the last restart: it zeroes its own there
        self.passed = -np.inf  # the last kink restarted at
        self._next_kink()
        return self

    def _next_kink(self):
        self.kink = self.kinks.pop(0) if self.kinks else np.inf
        self.left = float(np.nextafter(self.kink, -np.inf))

    def _restart(self):
        """At a kink: the solver restarted from the state there (order 1, a new first step, a fresh Jacobian; IDA
        from the rates it holds, the left limit), on the new segment; the counts kept."""
        res = self.res
        self.before = (self.before[0] + int(res.nfev), self.before[1] + int(res.njev))
        self._next_kink()
        while one_time(self.kink, self.t_reached):  # another drive's kink within round-off: one restart, at the last
            self.t_reached = self.kink
            self._next_kink()
        t = self.passed = self.t_reached
        init = unlisted_status(self.solver.init_step, t, res.y, *([res.yp] if self.ida else []))
        if not getattr(init, "unlisted", False):  # a status without counts: the last result's stand for the run's
            self.res = init
        if not init.success:
            raise self._failure(init, t)

    def advance(self, target):
        """One SUNDIALS step towards ``target`` (``tstop``: never past it, nor past the next kink of a drive). A kink
        within round-off of ``target`` (the one restarted at, or the next) stands for it: SUNDIALS refuses a first
        step that short after a restart; ``t`` is then ``target`` once the solver (``t_reached``) is at the kink."""
        method = self.method
        if self.t_reached >= self.kink:
            self._restart()
        near = [k for k in (self.passed, self.kink) if one_time(k, target)]
        stop = near[0] if near else min(float(target), self.kink)
        if self.t_reached < stop:
            self.calls_in_step = 0
            res = unlisted_status(self.solver.step, stop, method="onestep", tstop=stop)
            if getattr(res, "unlisted", False):  # no counts in it: the last result's stand for the run's
                raise self._failure(res, self.t_reached)
            self.res = res
            self.n_steps += 1
            self.counting = True
            if res.status == ROOT_RETURN:
                raise self._event_error(res)
            if not res.success:
                raise self._failure(res, self.t_reached)
            if method.constraints and np.min(np.asarray(res.y)[self.r_entries]) <= self.r_floor:
                raise self._constraint_limit(res)
            self.budget.step(float(res.t))  # max_steps, or a projection far beyond it, ends the run
            self.t_reached = float(res.t)
        self.t = max(self.t_reached, float(target)) if near and self.t_reached >= stop else self.t_reached

    def state(self, target):
        return self.to_hamiltonian(self.res.y, self.t)

    def stats(self):
        res, method = self.res, self.method
        return {
            "n_steps": int(self.n_steps), "n_rhs": self.before[0] + int(res.nfev),
            "n_jac": self.before[1] + int(res.njev),
            "n_failed_steps": int(self.failures),
            "linsolver": method.choose_linsolver(self.system.size), "route": "scikit-sundae",
            "jacobian_build_s": float(self.parts.get("build_time_s", 0.0)),
            **({"route_reason": self.route_reason} if self.route_reason else {}),
        }

    def _event_error(self, res):
        t = float(res.t_events[-1]) if res.t_events is not None else float(res.t)
        which = np.flatnonzero(res.i_events[-1])
        limit, where = self.names[int(which[0])]
        if limit.startswith("r reached"):
            limit += " (to within atol)"  # the event sits at r = atol_r: r > 0 is also a constraint
        return ModelLimitError(f"{limit} at t = {t:.9g} s, {where}: a limit of the model "
                               f"(root found by {self.method.name})", t, where)

    def _constraint_limit(self, res):
        r = np.asarray(res.y)[self.r_entries]
        i, t = int(self.system.radial_nodes[np.argmin(r)]), float(res.t)
        where = f"s = {self.system.s[i]:.6g} m"
        return ModelLimitError(
            f"r reached 0 (to within atol; r > 0 is a constraint of the model, held by {self.method.name}, "
            f"r = {r[i]:.3g} m) at t = {t:.9g} s, {where}", t, where)

    def _failure(self, res, t_prev):
        # the time of the last step that succeeded: a failed one-step call took no step, and SUNDIALS leaves the time
        # it returns unset when it refuses the call's input, which scikit-sundae then hands back as whatever was in
        # its uninitialised variable (6.9e-310 s, at E = 1e300)
        t = t_prev
        if res.status == CONSTRAINT_FAIL[self.method.kind]:
            r = self.system.unpack(self.to_hamiltonian(res.y, t))[1][self.system.radial_nodes]
            i = int(self.system.radial_nodes[np.argmin(r)])
            where = f"s = {self.system.s[i]:.6g} m"
            return ModelLimitError(
                f"r -> 0 (r > 0 is a constraint of the model; {self.method.name} could not keep it, "
                f"r = {r.min():.3g} m) at t = {t:.9g} s, {where}", t, where)
        what = ILL_INPUT if res.status == ILL_INPUT_FLAG else res.message  # the compiled route's words
        err = ModelLimitError(f"{self.method.name} failed at t = {t:.9g} s: {what} (status {res.status})",
                              t, "whole shell")
        err.status = "failed"
        return err
