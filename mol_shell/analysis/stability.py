"""Stability report: where each integrator stays stable on stiff and extreme cases, and what it costs.

For each case: the spectrum of the exact Jacobian at the initial state (largest
``|lambda|``, fastest damping rate, stiffness ratio), the leap-frog step bound it
predicts (``1 / max |lambda|``), the largest stable leap-frog step found by
bisection, and runs of the other integrators (steps, failures, wall time,
whether they finish, energy error). ``mol-shell stability SCENE`` runs it.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import xarray as xr

from mol_shell._core.constants import DENSE_MAX_STATES
from mol_shell._core.errors import ModelLimitError, ParameterError, by_interrupt
from mol_shell.integrators import INTEGRATORS, Leapfrog
from mol_shell.model.equilibrium import spectrum_bounds
from mol_shell.model.laws import COMPRESSIBLE
from mol_shell.model.layers import parse_layers
from mol_shell.model.material import MATERIALS as SVK_MATERIALS
from mol_shell.results.cf import header
from mol_shell.results.dataset import scene_attrs, with_units
from mol_shell.runs.checks import profile_scaled
from mol_shell.runs.leapfrog_guard import LEAPFROG_MAX_LOG_GROWTH
from mol_shell.runs.simulate import build, resolve, simulate, starting_state
from mol_shell.scenes import Cone, Sphere, Torus, TwistedCylinder


@dataclasses.dataclass(frozen=True)
class Case:
    """One row of the report: a labelled scene on ``n`` nodes, run to ``t_end``; with ``skip``, a case that does not
    apply to the base scene (``skip`` says why): a row of the table with that reason, nothing run."""

    label: str
    scene: object
    n: int = 40
    t_end: float = 0.01
    skip: str = ""


#: saved times per run (the energy balance of viscous runs is integrated on them)
SAVED = 100
#: the grid cases of the full report and of ``quick``
FULL_SIZES, QUICK_SIZES = (160, 640, 2560, 10240), (160, 640)


def shell_cases():
    """Shells that are not cylinders: a closed sphere (cells next to the poles are short in the hoop
    direction), a thin cone and a torus segment, each breathing or twisting a little."""
    return [Case("sphere, closed (R = 1.01a, gamma = 0.05)", Sphere(R=1.01, gamma=0.05)),
            Case("cone h=0.001 (gamma = 0.1)", Cone(h=1e-3, gamma=0.1)),
            Case("torus (dilation 1.01, gamma = 0.1)", Torus(dilation=1.01, gamma=0.1))]


def default_cases(base=None, quick=False):
    """The issue's set: paper scene, viscosity, near-incompressibility, thin shells, large twist, spin, fine grids,
    and the shells of :func:`shell_cases`. Variations a base scene has no parameter for are left out; a variation
    that does not apply to the base scene as it is (:func:`thickness_case`, :func:`law_case`) is kept as a row
    that says why (``Case.skip``), never as a relabelled copy of the base scene."""
    base = base or TwistedCylinder()
    names = {f.name for f in dataclasses.fields(base)}

    def rep(scene, **changes):
        return dataclasses.replace(scene, **changes) if set(changes) <= names else None

    cases = [Case("paper" if base == TwistedCylinder() else base.name, base)]
    cases += [Case(f"viscous eta_mu={eta:g}", rep(base, eta_mu=eta, eta_lambda=2 * eta)) for eta in (0.01, 1.0, 100.0)]
    cases += [law_case(base, f"nu={nu:g}", nu=nu) for nu in (0.3, 0.49, 0.499, 0.4999)]
    cases += [law_case(base, f"nu={nu:g} plane-stress", nu=nu, material="svk-plane-stress") for nu in (0.499, 0.4999)]
    cases += [thickness_case(base, h) for h in (1e-2, 1e-3, 1e-4)]
    cases += [Case(f"gamma={g:g}", rep(base, gamma=g)) for g in (0.5, 1.5, 3.0)]
    cases += [Case("psi0=1.5 (delta0 = 0.07)", rep(base, psi0=1.5))]  # sheared to near the fold delta = 0
    cases += [Case(f"omega={w:g}", rep(base, omega=w)) for w in (50.0, 200.0)]
    sizes = QUICK_SIZES if quick else FULL_SIZES
    cases += [Case(f"n={n}", base, n=n, t_end=0.002) for n in sizes]
    cases += shell_cases()
    return [case for case in cases if case.scene is not None or case.skip]


def thickness_case(base, h):
    """The case of half-thickness ``h``: the wall made ``k = h / base.h`` times as thick, as a whole.

    A uniform wall takes ``h``; a graded wall (``h_profile``) keeps its grading, its ``h(s)`` times ``k``; a layered
    one keeps its layers' shares, each thickness times ``k``; a ``zeta1`` set keeps its place in the wall (times
    ``k``). A wall so scaled that the scene refuses (a thicker graded wall reaching the axis) is a skipped case
    naming the scene's reason."""
    label, k = f"h={h:g}", h / base.h
    changes, scaled = {"h": h}, []
    if base.h_profile:
        changes["h_profile"], scaled = profile_scaled(base.h_profile, k), scaled + ["h_profile"]
    if base.layers:
        changes["layers"] = "; ".join(" ".join([f"{t * k:.12g}", material, *(f"{key}={value}" for key, value in
                                                                            keys.items())])
                                      for t, material, keys in parse_layers(base.layers))
        scaled.append("layers")
    if base.zeta1 is not None:
        changes["zeta1"], scaled = base.zeta1 * k, scaled + ["zeta1"]
    if scaled and k != 1:
        label += f" ({', '.join(scaled)} x {k:.3g})"
    try:
        return Case(label, dataclasses.replace(base, **changes))
    except ParameterError as exc:
        return Case(label, None, skip=f"the wall {k:.3g} times as thick is refused: {exc}")


