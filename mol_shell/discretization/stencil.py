"""Leap-frog on a vectorised stencil: the whole step loop in C, nodes in lanes of the processor's vector units.

The compiled RHS (:mod:`mol_shell.discretization.compiled`) assembles its maps of cell and node kernels in CasADi's MX
layer: at n = 10,240 about twenty passes over node-sized arrays between the maps are serial and the kernels
run one node at a time. For the leap-frog of an elastic, unloaded shell without poles, the same kernels
(:meth:`~mol_shell.discretization.cells.CellKernels.node_trig_kernel`, the shared cell kernel, the node kernels) are written
here as straight-line C from their SX instructions (:func:`sx_statements`) into three loops over blocks of
eight nodes (trigonometry, cells, nodes), each block's lanes one ``#pragma omp simd`` vector, the blocks
shared among threads. The state lives in a structure-of-arrays copy for the whole call (a row per field and
momentum), the update ``y_{k+1} = y_{k-1} + 2 dt f(y_k)`` is done in place and the two levels swap pointers.

Every lane computes a node by the same instructions as the generic compiled RHS, in the same order (IEEE
arithmetic, no fused multiply-adds; libm's ``sin`` and ``cos``, called lane by lane: glibc's vector variants
differ in the last bits), so the states equal the generic driver's to the last bit on any thread count
(``tests/test_stencil.py``). The model's limits (``delta`` at each cell's samples, ``r > 0``,
``|psi| < pi/2``) are checked in the same loops: the driver stops at the first state outside them, as
:meth:`CompiledRHS.leapfrog` does. At n = 10,240 a step costs 0.52 ms on one thread and 0.28 ms on two,
against 2.17 and 1.83 ms for the generic driver (``benchmarks/performance.py --targets large``, docs/performance.md).
"""

from __future__ import annotations

import ctypes
import math

import casadi as ca
import numpy as np

from mol_shell.discretization import kernel_cache
from mol_shell.discretization.cells import sample_trigs
from mol_shell.discretization.compiled import CFLAGS, CompilerMissing, load_cached
from mol_shell.discretization.threads import checked_threads, default_threads
from mol_shell.model.material import svk_turning_limit

#: the SX operations the emitter writes as C (each exactly as CasADi's own code generator does)
_BINARY = {ca.OP_ADD: "({0}+{1})", ca.OP_SUB: "({0}-{1})", ca.OP_MUL: "({0}*{1})", ca.OP_DIV: "({0}/{1})",
           ca.OP_LT: "({0}<{1})", ca.OP_LE: "({0}<={1})", ca.OP_IF_ELSE_ZERO: "({0}?{1}:0.)"}
_UNARY = {ca.OP_NEG: "(-{0})", ca.OP_SQ: "({0}*{0})", ca.OP_TWICE: "(2.*{0})", ca.OP_SIN: "sin({0})",
          ca.OP_COS: "cos({0})", ca.OP_ASSIGN: "{0}", ca.OP_FABS: "fabs({0})", ca.OP_NOT: "(!{0})"}
#: gcc flags: the generic ones, OpenMP, and no floating-point traps: with them gcc keeps every select (the
#: turning-point limit's ``tr > 0 ? det : -|det|``, the edge nodes' updates) as a branch, and neither the cell
#: nor the node loop is vectorised. The values are IEEE's either way (the status flags are not read); the
#: stencil stays bit-identical to the generic driver (tests/discretization/test_stencil.py)
FLAGS = CFLAGS + ("-fopenmp", "-fno-trapping-math")
#: lanes per block: one AVX-512 vector of doubles (two AVX2 ones); every node goes through the vector path
LANES = 8


class Unsupported(ValueError):
    """A scene or kernel the stencil driver does not cover (the generic driver runs it)."""


