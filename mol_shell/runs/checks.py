"""Values that pass every range check but leave the model's numbers meaningless: refused with the reason.

A half-thickness of 1e-300 m is inside ``(0, 0.5) m``, but the director's inertia ``rho_J ~ rho h^3``
underflows to 0 and the Jacobian of the discretised shell is no longer finite; a length of 1e-300 m
makes the differences of the right-hand side overflow. Such values are found by evaluating the
discretised system itself (state, right-hand side and Jacobian at t = 0 and their spectrum), not
by a table of thresholds, so every scene is covered. :func:`check_system` refuses them with a
:class:`~mol_shell._core.errors.ParameterError` that names the parameter responsible (the one that,
set back to its default, makes the numbers finite again) and, found by bisection, the range of
that parameter over which they are finite with the other parameters as given.
:func:`checked_equilibrium_radius` does the same for a radial equilibrium that cannot be computed
(``E = 1e308`` overflows the energy; the solver itself can only blame the twist).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import casadi as ca
import numpy as np

from mol_shell._core.errors import ParameterError, is_number, show
from mol_shell._core.ranges import Interval
from mol_shell.discretization.system import ShellSystem
from mol_shell.model.equilibrium import equilibrium_radius, spectrum_bounds
from mol_shell.model.geometry import self_intersects
from mol_shell.model.laws import ON_REDEFINED, user_material
from mol_shell.model.thickness_profile import thickness_function
from mol_shell.scenes import CylinderScene, check_radius
from mol_shell.scenes.ranges import parameter_bounds

#: nodes of the small systems used to find the responsible parameter and its threshold
PROBE_NODES = 5
#: bisection steps for a threshold between values of opposite signs (linear)
BISECTION_STEPS = 12


def problem(system, y0):
    """``None`` if the state, the right-hand side, the Jacobian and ``J f`` at ``(0, y0)`` are finite (and the
    Jacobian not zero), else what is not."""
    y0 = np.asarray(y0, dtype=float)
    if not np.all(np.isfinite(y0)):
        return "the initial state is not finite in double precision"
    with np.errstate(all="ignore"):
        f = np.asarray(system.rhs(0, y0)).ravel()
    if not np.all(np.isfinite(f)):
        return "the right-hand side at t = 0 is not finite in double precision"
    with np.errstate(all="ignore"):
        J = system.spectrum_jac(0, y0)
        values = np.asarray(J.nonzeros(), dtype=float)
    if not np.all(np.isfinite(values)):
        return "the Jacobian at t = 0 is not finite in double precision (stiffness and inertia out of its range)"
    if values.size and not np.any(values):
        return "the Jacobian at t = 0 is zero (stiffness or inertia below double precision's range)"
    with np.errstate(all="ignore"):
        accel = np.asarray(ca.mtimes(J, ca.DM(f))).ravel()  # y'' = J f: what step-size selection evaluates first
    if not np.all(np.isfinite(accel)):
        return "the second derivative y'' = J f at t = 0 is not finite in double precision (motions too fast)"
    return None


def step_problem(system, y0, omega_max):
    """``None`` if the right-hand side is still finite one stable step (``1/max|eig J(y0)|``) after t = 0, along the
    rate at t = 0, else why: a load whose rates at t = 0 are finite can still leave the numbers in one step
    (``end2_torque = 1e308``: a momentum of 1e308 on an end of inertia above 1 kg m^2 is finite, the centrifugal
    forces of its spin are not, and the run stopped at its first step where gravity = 1e308 was refused)."""
    tau = 1.0 / omega_max
    with np.errstate(all="ignore"):
        y1 = np.asarray(y0, dtype=float) + tau * np.asarray(system.rhs(0, y0), dtype=float).ravel()
        f1 = np.asarray(system.rhs(tau, y1), dtype=float).ravel()
    if np.all(np.isfinite(y1)) and np.all(np.isfinite(f1)):
        return None
    return "the right-hand side one stable step after t = 0 is not finite in double precision (the loads move the " \
        "shell too fast)"


def spectrum_problem(omega_max, damping):
    """``None`` for a usable spectrum bound, else why it is not (0, denormal or not finite)."""
    if not (math.isfinite(omega_max) and math.isfinite(damping)):
        return f"max |eig J(y0)| = {omega_max:.3g} /s is not finite in double precision"
    if not omega_max > 0 or not math.isfinite(1.0 / omega_max):
        return f"max |eig J(y0)| = {omega_max:.3g} /s: the shell's stiffness/inertia ratio underflows"
    return None


def checked_spectrum(scene, system, y0):
    """``(max |lambda|, max damping)`` of :func:`mol_shell.model.equilibrium.spectrum_bounds`; a scene whose numbers
    are not finite, or whose spectrum is not, is refused by :func:`refuse` instead."""
    found = problem(system, y0)
    if found is None:
        try:
            with np.errstate(all="ignore"):
                omega_max, damping = spectrum_bounds(system.spectrum_jac, y0, system.viscous, positions(system))
        except (np.linalg.LinAlgError, ValueError, ArithmeticError) as exc:
            found = f"the eigenvalues of the Jacobian at t = 0 cannot be computed ({type(exc).__name__})"
        else:
            found = spectrum_problem(omega_max, damping) or step_problem(system, y0, omega_max)
            if found is None:
                return omega_max, damping
    refuse(scene, system.n, found)


def positions(system):
    """Mask of the position entries of ``system``'s state (node-major: ``nf`` positions, then ``nf`` momenta per
    node), or ``None`` when the state also holds accumulators (the work and dissipation of a loaded scene)."""
    if system.n_extra:
        return None
    return np.arange(system.size) % system.ny < system.nf


def initial_state(scene, system):
    """``system.initial_state(scene)``; a state that cannot be formed in double precision (the momenta of
    fields a scene leaves out come out NaN, not 0, when masses overflow) is refused by :func:`refuse`."""
    try:
        with np.errstate(all="ignore"):
            return system.initial_state(scene)
    except ParameterError:  # a parameter refused by name on the way: not an overflow
        raise
    except (ValueError, ArithmeticError):
        refuse(scene, system.n, "the initial state is not finite in double precision (its momenta overflow)")


def check_system(scene, system, y0=None):
    """Refuse ``scene`` (see :func:`refuse`) if its discretised numbers at ``y0`` (default: its initial state)
    are not finite."""
    y0 = initial_state(scene, system) if y0 is None else y0
    found = problem(system, y0)
    if found is not None:
        refuse(scene, system.n, found)


@functools.lru_cache(maxsize=256)
def _is_bad(scene, n):
    """True if ``scene`` (with ``R`` resolved) has non-finite numbers (:func:`problem`) or spectrum on ``n`` nodes;
    None if it cannot be built (a parameter refused on the way)."""
    try:
        scene = resolve(scene)
        system = ShellSystem(scene, n)
        y0 = system.initial_state(scene)
        if problem(system, y0) is not None:
            return True
        with np.errstate(all="ignore"):
            omega_max, damping = spectrum_bounds(system.spectrum_jac, y0, system.viscous, positions(system))
        return (spectrum_problem(omega_max, damping) or step_problem(system, y0, omega_max)) is not None
    except ParameterError:
        return None
    except (np.linalg.LinAlgError, ValueError, ArithmeticError, RuntimeError):
        return True


def _changed(scene):
    """Numeric parameters of ``scene`` that differ from its class's defaults: ``{name: (value, default)}``."""
    try:
        default = type(scene)()
        resolved = resolve(default)  # parameters the code computes (R) compared with their computed default
    except (TypeError, ParameterError):
        return {}
    out = {}
    for f in dataclasses.fields(scene):
        value, base = getattr(scene, f.name), getattr(default, f.name)
        base = getattr(resolved, f.name) if base is None else base
        if is_number(value) and is_number(base) and value != base:
            out[f.name] = (float(value), float(base))
    return out