def law_case(base, label, **changes):
    """A change of ``nu`` (and of the law, ``material``) where it means something: skipped, with the reason, where
    no law of the wall reads ``nu`` (incompressible laws, laws of one's own, layers that set their own ``nu``) or
    where a layered wall's layers name their own laws. A law swapped for a law of one's own drops that law's
    ``material_parameters`` (they are its parameters, not the new law's)."""
    if base.layers:
        layers = parse_layers(base.layers)
        if "material" in changes:
            return Case(label, None, skip="a layered wall: each layer names its own law (layers)")
        if not any(_reads_nu(material) and "nu" not in keys for _, material, keys in layers):
            return Case(label, None, skip="no layer's law reads the wall's nu (each is incompressible or sets its own)")
    elif not _reads_nu(changes.get("material", base.material)):
        return Case(label, None, skip=f"material = {base.material} does not read nu")
    elif changes.get("material") == base.material:
        return Case(label, None, skip=f"the wall's law is {base.material} already: the row nu={changes['nu']:g}")
    if "material" in changes and base.material_parameters:
        changes["material_parameters"] = ""
    return Case(label, dataclasses.replace(base, **changes))


def _reads_nu(material):
    """Whether the law ``material`` reads the scene's ``nu`` (the SVK laws and the compressible neo-Hookeans)."""
    return material in SVK_MATERIALS or material in COMPRESSIBLE


def stable_leapfrog_step(system, compiled, y0, bound, damping=0.0, steps=3000, iterations=8, min_steps=100):
    """Largest stable leap-frog step by bisection in ``[bound/2, 2 bound]``; returns ``(dt, horizon)``
    (:func:`leapfrog_step_search` without its note)."""
    return leapfrog_step_search(system, compiled, y0, bound, damping, steps, iterations, min_steps)[:2]


