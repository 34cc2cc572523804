"""The compiled SUNDIALS driver: found, built once, loaded, and one solve driven through it.

The driver (:mod:`mol_shell.discretization.sundials_source`) links the SUNDIALS 7.9 libraries that the
scikit-sundae wheel installs in ``site-packages/scikit_sundae.libs`` (by full path, with an rpath, so nothing
else has to be on the loader's path). It is compiled once per SUNDIALS build and driver source, and cached under
``$MOL_SHELL_CACHE`` with the other kernels (:func:`~mol_shell.discretization.compiled.load_cached`: a lock file
for concurrent builders, an atomic rename, a damaged file rebuilt); the libraries' file names carry a hash of
their build, and are part of the cache key. ``$MOL_SHELL_SUNDIALS_LIBS`` points at another folder of the same
libraries; a value set there that is not such a folder is refused in one line naming it (:class:`ParameterError`), not
passed over for the wheel's. A driver in the cache is loaded without gcc, and gcc builds one that is not
(:func:`~mol_shell.discretization.kernel_cache.unavailable`). Where the driver cannot be had or loaded, :func:`driver`
raises :class:`DriverUnavailable` with one sentence saying why, and the integrators fall back to scikit-sundae's
Python loop.
"""

from __future__ import annotations

import ctypes
import functools
import importlib.util
import os
from pathlib import Path

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell._core.user_files import absent
from mol_shell.discretization import kernel_cache
from mol_shell.discretization.compiled import CompilerError, load_cached
from mol_shell.discretization.sundials_source import STALL_STEPS, SUNDIALS_DRIVER  # noqa: F401 (STALL_STEPS: for drv.)

#: the libraries the driver links, by the start of their file names
LIBRARIES = ("core", "cvode", "ida", "nvecserial", "sunmatrixdense", "sunmatrixband", "sunmatrixsparse",
             "sunlinsoldense", "sunlinsolband", "sunlinsolsuperlumt", "sunlinsollapackdense", "sunlinsollapackband")
#: the driver's own code needs no -march=native (the CasADi kernels it calls are built apart)
FLAGS = ("-O2", "-fPIC", "-shared")
#: iopts/opts layout of ms_create (see the C source)
LINSOLVERS = {"dense": 0, "band": 1, "sparse": 2, "lapack-dense": 3, "lapack-band": 4}
#: codes of ms_advance
REACHED, ROOT, R_FLOOR, MAX_STEPS, CHUNK, CALLS, STALLED = 0, 1, 2, 3, 4, 5, 6
#: SUNDIALS' flags for a failed constraint (CV_CONSTR_FAIL, IDA_CONSTR_FAIL)
CONSTRAINT_FAIL = {"cvode": -15, "ida": -11}


#: the environment variable that names another folder of the SUNDIALS libraries
LIBS_VARIABLE = "MOL_SHELL_SUNDIALS_LIBS"


class DriverUnavailable(RuntimeError):
    """The compiled driver cannot be built or loaded here; the message is one sentence saying why."""


def library_folder():
    """The folder of the wheel's SUNDIALS libraries (``$MOL_SHELL_SUNDIALS_LIBS`` overrides it: a folder that does not
    hold them is refused, :class:`ParameterError`, as the user's setting that cannot work)."""
    text = os.environ.get(LIBS_VARIABLE, "").strip()
    if text:
        allowed = (f"a folder holding SUNDIALS 7's shared libraries (libsundials_{LIBRARIES[0]}, _cvode, _ida, ...), "
                   "as the scikit-sundae wheel's scikit_sundae.libs; unset it for the wheel's own")
        problem = absent(text)  # a name too long for the file system: Path.is_dir raised it
        if problem not in (None, "does not exist") or not Path(text).is_dir():
            raise ParameterError.invalid(LIBS_VARIABLE, text, "is not a folder" if problem in (None, "does not exist")
                                         else problem, allowed)
        try:
            library_paths(text)
        except DriverUnavailable as exc:
            raise ParameterError.invalid(LIBS_VARIABLE, text, f"holds no {str(exc).split()[0]}", allowed) from None
        return Path(text)
    spec = importlib.util.find_spec("sksundae")
    if spec is None or not spec.submodule_search_locations:
        raise DriverUnavailable("scikit-sundae is not installed")
    return Path(list(spec.submodule_search_locations)[0]).parent / "scikit_sundae.libs"


