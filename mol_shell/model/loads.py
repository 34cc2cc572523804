"""External loads: pressure, gravity, an ambient viscous fluid, end forces and torques, and their time histories.

Each load is a potential or a Rayleigh function, so the variational form (Hamilton's equations with
generalised forces) keeps working (paper, section 3: the loads ``f`` and ``l`` of the balance laws):

* pressure ``p`` on the base surface, a follower load: potential ``-p V`` with ``V = pi int r^2 z_s ds``,
  the volume between the axis and the base surface, bounded by the planes of its edges (signed so that
  inflation increases it). An open meridian is closed by lids in its end planes: the term
  ``pi r^2 dz`` at an edge is the lids' axial push. Discretely ``V = pi sum_cells r_mid^2 (z_{i+1} - z_i)``;
* gravity ``g`` along ``-k``: potential ``g sum_nodes (mA z + mI d.k)`` with the nodal inertias of the
  lumped kinetic energy (``d.k = -sin(theta) cos(psi)``);
* drag ``c`` (an ambient viscous fluid): Rayleigh function ``c/2 sum_nodes A_i |r_t|^2`` with ``A_i`` the
  reference area of node ``i``'s dual cell; its power ``2 R`` is dissipated;
* end force ``F`` (along ``k``) and torque ``M`` (about ``k``) on an edge: potentials ``-F z_end`` and
  ``-M chi_end``.

A load's time history multiplies it: ``h(t)`` from :func:`history` (constant, step, ramp, sine or a table).
Functions take floats or CasADi expressions.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from mol_shell._core.errors import ParameterError

HISTORIES = ("constant", "step T0", "ramp T1", "sine F", "table t0:h0 t1:h1 ...")
#: the highest frequency of a ``sine`` history, Hz: a period of a picosecond, far beyond any shell's frequencies (and
#: 1e6 leap-frog steps of the paper's dt per period); beyond, a run only samples the sine's phase at random
MAX_FREQUENCY = 1e12
#: the shortest time of a history, s: a ramp's T1, the spacing of a table's points (1/T of the rate stays finite)
MIN_HISTORY_TIME = 1e-300
HISTORY_ALLOWED = ("'constant', 'step T0' (0 before T0 s, then 1; T0 >= 0 s), 'ramp T1' (t/T1 up to 1, T1 >= 1e-300 s), "
                   "'sine F' (sin(2 pi F t), 0 < F <= 1e12 Hz) or 'table t0:h0 t1:h1 ...' (linear between, held "
                   "beyond; times increasing, at least 1e-300 s apart, slopes finite)")


#: the fewest leap-frog steps a history's shortest time must span (a sine's period, a ramp's T, a table's interval):
#: leap-frog samples the history once a step at a fixed dt, so a sine of period 1e-6 s at dt = 1e-6 s acted as a
#: 50 Hz one (aliasing), and a drive's ramp within a step or two left the driver's work 35 % off. 10 steps a period
#: is ``omega dt = 0.63``, inside the scheme's own bound ``omega dt < 1`` on the shell's modes (Nyquist, 2 steps,
#: would let the sampled sine's phase err by 90 degrees); a drive's ramp of 10 steps keeps the balance ~2e-5
LEAPFROG_MIN_STEPS = 10


def check_leapfrog_history(name, spec, dt, rate=False):
    """Refuse a history that leap-frog's fixed step ``dt`` cannot resolve (``ParameterError`` naming ``name``, ``dt``
    and what it takes): a ``sine F`` whose period spans fewer than :data:`LEAPFROG_MIN_STEPS` steps (it aliases to a
    slower sine), and on a driven edge's rate (``rate``) a ``ramp T`` or a ``table`` interval as short (the driven
    node's acceleration, and the driver's power with it, are not resolved). A load's short ramp is a step to the
    scheme, taken as ``step`` is; a load's table with points that close returns a warning's text (it aliases if it
    oscillates), else ``None``."""
    kind, data = parse_history(name, spec, rate=rate)
    shortest = LEAPFROG_MIN_STEPS * dt * (1 - 1e-9)  # 10 * 1e-6 is 9.999999999999999e-06
    steps = f"{LEAPFROG_MIN_STEPS} leap-frog steps of dt = {dt:g} s"
    other = "a smaller dt (at most {:.3g} s), or an adaptive integrator (dop853-c, cvode-bdf)"
    if kind == "sine" and 1.0 / data[0] < shortest:
        raise ParameterError(name, spec, f"'sine F' with F <= {1.0 / shortest:.4g} Hz (a period of at least {steps})",
                             hint=f"leap-frog samples the history once a step, and a sine of period {1.0 / data[0]:.3g} "
                             f"s aliases to a slower one; {other.format(1.0 / data[0] / LEAPFROG_MIN_STEPS)}")
    if rate and kind == "ramp" and data[0] < shortest:
        raise ParameterError(name, spec, f"'ramp T' with T >= {shortest:.4g} s ({steps})", hint=f"the driven node's "
                             f"acceleration within a few steps is not resolved; {other.format(data[0] / LEAPFROG_MIN_STEPS)}")
    gap = float(np.min(np.diff(data[0]))) if kind == "table" else math.inf
    if rate and gap < shortest:
        raise ParameterError(name, spec, f"a table whose points are at least {shortest:.4g} s apart ({steps})",
                             hint=f"points {gap:.3g} s apart: the driven node's acceleration is not resolved; "
                             f"{other.format(gap / LEAPFROG_MIN_STEPS)}")
    if gap < shortest:
        return (f"{name} = {spec!r} has points {gap:.3g} s apart, closer than {steps}: leap-frog samples it once a step "
                "(a table that oscillates faster aliases to a slower one)")
    return None


#: a driven edge's rate may not jump after the start: the jump is an impulse the model does not represent
RATE_ALLOWED = ("a history without a jump after t = 0 on a driven edge's rate: 'constant', 'step 0', 'ramp T1', 'sine F' "
                "or 'table t0:h0 t1:h1 ...'")


def parse_history(name, spec, rate=False):
    """``(kind, data)`` of a history string; refuses anything else naming ``name`` and the forms allowed.

    ``rate``: the history of a driven edge's rate (``*_spin_history``, ``*_axial_speed_history``), which refuses a
    ``step T0`` at ``T0 > 0``: the jump of the prescribed rate is an impulse that the model does not represent (its
    kinetic energy would enter the balance from nowhere, and the runs stopped on a false numerical instability)."""
    parsed = _parse_history(name, spec)
    if rate and parsed[0] == "step" and parsed[1][0] > 0:
        t0 = parsed[1][0]
        t1 = t0 + max(0.05 * t0, LEAPFROG_MIN_STEPS * 1e-6)
        raise ParameterError(name, spec, RATE_ALLOWED, hint=f"the rate's jump at {t0:g} s is an impulse the model does "
                             f"not represent; for a quick start use 'ramp T' with a short T (with leap-frog, at least "
                             f"{LEAPFROG_MIN_STEPS} steps: {LEAPFROG_MIN_STEPS * 1e-6:g} s at its default dt = 1e-6 s), "
                             f"or delayed 'table {t0:g}:0 {t1:g}:1'")
    return parsed


def number_text(value):
    """A number as a history's normal form writes it: the shortest text that reads back as the same float, in plain
    or exponent notation, whichever is shorter (``0``, ``0.001``, ``1``, ``100``, ``1e+12``, ``1e-05``)."""
    value = float(value)
    plain = repr(value).removesuffix(".0")
    short = next(text for text in (f"{value:.{p}g}" for p in range(1, 18)) if float(text) == value)
    return short if len(short) < len(plain) else plain


def normal_history(name, spec, rate=False):
    """History ``spec`` checked (:func:`parse_history`) and written in one normal form: the kind in lower case, each
    number by :func:`number_text`, one space between (``"table 0:0 0.001:1"`` whether it was typed so, as
    ``"Table 0.0:0.0, 1e-3:1.0"`` or came from a scene file's inline table), so equal histories are equal strings
    (a study's cases, a run file's attrs). ``None`` stays ``None`` (constant)."""
    kind, data = parse_history(name, spec, rate=rate)
    if spec is None:
        return None
    if kind == "table":
        return "table " + " ".join(f"{number_text(t)}:{number_text(h)}" for t, h in zip(*data))
    return " ".join([kind, *map(number_text, data)])


def _parse_history(name, spec):
    if spec is None:
        return ("constant", ())
    if not isinstance(spec, str):
        raise ParameterError.not_a(name, spec, "a string", HISTORY_ALLOWED)
    words = spec.replace(",", " ").split()
    if not words:
        raise ParameterError(name, spec, HISTORY_ALLOWED)
    kind, rest, table = words[0].lower(), words[1:], None
    try:
        if kind == "constant" and not rest:
            return ("constant", ())
        if kind in ("step", "ramp", "sine") and len(rest) == 1:
            value = float(rest[0])
            ok = math.isfinite(value) and (value >= 0 if kind == "step" else value > 0)
            ok = ok and (kind != "sine" or value <= MAX_FREQUENCY) and (kind != "ramp" or value >= MIN_HISTORY_TIME)
            if ok:
                return (kind, (value,))
        if kind == "table" and len(rest) >= 2:
            pairs = [tuple(float(x) for x in item.split(":")) for item in rest]
            if all(len(p) == 2 for p in pairs):
                t = np.array([p[0] for p in pairs])
                h = np.array([p[1] for p in pairs])
                if np.all(np.isfinite(t)) and np.all(np.isfinite(h)) and np.all(np.diff(t) > 0):
                    table = ("table", (tuple(t), tuple(h)))
    except ValueError:
        pass
    if table is not None:  # its times and values numbers, the times increasing: are they far enough apart?
        _check_table_slopes(name, spec, *map(np.array, table[1]))
        return table
    raise ParameterError(name, spec, HISTORY_ALLOWED)


def _check_table_slopes(name, spec, t, h):
    """Refuse, naming ``name`` and the spacing allowed, a table whose points are closer than
    :data:`MIN_HISTORY_TIME` (as a ramp's ``T1``) or whose slope between two points overflows: the history's rate
    was not finite, and the run blamed the load (``pressure = 100.0 is outside about (-inf, 1e-300] Pa``)."""
    gaps = np.diff(t)
    with np.errstate(over="ignore", invalid="ignore"):
        slopes = np.diff(h) / gaps
    if np.min(gaps) < MIN_HISTORY_TIME:
        i = int(np.argmin(gaps))
        raise ParameterError(name, spec, HISTORY_ALLOWED, hint=f"points {gaps[i]:.3g} s apart, at t = {t[i]:.6g} s: "
                             f"a table's points are at least {MIN_HISTORY_TIME:g} s apart, as a ramp's T1")
    if not np.all(np.isfinite(slopes)):
        i = int(np.flatnonzero(~np.isfinite(slopes))[0])
        raise ParameterError(name, spec, HISTORY_ALLOWED, hint=f"from t = {t[i]:.6g} s to {t[i + 1]:.6g} s h goes "
                             f"from {h[i]:.6g} to {h[i + 1]:.6g}: a slope beyond the floats' range")


def history(parsed, t):
    """``h(t)`` of a parsed history, for a float or a CasADi ``t``."""
    kind, data = parsed
    if kind == "constant":
        return 1.0
    if kind == "step":
        return ca.if_else(t >= data[0], 1.0, 0.0) if not isinstance(t, (int, float)) else float(t >= data[0])
    if kind == "ramp":
        return ca.fmin(t / data[0], 1.0) if not isinstance(t, (int, float)) else min(t / data[0], 1.0)
    if kind == "sine":
        return ca.sin(2 * math.pi * data[0] * t) if not isinstance(t, (int, float)) else math.sin(2 * math.pi * data[0] * t)
    times, values = data
    if isinstance(t, (int, float)):
        return float(np.interp(t, times, values))
    tt = ca.fmax(ca.fmin(t, times[-1]), times[0])  # held beyond the table
    h = values[0]  # a sum of clipped ramps, one per segment (CasADi's pw_lin takes no MX time)
    for i, slope in enumerate(_slopes(times, values)):
        h = h + slope * (ca.fmin(ca.fmax(tt, times[i]), times[i + 1]) - times[i])
    return h


def _slopes(times, values):
    return [(values[i + 1] - values[i]) / (times[i + 1] - times[i]) for i in range(len(times) - 1)]


def history_rate(parsed, t):
    """``h'(t)`` (CasADi ``t``): 0 for constant and step (a step's impulse is not represented), ``1/T1`` on a
    ramp, ``2 pi F cos(2 pi F t)`` for a sine, the segment's slope in a table (0 beyond it)."""
    kind, data = parsed
    if kind in ("constant", "step"):
        return 0.0
    if kind == "ramp":
        return ca.if_else(t < data[0], 1.0 / data[0], 0.0)
    if kind == "sine":
        return 2 * math.pi * data[0] * ca.cos(2 * math.pi * data[0] * t)
    times, values = data
    rate = 0.0  # the segment's slope where t lies in it (CasADi's pw_const takes no MX time)
    for i, slope in enumerate(_slopes(times, values)):
        rate = rate + ca.if_else(ca.logic_and(t >= times[i], t < times[i + 1]), slope, 0.0)
    return rate


def cell_volume(zl, zr, rl, rr):
    """``pi r_mid^2 (z_r - z_l)``: a cell's share of the volume under the base surface (midpoint rule)."""
    r = (rl + rr) / 2
    return math.pi * r * r * (zr - zl)


def gravity_potential(q, m_a, m_i, g):
    """``g (mA z + mI d.k)`` of a node with fields ``q = (z, r, chi, theta, psi)`` (``d.k = -sin theta cos psi``)."""
    z, _, _, theta, psi = q
    out = g * m_a * z
    if not (isinstance(m_i, (int, float)) and m_i == 0):
        out = out - g * m_i * ca.sin(theta) * ca.cos(psi)
    return out


def drag_rayleigh(q, v, area, drag):
    """``drag/2 area |r_t|^2`` with ``r_t = z_t k + r_t a2 + r chi_t a3``: a node's Rayleigh function."""
    r = q[1]
    z_t, r_t, chi_t = v[0], v[1], v[2]
    return 0.5 * drag * area * (z_t * z_t + r_t * r_t + (r * chi_t) ** 2)
