"""Section 4: the azimuthally unshearable shell, a DAE with Lagrange multipliers, solved by IDA.

The constraints (4.1), ``chi_s = 0`` and ``psi = 0``, are imposed on the same discrete
Lagrangian as :class:`~mol_shell.discretization.system.ShellSystem` (its cell kernel for the stored
energy, the model's kinetic energy density lumped at nodes):

    L_h = sum_i T_i(q_i, v_i) - sum_cells V_c - 2 pi r0 [ sum_cells Lc (chi_{i+1} - chi_i)
                                                          + sum_i w_i Lp_i psi_i ],

so ``Lc`` (``lambda_chi``) is conjugate to ``chi_s`` and ``Lp`` (``lambda_psi``) to ``psi``, per
unit reference area: ``2 pi r0 lambda_chi`` is the axial torque carried across a section
by the constraint (the combination ``r n . a3`` of (3.11), (4.11)), ``-lambda_psi`` the couple
per unit area that keeps the director in the meridional plane (the multiplier of (4.13),
entering (3.12)). Lagrange's equations in residual form,

    q_t - v = 0,
    d/dt dT/dv - dT/dq + dV/dq + dD/dv + G^T (Lc, Lp) = 0,
    G v_t = 0   (the constraints differentiated twice: chi_s,tt = 0, psi_tt = 0),

form a DAE of index 1 in ``(q, v, Lc, Lp)``. The constraints are linear (``G`` is constant),
so BDF keeps ``G v = 0`` and ``G q = 0`` to the accuracy of its Newton iteration: no drift.

Physics (sections 4-5). Each section of a spinning shell whose radius varies along ``s``
carries the angular momentum ``rhoA r^2 chi_t`` (plus the director's); as sections breathe by
different amounts, conservation alone would spin them at different rates (4.7), so a free
shell twists (``chi_s`` grows) and, through the Coriolis terms ``2 r_t chi_t`` and
``2 chi_t theta_t sin(theta)`` of (4.6), shears out of the meridional plane (``psi`` grows).
The unshearable shell keeps ``chi_s = psi = 0``; its multipliers supply exactly those
Coriolis torques and couples and vanish without spin.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time

import numpy as np

from mol_shell._core import interrupts
from mol_shell._core.errors import ParameterError, flag
from mol_shell._core.progress import progress_mode, time_meter
from mol_shell.discretization.unshearable_dae import NODE, UnshearableDAE
from mol_shell.integrators import Leapfrog
from mol_shell.integrators.constrained import ConstrainedIDA, ida_solver
from mol_shell.integrators.loop import run
from mol_shell.model.edges import EDGE_FIELDS, IMPOSED, resolve_edges
from mol_shell.results.dataset import build_dataset
from mol_shell.runs import asked_times, resources
from mol_shell.runs.building import as_scene, build, observe, parse_times, resolve
from mol_shell.runs.checks import check_system, checked_spectrum
from mol_shell.runs.ellipticity import check_ellipticity
from mol_shell.runs.leapfrog_guard import check_parasitic, check_step
from mol_shell.runs.post_run import cut_short, kept
from mol_shell.scenes.unshearable import Unshearable

#: the options of the two runs, with their defaults: the constrained DAE's (IDA) and the free shell's (leap-frog's
#: own, as on any other scene: ``dt``, ``chunk``, ``restart``)
DAE_OPTIONS = {"rtol": 1e-8, "atol": 1e-10, "max_step": 0.0}
FREE_OPTIONS = {f.name: f.default for f in dataclasses.fields(Leapfrog)}
#: what runs a free shell that leap-frog cannot (the parasitic root of a viscous one): no implicit integrator does
FREE_ALTERNATIVE = ("no other integrator for the free shell (ida on this scene solves the constrained DAE, another "
                    "model)")


def simulate_unshearable(scene, *, n=40, times=None, t_end=None, constrained=True, rtol=None, atol=None,
                         dt=None, max_step=None, progress=None, restart=None, chunk=None):
    """Run an :class:`Unshearable` scene, constrained (DAE, IDA) or free (the PDE, leap-frog).

    Parameters
    ----------
    scene : Unshearable
    n : int
        Nodes in ``s``.
    times, t_end : optional
        Saved times as for :func:`mol_shell.simulate`.
    constrained : bool
        ``True``: ``chi_s = 0`` and ``psi = 0`` imposed (the DAE, solved by IDA, BDF with an
        exact band Jacobian). ``False``: the ordinary shell from the same initial state
        (leap-frog, step ``dt``). A bool (``"no"`` ran the DAE).
    rtol, atol : float
        IDA tolerances (``atol`` for lengths and angles; scaled for rates and multipliers); default 1e-8, 1e-10.
        Constrained runs only.
    dt, restart, chunk : float, float, int
        Leap-frog's options (:class:`~mol_shell.integrators.Leapfrog`; step default 1e-6 s). Free runs only (the
        constrained run ignored ``dt``). A viscous shell whose damped modes leap-frog's parasitic root would blow up
        is refused before the run (:func:`~mol_shell.runs.leapfrog_guard.check_parasitic`), as on any scene.
    max_step : float
        Largest IDA step (0: unbounded, the default). Constrained runs only.
    progress : bool, optional
        As :func:`mol_shell.simulate`'s: a bar on a terminal, else a line a minute of a longer run (``None``).

    Returns
    -------
    xarray.Dataset
        The variables of :func:`mol_shell.simulate`, plus ``chi_s_max`` and ``psi_max`` (the
        constraint defects, per time) and, constrained, ``lambda_chi`` on cells ``(time,
        s_cell)`` and ``lambda_psi`` on nodes ``(time, s)``; free, ``ellipticity_margin``
        (:func:`~mol_shell.runs.ellipticity.check_ellipticity`, with its warning; the DAE's principal symbol is
        another one, not checked).
    """
    constrained = flag("constrained", constrained)
    given = {k: v for k, v in (("rtol", rtol), ("atol", atol), ("max_step", max_step), ("dt", dt), ("restart", restart),
                               ("chunk", chunk)) if v is not None}
    taken = DAE_OPTIONS if constrained else FREE_OPTIONS
    run_name = "the constrained DAE (ida)" if constrained else "the free shell (leapfrog)"
    for name in given:  # an option of the other run was ignored (dt of the constrained one), as simulate refuses it
        if name not in taken:
            raise ParameterError.not_an_option(name, run_name, taken)
    options = {**taken, **given}
    scene = as_scene(scene) if isinstance(scene, str) else scene  # a registered name, as simulate takes
    requested = scene.params() if isinstance(scene, Unshearable) else None  # R = auto: R_requested beside R
    scene = resolve(scene)
    if not isinstance(scene, Unshearable):
        raise ParameterError("scene", getattr(scene, "name", scene), "{unshearable} (a mol_shell.Unshearable)")
    times_given = times is not None
    times = parse_times(times, t_end)
    method = None if constrained else Leapfrog(**options)  # its options refused by name before the build
    resources.check_before_build(n, times, "ida" if constrained else "leapfrog", dt=options.get("dt"),
                                 times_given=times_given)
    if constrained:
        _check_constrained_edges(scene)  # before the graph is built and compiled
    shell, compiled = build(scene, n)
    Q0, V0 = scene.initial_fields(shell.s)
    check_system(scene, shell, shell.pack(Q0, shell.momenta(Q0, V0)))  # numbers finite in double precision
    mode = progress_mode(progress)
    start = time.perf_counter()
    if constrained:
        with _meter(mode, times[-1]) as bar:
            traj, V, multipliers, stats = _integrate_dae(shell, Q0, V0, times, options["rtol"], options["atol"],
                                                         options["max_step"], bar)
        attrs = {"integrator": "ida", "rtol": options["rtol"], "atol": options["atol"], "constrained": 1, **stats}
    else:
        dt = method.dt
        y0 = shell.pack(Q0, shell.momenta(Q0, V0))
        omega_max, damping = checked_spectrum(scene, shell, y0)
        check_step(dt, omega_max)
        check_parasitic("leapfrog", method, damping, omega_max, float(times[-1]), FREE_ALTERNATIVE)
        with _meter(mode, times[-1]) as bar:
            traj = method.integrate(shell, compiled, y0, method.step_counts(times) * dt, progress=bar)
        multipliers = None
        attrs = {"integrator": "leapfrog", **method.settings(), "chunk": method.chunk, "constrained": 0,
                 "leapfrog_dt_bound_s": 1.0 / omega_max, "max_damping_rate": damping, "units_max_damping_rate": "s-1"}
    attrs["build_and_run_time_s"] = time.perf_counter() - start
    attrs["t_end_requested"] = float(times[-1])  # as simulate's: what a run that stops early was asked to reach
    if len(traj.t) < len(times):  # as simulate's: the times it asked for
        attrs[asked_times.ATTR] = asked_times.times_text(times)
    with interrupts.watched() as watch:  # the states are the run from here: a Ctrl-C is noted, the run kept
        velocities, totals = observe(shell, traj.y)
        if constrained:  # a held chi's support shares the torque with the constraint chi_s = 0, whose multiplier the
            # shell's own equations do not hold: its reaction is not computed (NaN; a held z's is: no constraint acts on z)
            for j, (_, field) in enumerate(shell.reaction_names):
                if field == 2:
                    totals["reactions"][:, j] = np.nan
                    attrs["reaction_torque_note"] = ("not computed for the constrained DAE: the held chi's support "
                                                     "shares the torque with the constraint chi_s = 0 (lambda_chi)")

        ds = build_dataset(shell, scene, traj, velocities, totals, attrs, requested)
        ds.attrs["title"] = f"mol_shell run of scene unshearable ({'constrained DAE' if constrained else 'free shell'})"
        ds = _add_defects(ds, shell, multipliers)
        if not constrained and not watch.caught:  # the free shell's equations, checked as any shell's
            with cut_short(watch):
                ds = check_ellipticity(shell, ds)
    return kept(ds, watch, stresses=False, ellipticity=not constrained)  # (mol_shell.runs.post_run)


def _check_constrained_edges(scene):
    """Edges the constraints leave room for: ``psi = 0`` is imposed at every node, so an edge that holds ``psi`` too
    (clamped, or a set with ``psi``) holds it twice (the multipliers are then not determined: a singular Newton
    matrix); ``chi_s = 0`` makes every section turn with an edge that holds ``chi``, so the shell cannot spin."""
    active = tuple(getattr(scene, "fields", range(len(EDGE_FIELDS))))
    edges = resolve_edges(scene.end1, scene.end2, scene.meridian().poles)
    for name, kind in zip(("end1", "end2"), edges):
        held = {EDGE_FIELDS[k] for k in IMPOSED[kind] if k in active}
        if "psi" in held:
            raise ParameterError.invalid(name, kind, "holds psi, which the constrained shell holds at 0 at every node "
                                         "already", "an edge that leaves psi free (magnet, pinned, free, or a set "
                                         "without psi)")
        if "chi" in held and scene.omega != 0:
            raise ParameterError.invalid("omega", scene.omega, f"spins a shell whose {name} = {kind} holds chi (the "
                                         "constraint chi_s = 0 turns every section with that edge)", "0, or an edge "
                                         "that leaves chi free (magnet, free, or a set without chi)")


@contextlib.contextmanager
def _meter(mode, t_end):
    """The run's progress (:func:`mol_shell._core.progress.time_meter`), closed when the run ends."""
    bar = time_meter(mode, t_end)
    try:
        yield bar
    finally:
        if bar is not None:
            bar.close()