def leapfrog_step_search(system, compiled, y0, bound, damping=0.0, steps=3000, iterations=8, min_steps=100):
    """Largest stable leap-frog step by bisection in ``[bound/2, 2 bound]``; returns ``(dt, horizon, note)``.

    A step counts as stable when its run reaches ``horizon`` (status ``complete``). The horizon is
    ``steps`` steps of ``bound/2``, cut to where the step is what is being judged:

    * with damping, to where leap-frog's parasitic root has grown by ``exp(LEAPFROG_MAX_LOG_GROWTH)``
      at small steps (near the bound it grows faster, by ``1/sqrt(1 - (w dt)^2)``: that is part of
      what the bisection measures);
    * when a run at ``bound/10`` fails too (the shell itself folds or collapses, as at large twist),
      to 0.9 of its failure time. Within that horizon a run that ends early, by energy growth or at a
      limit, does so because of its step: an unstable step can cross ``delta = 0`` before the
      energy check sees it grow.

    ``dt`` is a step found stable below one found unstable, else ``nan`` with ``note`` saying why (``""`` when
    measured): ``bound/2`` is unstable on the horizon; the horizon is shorter than ``min_steps`` steps of ``2 bound``
    (damping or a fold cuts it: leap-frog's growth at ``omega dt = 2``, 3.73 per step, is not judged in a few steps);
    or ``2 bound`` ran stable, so the top of the bracket never tested unstable (leap-frog is unstable past
    ``omega dt = 1``: the run did not excite the fastest mode enough for its growth to show).
    """

    def run(dt, horizon):
        end = math.ceil(horizon / dt) * dt  # on the step grid
        result = Leapfrog(dt=dt, chunk=100).integrate(system, compiled, y0, np.array([0.0, end]))
        if result.status == "interrupted":  # Ctrl-C, kept by the integrator as the run's end: not an unstable step
            raise KeyboardInterrupt
        return result

    def stable(dt):
        return run(dt, horizon).status == "complete"

    def too_short(why):
        return f"n/a: {why} in {horizon / hi:.3g} steps of 2 bound (< {min_steps})"

    nan = float("nan")
    horizon = steps * 0.5 * bound
    lo, hi = 0.5 * bound, 2.0 * bound
    if damping > 0 and LEAPFROG_MAX_LOG_GROWTH / damping < horizon:
        horizon = LEAPFROG_MAX_LOG_GROWTH / damping
        if horizon < min_steps * hi:  # the damping's cut: no run can tell a stable step from an unstable one
            return nan, horizon, too_short("damped 1e6-fold")
    if not stable(lo):
        small = run(0.1 * bound, horizon)
        if small.status == "complete":
            return nan, horizon, "< bound/2"
        horizon = 0.9 * small.failure_time  # the physics ends the run, whatever the step
        if horizon == 0:
            return nan, horizon, "n/a: stopped at t = 0"
        if horizon < min_steps * hi:
            return nan, horizon, too_short("folds")
        if not stable(lo):
            return nan, horizon, "< bound/2"
    if stable(hi):
        return nan, horizon, "n/a: 2 bound ran stable (the top never tested unstable)"
    for _ in range(iterations):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo, horizon, ""


def run_case(case, integrators=("cvode-bdf", "ida"), bisect=True, rtol=1e-6, atol=1e-9):
    """Measure one case; returns a dict of numbers (NaN where not applicable)."""
    try:
        scene = resolve(case.scene)
        system, compiled = build(scene, case.n)
        y0, _ = starting_state(scene, system, case.n, asked=case.scene)  # where its runs start (R = auto: the statics)
    except (ParameterError, ModelLimitError) as exc:
        raise NoStart(exc) from None
    jac = np.array(system.jac(0, y0)) if system.size <= DENSE_MAX_STATES else None
    omega_max, damping = spectrum_bounds(system.jac, y0, system.viscous)
    row = {"label": case.label, "n": case.n, "t_end": case.t_end, "omega_max": omega_max, "damping_max": damping,
           "case_status": "measured", "case_note": ""}
    # the scene's parameters as its runs used them, as a run or compare file has them (report keeps the base case's)
    row[SCENE] = with_units(scene_attrs(scene, system.edges, system.thickness.zeta1, system.unpack(y0)[:2],
                                        system.reference[:2], requested=case.scene.params()))
    if jac is not None:
        mags = np.abs(np.linalg.eigvals(jac))
        # the rigid rotation chi -> chi + c is a double zero eigenvalue (a Jordan block), which
        # round-off splits into a pair of size ~sqrt(eps) max|lambda|: exclude it
        floor = 1e-6 * mags.max()
        row["stiffness_ratio"] = float(mags.max() / mags[mags > floor].min())
    else:
        row["stiffness_ratio"] = float("nan")
    bound = 1.0 / omega_max
    row["leapfrog_dt_bound"] = bound
    row["leapfrog_dt_stable"], row["bisection_horizon_s"], row["leapfrog_dt_note"] = (
        leapfrog_step_search(system, compiled, y0, bound, damping) if bisect else (float("nan"), float("nan"), ""))
    for name in ("leapfrog", *integrators):
        if name not in INTEGRATORS:
            continue
        key = name.replace("-", "_")
        options = {"dt": _leapfrog_step(case, 0.5 * bound)} if name == "leapfrog" else {"rtol": rtol, "atol": atol}
        try:
            ds = simulate(scene, name, n=case.n, times=_times(case, options), progress=False, **options)
            if ds.attrs["status"] == "interrupted":  # Ctrl-C: the report stops here, not after the other integrators
                raise KeyboardInterrupt
            row[f"{key}_status"] = ds.attrs["status"]
            row[f"{key}_steps"] = int(ds.attrs["n_steps"]) if "n_steps" in ds.attrs else float("nan")
            row[f"{key}_failures"] = ds.attrs.get("n_failed_steps", float("nan"))
            row[f"{key}_wall_s"] = ds.attrs["wall_time_s"]
            # one saved state (a run stopped at its start) has no energy error to show, not an error of 0
            row[f"{key}_energy_error"] = _energy_error(ds) if ds.sizes["time"] > 1 else float("nan")
            if ds.attrs["status"] != "complete":
                row[f"{key}_message"] = str(ds.attrs.get("message", ""))
        except (ParameterError, ModelLimitError) as exc:  # nothing ran: no steps, wall time or error to show
            row[f"{key}_status"] = "refused"
            row[f"{key}_message"] = str(exc)
    return row