def sx_statements(f, read, outputs):
    """C statements computing SX Function ``f``: ``read(i, row)`` gives input ``i``'s entry ``row`` as C,
    ``outputs[j]`` is the prefix of ``f.size1_out(j)`` local doubles ``<prefix><row>`` it declares (``None``: not
    needed), 0 where the output is structurally zero. Raises :class:`Unsupported` on an operation it does not write.
    """
    if not f.is_a("SXFunction"):
        raise Unsupported(f"{f.name()} is not an SX function")
    rows_in = [f.sparsity_in(i).row() for i in range(f.n_in())]
    rows_out = [f.sparsity_out(j).row() for j in range(f.n_out())]
    work = [f"w{k}" for k in range(max(f.sz_w(), 1))]
    head = [f"double {', '.join(f'{name}{r} = 0' for r in range(f.size1_out(j)))};"  # structural zeros: 0
            for j, name in enumerate(outputs) if name is not None]
    lines = ["{", "double " + ", ".join(work) + ";"]
    for k in range(f.n_instructions()):
        op, o, i = f.instruction_id(k), f.instruction_output(k), f.instruction_input(k)
        if op == ca.OP_INPUT:
            lines.append(f"w{o[0]} = {read(i[0], rows_in[i[0]][i[1]])};")
        elif op == ca.OP_OUTPUT:
            if outputs[o[0]] is not None:
                lines.append(f"{outputs[o[0]]}{rows_out[o[0]][o[1]]} = w{i[0]};")
        elif op == ca.OP_CONST:
            value = float(f.instruction_constant(k))
            if not math.isfinite(value):
                raise Unsupported(f"{f.name()} has the constant {value}")
            lines.append(f"w{o[0]} = {value.hex()};")
        elif op in _BINARY:
            lines.append(f"w{o[0]} = " + _BINARY[op].format(f"w{i[0]}", f"w{i[1]}") + ";")
        elif op in _UNARY:
            lines.append(f"w{o[0]} = " + _UNARY[op].format(f"w{i[0]}") + ";")
        else:
            raise Unsupported(f"{f.name()} uses CasADi operation {op}")
    return "\n".join(head + lines + ["}"])


def unsupported_reason(system):
    """Why ``system`` cannot run on the stencil driver, or ``None`` when it can."""
    checks = [
        (system.reference_kernel, "the reference kernel"),
        (system.law is not None, f"material = {system.scene.material}"),
        (system.fibres is not None, "fibres"),
        (system.n_extra > 0 or bool(system.drives), "loads or driven edges"),
        (system.viscous, "viscosity"),
        (bool(system.ties), "a pole"),
        (tuple(system.active) != tuple(range(5)), "a scene without all five fields"),
        (bool(system.fixed[1:-1].any()), "imposed fields at interior nodes"),
        (system.ellipticity_limit, "ellipticity_limit"),
    ]
    return next((what for bad, what in checks if bad), None)


def cell_limits_kernel(system):
    """``(ql, qr, tl, tr, geo) -> (dV/dq_l, dV/dq_r, ds x delta at the two samples)``: the shared cell kernel
    with the limit ``delta = r beta1 cos(psi)`` (:func:`~mol_shell.model.kinematics.delta`) from the same
    trigonometry (the midpoint ``theta``'s cosine and sine as products of the half angles')."""
    ql, qr = ca.SX.sym("ql", 5), ca.SX.sym("qr", 5)
    tl, tr = ca.SX.sym("tl", 4), ca.SX.sym("tr", 4)
    geo = ca.SX.sym("geo", system.shared_cell_data.shape[0])
    gl, gr = system.cell_forces_shared_kernel()(ql, qr, tl, tr, geo)
    cos_mid, sin_mid = tl[2] * tr[2] - tl[3] * tr[3], tl[3] * tr[2] + tl[2] * tr[3]
    beta1 = (qr[0] - ql[0]) * cos_mid + (qr[1] - ql[1]) * sin_mid
    r_mid = (qr[1] + ql[1]) / 2
    deltas = [r_mid * beta1 * tl[0], r_mid * beta1 * tr[0]]
    if system.turning_limit:  # SVK's compressive turning point at the two samples, from the same trigonometry
        beta2_0, moments = system.shared_moments(geo)
        deltas += [svk_turning_limit(e, moments, beta2_0, trig)
                   for e, trig in zip(system.cell_samples(ql, qr), sample_trigs(tl, tr))]
    return ca.Function("cell_limits", [ql, qr, tl, tr, geo], ca.cse([gl, gr, ca.vertcat(*deltas)]))