def _integrate_dae(shell, Q0, V0, times, rtol, atol, max_step, progress=None):
    """The constrained run on the one run loop (:func:`mol_shell.integrators.loop.run`): ``(traj, V, (Lc, Lp), stats)``."""
    dae = UnshearableDAE(shell)
    y0, yp0 = dae.consistent(Q0, V0)
    ida = ConstrainedIDA(dae, y0, yp0, ida_solver(dae, rtol, atol * _atol_scale(dae, y0, yp0), max_step))
    traj = run(ida, shell, None, shell.pack(Q0, shell.momenta(Q0, V0)), times, progress=progress)
    raw = np.array((ida.stepper.saved if ida.stepper is not None else [y0])[: len(traj.t)])
    _, V, Lc, Lp = dae.unpack(raw)
    return traj, V, (Lc, Lp), traj.stats


def _atol_scale(dae, y0, yp0):
    """Absolute-tolerance weights: 1 for lengths and angles, a time scale for rates, force scales for multipliers."""
    sh = dae.shell
    speed = math.sqrt((sh.lam + 2 * sh.mu) / sh.scene.rho)  # fastest wave, m/s
    scale = np.ones((dae.n, NODE))
    scale[:, 5:10] = speed / sh.scene.L  # rates: lengths per time scale L / c
    stiffness = (sh.lam + 2 * sh.mu) * 2 * sh.scene.h  # membrane stiffness per unit length, N/m
    scale[:, 10] = stiffness * sh.scene.L
    scale[:, 11] = stiffness
    return scale.reshape(-1)