class NoStart(ParameterError):
    """A case's scene refused, or without a starting state (:func:`run_case`): a row ``not run``, not the report's
    end (the base scene's is the input's error)."""

    def __init__(self, cause):
        super().__init__("case", None, "", message=str(cause))
        self.cause = cause


def _not_run(case, status, why, integrators=("cvode-bdf", "ida"), **_):
    """The row of a case that did not run: ``status`` in the column of each integrator :func:`run_case` would have
    run, ``why`` in ``case_note``."""
    names = [name.replace("-", "_") for name in ("leapfrog", *integrators) if name in INTEGRATORS]
    return {"label": case.label, "n": case.n, "t_end": case.t_end, "case_status": status, "case_note": why,
            **{f"{name}_status": status for name in names}}


def _energy_error(ds):
    """The run's energy-work balance error where it accounts loads (relative to the energy exchanged:
    a loaded shell starting at rest has ``E(0) = 0``, and the error relative to it read 1e25-1e29); else the
    drift of the energy (plus what the saved dissipation rate removed) relative to ``E(0)``."""
    balance = ds.attrs.get("energy_balance_error")
    if isinstance(balance, (float, np.floating)):
        return float(balance)
    if _at_rest(ds):  # E(0) is round-off (1e-26 J for the unloaded sphere): its "error" read 250, noise over noise
        return float("nan")
    e = ds.energy.values + _dissipated(ds)
    return float(np.abs(e - e[0]).max() / abs(e[0])) if e[0] else float("nan")


#: a run whose positions move less than this share of the shell's size, and whose angles less than this many
#: radians, stays at rest: its energy is round-off, and an error relative to it means nothing (the table leaves it
#: empty, NaN in the file)
AT_REST = 1e-10


def _at_rest(ds):
    """Whether the run never left its starting state (to :data:`AT_REST`): an unloaded shell at its natural state."""
    size = max(float(np.abs(ds[name].values).max()) for name in ("z", "r"))
    moved = max(float(np.abs(ds[name].values - ds[name].values[:1]).max()) / (size if name in ("z", "r") else 1.0)
                for name in ("z", "r", "chi", "theta", "psi") if name in ds)
    return moved < AT_REST


def _times(case, options, saved=SAVED):
    """``saved + 1`` times to ``t_end``: the dissipated energy is integrated on them."""
    return np.linspace(0.0, case.t_end, saved + 1)


def _leapfrog_step(case, dt_max, saved=SAVED):
    """The largest step <= ``dt_max`` that puts every saved time on the step grid."""
    return case.t_end / (saved * math.ceil(case.t_end / (saved * dt_max)))


def _dissipated(ds):
    """Energy dissipated up to each saved time (trapezoid on the saved times); 0 for elastic shells."""
    if "dissipation" not in ds:
        return np.zeros(ds.sizes["time"])
    p, t = ds.dissipation.values, ds.time.values
    return np.concatenate([[0.0], np.cumsum(np.diff(t) * 0.5 * (p[1:] + p[:-1]))])


#: the key of a row of :func:`run_case` that holds the case scene's parameters as used (attributes, not a variable)
SCENE = "_scene_attrs"