_HEAD = r"""#include <math.h>
#include <stdlib.h>
#include <string.h>
#define LANES %(lanes)d
"""

_DRIVER = r"""
/* Leap-frog on the stencil: ya, yb (node-major, 10 n) hold steps k-1 and k and are advanced in place by up
   to nsteps steps. geo: the cells' data (rows x ld, or one column), inertia: the nodes' (3 x ld, or one
   column), mask: the fixed entries of the edge nodes' forces (0 or 1, node 0 then node n-1), ld the padded
   length. Returns 0 after nsteps steps, j > 0 if the state after step j is outside the model's limits (the
   pair then holds steps j-1 and j), -1 if memory ran out. */
long long ms_stencil_leapfrog(double* ya, double* yb, long long nsteps, double dt, int n, int ld, int threads,
                              const double* geo, const double* inertia, const double* mask) {
  const int nb = ld / LANES - 1;  /* blocks: every node and cell of the grid, and padding */
  double* mem = (double*) malloc(sizeof(double) * (size_t) ld * 34);
  double *A, *B, *T, *GL, *GR, *swap;
  long long step, result = 0;
  int i, k;
  if (!mem) return -1;
  A = mem; B = mem + 10 * (size_t) ld; T = mem + 20 * (size_t) ld; GL = T + 4 * (size_t) ld; GR = GL + 5 * (size_t) ld;
  for (i = 0; i < ld; ++i) {  /* padding: copies of the last node (finite; its results are not used) */
    int j = i < n ? i : n - 1;
    for (k = 0; k < 10; ++k) { A[k * ld + i] = ya[10 * j + k]; B[k * ld + i] = yb[10 * j + k]; }
  }
  memset(GR, 0, sizeof(double) * 5 * (size_t) ld);  /* GR[k][i]: the force of cell i-1 on node i; none on node 0 */
  for (step = 0; step <= nsteps; ++step) {
    int bad = 0;
    #pragma omp parallel num_threads(threads) if(threads > 1)
    {
      int b;
      #pragma omp for schedule(static) reduction(|:bad)
      for (b = 0; b < nb; ++b) {
        int l;
        for (l = 0; l < LANES; ++l) {
          const int i = LANES * b + l;
%(trig)s
          T[i] = tc0; T[ld + i] = tc1; T[2 * ld + i] = tc2; T[3 * ld + i] = tc3;
          bad |= (i < n) & !((B[ld + i] > 0) & (B[4 * ld + i] * B[4 * ld + i] < %(psi_max_sq)s));
        }
      }
      #pragma omp for schedule(static) reduction(|:bad)
      for (b = 0; b < nb; ++b) {
        int l;
        #pragma omp simd reduction(|:bad)
        for (l = 0; l < LANES; ++l) {
          const int c = LANES * b + l;
%(cell)s
          GL[c] = cl0; GL[ld + c] = cl1; GL[2 * ld + c] = cl2; GL[3 * ld + c] = cl3; GL[4 * ld + c] = cl4;
          GR[c + 1] = cr0; GR[ld + c + 1] = cr1; GR[2 * ld + c + 1] = cr2; GR[3 * ld + c + 1] = cr3;
          GR[4 * ld + c + 1] = cr4;
          bad |= (c < n - 1) & !(%(cell_ok)s);
        }
      }
      if (!(bad && step > 0) && step < nsteps) {  /* bad: reduced, and seen by every thread after the barrier */
        #pragma omp for schedule(static)
        for (b = 0; b < nb; ++b) {
          int l;
          #pragma omp simd
          for (l = 0; l < LANES; ++l) {
            const int i = LANES * b + l;
            const int inner = (i > 0) & (i < n - 1);
%(node)s
            const double g0 = nf0 - (GL[i] + GR[i]), g1 = nf1 - (GL[ld + i] + GR[ld + i]);
            const double g2 = nf2 - (GL[2 * ld + i] + GR[2 * ld + i]), g3 = nf3 - (GL[3 * ld + i] + GR[3 * ld + i]);
            const double g4 = nf4 - (GL[4 * ld + i] + GR[4 * ld + i]);
            /* every load unconditional (vectorised without masks); the edges and padding keep their values */
%(update_inner)s
          }
        }
      }
    }
    if (bad && step > 0) { result = step; break; }
    if (step == nsteps) break;
    { /* the edge nodes, with their own free rates and fixed forces */
      const int i = 0;
%(first)s
%(v_edge)s
%(f_first)s
    }
    {
      const int i = n - 1;
%(last)s
%(v_edge)s
%(f_last)s
    }
    swap = A; A = B; B = swap;
  }
  for (i = 0; i < n; ++i)
    for (k = 0; k < 10; ++k) { ya[10 * i + k] = A[k * ld + i]; yb[10 * i + k] = B[k * ld + i]; }
  free(mem);
  return result;
}
"""