def _add_defects(ds, shell, multipliers):
    """Constraint defects per time; multipliers with their units when given."""
    chi_s = np.diff(ds.chi.values, axis=1) / shell.ds
    ds["chi_s_max"] = (("time",), np.abs(chi_s).max(axis=1),
                       {"units": "rad m-1", "long_name": "max over cells of |chi_s| (0 for an axisymmetric motion)"})
    ds["psi_max"] = (("time",), np.abs(ds.psi.values).max(axis=1),
                     {"units": "rad", "long_name": "max over s of |psi| (0 for an axisymmetric motion)"})
    if multipliers is not None:
        Lc, Lp = multipliers
        cells = (shell.s[:-1] + shell.s[1:]) / 2
        ds = ds.assign_coords(s_cell=("s_cell", cells, {"units": "m", "long_name": "arc length at cell midpoints"}))
        ds["lambda_chi"] = (("time", "s_cell"), Lc, {
            "units": "N", "long_name": "Lagrange multiplier of chi_s = 0: axial moment per unit reference "
            "circumferential length (2 pi r0 lambda_chi = torque across the section)"})
        ds["lambda_psi"] = (("time", "s"), Lp, {
            "units": "N m-1", "long_name": "Lagrange multiplier of psi = 0 per unit reference area "
            "(minus the couple keeping the director in the meridional plane)"})
    return ds


def defects(ds):
    """``(max |chi_s|, max |psi|)`` over a whole run Dataset (any scene)."""
    chi_s = ds.chi.diff("s") / ds.s.diff("s")
    return float(abs(chi_s).max()), float(abs(ds.psi).max())


__all__ = ["defects", "simulate_unshearable"]