def _changed_texts(scene):
    """Text parameters of ``scene`` (a file of points, a profile) that differ from its class's defaults:
    ``{name: (value, default)}``; edges and histories, which scale no number, left out."""
    try:
        default = type(scene)()
    except (TypeError, ParameterError):
        return {}
    out = {}
    for f in dataclasses.fields(scene):
        value, base = getattr(scene, f.name), getattr(default, f.name)
        if (isinstance(value, str) and isinstance(base, str) and value != base and not f.name.endswith("_history")
                and f.name not in ("end1", "end2")):
            out[f.name] = (value, base)
    return out


def _bad_numbers(scene):
    return _is_bad(scene, PROBE_NODES)


def responsible(scene, bad=_bad_numbers):
    """Parameters that, each set back to its default, make ``bad(scene)`` false (the numbers finite) again."""
    names = []
    for name, (_, base) in _changed(scene).items():
        try:
            candidate = dataclasses.replace(scene, **{name: base})
        except ParameterError:
            continue
        if bad(candidate) is False:
            names.append(name)
    return names


def threshold(scene, name, bad=_bad_numbers, decades=0.5):
    """The value of ``name`` closest to the given one for which the numbers are still finite: bisection towards
    the default (geometric between values of one sign, to ``decades``; linear otherwise, 12 halvings)."""
    given, good = _changed(scene)[name]
    if good == 0 and given != 0:  # a default of 0 (spin, twist, viscosity): search the magnitudes of the value's sign
        good = math.copysign(1e-300, given)
    geometric = given != 0 and good != 0 and (given > 0) == (good > 0)

    def at(t):
        if geometric:
            return math.copysign(math.exp((1 - t) * math.log(abs(given)) + t * math.log(abs(good))), good)
        return (1 - t) * given + t * good

    span = abs(math.log10(abs(given)) - math.log10(abs(good))) if geometric else 0.0
    steps = max(1, math.ceil(math.log2(span / decades))) if geometric and span > decades else BISECTION_STEPS
    lo, hi = 0.0, 1.0  # at(lo) bad, at(hi) good
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        try:
            candidate = dataclasses.replace(scene, **{name: at(mid)})
        except ParameterError:
            lo = mid
            continue
        if bad(candidate) is False:
            hi = mid
        else:
            lo = mid
    return at(hi)