def _updates(rates, indent=6, inner=False):
    """``A[row] += 2 dt rate`` for the rows and rates given (``y_{k+1} = y_{k-1} + 2 dt f(y_k)`` in the generic
    driver's order); ``inner``: only at interior nodes (an unconditional load, a select on the increment)."""
    step = "(inner ? 2.0 * dt * {} : 0.0)" if inner else "2.0 * dt * {}"
    return "\n".join(" " * indent + f"A[{row} * ld + i] += {step.format(rate)};" for row, rate in rates)


def _edge_forces(cell_sum, mask_offset):
    """The momentum updates of an edge node: ``(dT/dq - cell forces) x mask`` (the generic graph's order)."""
    return _updates([(5 + k, f"((nf{k} - ({cell_sum.format(k=k)})) * mask[{mask_offset + k}])") for k in range(5)])


def stencil_source(system):
    """The C of :func:`ms_stencil_leapfrog` for ``system``'s kernels (independent of ``n``)."""
    reason = unsupported_reason(system)
    if reason:
        raise Unsupported(f"the stencil driver does not cover {reason}")
    first, inner, last = system.free_sets()
    geo_uniform = system.shared_cell_data.shape[1] == 1
    inertia_uniform = bool(np.all(system.inertia == system.inertia[:, :1]))
    geo = (lambda r: f"geo[{r}]") if geo_uniform else (lambda r: f"geo[{r} * ld + c]")
    mass = (lambda r: f"inertia[{r}]") if inertia_uniform else (lambda r: f"inertia[{r} * ld + i]")

    def node_read(j, r):
        return (f"B[{r} * ld + i]", f"B[{5 + r} * ld + i]", mass(r), f"T[{r} * ld + i]")[j]

    def cell_read(j, r):
        return (f"B[{r} * ld + c]", f"B[{r} * ld + c + 1]", f"T[{r} * ld + c]", f"T[{r} * ld + c + 1]", geo(r))[j]

    def node(free):
        return sx_statements(system._node_kernel(free, True), node_read, ["nv", "nf", None])

    parts = {
        "lanes": LANES,
        "psi_max_sq": ((math.pi / 2) ** 2).hex(),
        "trig": sx_statements(system.node_trig_kernel(), lambda j, r: f"B[{r} * ld + i]", ["tc"]),
        "cell": sx_statements(cell_limits_kernel(system), cell_read, ["cl", "cr", "cd"]),
        "cell_ok": " & ".join(f"(cd{k} > 0)" for k in range(4 if system.turning_limit else 2)),
        "node": node(inner),
        "first": node(first),
        "last": node(last),
        "update_inner": _updates([(k, f"nv{k}") for k in range(5)] + [(5 + k, f"g{k}") for k in range(5)], 12, True),
        "v_edge": _updates([(k, f"nv{k}") for k in range(5)]),
        "f_first": _edge_forces("GL[{k} * ld + i] + GR[{k} * ld + i]", 0),
        "f_last": _edge_forces("0.0 + GR[{k} * ld + i]", 5),
    }
    return (_HEAD + _DRIVER) % parts, geo_uniform, inertia_uniform


