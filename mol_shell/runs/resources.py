"""Resource limits named before work starts: memory of the output and the solver, steps and time.

:func:`check_before_build` runs before any graph is built (it needs only ``n``, the saved times
and the integrator): it refuses a run whose memory would not fit in what the machine has
available, naming the estimate and what to change, and warns (:class:`LongRunWarning`, a
``RuntimeWarning``) about one whose projected time exceeds :data:`LONG_RUN_S`. Once the spectrum
and the compiled right-hand side are known, :func:`check_before_run` sharpens the time: leap-frog's
step count is exact (``t_end / dt``), an explicit Runge-Kutta method's is bounded below by its
stability interval, and every adaptive method takes at least one step per saved interval.

The constants are measurements on a 2-core machine (AMD EPYC, docs/reliability.md); the estimates
are meant to be right within a factor of about two, which is all a refusal or a warning needs.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import time
import warnings
from dataclasses import dataclass

import numpy as np

from mol_shell._core.constants import DEFAULT_INTERVALS, DENSE_MAX_STATES
from mol_shell._core.errors import ParameterError, RunWarning
from mol_shell._core.units import show_seconds
from mol_shell.results.stresses import MAX_SAMPLES
from mol_shell.runs.machine_memory import (  # parse_bytes, show_bytes and MEMORY_ENV also re-exported
    MEMORY_ENV,
    cgroup_room,
    meminfo_available,
    parse_bytes,
    show_bytes,
)

#: a run projected to take longer than this (s) is announced before it starts
LONG_RUN_S = 3600.0
BYTES = 8
#: variables per node and saved time in a run's Dataset: 5 fields and their 5 rates (every field, active or not)
OUTPUT_PER_NODE = 10
#: per saved time: the three energies, angular momentum, delta_min, the ellipticity margin and the two edges' axial
#: force (an edge that holds z: most scenes; dissipation, work and torques add a few more)
OUTPUT_PER_TIME = 8
#: peak memory while a run's saved states become its Dataset, in multiples of the output (the saved states, the
#: observables evaluated over all of them at once, velocities, fields, the Dataset): measured 10.6x at n = 10 and
#: 40 (flat graphs), 5.3x at n = 400 (mapped), 20,000-80,000 saved times
ASSEMBLY_COPIES = 11.0
#: memory of graph building, spectrum and compiled code per node (bytes; measured 37-41 kB per node at
#: n = 1,000 .. 16,000, the twisted cylinder) and a fixed part (the imported libraries, ~150 MB, and margin)
BUILD_BYTES_PER_NODE = 40e3
BUILD_BYTES_FIXED = 300e6
#: graphs, the spectrum's Jacobian and the spectrum per node (s): 26.8 s at n = 20,000, load 3 on 2 cores (the
#: Jacobian's graph 13.8 s, its evaluation 2.6 s, ARPACK 2.9 s); 1.9, 1.7, 0.96 ms per node at 1,000, 4,000, 16,000
BUILD_S_PER_NODE = 1.3e-3
#: the DAE's own exact Jacobian graph (casadi.jacobian), per node (s), for the SUNDIALS routes that build it:
#: 18.8 s at n = 20,000 (ida, load 3-4 on 2 cores; its C compiles are announced on their own)
JACOBIAN_S_PER_NODE = 0.9e-3
JACOBIAN_ROUTES = frozenset(f"{p}{r}" for p in ("", "sksundae-") for r in ("cvode-bdf", "cvode-adams", "ida"))
#: assembling a run's Dataset (observables, checks) and writing it, per saved time and node (s): 1,001 saved times
#: x 3,000 nodes took 25.5 s (the observables 23.3 s, the file 1.6 s; load 3 on 2 cores)
OUTPUT_S_PER_VALUE = 8.5e-6
#: a build (or the output's assembly) projected to take longer than this (s) is announced before the run (n = 100,000
#: took 107 s in silence; at 30 s, ida at n = 20,000 69 s, 1,001 saved times x 3,000 nodes 40 s without a word)
LONG_BUILD_S = 10.0
#: the same for an analysis (modes, a path, a comparison), which builds and evaluates the exact Jacobian before it
#: says anything: measured 1.0 ms per node for modes at n = 30,000 (31 s in silence)
LONG_ANALYSIS_BUILD_S = 20.0
#: one compiled right-hand side per node (s): 17.35 us per leap-frog step at n = 40, 0.55 us per node at 16,000
RHS_S_PER_NODE = 0.5e-6
#: right-hand sides per step and the imaginary-axis stability interval ``|lambda| dt`` of explicit Runge-Kutta
#: methods: a lower bound on their steps is ``t_end max|lambda| / interval`` (slightly generous intervals)
EXPLICIT_RK = {"scipy-rk45": (6, 3.5), "scipy-dop853": (12, 6.1)}
#: state-sized vectors a solver keeps (leap-frog: pair, rates, limits, copies; SUNDIALS: history and work)
SOLVER_VECTORS = {"leapfrog": 8}
SOLVER_VECTORS_DEFAULT = 30


class LongRunWarning(RunWarning):
    """A run is projected to take longer than :data:`LONG_RUN_S`; the message holds the estimate."""


def smallest_run_bytes():
    """What the smallest run needs (leap-frog, n = 3, two saved times): the fixed part of a build, mostly."""
    return estimate(3, 2, 0.0).memory_bytes


def memory_limit(text):
    """:data:`MEMORY_ENV`'s value in bytes: a finite size at least what the smallest run needs (a smaller one
    refused every run, blaming ``n`` with the range ``3..3``)."""
    value = parse_bytes(text)
    least = smallest_run_bytes()
    if not (math.isfinite(value) and value >= least):
        mib = math.ceil(least / 1024**2)
        raise ParameterError(MEMORY_ENV, text, f"finite sizes of at least {mib}M",
                             hint=f"{show_bytes(mib * 1024**2)}: what the smallest run, n = 3, needs; unset it to use "
                             "the machine's available memory")
    return value


def available_memory():
    """``(bytes, where from)``: :data:`MEMORY_ENV` if set, else the machine's available memory (and a cgroup limit)."""
    if os.environ.get(MEMORY_ENV):
        return memory_limit(os.environ[MEMORY_ENV]), f"${MEMORY_ENV}"
    found = [(v, src) for v, src in ((meminfo_available(), "MemAvailable"), (cgroup_room(), "cgroup limit")) if v is not None]
    if not found:
        try:
            found = [(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"), "sysconf")]
        except (ValueError, OSError, AttributeError):
            return math.inf, "unknown"
    return min(found)


@dataclass
class Estimate:
    """What a run will need, before it starts.

    Attributes
    ----------
    n, n_times, size : int
        Nodes, saved times and unknowns (``2 x fields x n``).
    output_bytes : float
        The saved output: ``n_times x (10 n + 8) x 8`` bytes (fields and rates per node, totals per time).
    memory_bytes : float
        Peak estimate: output while it is assembled, solver state and Jacobian, graphs and spectrum.
    steps : float
        Leap-frog: exact (``t_end / dt``); adaptive: a lower bound (``steps_lower_bound`` is true).
    seconds : float
        Projected wall time (graph building, and stepping at the measured or estimated RHS cost).
    dense_bytes, dense_matrices, linsolver : float, int, str
        What a dense linear solver's N x N matrices add to ``memory_bytes``, how many it keeps, and the
        ``linsolver`` option that chose it (0, 0 and None without one).
    """

    n: int
    n_times: int
    size: int
    output_bytes: float
    memory_bytes: float
    steps: float
    steps_lower_bound: bool
    seconds: float
    build_seconds: float
    dense_bytes: float = 0.0
    output_seconds: float = 0.0  # assembling the Dataset and writing it after the last step (s)
    dense_matrices: int = 0
    linsolver: str | None = None
    #: ``m -> memory_bytes`` of the same run on ``m`` nodes (the largest ``n`` that fits, said in a refusal)
    memory_at: object = dataclasses.field(default=None, repr=False, compare=False)

    def describe(self):
        steps = f"{'at least ' if self.steps_lower_bound else ''}{self.steps:.3g} steps"
        return (f"{self.n_times} saved times x {self.n} nodes: output {show_bytes(self.output_bytes)}, about "
                f"{show_bytes(self.memory_bytes)} in all; {steps}, {'at least ' if self.steps_lower_bound else ''}"
                f"about {show_seconds(self.seconds)}")


#: stress and resultant values per cell and saved time (:mod:`mol_shell.results.stresses`), when they are computed
STRESS_PER_CELL = 17


def output_bytes(n_times, n, stresses=True):
    """Bytes of a run's Dataset: fields and rates per node, totals per time, the stresses per cell and time
    when they are computed (up to :data:`mol_shell.results.stresses.MAX_SAMPLES` cell samples x times), and the
    reference meridian (3 values per node)."""
    per_time = OUTPUT_PER_NODE * n + OUTPUT_PER_TIME
    if stresses and float(n_times) * 2 * (n - 1) <= MAX_SAMPLES:
        per_time += STRESS_PER_CELL * (n - 1)
    return (float(n_times) * per_time + 3 * n) * BYTES


def solver_bytes(integrator, size, n, dense_bytes=0.0):
    """State vectors, and the Jacobian where the integrator keeps one (scikit-sundae hands dense and banded
    solvers a full N x N array; sparse solvers keep the non-zeros and their LU factors). ``dense_bytes``: the N x N
    matrices a dense linear solver keeps, whatever ``n`` (:func:`dense_matrices`: CVODE's matrix and saved
    Jacobian, IDA's one matrix, factorised in place), in place of that estimate."""
    vectors = SOLVER_VECTORS.get(integrator, SOLVER_VECTORS_DEFAULT) * size * BYTES
    if integrator == "leapfrog":
        return vectors
    if dense_bytes:
        return vectors + dense_bytes
    return vectors + (size * size * BYTES if size <= DENSE_MAX_STATES else 40 * size * 12 * 4)


def spectrum_bytes(size):
    """Dense eigenvalues up to 2,000 unknowns (the matrix, its complex copy and LAPACK's work), ARPACK above."""
    return 4 * size * size * BYTES if size <= DENSE_MAX_STATES else 60 * size * 2 * BYTES


def dense_matrices(method, size):
    """The N x N matrices ``method`` (an integrator, or None: its defaults) keeps at ``size`` unknowns: a dense
    linear solver's, none for banded, sparse or no linear solvers."""
    count = getattr(method, "dense_matrices", None)
    return int(count(size)) if count is not None else 0


def estimate(n, n_times, t_end, integrator="leapfrog", *, fields=5, dt=None, omega_max=None, rhs_seconds=None,
             method=None):
    """An :class:`Estimate` of a run; ``omega_max`` (1/s) and ``rhs_seconds`` sharpen it once known; ``method``
    (the integrator with its options) counts a dense linear solver's matrices."""
    n, n_times, t_end = int(n), int(n_times), float(t_end)
    size = 2 * fields * n
    out = output_bytes(n_times, n)
    dense = dense_matrices(method, size) if integrator != "leapfrog" else 0
    dense_bytes = dense * float(size) * size * BYTES
    memory = (out * ASSEMBLY_COPIES + solver_bytes(integrator, size, n, dense_bytes) + spectrum_bytes(size)
              + BUILD_BYTES_FIXED + BUILD_BYTES_PER_NODE * n)
    rhs = rhs_seconds if rhs_seconds is not None else RHS_S_PER_NODE * n
    if integrator == "leapfrog" and dt:
        steps, lower, per_step = t_end / dt, False, 1
    else:
        steps, lower, per_step = max(n_times - 1, 1), True, 1
        if integrator in EXPLICIT_RK:
            per_step, interval = EXPLICIT_RK[integrator]
            if omega_max is not None and math.isfinite(omega_max):
                steps = max(steps, t_end * omega_max / interval)
    build = (BUILD_S_PER_NODE + (JACOBIAN_S_PER_NODE if integrator in JACOBIAN_ROUTES else 0.0)) * n
    output = OUTPUT_S_PER_VALUE * n_times * n
    return Estimate(n, n_times, size, out, memory, steps, lower, steps * per_step * rhs + build + output, build,
                    dense_bytes, output, dense, getattr(method, "linsolver", None),
                    functools.partial(_memory_at, n_times=n_times, integrator=integrator, fields=fields, method=method))


def _memory_at(m, *, n_times, integrator, fields, method):
    """:func:`estimate`'s memory of the run on ``m`` nodes."""
    return estimate(m, n_times, 0.0, integrator, fields=fields, method=method).memory_bytes


def largest_n(est, available):
    """The largest number of nodes (at least 3, at most ``est.n``) at which ``est``'s run fits in ``available``
    bytes, by bisection on its own estimate (the spectrum's dense matrices make it grow faster than linearly below
    2,000 unknowns: a line through the refused ``n`` said n = 8 where 9 ran); 3 where none does."""
    if est.memory_at is None:
        per_node = (est.memory_bytes - BUILD_BYTES_FIXED) / est.n
        return max(int((available - BUILD_BYTES_FIXED) / per_node) if available > BUILD_BYTES_FIXED else 0, 3)
    lo, hi = 3, int(est.n)  # est.memory_at(hi) > available: the refused n
    if est.memory_at(lo) > available:
        return 3
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if est.memory_at(mid) <= available else (lo, mid)
    return lo


def check_memory(est, *, times_name="times", times_value=None, n_name="n", what="the run", kept="saved times",
                 fewer="save fewer times (--times)", offset=0, default_times=False, fewer_nodes="use fewer nodes (--n)"):
    """Refuse a run whose memory estimate exceeds what is available; the message names the estimate and the fix.

    The saved times (``times_name``; None: never) are named when fewer of them would fit (at least two), else the
    nodes. ``what`` is the work the message speaks of, ``kept`` what its states are; ``fewer`` the advice for
    fewer of them, ``offset`` how many states the named parameter does not count (a path's start: ``max_steps + 1``
    states). ``default_times``: the saved times are the default (:data:`DEFAULT_INTERVALS` intervals, no ``times``
    given), said as such. Where ``$MOL_SHELL_MEMORY`` set the memory available, the advice names it too.
    ``fewer_nodes``: the advice for fewer nodes (a script's own option: ``--check-n``).
    """
    available, source = available_memory()
    if est.memory_bytes <= available:
        return
    if est.dense_bytes and est.linsolver not in (None, "auto") and est.memory_bytes - est.dense_bytes <= available:
        # a dense solver chosen (auto's dense matrices, up to 100 unknowns, are the nodes': named as the rest)
        raise dense_refusal(est, available, source, what)
    if est.n_times < 1e15:
        per_time = est.output_bytes * ASSEMBLY_COPIES / max(est.n_times, 1)
        fixed = est.memory_bytes - per_time * est.n_times
    else:  # astronomically many saved times (0:1e300:1e-6): the estimate overflows; the times' own share is the floor
        per_time, fixed = (OUTPUT_PER_NODE * est.n + OUTPUT_PER_TIME) * BYTES * ASSEMBLY_COPIES, 0.0
    fits = int(min((available - fixed) / per_time, 1e18)) if available > fixed else 0
    need = (f"needs about {show_bytes(est.memory_bytes)} (the output alone {show_bytes(est.output_bytes)}: "
            f"{est.n_times:.4g} {kept} x {est.n} nodes x {OUTPUT_PER_NODE} values x 8 bytes), "
            f"{show_bytes(available)} available ({source})")
    more = f", or a larger {MEMORY_ENV}" if source == f"${MEMORY_ENV}" else ""
    if fits >= 2 + offset and times_name is not None:
        value = times_value if times_value is not None else f"<{est.n_times} saved times>"
        allowed = f"at most {fits - offset:,} {'steps' if offset else kept} at n = {est.n}"
        if default_times:  # no times given: not said as if they had been
            fewer = f"save fewer times (--times; the default is {DEFAULT_INTERVALS} intervals to t_end)"
        message = (f"{times_name} = the default {est.n_times} saved times (none given) is outside {allowed}"
                   if default_times else None)
        raise ParameterError(times_name, value, allowed, hint=f"{what} {need}; {fewer} or {fewer_nodes}{more}",
                             message=message)
    raise ParameterError(n_name, est.n,
                         f"integers 3..{largest_n(est, available):,} on this machine with "
                         + (f"{est.n_times:,} {kept}" if est.n_times < 1e15 else f"{est.n_times:.3g} {kept}"),
                         hint=f"{what} {need}; {fewer_nodes}" + (" or save fewer times (--times)"
                                                                        if times_name == "times" else "") + more)


def dense_refusal(est, available, source, what="the run"):
    """The :class:`ParameterError` naming ``linsolver`` when a dense solver's matrices are what does not fit: the
    largest ``n`` they fit at (memory ``F + a n + b n^2``: the fixed part, the rest per node, the matrices)."""
    quadratic = est.dense_bytes / float(est.n) ** 2
    linear = max(est.memory_bytes - est.dense_bytes - BUILD_BYTES_FIXED, 0.0) / est.n
    room = max(available - BUILD_BYTES_FIXED, 0.0)
    max_n = int((math.sqrt(linear * linear + 4 * quadratic * room) - linear) / (2 * quadratic))
    needs = f"{what} needs about {show_bytes(est.memory_bytes)}, of which {show_bytes(est.dense_bytes)} for the "
    fits = f"{show_bytes(available)} available ({source})"
    if est.linsolver == "band":  # scikit-sundae's route: its Jacobian callback fills a full N x N array for a band
        allowed, fit, no_fit, default = "{auto, sparse}", "band up to", "no band solver here", (
            f"sparse above {DENSE_MAX_STATES:,} unknowns there, and cvode-bdf and ida band in C without that array")
        matrices = (f"full {est.size:,} x {est.size:,} array x 8 bytes that scikit-sundae's route fills for a banded "
                    "solver's Jacobian")
    else:
        allowed, fit, no_fit, default = ("{auto, band, sparse}", "a dense solver up to", "no dense solver here",
                                         "banded or sparse above 100 unknowns")
        matrices = (f"dense solver's {est.dense_matrices} {'matrix' if est.dense_matrices == 1 else 'matrices'} of "
                    f"{est.size:,} x {est.size:,} unknowns x 8 bytes")
    return ParameterError("linsolver", est.linsolver,
                          f"{allowed} at n = {est.n:,} ({f'{fit} n = {max_n:,} here' if max_n >= 3 else no_fit})",
                          hint=f"{needs}{matrices}, {fits}; the default, auto, is {default}")


def warn_if_long(est, what="run"):
    """:class:`LongRunWarning` (one line) when the projected time exceeds :data:`LONG_RUN_S`."""
    if est.seconds <= LONG_RUN_S:
        return False
    least = "at least " if est.steps_lower_bound else ""
    build = f", building the graphs about {show_seconds(est.build_seconds)}" if est.build_seconds > 60 else ""
    warnings.warn(f"this {what} will take {least}about {show_seconds(est.seconds)} ({least}{est.steps:.3g} steps at "
                  f"n = {est.n}{build}); a shorter t_end, a larger step or fewer nodes (--t-end, --dt, --n) "
                  "make it shorter", LongRunWarning, stacklevel=4)
    return True


def check_nodes(n):
    """``n`` must be an integer >= 3 (checked here too, so estimates never see anything else)."""
    if not (isinstance(n, (int, np.integer)) and not isinstance(n, (bool, np.bool_)) and n >= 3):
        raise ParameterError("n", n, "integers >= 3")
    if n > np.iinfo(np.int64).max:  # beyond NumPy's indices (and the floats' range: the estimates raised OverflowError)
        raise ParameterError("n", n, f"integers in [3, {np.iinfo(np.int64).max:,}] (NumPy's 64-bit indices)")


def check_saved_times(count, n, *, name="--times", value=None, integrator="leapfrog"):
    """Before a list of ``count`` saved times is even made: refuse it if the output would not fit in memory."""
    if isinstance(n, (int, np.integer)) and n >= 3:
        check_memory(estimate(n, count, 0.0, integrator), times_name=name, times_value=value)


def check_before_build(n, times, integrator="leapfrog", *, fields=5, dt=None, times_value=None, method=None,
                       times_given=True):
    """Before any graph is built: refuse what does not fit in memory (``method``, the integrator with its options:
    a dense linear solver's matrices too), warn about what takes over an hour. ``times_given``: False where ``times``
    are the default ones (none given), which a refusal says as such."""
    check_nodes(n)
    est = estimate(n, len(times), times[-1], integrator, fields=fields, dt=dt, method=method)
    check_memory(est, times_value=times_value, default_times=times_value is None and not times_given)
    if not warn_if_long(est):
        warn_if_long_build(est)
    return est


def warn_if_long_build(est, each=""):
    """:class:`LongRunWarning` (one line) when building the graphs and the spectrum is projected to take over
    :data:`LONG_BUILD_S` (a run's, or ``each="each case's "`` for a study's): said before the build, which is silent."""
    if est.build_seconds > LONG_BUILD_S:
        jacobian = ", the Jacobian" if est.build_seconds > 1.5 * BUILD_S_PER_NODE * est.n else ""
        warnings.warn(f"building the graphs{jacobian} and the spectrum at n = {est.n:,} takes about "
                      f"{show_seconds(est.build_seconds)} before {each or 'the '}first step (the step's stability "
                      "bound is known only then)", LongRunWarning, stacklevel=4)
    if not each and est.output_seconds > LONG_BUILD_S:
        warnings.warn(f"assembling and writing {est.n_times:,} saved times x {est.n:,} nodes takes about "
                      f"{show_seconds(est.output_seconds)} after the last step (fewer saved times make it shorter)",
                      LongRunWarning, stacklevel=4)


def check_analysis(n, states, what, kept, *, integrator="cvode-bdf", fields=5, name=None, value=None, fewer=None,
                   announce=True, method=None):
    """Before a graph is built for an analysis (``what``: natural modes, an equilibrium path, a comparison of
    integrators): refuse ``n`` when the graph, the spectrum, the matrices and the ``states`` kept (modes, path
    steps, saved times) would not fit in memory. ``integrator`` names the matrices kept (a comparison's most
    demanding one; modes and paths factorise a sparse Jacobian, as an implicit integrator does). With ``name``
    (the parameter that sets how many states: a path's ``max_steps``, whose ``value`` is ``states - 1``), it is
    named when fewer states would fit, with the advice ``fewer``. ``announce``: warn when the build takes over
    :data:`LONG_ANALYSIS_BUILD_S` (not for a plain build, whose caller announces it). ``method``: the integrator
    with its options, whose linear solver's matrices are counted as a run's are (:func:`check_before_build`)."""
    check_nodes(n)
    est = estimate(n, max(int(states), 2), 0.0, integrator, fields=fields, method=method)
    check_memory(est, times_name=name, times_value=value, what=what, kept=kept, fewer=fewer or "",
                 offset=int(states) - value if name is not None else 0)
    build = BUILD_S_PER_NODE * int(n)  # the graphs and the Jacobian, as a run's spectrum (no DAE of its own)
    if announce and build > LONG_ANALYSIS_BUILD_S:  # modes at n = 30,000: 31 s in silence
        warnings.warn(f"building the graphs and the Jacobian at n = {int(n):,} takes about "
                      f"{show_seconds(build)} before {what}", LongRunWarning, stacklevel=3)


def measure_rhs_seconds(compiled, y0, repeats=20):
    """Seconds per compiled right-hand-side evaluation, timed on ``y0`` (a few ms at most)."""
    f = compiled.evaluator()
    f(y0)
    start = time.perf_counter()
    for _ in range(repeats):
        f(y0)
    return (time.perf_counter() - start) / repeats


def check_before_run(n, times, integrator, *, fields=5, dt=None, omega_max=None, compiled=None, y0=None,
                     warned=False):
    """With the spectrum and the compiled code known: the projected time again, warned about once."""
    rhs = measure_rhs_seconds(compiled, y0) if compiled is not None and y0 is not None else None
    est = estimate(n, len(times), times[-1], integrator, fields=fields, dt=dt, omega_max=omega_max, rhs_seconds=rhs)
    est.seconds -= est.build_seconds  # the graphs are built by now
    est.build_seconds = 0.0
    if not warned:
        warn_if_long(est)
    return est


def check_cases(count, n, n_times=2, *, name="vary", value=None, early=False):
    """Refuse a study of ``count`` cases whose combined Dataset would not fit in memory (before the cases are made).
    Not one case fitting is blamed on ``n``; ``early`` (before the saved times are known) leaves that to the
    per-case check of :func:`check_study`, which names the range of ``n`` a run has."""
    if not (isinstance(n, (int, np.integer)) and n >= 3):
        return
    per_case = output_bytes(n_times, n) * ASSEMBLY_COPIES
    available, source = available_memory()
    if count * per_case + BUILD_BYTES_FIXED > available:
        fits = int(max(available - BUILD_BYTES_FIXED, 0) / per_case)
        if fits < 1 and early:
            return
        if fits < 1:  # not one case: the grid is too fine, whatever is varied (output_bytes grows like n)
            raise ParameterError("n", n, f"[3, {max(int(n * fits_fraction(available, per_case)), 3):,}] for a "
                                 f"study with {n_times} saved times", hint=f"one case's Dataset would need about "
                                 f"{show_bytes(per_case)}, {show_bytes(available)} available ({source})")
        kept = f"at least {n_times} states each (saved times or path steps)" if early else f"{n_times} saved times"
        raise ParameterError(name, value if value is not None else f"<{count:.4g} cases>",
                             f"at most {fits:,} cases at n = {n} with {kept}",
                             hint=f"the study's Dataset would need about {show_bytes(count * per_case)}, "
                             f"{show_bytes(available)} available ({source}); vary fewer values (--vary)")


def fits_fraction(available, per_case):
    """The share of a case's bytes that fits in ``available`` beside the fixed cost of a build."""
    return max(available - BUILD_BYTES_FIXED, 0) / per_case


def check_study(n_cases, n, times, integrator="leapfrog", *, fields=5, dt=None, workers=1, methods=()):
    """A study: its combined output must fit in memory; warn when its cases take more than an hour in all.

    One case must fit (each worker runs one at a time: a grid too fine for any is refused naming ``n``), as each
    run's own check (:func:`check_before_build`) counts it: with ``methods``, the integrators with the options of the
    cases (each distinct one once), their linear solvers' matrices counted; the study is refused (as the first
    case's run would be, naming ``linsolver`` for a dense solver that does not fit) when not one of them fits."""
    est = estimate(n, len(times), times[-1], integrator, fields=fields, dt=dt)
    refusals = []
    for method in methods:
        try:
            check_memory(estimate(n, len(times), times[-1], integrator, fields=fields,
                                  dt=getattr(method, "dt", None), method=method))
            break
        except ParameterError as exc:
            refusals.append(exc)
    else:
        if refusals:
            raise refusals[0]
        check_memory(est)
    check_cases(n_cases, n, len(times))
    total = dataclasses.replace(est, seconds=est.seconds * n_cases / max(int(workers or 1), 1),
                                steps=est.steps * n_cases)
    if not warn_if_long(total, what=f"study ({n_cases} cases on {max(int(workers or 1), 1)} workers)"):
        warn_if_long_build(est, each="each case's ")  # as a run says it (its own warning is not said in a study)
    return total