def refuse(scene, n, reason):
    """Raise the :class:`ParameterError` for a scene whose numbers are not finite, naming who and the range."""
    name, value, allowed, hint, message = _refusal(scene, reason)
    raise ParameterError(name, value, allowed, hint, message=message)


@functools.lru_cache(maxsize=64)
def _refusal(scene, reason, bad=_bad_numbers):
    """``(name, value, allowed, hint, message)`` of the refusal (cached: the bisection costs a second or two)."""
    error = _diagnose(scene, reason, bad)
    return error.name, error.value, error.range or error.allowed, "", str(error)


def profile_scaled(text, factor):
    """``h_profile`` text for ``factor`` times the profile ``text``: a table's values scaled, an expression multiplied."""
    words = text.split()
    if words and words[0] == "table":
        pairs = [w.split(":") for w in words[1:]]
        return "table " + " ".join(f"{a}:{factor * float(b):.12g}" for a, b in pairs)  # as typed: 0.003, not
    return f"{factor:.12g} * ({text})"  # 0.0030000000000000005


def _profile_diagnosis(scene, reason, bad, decades=0.5):
    """The refusal naming ``h_profile`` when the graded wall alone leaves the numbers non-finite (a uniform wall of
    the nominal ``h`` has finite ones), else ``None``. Its range, found by bisection of a factor scaling the whole
    profile (geometric, to ``decades``) towards a profile whose extreme value is the nominal ``h``: the least (or the
    greatest) ``h(s)`` with which the numbers stay finite, the other parameters as given."""
    text = getattr(scene, "h_profile", "")
    if not (isinstance(text, str) and text) or bad(dataclasses.replace(scene, h_profile="")) is not False:
        return None
    values = thickness_function(text, scene.meridian().length)(np.linspace(0.0, scene.meridian().length, 1001))
    low, high = float(np.min(values)), float(np.max(values))
    if not low > 0:
        return None
    # in decades: the factor towards the nominal h overflows for a profile of subnormal values (h_profile = 1e-320
    # then blamed R), so the profile is scaled by powers of 10 applied in steps of at most 1e300

    def at(decades_up):
        steps = max(1, math.ceil(abs(decades_up) / 300))
        scaled = text
        for _ in range(steps):
            scaled = profile_scaled(scaled, 10.0 ** (decades_up / steps))
        return scaled

    def bad_at(decades_up):
        try:
            return bad(dataclasses.replace(scene, h_profile=at(decades_up))) is not False
        except (ParameterError, ValueError, ArithmeticError):
            return True

    towards = (math.log10(scene.h) - math.log10(low), math.log10(scene.h) - math.log10(high))
    good = next((d for d in towards if math.isfinite(d) and not bad_at(d)), None)
    if good is None:
        return None
    lo, hi = 0.0, 1.0  # the fraction t of good's decades: bad at lo, good at hi
    for _ in range(max(1, math.ceil(math.log2(abs(good) / decades))) if abs(good) > decades else 1):
        mid = 0.5 * (lo + hi)
        if bad_at(good * mid):
            lo = mid
        else:
            hi = mid
    edge = good * hi  # decades
    if edge > 0:  # too thin: the least h(s) must grow
        least = 10.0 ** (math.log10(low) + edge)
        allowed = Interval(least, math.inf, low_closed=True, unit="m",
                           shown=f"profiles whose least h(s) is within about [{least:.4g}, inf) m")
    else:
        greatest = 10.0 ** (math.log10(high) + edge)
        allowed = Interval(0.0, greatest, high_closed=True, unit="m",
                           shown=f"profiles whose greatest h(s) is within about (0, {greatest:.4g}] m")
    return ParameterError("h_profile", text, allowed, hint=f"h(s) in [{low:.4g}, {high:.4g}] m, with the other "
                          f"parameters as given: beyond it {reason}")