def report(cases, **kwargs):
    """Run every case; one Dataset with a ``case`` dimension (strings for statuses). Ctrl-C stops it with the cases
    finished so far (``attrs["status"] = "interrupted"``, the message naming the cases not run).

    A case that cannot run is a row that says why (``case_status``, ``case_note``; each integrator's status the
    same): ``not applicable`` (``Case.skip``) or ``not run`` (its scene refused, or no starting state, as a
    twisted pressurised sphere without a static equilibrium: the error's one line). The first case is the base
    scene as given: its error is the input's and is raised (``mol-shell run`` would refuse it alike); the file's
    global attributes are those of every mol_shell file (``Conventions``, ``mol_shell_version``, ``history``, ...)
    and the base scene's parameters as its case used them, as a run or compare file has them."""
    rows, cases, interrupted = [], list(cases), ""
    try:
        for number, case in enumerate(cases):
            start = time.perf_counter()
            try:
                row = _not_run(case, "not applicable", case.skip, **kwargs) if case.skip else run_case(case, **kwargs)
            except NoStart as exc:
                if number == 0:  # the base scene as given: the input's error, as mol-shell run says it
                    raise exc.cause from None
                row = _not_run(case, "not run", f"the case's scene could not start: {exc}", **kwargs)
            if any(v == "interrupted" for k, v in row.items() if k.endswith("_status")):  # a run kept it as data
                raise KeyboardInterrupt
            rows.append(row)
            done = "done" if row["case_status"] == "measured" else row["case_status"]
            print(f"{case.label:28s} {done} in {time.perf_counter() - start:6.1f} s", flush=True)
    except BaseException as exc:  # a Ctrl-C, or an error of a C call that wraps one (by_interrupt)
        if not by_interrupt(exc) or not rows:
            raise
        left = [case.label for case in cases[len(rows):]]
        interrupted = (f"interrupted by the user at case {left[0]!r}: the {len(rows)} case{'s' * (len(rows) != 1)} "
                       f"before it measured, {len(left)} not run")
    used = [row.pop(SCENE, None) for row in rows]  # attributes, not variables: the base case's (the first) kept
    keys = sorted({k for row in rows for k in row if k != "label"})
    data = {}
    for key in keys:
        values = [row.get(key, float("nan")) for row in rows]
        if any(isinstance(v, str) for v in values):
            values = [str(v) if not isinstance(v, float) or not math.isnan(v) else "" for v in values]
        data[key] = ("case", values, _meta(key))
    ds = xr.Dataset(data, coords={"case": ("case", [row["label"] for row in rows], {"long_name": "case"})})
    base = cases[0].scene  # the scene as given (a case of one's own that did not run: its parameters as asked)
    name = getattr(base, "name", "")
    ds.attrs.update(header(f"stability report of mol_shell integrators, base scene {name}"), scene=name,
                    base_case=cases[0].label)
    ds.attrs.update(used[0] if used and used[0] else with_units(base.params() if base is not None else {}))
    ds.attrs["bisected"] = int(kwargs.get("bisect", True))
    ds.attrs["cases_not_measured"] = sum(row["case_status"] != "measured" for row in rows)
    ds.attrs.update({"status": "interrupted" if interrupted else "complete", "message": interrupted})
    return ds


#: units and long names of the report's variables: the spectrum's, then each integrator's (``NAME_...``)
META = {
    "n": ("1", "nodes"), "t_end": ("s", "end time of the case's runs"),
    "omega_max": ("s-1", "largest |eigenvalue| of the Jacobian at t = 0"),
    "damping_max": ("s-1", "fastest damping rate at t = 0, max(-Re eigenvalue)"),
    "stiffness_ratio": ("1", "largest over smallest nonzero |eigenvalue| (the rigid rotation excluded)"),
    "leapfrog_dt_bound": ("s", "leap-frog's step bound 1 / max |eigenvalue|"),
    "leapfrog_dt_stable": ("s", "largest leap-frog step found stable by bisection"),
    "bisection_horizon_s": ("s", "time over which the bisection's runs were checked"),
    "leapfrog_dt_note": (None, "why the bisection found no stable step (empty where it found one)"),
    "case_status": (None, "measured, not applicable (the variation does not apply to the base scene) or not run"),
    "case_note": (None, "why a case was not measured"),
}
SUFFIXES = {
    "_status": (None, "how the {} run ended"), "_message": (None, "what the {} run said where it did not complete"),
    "_steps": ("1", "{} steps"), "_failures": ("1", "{} failed steps"),
    "_wall_s": ("s", "{} wall time"),
    "_energy_error": ("1", ("{} energy error: the energy-work balance's relative to the energy exchanged where loads "
                           "act, else the drift of the energy plus what viscosity dissipated, relative to E(0); NaN "
                           "for a shell that stays at rest (its energy is round-off)")),
}