class StencilLeapfrog:
    """The leap-frog driver of :mod:`mol_shell.discretization.stencil` for one system: ``leapfrog(ya, yb, nsteps, dt, t)`` like
    :meth:`~mol_shell.discretization.compiled.CompiledRHS.leapfrog`. Raises :class:`Unsupported` for a system it does not cover.

    Parameters
    ----------
    system : ShellSystem
    threads : int, optional
        Threads for the blocks of nodes (default :func:`~mol_shell.discretization.compiled.default_threads`).
    """

    def __init__(self, system, threads=None):
        source, geo_uniform, inertia_uniform = stencil_source(system)
        n = system.n
        self.n, self.ld = n, LANES * (-(-(n + 1) // LANES)) + LANES

        def padded(table, uniform):
            if uniform:
                return np.ascontiguousarray(table[:, 0], dtype=float)
            out = np.repeat(table[:, -1:], self.ld, axis=1)
            out[:, : table.shape[1]] = table
            return np.ascontiguousarray(out, dtype=float)

        self._geo = padded(system.shared_cell_data, geo_uniform)
        self._inertia = padded(system.inertia, inertia_uniform)
        self._mask = np.ascontiguousarray((~system.fixed[[0, -1]]).astype(float).ravel())
        self.path, self._lib = load_cached(source, "stencil", kernel_cache.optimised(FLAGS), lambda p: ctypes.CDLL(str(p)),
                                           what="the leap-frog stencil")
        fn = self._lib.ms_stencil_leapfrog
        fn.restype = ctypes.c_longlong
        dptr = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        fn.argtypes = [dptr, dptr, ctypes.c_longlong, ctypes.c_double, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                       dptr, dptr, dptr]
        self.threads = default_threads() if threads is None else checked_threads("threads", threads)

    def set_threads(self, threads):
        self.threads = checked_threads("threads", threads)

    def leapfrog(self, ya, yb, nsteps, dt, t=0.0):
        """Advance ``(y_{k-1}, y_k)`` in place by up to ``nsteps`` steps; returns ``(steps taken, stopped)``."""
        code = self._lib.ms_stencil_leapfrog(ya, yb, int(nsteps), float(dt), self.n, self.ld, self.threads,
                                             self._geo, self._inertia, self._mask)
        if code < 0:
            raise MemoryError("the leap-frog stencil could not allocate its arrays")
        return (int(code), True) if code > 0 else (int(nsteps), False)


#: from this many nodes the stencil runs its blocks on threads; below, a parallel region per step costs more
#: than it saves (measured on 2 cores: 2.6 against 2.7 us per step at n = 40, 21 against 15 us at n = 640)
PARALLEL_MIN_NODES = 512


def leapfrog_stepper(system, compiled):
    """What advances the leap-frog for ``system``: its :class:`StencilLeapfrog` (built once and kept on the system)
    when the stencil covers it, else ``compiled``'s generic driver. Threads: those asked of ``compiled``
    (:meth:`~mol_shell.discretization.compiled.CompiledRHS.set_threads`) from :data:`PARALLEL_MIN_NODES` nodes, else one."""
    stepper = system.__dict__.get("_stencil")
    if stepper is None:
        try:
            stepper = StencilLeapfrog(system)  # its library from the cache without gcc, the RHS's compiled or not
        except Unsupported:
            stepper = False
        except CompilerMissing:  # neither cached nor built: said as the loop the run needs where the RHS lacks it too
            compiled.need_c("the leap-frog's step loop")
            raise
        system._stencil = stepper
    if stepper is False:
        compiled.need_c("the leap-frog's step loop")  # the RHS in CasADi's virtual machine: no gcc on PATH
        return compiled
    threads = getattr(compiled, "requested_threads", None)
    stepper.set_threads(1 if system.n < PARALLEL_MIN_NODES else threads if threads else 1)
    return stepper
