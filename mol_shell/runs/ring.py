"""Section 5: spatially uniform motions (the breathing, spinning and shearing ring) as an ODE.

With ``z_s = 1`` and ``chi_s = theta = theta_s = psi_s = r_s = 0`` (eq. 5.1 with no twist)
every section of the cylinder moves alike, and the balance laws (5.2) reduce to ordinary
differential equations in time for ``r(t), chi(t), psi(t)``. We do not transcribe (5.2)
(its extraction is garbled); we take the same Lagrangian as the PDE,

    l(q, q_t) = T(q, q_t) - What(z_s = 1, r_s = chi_s = theta_s = psi_s = 0; r, theta = 0, psi)

per unit reference area, from the same model functions
(:func:`~mol_shell.model.kinematics.kinetic_energy_density`,
:func:`~mol_shell.model.material.shell_energy`), and write Hamilton's equations

    q_t = M(q)^-1 p,    p_t = dT/dq|_{q_t} - dWhat/dq - dD/dq_t,    q = (r, chi, psi),

(``D`` the Kelvin-Voigt Rayleigh function when the scene is viscous: the kernels', so an incompressible law's
follows ``det C = 1``, :func:`~mol_shell.model.hyperelastic.law_shell_dissipation`). ``chi`` is cyclic,
so ``p_chi`` (the axial angular momentum per unit area) is conserved. The PDE of
:class:`~mol_shell.scenes.SpinningRing` started from uniform data must follow this ODE at
every node: the discrete energy's ``s``-derivatives of ``What`` vanish at uniform states and
the ends carry half a cell's energy and half a node's mass.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import casadi as ca
import numpy as np
import xarray as xr

from mol_shell._core.constants import ATOL_MIN, RTOL_RANGE
from mol_shell._core.errors import ParameterError, is_number
from mol_shell._core.ranges import Choice
from mol_shell.discretization.limits import DELTA_REACHED, PSI_REACHED, R_REACHED, TURNING_REACHED
from mol_shell.model.edges import resolve_edges
from mol_shell.model.fibres import scene_fibres
from mol_shell.model.hyperelastic import law_shell_dissipation
from mol_shell.model.kinematics import delta, kinetic_energy_density
from mol_shell.model.laws import (
    SVK_LAW,
    law_parameters,
    layer_laws,
    scene_shell_energy,
    thickness_treatment,
    viscosities,
)
from mol_shell.model.linalg import spd_solve
from mol_shell.model.material import (
    Thickness,
    centroidal_offset,
    inertias,
    quadrature_factors,
    shell_dissipation,
    svk_turning_limit,
    thickness_moments,
)
from mol_shell.results.cf import coordinates, header, variables
from mol_shell.results.dataset import FIELD_META, RATE_UNITS, TIME_COMMENT, scene_attrs, with_units
from mol_shell.runs.simulate import as_scene, parse_times, resolve
from mol_shell.scenes.base import refuse_loads
from mol_shell.scenes.cylinder import TwistedCylinder, check_uniform

#: the ODE's unknowns, indices into :data:`mol_shell.model.FIELDS`
RING_FIELDS = (1, 2, 4)


@dataclass(frozen=True)
class RingSystem:
    """The reduced ODE of one scene; every CasADi object of the ring lives here.

    Attributes
    ----------
    rhs : casadi.Function
        ``(t, y) -> y_t`` with ``y = (r, chi, psi, p_r, p_chi, p_psi)``; momenta per unit
        reference area (kg m-1 s-1 and kg s-1).
    jac : casadi.Function
        ``(t, y) -> d y_t / d y``.
    observables : casadi.Function
        ``y -> (rates (3), kinetic, stored, p_chi, delta, dissipation)`` per unit reference area.
    momenta : casadi.Function
        ``(q, q_t) -> p``.
    area : float
        Reference area ``2 pi r0 L`` (m^2) that turns densities into whole-shell totals.
    limits : casadi.Function
        ``(t, y) -> g``: the model's limits on the ring's uniform state, which must stay positive (the PDE's
        :attr:`~mol_shell.discretization.limits.ModelLimits.limits` at every node): ``(pi/2)^2 - psi^2``, ``r``,
        ``delta``, and SVK's turning point where the PDE watches it (:func:`turning_moments`).
    limit_names : tuple of str
        What reaching each entry of ``limits`` is, as the PDE's runs say it.
    """

    rhs: ca.Function
    jac: ca.Function
    observables: ca.Function
    momenta: ca.Function
    area: float
    rho_a: float
    rho_i: float
    rho_j: float
    viscous: bool
    limits: ca.Function
    limit_names: tuple


def ring_system(scene):
    """Build the reduced ODE of section 5 for ``scene`` (its material, thickness and density).

    Parameters
    ----------
    scene : ShellScene
        A cylinder scene; only material, thickness, density, ``a`` and ``L`` enter the equations.

    Returns
    -------
    RingSystem
    """
    r0 = getattr(scene, "a", 1.0)
    zeta1 = centroidal_offset(scene.h, r0) if scene.zeta1 is None else scene.zeta1
    thickness = Thickness(zeta1, scene.h, scene.n_quad)
    rho_a, rho_i, rho_j = inertias(scene.rho, thickness, r0)
    if abs(rho_i) < 1e-14 * rho_a:
        rho_i = 0  # as ShellSystem: the rhoI terms are left out
    q, v, p = ca.SX.sym("q", 3), ca.SX.sym("v", 3), ca.SX.sym("p", 3)
    r, chi, psi = ca.vertsplit(q)
    r_t, chi_t, psi_t = ca.vertsplit(v)
    kinetic = kinetic_energy_density((0.0, r, chi, 0.0, psi), (0.0, r_t, chi_t, 0.0, psi_t), rho_a, rho_i, rho_j)
    strains = (1.0, 0.0, 0.0, 0.0, 0.0, r, 0.0, psi)
    stored = scene_shell_energy(scene, strains, thickness, r0)
    mass = ca.hessian(kinetic, v)[0]
    v_of_p = spd_solve(mass, p)
    forces = ca.substitute(ca.gradient(kinetic, q), v, v_of_p) - ca.gradient(stored, q)
    viscous = scene.eta_lambda > 0 or scene.eta_mu > 0
    dissipation = ca.SX(0)
    if viscous:
        rates = (0.0, 0.0, 0.0, 0.0, 0.0, r_t, 0.0, psi_t)
        if thickness_treatment(scene.material) == "incompressible" and not getattr(scene, "layers", ""):
            D = law_shell_dissipation(strains, rates, scene.eta_mu, thickness, r0)  # det C = 1: eta_mu alone
        else:
            D = shell_dissipation(strains, rates, *viscosities(scene), thickness, r0)
        forces -= ca.substitute(ca.gradient(D, v), v, v_of_p)
        dissipation = ca.substitute(2 * D, v, v_of_p)
    t, y = ca.SX.sym("t"), ca.SX.sym("y", 6)
    ydot = ca.substitute(ca.vertcat(v_of_p, forces), ca.vertcat(q, p), y)
    rhs = ca.Function("ring_rhs", [t, y], [ydot], ["t", "y"], ["ydot"])
    jac = ca.Function("ring_jac", [t, y], [ca.jacobian(ydot, y)], ["t", "y"], ["J"])
    outs = [v_of_p, ca.substitute(kinetic, v, v_of_p), stored, p[1], delta(1.0, 0.0, r, 0.0, psi), dissipation]
    outs = [ca.substitute(o, ca.vertcat(q, p), y) for o in outs]
    observables = ca.Function(
        "ring_observables", [y], outs, ["y"], ["v", "kinetic", "stored", "p_chi", "delta", "dissipation"]
    )
    momenta = ca.Function("ring_momenta", [q, v], [ca.gradient(kinetic, v)])
    # the model's limits, in the order the leap-frog checks them (psi, r, delta, the law's): the first of those
    # reached at once is said (|psi| -> pi/2 takes delta -> 0 with it)
    g = [(math.pi / 2) ** 2 - psi**2, r, delta(1.0, 0.0, r, 0.0, psi)]
    names = [PSI_REACHED, R_REACHED, DELTA_REACHED]
    moments = turning_moments(scene, thickness, r0)
    if moments is not None:
        g.append(svk_turning_limit(strains, moments))
        names.append(TURNING_REACHED)
    limits = ca.Function("ring_limits", [t, y], [ca.substitute(ca.vertcat(*g), ca.vertcat(q, p), y)], ["t", "y"], ["g"])
    return RingSystem(rhs, jac, observables, momenta, 2 * math.pi * r0 * scene.L, rho_a, rho_i, rho_j, viscous,
                      limits, tuple(names))


def turning_moments(scene, thickness, r0):
    """The thickness moments (:func:`~mol_shell.model.material.thickness_moments`) SVK's compressive turning point
    (:func:`~mol_shell.model.material.svk_turning_limit`) is taken with on the ring, or ``None`` where the PDE's runs
    do not watch it: as :attr:`~mol_shell.discretization.cells.CellKernels.turning_limit`, the SVK laws without fibres,
    a layered wall with such a layer (its layers' thickness rule), unless ``law_limit`` is off."""
    if getattr(scene, "layers", ""):
        thickness, laws = layer_laws(scene)
        svk = any(law is SVK_LAW and fibres is None for law, _, fibres in laws)
    else:
        svk = law_parameters(scene)[0] is None and scene_fibres(scene) is None
    if not (svk and getattr(scene, "law_limit", True)):
        return None
    return thickness_moments(quadrature_factors(thickness, r0))


def ring_initial_state(system, scene):
    """``y0`` of the uniform initial data of ``scene``: ``r = R``, ``chi = 0``, ``psi = psi0``, ``chi_t = omega``."""
    q0 = [scene.R, 0.0, getattr(scene, "psi0", 0.0)]
    v0 = [0.0, getattr(scene, "omega", 0.0), 0.0]
    return np.concatenate([q0, np.array(system.momenta(q0, v0)).ravel()])


def simulate_ring(scene, times=None, rtol=1e-12, atol=1e-12, *, t_end=None, n=None, method=None):
    """Solve the reduced ODE of section 5 for the uniform data of ``scene``.

    Parameters
    ----------
    scene : SpinningRing or TwistedCylinder, or a registered name (``"spinning-ring"``)
        Its ``gamma`` must be 0 (no twist: section 5 shows that twisted uniform motions
        do not exist); ``R = None`` is resolved as by :func:`mol_shell.simulate`.
    times : array_like, optional
        Saved times (s), starting at 0.
    t_end : float, optional
        Final time (s); alone it gives 11 evenly spaced saved times, as :func:`mol_shell.simulate` does.
    rtol, atol : float
        Tolerances of the ODE solver (``atol`` applies to ``r, chi, psi`` and, scaled by
        the initial momentum magnitude, to the momenta).
    n : int, optional
        ``None`` (default): the fields have dims ``(time,)`` only, so they broadcast against
        any PDE Dataset (``pde.r - ring.r`` works for every grid). An integer ``n >= 2``
        broadcasts them onto the PDE's grid ``linspace(0, L, n)`` (dims ``(time, s)``, and
        ``z = s`` is included).
    method : str, optional
        ``scipy.integrate.solve_ivp`` method; default ``"DOP853"`` (explicit, 8th order),
        ``"Radau"`` (with the exact Jacobian) for viscous scenes.

    Returns
    -------
    xarray.Dataset
        The PDE Dataset's names and units: ``r, chi, theta, psi`` and their rates,
        ``kinetic_energy``, ``stored_energy``, ``energy``, ``angular_momentum`` (whole shell:
        densities times ``2 pi r0 L``), ``delta_min``; scene parameters, solver and
        statistics in attrs (``integrator = "ring-ode/<method>"``).

        A motion that reaches a limit of the model (the PDE's: ``|psi| -> pi/2``, ``r -> 0``, ``delta -> 0``, SVK's
        compressive turning point where the PDE watches it; :attr:`RingSystem.limits`) stops there as the PDE's runs
        do: found by ``solve_ivp``'s terminal events, ``status = "limit"``, ``complete = 0``, the limit and its time in
        ``message`` and ``failure_time``, the saved times reached kept, and a ``RuntimeWarning``; a start past one
        stops at its first time.
    """
    scene = as_scene(scene) if isinstance(scene, str) else scene  # a name, as simulate takes it
    _check_arguments(scene, rtol, atol, n, method)
    if getattr(scene, "gamma", 0.0) != 0.0:
        raise ParameterError("gamma", scene.gamma, "{0} for the ring ODE", hint="twisted motions are not uniform in s")
    refuse_loads(scene, "the ring ODE of section 5")
    requested = scene.params()
    scene = resolve(scene)
    check_uniform(scene, "the ring ODE", "mol_shell.simulate runs it")
    times = parse_times(times, t_end)
    system = ring_system(scene)
    y0 = ring_initial_state(system, scene)
    method = method or ("Radau" if system.viscous else "DOP853")
    scale = np.r_[np.ones(3), np.maximum(np.abs(y0[3:]), 1e-3 * np.abs(y0[3:]).max(initial=1.0))]
    fun = _numpy_rhs(system.rhs)
    extra = {}
    if method in ("Radau", "BDF", "LSODA"):
        extra["jac"] = lambda t, y: np.array(system.jac(t, y))
    start = time.perf_counter()
    from scipy.integrate import solve_ivp

    integrator = f"ring-ode/{method}"
    limits = _numpy_rhs(system.limits)
    outside = np.flatnonzero(~(limits(times[0], y0) > 0))
    if outside.size:  # a start past a limit (SVK's turning point at R < a/sqrt(3)): stopped at t = 0, as the PDE
        t, y, nfev, njev = times[:1], y0[None], 0, 0
        stop = (int(outside[0]), float(times[0]))
    else:
        events = [_event(limits, k) for k in range(len(system.limit_names))]
        sol = solve_ivp(fun, (times[0], times[-1]), y0, method=method, t_eval=times, rtol=rtol, atol=atol * scale,
                        events=events, **extra)
        t, y, nfev, njev = sol.t, sol.y.T, int(sol.nfev), int(getattr(sol, "njev", 0))
        stop = _first_limit(sol, limits, times) if sol.status == 1 else None
    wall = time.perf_counter() - start
    if stop is not None:
        k, t_stop = stop
        message = (f"{system.limit_names[k]} at t = {t_stop:.9g} s, at every s (the ring's state is uniform): a limit "
                   f"of the model (root found by {integrator})")
        status, complete = "limit", 0
        warnings.warn(f"run incomplete: {message}; keeping {len(t)} saved times", RuntimeWarning, stacklevel=2)
    else:
        t_stop, message = float("nan"), sol.message
        status, complete = ("complete", 1) if sol.success else ("error", 0)
    attrs = {
        "integrator": integrator, "rtol": rtol, "atol": atol, "n_rhs": nfev, "n_jac": njev, "wall_time_s": wall,
        "status": status, "complete": complete, "message": message, "failure_time": t_stop,
    }
    return _ring_dataset(system, scene, t, y, attrs, n, requested)


#: ``scipy.integrate.solve_ivp``'s methods
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _check_arguments(scene, rtol, atol, n, method):
    """The arguments of :func:`simulate_ring`, each refused by name (before anything is built)."""
    if not isinstance(scene, TwistedCylinder):
        raise ParameterError.not_a("scene", getattr(scene, "name", scene), "a cylinder scene of section 5",
                                   "mol_shell.SpinningRing() (or 'spinning-ring') or mol_shell.TwistedCylinder(gamma=0)")
    lo, hi = RTOL_RANGE
    for name, value, allowed, ok in (("rtol", rtol, f"[{lo:g}, {hi:g})", lambda v: lo <= v < hi),
                                     ("atol", atol, f"[{ATOL_MIN:g}, inf)", lambda v: ATOL_MIN <= v < math.inf)):
        if not is_number(value):
            raise ParameterError.not_a(name, value, "a number", allowed)
        if not ok(value):
            raise ParameterError(name, value, allowed)
    if n is not None and (not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 2):
        raise ParameterError("n", n, "None or integers >= 2")
    if method is not None and method not in METHODS:
        raise ParameterError("method", method, Choice(METHODS), hint="scipy.integrate.solve_ivp's methods, or None")


def _event(limits, k):
    """``solve_ivp``'s terminal event of entry ``k`` of the ring's limits (``limits``: :func:`_numpy_rhs` of them)."""

    def event(t, y):
        return limits(t, y)[k]

    event.terminal, event.direction = True, -1
    return event


def _first_limit(sol, limits, times):
    """``(entry, time)`` of the first limit reached (``solve_ivp``'s ``sol`` with its terminal events); of those
    reached at once, the first in :attr:`RingSystem.limit_names`'s order. At once: a root within round-off of the
    time span of the first, or a limit within 1e-12 of 0 (of its scale, at least 1) in the state at the first root.
    ``solve_ivp`` keeps only the roots up to the first terminal one in a step, and |psi| -> pi/2 takes
    delta = r cos(psi) to 0 at the same instant: which of the two roots came first was the last bits' choice (a
    machine with other vector units said delta)."""
    reached = [(float(te[0]), k) for k, te in enumerate(sol.t_events) if len(te)]
    first, k_first = min(reached)
    tie = 1e-9 * (times[-1] - times[0])
    at_once = {k for t, k in reached if t <= first + tie}
    scale = np.maximum(1.0, np.abs(limits(sol.t[0], sol.y[:, 0])))
    at_once.update(np.flatnonzero(limits(first, sol.y_events[k_first][0]) <= 1e-12 * scale).tolist())
    return min(at_once), first


def _numpy_rhs(f):
    """``(t, y) -> f(t, y)`` as NumPy through a CasADi buffer (the ODE is called ~1e5 times): the right-hand side,
    or the limits."""
    buf, trigger = f.buffer()
    t_in, y_in, out = np.zeros(1), np.zeros(6), np.zeros(f.size1_out(0))
    buf.set_arg(0, memoryview(t_in))
    buf.set_arg(1, memoryview(y_in))
    buf.set_res(0, memoryview(out))

    def fun(t, y):
        t_in[0] = t
        y_in[:] = y
        trigger()
        return out.copy()

    fun.keep = (buf, t_in, y_in, out)
    return fun


def _ring_dataset(system, scene, t, y, attrs, n, requested=None):
    outs = system.observables.map(len(t))(y.T)
    rates, kinetic, stored, p_chi, dlt, dissipation = (np.array(o) for o in outs)
    q = {"r": y[:, 0], "chi": y[:, 1], "theta": np.zeros(len(t)), "psi": y[:, 2]}
    qt = {"r": rates[0], "chi": rates[1], "theta": np.zeros(len(t)), "psi": rates[2]}
    coords = {"time": ("time", t, {"units": "s", "long_name": "time", "standard_name": "time", "axis": "T",
                                   "comment": TIME_COMMENT})}  # as a run's (docs/netcdf.md): it had units only
    dims, expand = ("time",), (lambda a: a)
    if n is not None:
        s = np.linspace(0.0, scene.L, int(n))
        coords["s"] = ("s", s, {"units": "m", "long_name": "arc length of the reference generator"})
        dims, expand = ("time", "s"), (lambda a: np.repeat(np.asarray(a)[:, None], len(s), axis=1))
        q = {"z": None, **q}
        qt = {"z": np.zeros(len(t)), **qt}
    data = {}
    for name in q:
        units, long_name = FIELD_META[name]
        values = np.broadcast_to(s, (len(t), len(s))).copy() if name == "z" else expand(q[name])
        data[name] = (dims, values, {"units": units, "long_name": long_name})
        data[name + "_t"] = (dims, expand(qt[name]), {"units": RATE_UNITS[units], "long_name": f"rate of change of {name}"})
    A = system.area
    totals = {
        "kinetic_energy": (A * kinetic.ravel(), "J", "kinetic energy of the shell"),
        "stored_energy": (A * stored.ravel(), "J", "stored (strain) energy"),
        "energy": (A * (kinetic + stored).ravel(), "J", "total energy (kinetic + stored)"),
        "angular_momentum": (A * p_chi.ravel(), "kg m2 s-1", "angular momentum of the whole shell about the axis"),
        "delta_min": (dlt.ravel(), "m", "minimum over s of delta = r beta1 cos(psi) (must stay positive)"),
    }
    if system.viscous:
        totals["dissipation"] = (A * dissipation.ravel(), "W", "power dissipated by the Kelvin-Voigt stress")
    for name, (values, units, long_name) in totals.items():
        data[name] = (("time",), values, {"units": units, "long_name": long_name})
    meta = {
        **header(f"mol_shell reduced ODE (section 5) of scene {scene.name}", comment="time: " + TIME_COMMENT),
        "scene": scene.name,
        "rho_A": system.rho_a, "rho_I": float(system.rho_i), "rho_J": system.rho_j,
    }
    edges = resolve_edges(scene.end1, scene.end2, scene.meridian().poles)
    meta.update(scene_attrs(scene, edges, scene.zeta1_used(), requested=requested))
    meta.update(attrs)
    return xr.Dataset(variables(data), coords=coordinates(coords), attrs=with_units(meta))
