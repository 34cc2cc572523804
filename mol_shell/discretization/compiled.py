"""Generated C for the hot paths, compiled once with gcc and cached on disk.

CasADi writes C for the right-hand side (common subexpressions eliminated); we
append a small driver that runs the leap-frog loop in C, so a Python call
advances many steps and no per-step Python or NumPy conversion is paid. The
shared object is cached under ``$MOL_SHELL_CACHE`` (default
``~/.cache/mol_shell``), keyed by a hash of its source and flags.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import casadi as ca
import numpy as np

from mol_shell._core.atomic import atomic_path
from mol_shell._core.units import show_seconds
from mol_shell.discretization import kernel_cache
from mol_shell.discretization.kernel_cache import CompilerError, CompilerMissing, cache_dir  # also re-exported
from mol_shell.discretization.rk_driver import RK_DRIVER
from mol_shell.discretization.threads import checked_threads, default_threads  # also re-exported

#: -fno-semantic-interposition lets gcc inline CasADi's exported helpers (``casadi_sq``; calls through the PLT
#: otherwise): 10 % of an RHS evaluation. -O3 -march=native (this machine's vector units and fused
#: multiply-adds, so the last bits differ from CasADi's virtual machine) another ~20 % of a dop853-c run, with
#: the cache keyed by the processor (:func:`~mol_shell.discretization.kernel_cache.machine_key`)
CFLAGS = ("-O3", "-march=native", "-ffp-contract=off", "-fno-semantic-interposition", "-fPIC", "-shared")
#: what CasADi writes for an "openmp" map, and what we make of it: a thread count set at run time, and chunks
#: of 32 cells handed out as threads get free (a core busy with another process then slows the run less)
_OMP_PRAGMA = "#pragma omp parallel for private("
_OMP_THREADS = "#pragma omp parallel for num_threads(ms_threads) if(ms_threads > 1) schedule(dynamic, 32) private("
_THREADS_HEAD = "#include <stdlib.h>\nstatic int ms_threads = 1; /* threads of the OpenMP maps (ms_set_threads) */\n"
_THREADS_API = r"""
CASADI_SYMBOL_EXPORT void ms_set_threads(int k) { ms_threads = k > 0 ? k : 1; }
CASADI_SYMBOL_EXPORT int ms_get_threads(void) { return ms_threads; }
"""


_DRIVER = r"""
/* ---- mol_shell leap-frog driver: y(k+1) = y(k-1) + 2 dt f(y(k)) ---- */
#define MS_N {n}
#define MS_NG {ng}
static int ms_call(int (*fn)(const casadi_real**, casadi_real**, casadi_int*, casadi_real*, int),
                   casadi_real t, const casadi_real* in, casadi_real* out) {{
  /* work on the heap, allocated once: OpenMP maps hold one work vector per cell (MBs at large n) */
  static casadi_int* iw = 0;
  static casadi_real* w = 0;
  const casadi_real* arg[{sz_arg} + 1];
  casadi_real* res[{sz_res} + 1];
  int i;
  if (!w) {{
    iw = (casadi_int*) malloc(sizeof(casadi_int) * ({sz_iw} + 1));
    w = (casadi_real*) malloc(sizeof(casadi_real) * ({sz_w} + 1));
    if (!iw || !w) return 1;
  }}
  for (i = 0; i < {sz_arg}; ++i) arg[i] = 0;
  for (i = 0; i < {sz_res}; ++i) res[i] = 0;
  arg[0] = &t; arg[1] = in; res[0] = out;
  return fn(arg, res, iw, w, 0);
}}
static int ms_limits_call(const casadi_real* y, casadi_real* g) {{
  {limits_call}
}}
/* Returns 0 after nsteps steps, j > 0 if step j left a limit function <= 0 or not finite
   (the pair then holds steps j-1 and j), -1 if the right-hand side failed. t0 is the time of yb. */