def _meta(key):
    """``{units, long_name}`` of a report variable."""
    units, long_name = META.get(key, (None, key))
    for suffix, (u, text) in SUFFIXES.items():
        if key.endswith(suffix):
            units, long_name = u, text.format(key[: -len(suffix)].replace("_", "-"))
    return {"long_name": long_name} if units is None else {"units": units, "long_name": long_name}


def stopped_at_start(ds, i):
    """The stable-step cell of case ``i`` whose bisection had nothing to judge because its runs stop at t = 0 (a start
    past SVK's compressive turning point: a law limit, not a fold): the reason its runs' messages give."""
    for key in ds.data_vars:
        message = str(ds[key].values[i]) if key.endswith("_message") else ""
        if "at t = 0 s" in message:
            what = ("a limit of the law" if "a limit of the law" in message else
                    "a limit of the model" if "a limit of the model" in message else
                    f"status {ds[key[: -len('_message')] + '_status'].values[i]}")
            return f"n/a: stopped at t = 0 by {what}"
    return "n/a: stopped at t = 0"


def markdown_table(ds, integrators=("leapfrog", "cvode_bdf", "ida"), spectrum=True):
    """The report as a markdown table (columns that exist): the spectrum and each integrator's run."""
    cols = [("n", "n", "{:d}")]
    if spectrum:
        cols += [
            ("omega_max", "max abs(eig) [1/s]", "{:.3g}"), ("damping_max", "max damping [1/s]", "{:.3g}"),
            ("stiffness_ratio", "stiffness ratio", "{:.3g}"), ("leapfrog_dt_bound", "LF dt bound [s]", "{:.3g}"),
            ("leapfrog_dt_stable", "LF dt stable (bisection) [s]", "{:.3g}"),
            ("bisection_horizon_s", "bisection horizon [s]", "{:.3g}"),
        ]
    for name in integrators:
        cols += [(f"{name}_status", f"{name} status", "{}"), (f"{name}_steps", f"{name} steps", "{:.0f}"),
                 *([(f"{name}_failures", f"{name} failed steps", "{:.0f}")] if name != "leapfrog" else []),
                 (f"{name}_wall_s", f"{name} wall [s]", "{:.3g}"), (f"{name}_energy_error", f"{name} energy err", "{:.2g}")]
    cols = [c for c in cols if c[0] in ds]
    lines = ["| case | " + " | ".join(c[1] for c in cols) + " |", "|---" * (len(cols) + 1) + "|"]
    for i, label in enumerate(ds.case.values):
        cells = []
        for key, _, fmt in cols:
            v = ds[key].values[i]
            if (key == "leapfrog_dt_stable" and isinstance(v, float) and math.isnan(v) and ds.attrs.get("bisected", 1)
                    and np.isfinite(float(ds["bisection_horizon_s"].values[i]))):
                horizon = float(ds["bisection_horizon_s"].values[i])
                short = horizon < 200 * float(ds["leapfrog_dt_bound"].values[i])
                note = str(ds["leapfrog_dt_note"].values[i]) if "leapfrog_dt_note" in ds else ""  # older files: none
                cells.append(stopped_at_start(ds, i) if horizon == 0 else note or
                             ("n/a: folds within 100 steps" if short else "< bound/2"))
                continue
            try:
                cells.append(fmt.format(int(v) if fmt == "{:d}" else v) if not (isinstance(v, float) and math.isnan(v)) else "")
            except (ValueError, TypeError):
                cells.append(str(v))
        lines.append(f"| {label} | " + " | ".join(c[:60] for c in cells) + " |")
    notes = [f"- {label}, {name.replace('_', '-')}: {ds[f'{name}_message'].values[i]}"
             for i, label in enumerate(ds.case.values) for name in integrators
             if f"{name}_message" in ds and str(ds[f"{name}_message"].values[i])]
    if notes:  # why a run did not complete: where and when it stopped, or why it was refused
        lines += ["", "Runs that did not complete:", *notes]
    skipped = [f"- {label}, {ds.case_status.values[i]}: {ds.case_note.values[i]}"
               for i, label in enumerate(ds.case.values) if "case_status" in ds and str(ds.case_note.values[i])]
    if skipped:  # cases that did not run at all: why
        lines += ["", "Cases not measured:", *skipped]
    return "\n".join(lines)