def library_paths(folder):
    """Full paths of :data:`LIBRARIES` in ``folder``; :class:`DriverUnavailable` naming the first one missing."""
    paths = []
    for name in LIBRARIES:
        found = sorted(Path(folder).glob(f"libsundials_{name}-*.so*")) + sorted(Path(folder).glob(f"libsundials_{name}.so*"))
        if not found:
            raise DriverUnavailable(f"libsundials_{name} not found in {folder}")
        paths.append(str(found[0]))
    return paths


def link_arguments(folder):
    """gcc's arguments after the source: the libraries by full path, and their folder as the run-time path."""
    return (*library_paths(folder), f"-Wl,-rpath,{Path(folder).resolve()}")


@functools.lru_cache(maxsize=None)
def _load(folder):
    link = link_arguments(folder)
    problem = kernel_cache.unavailable(SUNDIALS_DRIVER, "sundials", FLAGS, link)  # cached, or a gcc that works
    if problem is not None:
        raise DriverUnavailable(problem)
    try:
        _, lib = load_cached(SUNDIALS_DRIVER, "sundials", FLAGS, lambda path: ctypes.CDLL(str(path)),
                             what="the SUNDIALS driver", link=link)
    except CompilerError as exc:  # gcc failed (its last lines are in the message); a cache that refuses is said as is
        raise DriverUnavailable(str(exc)[:300]) from None
    except OSError as exc:
        raise DriverUnavailable(f"it could not be loaded ({str(exc)[:160]})") from None
    if lib.ms_check_index() != 0:
        raise DriverUnavailable("the SUNDIALS libraries use another index type than the 32-bit one declared")
    _declare(lib)
    return lib


def driver():
    """The loaded driver library (built on first use); :class:`DriverUnavailable` if it cannot be had."""
    return _load(str(library_folder()))


PY_JAC = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, ctypes.POINTER(ctypes.c_double),
                          ctypes.POINTER(ctypes.c_double), ctypes.c_double, ctypes.POINTER(ctypes.c_double))


def _declare(lib):
    vp, ll, dbl, i32 = ctypes.c_void_p, ctypes.c_longlong, ctypes.c_double, ctypes.c_int
    arr = {t: np.ctypeslib.ndpointer(dtype=t, flags="C_CONTIGUOUS") for t in (np.float64, np.int64, np.int32)}
    lib.ms_create.restype = vp
    lib.ms_create.argtypes = [arr[np.int64], arr[np.float64], i32, dbl, arr[np.float64], arr[np.float64],
                              arr[np.float64], vp, arr[np.int64], vp, arr[np.int64], PY_JAC, arr[np.int64],
                              arr[np.int64], i32, vp, arr[np.int64], i32, arr[np.float64], arr[np.int32], i32,
                              ctypes.POINTER(i32)]
    lib.ms_advance.restype = i32
    lib.ms_advance.argtypes = [vp, dbl, ll, dbl, ctypes.POINTER(dbl), arr[np.float64], arr[np.float64]]
    lib.ms_stats.argtypes = [vp, arr[np.int64]]
    lib.ms_costs.argtypes = [vp, i32, arr[np.float64]]
    lib.ms_set_kinks.restype = i32
    lib.ms_set_kinks.argtypes = [vp, arr[np.float64], i32]
    lib.ms_event_time.restype = dbl
    lib.ms_event_time.argtypes = [vp]
    lib.ms_free.argtypes = [vp]


def address(lib, name):
    """Address of the exported C function ``name`` of a loaded library."""
    return ctypes.cast(getattr(lib, name), ctypes.c_void_p).value


def work_sizes(f):
    """``[sz_arg, sz_res, sz_iw, sz_w]`` of a CasADi Function (what its generated C needs)."""
    return np.array([f.sz_arg(), f.sz_res(), f.sz_iw(), f.sz_w()], dtype=np.int64)