CASADI_SYMBOL_EXPORT long long ms_leapfrog(casadi_real* ya, casadi_real* yb, casadi_real* f, casadi_real* g,
                                           long long nsteps, casadi_real dt, casadi_real t0) {{
  long long k; int i;
  for (k = 0; k < nsteps; ++k) {{
    if (ms_call({name}, t0 + k * dt, yb, f)) return -1;
    for (i = 0; i < MS_N; ++i) {{
      casadi_real next = ya[i] + 2.0 * dt * f[i];
      ya[i] = yb[i];
      yb[i] = next;
    }}
    if (MS_NG > 0) {{
      if (ms_limits_call(yb, g)) return -1;
      for (i = 0; i < MS_NG; ++i) if (!(g[i] > 0)) return k + 1;
    }}
  }}
  return 0;
}}
"""

_LIMITS_CALL = """const casadi_real* arg[{sz_arg} + 1]; casadi_real* res[{sz_res} + 1];
  casadi_int iw[{sz_iw} + 1]; casadi_real w[{sz_w} + 1];
  int i;
  for (i = 0; i < {sz_arg}; ++i) arg[i] = 0;
  for (i = 0; i < {sz_res}; ++i) res[i] = 0;
  arg[0] = y; res[0] = g;
  return {name}(arg, res, iw, w, 0);"""


#: a compilation still running after this many seconds is announced on stderr (None: never)
COMPILE_PROGRESS_AFTER = 5.0
#: seconds between "still compiling" lines when stderr is not a terminal
COMPILE_PROGRESS_EVERY = 30.0


def estimated_compile_seconds(source_bytes, flags=CFLAGS):
    """gcc's time for ``source_bytes`` of CasADi-generated C, from measurements on a 2-core machine.

    Power laws fitted to the twisted cylinder at n = 40, n_quad = 4 .. 32 (docs/reliability.md): right-hand
    sides at ``-O2``/``-O3`` (108 .. 607 kB of C: 0.6 .. 4.3 s) and exact Jacobians at ``-O1`` (1.1 .. 4.6 MB:
    3 .. 106 s; gcc's time grows faster than the source). An order of magnitude, for the progress line;
    ``None`` beyond the measured sizes, where the power law says nothing (far too long for large grids).
    """
    size = source_bytes / 1e5
    jacobian = "-O1" in flags and "-march=native" not in flags  # a right-hand side at $MOL_SHELL_OPT_LEVEL=1 is not
    if source_bytes > (4.6e6 if jacobian else 6.1e5):
        return None  # beyond the measured sizes (a Jacobian at n = 10,240 is 300 MB of mostly data: 1.1 min)
    return 0.0105 * size**2.49 if jacobian else 0.58 * size**1.12


def _announce(line):
    print(f"mol-shell: {line}", file=sys.stderr, flush=True)


def run_compiler(command, what, source_bytes, flags):
    """Run gcc; when it takes longer than :data:`COMPILE_PROGRESS_AFTER` s, say so on stderr, with progress."""
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    start = time.perf_counter()
    announced = False
    try:
        wait = COMPILE_PROGRESS_AFTER
        while True:
            try:
                out, err = proc.communicate(timeout=wait)
                break
            except subprocess.TimeoutExpired:
                if wait is None:
                    continue
                elapsed = time.perf_counter() - start
                if not announced:
                    announced = True
                    expect = estimated_compile_seconds(source_bytes, flags)
                    when = "time not known" if expect is None else f"about {show_seconds(max(expect, elapsed))} expected"
                    _announce(f"compiling {what} ({source_bytes / 1e3:.0f} kB of C; gcc {' '.join(flags)}; {when}, "
                              f"cached in {cache_dir()} for later runs)")
                    wait = COMPILE_PROGRESS_EVERY
                else:
                    _announce(f"still compiling {what}: {show_seconds(elapsed)} so far")
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    if announced:
        _announce(f"compiled {what} in {show_seconds(time.perf_counter() - start)}")
    if proc.returncode:
        raise subprocess.CalledProcessError(proc.returncode, command, out, err)


def compile_cached(source, prefix, flags=CFLAGS, what=None, link=()):
    """Path of a shared object built from C ``source`` with gcc ``flags``, cached on disk by hash.

    Concurrent processes that need the same object (the workers of a study) wait on a lock file for the
    first one's build instead of compiling it again. gcc writes into a private temporary directory and the
    library is renamed onto its cache name (:func:`mol_shell._core.atomic.atomic_path`), so a process that does
    not lock never loads a half-written file. Each library carries a record of its build (key, size, digest:
    :mod:`mol_shell.discretization.kernel_cache`); a cached one whose record does not match (cut short, changed, a
    copy of another kernel's) is compiled again, with a note on stderr. Each gcc build appends a line (object,
    pid, seconds) to ``builds.log`` in the cache: how a study shows that no case recompiled a kernel. ``link``:
    libraries by full path (and linker flags) after the source; part of the key, so a library of another version
    gets another object. A gcc missing or failing, and a cache that refuses the build (a full disk, a file it may
    not replace), raise a :class:`ParameterError` of one line (:class:`CompilerMissing`, :class:`CompilerError`).
    """
    lib, key = kernel_cache.library(source, prefix, flags, link)  # the folder checked writable once (a probe file)
    folder = lib.parent
    what = what or f"the {prefix} kernels"
    if kernel_cache.damage(lib, key) is None:
        return lib
    if not kernel_cache.have_gcc():
        raise CompilerMissing(what)
    with kernel_cache.locked(folder / f".{prefix}_{key}.lock"):
        problem = kernel_cache.damage(lib, key)  # another process may have built it while this one waited
        if problem is None:
            return lib
        if problem == kernel_cache.DIRECTORY:  # an empty one is removed, another refused by name
            kernel_cache.clear_directory(lib)
            _announce(f"note: an empty directory {lib.name} stood in {folder} where a library goes; removed it, "
                      "compiling the library")
        elif problem != kernel_cache.MISSING:
            _announce(f"note: the cached {lib.name} in {folder} is damaged ({problem}); compiling it again")
        kernel_cache.sweep(folder)  # what killed builds left here
        start = time.perf_counter()
        try:
            with tempfile.TemporaryDirectory(prefix=f".{prefix}_{key}.{os.getpid()}.", dir=folder) as tmp:
                src = Path(tmp, f"{prefix}.c")
                src.write_text(source)
                with atomic_path(lib) as out:
                    run_compiler(["gcc", *flags, str(src), "-o", str(out), *link, "-lm"], what, len(source), flags)
                    kernel_cache.seal(out, key)
        except (subprocess.CalledProcessError, OSError) as exc:
            said = kernel_cache.build_failed(exc, folder, what, lib.name)
            if said is None:
                raise
            raise said from None
        kernel_cache.log_build(folder, f"{lib.name} {os.getpid()} {time.perf_counter() - start:.2f}")
    return lib


def load_cached(source, prefix, flags, load, what=None, link=()):
    """``load(path)`` of the cached library of ``source``; a cached file that does not load is rebuilt once.

    A library damaged in the cache (a disk error, a copy cut short, another kernel's copied onto its name) is found
    by its record of its build before it is loaded, and compiled again (:func:`compile_cached`); one that still fails
    in ``dlopen`` is removed and compiled again.
    """
    lib = compile_cached(source, prefix, flags, what, link)
    try:
        return lib, load(lib)
    except (OSError, RuntimeError):
        with contextlib.suppress(OSError):
            lib.unlink()
        lib = compile_cached(source, prefix, flags, what, link)
        return lib, load(lib)


def with_cse(f):
    """The same SX Function with common subexpressions eliminated (``casadi.cse``); MX as it is."""
    if not f.is_a("SXFunction"):
        return f
    args = f.sx_in()
    return ca.Function(f.name(), args, ca.cse(f.call(args)), f.name_in(), f.name_out())


class CompiledRHS:
    """A right-hand side ``(t, y) -> y_t`` compiled to C, with the leap-frog driver.

    Parameters
    ----------
    rhs : casadi.Function
        ``(t, y) -> y_t``.
    limits : casadi.Function, optional
        ``y -> g``; the leap-frog driver stops at the first step that leaves an entry of ``g``
        ``<= 0`` or not finite (the model's limits, :attr:`ShellSystem.limits`).
    threads : int, optional
        Threads for the OpenMP maps of a parallel RHS (:attr:`ShellSystem.rhs_parallel`); default
        :func:`default_threads`. Ignored (1) for a serial RHS. Changed later by :meth:`set_threads`.

    Attributes
    ----------
    function : casadi.Function
        The compiled RHS as an external CasADi Function; without gcc on ``PATH`` (and nothing cached) the RHS itself,
        in CasADi's virtual machine (:attr:`vm_reason` says so): what evaluates it runs, the C loops
        (:meth:`leapfrog`, :meth:`runge_kutta`) refuse in one line (:class:`CompilerMissing`).
    compile_time_s : float
        Seconds spent in gcc (0 when the cache had it).
    """

    def __init__(self, rhs, limits=None, threads=None):
        rhs = with_cse(rhs)
        self.size = rhs.size1_in(1)
        gen = ca.CodeGenerator("ms_rhs.c")
        gen.add(rhs)
        self.n_limits = 0
        limits_call = "(void)y; (void)g; return 0;"
        if limits is not None:
            limits = with_cse(limits)
            gen.add(limits)
            self.n_limits = limits.nnz_out(0)
            limits_call = _LIMITS_CALL.format(name=limits.name(), sz_arg=limits.sz_arg(), sz_res=limits.sz_res(),
                                              sz_iw=limits.sz_iw(), sz_w=limits.sz_w())
        with tempfile.TemporaryDirectory() as tmp:
            gen.generate(tmp + os.sep)
            source = Path(tmp, "ms_rhs.c").read_text()
        #: the RHS has OpenMP maps (:attr:`ShellSystem.rhs_parallel`): built with -fopenmp, threads set at run time
        self.parallel = _OMP_PRAGMA in source
        source = _THREADS_HEAD + source.replace(_OMP_PRAGMA, _OMP_THREADS) + _THREADS_API
        source += _DRIVER.format(
            n=self.size, ng=self.n_limits, name=rhs.name(), sz_iw=rhs.sz_iw(), sz_w=rhs.sz_w(), sz_arg=rhs.sz_arg(),
            sz_res=rhs.sz_res(), limits_call=limits_call,
        ) + RK_DRIVER.replace("{name}", rhs.name())
        start = time.perf_counter()
        flags = kernel_cache.optimised(CFLAGS) + (("-fopenmp",) if self.parallel else ())
        #: why the RHS runs in CasADi's virtual machine (no gcc on PATH and nothing cached), else None
        self.vm_reason = None
        try:  # one handle for CasADi's external and ctypes (the same path): ms_threads is shared
            lib, (self.function, self._lib) = load_cached(
                source, "rhs", flags, lambda path: (ca.external(rhs.name(), str(path)), ctypes.CDLL(str(path))),
                what="the right-hand side")
        except CompilerMissing as exc:  # the routes that only evaluate the RHS run on; the C loops refuse by name
            lib, self.function, self._lib, self.vm_reason = None, rhs, None, str(exc)
            self.parallel = False
        self.compile_time_s = time.perf_counter() - start
        self.path = lib
        self._f = np.zeros(self.size)
        self._g = np.zeros(max(self.n_limits, 1))
        if self._lib is None:
            self.set_threads(threads)
            return
        self._lib.ms_leapfrog.restype = ctypes.c_longlong
        dptr = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        self._lib.ms_leapfrog.argtypes = [dptr, dptr, dptr, dptr, ctypes.c_longlong, ctypes.c_double, ctypes.c_double]
        real, ptr = ctypes.c_double, ctypes.POINTER(ctypes.c_double)
        self._lib.ms_rk.restype = ctypes.c_int
        self._lib.ms_rk.argtypes = [dptr, dptr, dptr, dptr, real, real, dptr, real, ctypes.c_int, dptr, dptr, dptr,
                                    dptr, ptr, ctypes.c_int, real, dptr, dptr, ctypes.c_longlong,
                                    np.ctypeslib.ndpointer(dtype=np.int64, flags="C_CONTIGUOUS")]
        self._lib.ms_limits.argtypes = [dptr, dptr]
        self._lib.ms_set_threads.argtypes = [ctypes.c_int]
        self._lib.ms_get_threads.restype = ctypes.c_int
        self.set_threads(threads)

    def set_threads(self, threads=None):
        """Threads for the cell and node kernels (``None``: :func:`default_threads`); 1 when the RHS is serial."""
        if threads is None:
            threads = default_threads()
        threads = checked_threads("threads", threads)
        #: the threads asked for (the leap-frog stencil of :mod:`mol_shell.discretization.stencil` takes them too)
        self.requested_threads = int(threads)
        if self._lib is not None:
            self._lib.ms_set_threads(int(threads) if self.parallel else 1)

    @property
    def threads(self):
        """Threads the compiled RHS uses now (1 in CasADi's virtual machine)."""
        return 1 if self._lib is None else int(self._lib.ms_get_threads())

    def need_c(self, what):
        """Refuse ``what`` (a C loop on this RHS) in one line when the RHS runs in CasADi's virtual machine."""
        if self._lib is None:
            raise CompilerMissing(what)

    def leapfrog(self, ya, yb, nsteps, dt, t=0.0):
        """Advance the pair ``(y_{k-1}, y_k)`` in place by up to ``nsteps`` leap-frog steps (``t``: the time of ``y_k``).

        Returns ``(steps taken, stopped)``: ``stopped`` is true if the last step taken left the
        limits (``yb`` is then the first state outside them), which may be step ``nsteps`` itself.
        """
        self.need_c("the leap-frog's step loop")
        code = self._lib.ms_leapfrog(ya, yb, self._f, self._g, int(nsteps), float(dt), float(t))
        if code < 0:
            raise RuntimeError("compiled right-hand side failed")
        return (int(code), True) if code > 0 else (int(nsteps), False)

    def runge_kutta(self, state, t_end, rtol, atol, max_step, tableau, max_steps, stats, work=None):
        """Advance ``state = [t, y, f, h]`` (arrays, updated in place) towards ``t_end`` in C (:mod:`mol_shell.discretization.rk_driver`).

        ``tableau``: ``(A, B, C, E, E3 or None, error exponent)``; ``stats``: int64 ``[accepted, rejected,
        RHS evaluations]``, added to; ``work``: ``(s + 4) N`` doubles (allocated if None). Returns the driver's code: 0
        at ``t_end``, 1 at a limit (the step that left it kept: ``state`` its start, ``h`` its end's time, ``work`` its
        stages and end), 2 after ``max_steps`` steps, -1 RHS failure, -2 step below the minimum.
        """
        self.need_c("the Runge-Kutta step loop of dop853-c and rk45-c")
        t, y, f, h = state
        A, B, C, E, E3, exponent = tableau
        s = len(B)
        work = np.empty((s + 4) * self.size) if work is None else work
        e3 = E3.ctypes.data_as(ctypes.POINTER(ctypes.c_double)) if E3 is not None else None
        return int(self._lib.ms_rk(t, y, f, h, float(t_end), float(rtol), atol, float(max_step), s, A, B, C, E, e3,
                                   int(E3 is not None), float(exponent), work, self._g, int(max_steps), stats))

    def limits(self, y):
        """The model's limits ``g`` at ``y`` (a copy), in C: for the search of a crossing inside a step."""
        if self._lib.ms_limits(np.ascontiguousarray(y, dtype=float), self._g):
            raise RuntimeError("compiled limits failed")
        return self._g[: self.n_limits].copy()

    def evaluator(self):
        """``(y, t=0) -> y_t`` through a preallocated CasADi buffer (about 0.2 us of call overhead).

        Returns the callable and keeps the buffer and its arrays alive in its closure.
        """
        buf, trigger = self.function.buffer()
        t, y, out = np.zeros(1), np.zeros(self.size), np.zeros(self.size)
        buf.set_arg(0, memoryview(t))
        buf.set_arg(1, memoryview(y))
        buf.set_res(0, memoryview(out))

        def evaluate(state, time=0.0):
            t[0] = time
            y[:] = state
            trigger()
            return out

        evaluate.buffer = (buf, t, y, out)
        return evaluate


class CompiledFunctions:
    """Several CasADi Functions generated into one C file, compiled once with gcc and cached.

    Parameters
    ----------
    functions : sequence of casadi.Function
        Distinct names; SX ones get common subexpressions eliminated first.
    flags : tuple of str
        gcc flags. ``-O1`` by default: the large derivative graphs (exact Jacobians)
        compile about twice as fast as at ``-O2`` (measured 6.8 s against 15 s for the
        n = 40 Jacobian) and run 4.4x faster than at ``-O0``.
    vm_without_gcc : bool
        Without a gcc on ``PATH`` that builds them (and nothing cached) keep the Functions in CasADi's virtual machine
        (``path`` None) instead of refusing (:class:`CompilerError`): for callers that only evaluate them (the
        stresses after a run, whose data a failing gcc must not cost).
    generated : tuple, optional
        What :meth:`generate` gave for ``functions`` (asked :meth:`unavailable` first): not generated again.

    Attributes
    ----------
    functions : dict
        Name to external (compiled) CasADi Function.
    compile_time_s : float
        Seconds spent in code generation and gcc (about 0 when the cache had it).
    """

    FLAGS = ("-O1", "-fno-semantic-interposition", "-fPIC", "-shared")

    def __init__(self, functions, flags=FLAGS, vm_without_gcc=False, generated=None):
        start = time.perf_counter()
        functions, source = generated or self.generate(functions)
        #: why the Functions run in CasADi's virtual machine (gcc missing or failing, vm_without_gcc), else None
        self.vm_reason = None
        try:
            self.path, self.functions = load_cached(
                source, "funcs", tuple(flags),
                lambda path: {f.name(): ca.external(f.name(), str(path)) for f in functions},
                what="functions " + ", ".join(f.name() for f in functions))
        except CompilerError as exc:  # vm_without_gcc: the Functions themselves, in CasADi's VM (path None)
            if not vm_without_gcc:
                raise
            self.path, self.functions, self.vm_reason = None, {f.name(): f for f in functions}, str(exc)
        self.compile_time_s = time.perf_counter() - start

    @staticmethod
    def generate(functions):
        """``(functions, source)``: the Functions as compiled (SX ones with common subexpressions eliminated) and
        their C source; given as ``generated``, the class compiles it without generating it again."""
        functions = [with_cse(f) for f in functions]
        gen = ca.CodeGenerator("ms_funcs.c")
        for f in functions:
            gen.add(f)
        with tempfile.TemporaryDirectory() as tmp:
            gen.generate(tmp + os.sep)
            return functions, Path(tmp, "ms_funcs.c").read_text()

    @staticmethod
    def unavailable(generated, flags=FLAGS):
        """Why the library of ``generated`` (:meth:`generate`) cannot be had here (neither cached nor built by a
        working gcc: :func:`~mol_shell.discretization.kernel_cache.unavailable`), or ``None`` where it can."""
        return kernel_cache.unavailable(generated[1], "funcs", tuple(flags))

    def evaluator(self, name):
        """``(*inputs) -> nonzeros of output 0`` through a preallocated buffer.

        The returned array is reused by the next call: copy it to keep it. Inputs are
        copied into the buffer's arrays (dense inputs only).
        """
        return buffered(self.functions[name])


def buffered(f):
    """A fast callable for any CasADi Function with dense inputs: ``(*inputs) -> nonzeros of output 0``.

    Works for SX/MX (virtual machine) and external Functions alike; the buffer and its
    arrays live in the closure (CasADi segfaults if they are collected).
    """
    buf, trigger = f.buffer()
    ins = [np.zeros(f.nnz_in(i)) for i in range(f.n_in())]
    outs = [np.zeros(f.nnz_out(i)) for i in range(f.n_out())]
    for i, a in enumerate(ins):
        buf.set_arg(i, memoryview(a))
    for i, a in enumerate(outs):
        buf.set_res(i, memoryview(a))
    out0 = outs[0]

    def evaluate(*args):
        for a, x in zip(ins, args):
            a[:] = x
        trigger()
        return out0

    evaluate.buffer = (buf, ins, outs)
    evaluate.outputs = outs
    return evaluate