def _diagnose(scene, reason, bad=_bad_numbers, exclude=()):
    if "h_profile" not in exclude:
        graded = _profile_diagnosis(scene, reason, bad)
        if graded is not None:
            return graded
    if "material" not in exclude and user_material(getattr(scene, "material", "svk")) is not None:
        try:  # a law of one's own: the same scene with a built-in law of its small-strain stiffness
            builtin = dataclasses.replace(scene, material="svk-plane-stress", material_parameters="")
        except ParameterError:
            builtin = None
        if builtin is not None and bad(builtin) is False:
            return ParameterError("material", scene.material, "a law whose energy and forces are finite at the "
                                  "scene's state", hint=f"with material = svk-plane-stress the numbers are finite; "
                                  f"with {scene.material} {reason}")
    if "layers" not in exclude and str(getattr(scene, "layers", "") or "").strip():
        try:  # a layered wall: the same scene with one wall of its own law
            single = dataclasses.replace(scene, layers="")
        except ParameterError:
            single = None
        if single is not None and bad(single) is False:
            return ParameterError("layers", scene.layers, "layers whose numbers are finite in double precision",
                                  hint=f"with one wall of the scene's law they are; with these layers {reason}")
    names = [k for k in responsible(scene, bad) if k not in exclude]
    if len(names) == 1:
        name = names[0]
        value = getattr(scene, name)
        edge = threshold(scene, name, bad)
        declared = parameter_bounds(scene, name) or Interval(-math.inf, math.inf)  # both ends: h = 1e-300 was
        allowed = declared.with_high(edge) if edge < value else declared.with_low(edge)  # told [2e-104, inf) m,
        words = declared.shown.partition(", and ")[2]  # h = 0.6 (0, 0.5) m; a wall's words kept
        return ParameterError(name, value, dataclasses.replace(allowed, shown=f"about {allowed.text()}"
                                                               + (f", and {words}" if words else "")),
                              hint=f"with the other parameters as given: beyond it {reason}")
    if exclude:
        return None
    changed = _changed(scene)
    names = names or sorted(changed, key=lambda k: -abs(math.log10(abs(changed[k][0]) + 1e-300)
                                                         - math.log10(abs(changed[k][1]) + 1e-300)))
    if not names:  # no number changed: a text parameter (a file of points, a profile) that, set back, is fine
        for name, (value, base) in _changed_texts(scene).items():
            try:
                fine = bad(dataclasses.replace(scene, **{name: base})) is False
            except ParameterError:
                fine = False
            if fine:
                return ParameterError.invalid(name, value, f"leaves the model's numbers outside double precision: "
                                              f"{reason}", "values whose discretised numbers are finite in double "
                                              "precision", hint=f"they are with {name} = {show(base)}, the default")
        given = ", ".join(f"{k} = {show(v)}" for k, (v, _) in _changed_texts(scene).items()) or "the defaults"
        return ParameterError.invalid("scene", getattr(scene, "name", type(scene).__name__), f"with {given} leaves "
                                      f"the model's numbers outside double precision: {reason}",
                                      "parameters whose discretised numbers are finite in double precision")
    listed = ", ".join(f"{k} = {show(getattr(scene, k))}" for k in names)
    return ParameterError(names[0], getattr(scene, names[0]), "values for which the model's numbers are finite",
                          message=f"{listed} together leave the model's numbers outside double precision ({reason}); "
                          "allowed: values closer to the defaults")