class Solve:
    """One SUNDIALS solve in the driver: created from plain arrays and C function addresses, freed with the object.

    Parameters
    ----------
    ida : bool
        IDA on ``F(t, x, x_t) = 0`` (``rhs`` is the residual ``(t, x, xp) -> F``) or CVODE on ``y_t = f(t, y)``.
    iopts, opts : sequences
        Integer and real settings in the driver's order (:class:`mol_shell.integrators.sundials_c`).
    rhs, jac, limits : tuple ``(address, work sizes)`` or None
        Compiled CasADi functions; ``jac`` None with ``py_jac`` given: the Jacobian's non-zeros from Python.
    pattern : casadi.Sparsity
        The Jacobian's compressed-column pattern.
    floor : ndarray
        Subtracted from the limits to make the root functions; ``r_entries`` the constrained ``r`` entries.
    kinks : sequence of float
        Times after the start where a drive's rate has a kink (increasing): the solve stops at each and restarts
        there (:func:`mol_shell.discretization.loading.drive_kinks`).
    """

    def __init__(self, ida, iopts, opts, y0, yp0, atol, rhs, jac, py_jac, pattern, limits, floor, r_entries,
                 kinks=()):
        self.lib = driver()
        self.n = len(y0)
        self.ida = ida
        self.y, self.yp = np.array(y0, dtype=float), np.array(yp0 if ida else y0, dtype=float)
        colind, row = (np.asarray(a, dtype=np.int64) for a in (pattern.colind(), pattern.row()))
        self._keep = [np.asarray(iopts, dtype=np.int64), np.asarray(opts, dtype=float), np.asarray(atol, dtype=float),
                      colind, row, np.ascontiguousarray(floor, dtype=float),
                      np.ascontiguousarray(r_entries, dtype=np.int32)]
        self.py_jac = PY_JAC(py_jac) if py_jac is not None else ctypes.cast(None, PY_JAC)
        empty = np.zeros(4, dtype=np.int64)
        err = ctypes.c_int(0)
        self.handle = self.lib.ms_create(
            self._keep[0], self._keep[1], self.n, 0.0, self.y, self.yp, self._keep[2], rhs[0], rhs[1],
            jac[0] if jac else None, jac[1] if jac else empty, self.py_jac, colind, row, int(pattern.nnz()),
            limits[0] if limits else None, limits[1] if limits else empty, len(floor) if limits else 0,
            self._keep[5], self._keep[6], len(r_entries), ctypes.byref(err))
        if not err.value and len(kinks):
            self._keep.append(np.ascontiguousarray(kinks, dtype=float))
            err.value = 7 if self.lib.ms_set_kinks(self.handle, self._keep[-1], len(kinks)) else 0
        if err.value:
            self.close()
            raise RuntimeError(f"the SUNDIALS driver could not set up the solver (stage {err.value})")
        self.t = 0.0
        self._stats = np.zeros(11, dtype=np.int64)

    def advance(self, target, max_steps, seconds):
        """Step towards ``target``; returns the driver's code (:data:`REACHED`, :data:`ROOT`, ...)."""
        t = ctypes.c_double(self.t)
        code = self.lib.ms_advance(self.handle, float(target), int(max_steps), float(seconds), ctypes.byref(t),
                                   self.y, self.yp)
        self.t = t.value
        return int(code)

    def stats(self):
        """Steps, evaluations, Jacobians, set-ups, failures, Newton iterations, root evaluations, the root, calls."""
        self.lib.ms_stats(self.handle, self._stats)
        keys = ("sundials_steps", "n_rhs", "n_jac", "n_setups", "n_error_test_fails", "n_convergence_fails",
                "n_newton", "n_root_evals", "root", "n_steps", "n_rhs_jacobian")
        return dict(zip(keys, (int(v) for v in self._stats)))

    def costs(self, reps=20):
        """Seconds per call at the current state: right-hand side, Jacobian (NaN: difference quotients), copy and
        factorisation, solve, limits (see ``ms_costs``)."""
        out = np.zeros(5)
        self.lib.ms_costs(self.handle, int(reps), out)
        keys = ("rhs_s", "jacobian_s", "factorisation_s", "solve_s", "limits_s")
        return {k: (float(v) if v >= 0 else float("nan")) for k, v in zip(keys, out)}

    def event_time(self):
        return float(self.lib.ms_event_time(self.handle))

    def close(self):
        if getattr(self, "handle", None):
            self.lib.ms_free(self.handle)
            self.handle = None

    def __del__(self):
        self.close()