@functools.lru_cache(maxsize=256)
def _no_equilibrium(scene):
    try:
        with np.errstate(all="ignore"):
            R = equilibrium_radius(scene)
        return not math.isfinite(R)
    except (ParameterError, ArithmeticError, ValueError, RuntimeError):
        return True


def checked_equilibrium_radius(scene):
    """:func:`mol_shell.model.equilibrium.equilibrium_radius`, but a failure caused by another parameter than the one the
    solver names (``E = 1e308`` overflows the energy, and the solver can only blame the twist) names that
    parameter and the range over which the equilibrium can be computed."""
    try:
        with np.errstate(all="ignore"):
            return equilibrium_radius(scene)
    except ParameterError as exc:
        if exc.name == "pressure":  # the solver's own bound: past the least pressure the wall holds at any radius
            raise
        error = _diagnose(scene, "the radial equilibrium cannot be computed in double precision", _no_equilibrium,
                          exclude=(exc.name,))
        if error is None:
            raise
        raise error from None


def check_start_inside_limits(scene, requested, system, y0, how):
    """A starting state the code computed (``R`` left to the code, or the static equilibrium under the loads) must lie
    inside the model's limits (:meth:`~mol_shell.discretization.limits.ModelLimits.limits`): a 1 m sphere under
    -1e9 Pa has a Newton equilibrium at R = 0.4 mm, thinner than its wall and far past SVK's turning point, which is
    no state of the model. Refused naming the load (or what the radius was computed from) and the limit reached;
    a state the user gave is left to the run, which stops at its first step with time and place."""
    computed = (isinstance(scene, CylinderScene) and requested.get("R") in (None, "auto")) or str(how).startswith(
        "static equilibrium")
    if not computed:
        return
    g = np.array(system.limits(y0)).ravel()
    bad = np.flatnonzero(~(g > 0))
    fields = system.unpack(np.asarray(y0, dtype=float))
    crossed = self_intersects(np.column_stack([fields[1], fields[0]]))  # the meridian (r, z) through the nodes
    if not bad.size and not crossed:
        return
    # inside every pointwise limit, a meridian that crosses itself is still no shell (a sphere under external
    # pressure far past buckling: Newton's state had its poles swapped, reported as R = 0.46 m)
    what, where = system.limit_names()[int(bad[0])] if bad.size else ("its meridian crosses itself", "")
    loads = scene.loads_on()
    name = loads[0] if loads else next((k for k in _changed(scene) if k != "R"), "R")
    others = " with the other parameters as given" if len(loads) > 1 or not loads else ""
    static = str(how).startswith("static equilibrium")
    state = "the static equilibrium computed at t = 0" if static else f"the equilibrium radius R = {scene.R:.4g} m"
    raise ParameterError(name, getattr(scene, name), f"values whose equilibrium at t = 0 lies inside the model's "
                         f"limits{others}", hint=f"{state} is past one: {what}" + (f" at {where}" if where else ""))


def resolve(scene):
    """The scene with ``R`` computed when it was left to the code."""
    if isinstance(scene, CylinderScene) and scene.R is None:
        R = checked_equilibrium_radius(scene)
        try:
            check_radius(R, scene.h, scene.zeta1, hint="the computed equilibrium radius; set R", a=scene.a)
        except ParameterError as exc:  # a parameter the user set made it so (a twist far too large): named
            name = next((k for k in _changed(scene) if k != "R"), None)
            if name is None:
                raise
            others = " with the other parameters as given" if len(_changed(scene)) > 1 else ""
            raise ParameterError(name, getattr(scene, name), "values whose equilibrium radius (R = auto) keeps the "
                                 f"wall off the axis{others}", hint=f"{exc}") from None
        return dataclasses.replace(scene, R=R)
    return scene


# a mol_shell.Material's name given to another law: check afresh (the refusals are keyed by scenes)
ON_REDEFINED.extend([_is_bad.cache_clear, _refusal.cache_clear, _no_equilibrium.cache_clear])
