"""The paper's figures 4-8: r, theta, chi against s at t = 0, 0.02, 0.07, 0.106, 0.143 s.

The scene of section 6 (N = 40 nodes, leap-frog, dt = 1e-6 s, gamma = 0.1 rad/m, R computed),
saved every millisecond for the figures and the netCDF. psi is sampled every 20 us (PSI_STEP): it carries the
transverse-shear mode, sqrt(3 mu / rho) / h = 5,050 rad/s (804 Hz, period 1.24 ms; h the half-thickness) for the
natural cylinder, the top of psi's band at N = 40 being 5,290 rad/s (1 / the leap-frog bound), so 1 ms samples
alias it (to 194 Hz at s = 0, with max |psi| 12 % low); 20 us gives 60 samples a period. The psi panels, the whole
run's max |psi| and the per-grid summaries use the 20 us samples.
Writes OUT/paper_figures.nc, OUT/fig4.png .. OUT/fig8.png (one per paper time, as the paper)
and OUT/paper_psi.png; prints the numbers. ``main`` returns the run, its relative energy change,
the per-grid summaries and the files written.

A second run on a finer grid (--check-n, default 160) compares psi across grids. The cell energy
samples psi at the cell's two nodes, so the (-1)^i node pattern has the full transverse-shear
stiffness (a mode at 5,063 rad/s on 40 nodes, just above the uniform shear mode at 5,050 rad/s)
and stays at 3.3e-6 .. 5.4e-6 rad on every grid (column "(-1)^i node pattern", from
mol_shell.results.study_store.grid_mode). psi itself is small (max |psi| over the run, 20 us samples:
6.6e-5 rad at N = 40, 8.3e-5 at 80, 1.4e-4 at 160, 2.1e-4 at 320; 1 ms samples gave 5.8e-5, 8.2e-5, 1.0e-4,
1.6e-4) but is not pointwise converged: it is short-wave content radiated at the torsional fronts, which are
as sharp as the grid because the initial data make chi_s jump at the free ends (its dominant frequency at
s = L/2 rises with the grid: about 35, 63, 119, 266 Hz at N = 40, 80, 160, 320). r, theta and chi converge
(max |r - R| = 0.01126, 0.01112, 0.01108, 0.01107 m on the same grids).
Usage: python studies/paper_figures.py [--n 40] [--dt 1e-6] [--check-n 160] [--quick] [--out out]
(--quick: the paper run only, without the finer grid; about 10-15 s.)
"""

import os

import numpy as np

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.args import integer_arg, number_arg
from mol_shell.cli.scripts import MIN_NODES, Stopped, output_folder, run_script, script_parser, simulate
from mol_shell.runs import resources
from mol_shell.views.figures import save_figure
from mol_shell.views.plotting import plot_snapshots
from mol_shell.results.study_store import summarize

PAPER_TIMES = (0.0, 0.02, 0.07, 0.106, 0.143)
FIELD_STEP = 1e-3  # s: the fields' saved times (netCDF, figures 4-8, the table)
PSI_STEP = 2e-5  # s: psi's samples, 60 in the shear mode's period (module docstring)
QUICK = {"check_n": 0}  # --quick: no finer grid
#: --dt's range beyond (0, FIELD_STEP]: the fields are saved every FIELD_STEP, at the leap-frog steps nearest, so a
#: longer step saved fewer times than the figures take (--dt 1: only t = 0, which simulate refused naming ``times``)
DT_NOTE = " (the fields' saved step; leap-frog's stability bound, which --n sets, is checked as the run starts)"
NO_CHECK = "no finer grid"  # what --check-n 0 means


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--n", type=integer_arg("--n", MIN_NODES), default=40, help="nodes (default 40)")
    parser.add_argument("--dt", type=number_arg("--dt", 0.0, FIELD_STEP, high_closed=True, unit="s", note=DT_NOTE),
                        default=1e-6, help=f"leap-frog step, s, at most {FIELD_STEP:g} (default 1e-6)")
    parser.add_argument("--check-n", type=integer_arg("--check-n", MIN_NODES, zero=NO_CHECK), default=None,
                        help=f"finer grid for the psi comparison, nodes (default 160; 0: {NO_CHECK}, as --quick)")
    parser.add_argument("--quick", action="store_true", help="the paper run only (no finer grid): a few seconds")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    check_n = args.check_n if args.check_n is not None else (QUICK["check_n"] if args.quick else 160)
    out = args.out
    scene = mol_shell.TwistedCylinder()
    check_fits("--n", args.n, args.dt, len(scene.fields))  # both grids before any work, by the script's options
    if check_n:
        check_fits("--check-n", check_n, args.dt, len(scene.fields), zero=NO_CHECK)
    output_folder(out)
    try:
        run, stopped = _simulate_sampled(scene, args.n, args.dt), None
    except Stopped as exc:  # Ctrl-C: the run kept as far as it got, the figures of the times it reached drawn
        run, stopped = exc.ds, exc
    ds = _fields(run, args.dt)
    files = [os.path.join(out, "paper_figures.nc")]
    mol_shell.write_netcdf(ds, files[0])
    figures = dict(zip(range(4, 9), PAPER_TIMES))
    for number, t in figures.items():
        if reached(run, t, args.dt):
            files.append(os.path.join(out, f"fig{number}.png"))
            plot_snapshots(ds.sel(time=[t], method="nearest"), files[-1])
    whole = reached(run, PAPER_TIMES[-1], args.dt)  # a Ctrl-C after the run's end (in its ellipticity check) kept it all
    if whole:
        files.append(os.path.join(out, "paper_psi.png"))
        _plot_psi(run, files[-1])
    if stopped is not None:  # said in one line, exit 130 (mol_shell.cli.scripts)
        stopped.note = _stopped_note(run, args.dt, figures, check_n)
        raise stopped
    e = run.energy.values
    drift = float(np.abs(e - e[0]).max() / e[0])
    mid = ds.sizes["s"] // 2
    print(f"R = {ds.attrs['R']:.10f} m, n = {args.n}, dt = {args.dt:g} s, {ds.attrs['n_steps']} steps in "
          f"{ds.attrs['wall_time_s']:.2f} s, status {ds.attrs['status']}")
    print("| t [s] | r min .. max [m] | max abs(theta) [rad] | chi min .. max [rad] | max abs(psi) [rad] |")
    print("|---|---|---|---|---|")
    for t in PAPER_TIMES:
        x = ds.sel(time=t, method="nearest")
        print(f"| {t:g} | {float(x.r.min()):.5f} .. {float(x.r.max()):.5f} | {float(abs(x.theta).max()):.4f} "
              f"| {float(x.chi.min()):+.4f} .. {float(x.chi.max()):+.4f} | {float(abs(x.psi).max()):.2e} |")
    peaks = [psi_peak(run.psi.isel(s=i)) for i in (0, mid)]
    print(f"whole run ({psi_step(args.dt) * 1e6:g} us samples): r in {float(run.r.min()):.5f} .. {float(run.r.max()):.5f} m, "
          f"max |theta| = {float(abs(run.theta).max()):.4f}, max |psi| = {float(abs(run.psi).max()):.2e} rad "
          f"({float(abs(ds.psi).max()):.2e} on the 1 ms samples); relative energy change {drift:.2e}; psi's FFT peak "
          f"at s = 0: {peaks[0]:.0f} Hz, at s = L/2: {peaks[1]:.0f} Hz (resolution {1 / PAPER_TIMES[-1]:.0f} Hz)")
    grids = {args.n: run}
    if check_n:
        grids[check_n] = _simulate_sampled(scene, check_n, args.dt)
    print("| N | max abs(r - R) [m] | max abs(theta) | max abs(psi) | psi: (-1)^i node pattern | psi: the rest | max abs(chi_s) |")
    print("|---|---|---|---|---|---|---|")
    summaries = {}
    for n, run in grids.items():
        m = summaries[n] = summarize(run)
        print(f"| {n} | {float(m.dr_max):.5f} | {float(m.theta_max):.4f} | {float(m.psi_max):.2e} | "
              f"{float(m.psi_grid_mode_max):.2e} | {float(m.psi_smooth_max):.2e} | {float(m.chi_s_max):.4f} |")
    print("wrote " + ", ".join(files))
    return {"ds": ds, "energy_drift": drift, "summaries": summaries, "files": files}


def _stopped_note(run, dt, figures, check_n):
    """What a Ctrl-C left out: the figures of the paper's times the run did not reach (and paper_psi.png, whose
    right panel is t = 0.143 s), or, a run stopped after its end (in its ellipticity check), that every figure was
    drawn from its whole data and what was not done after them."""
    left = [number for number, t in figures.items() if not reached(run, t, dt)]
    if left:
        return ("not drawn, their times not reached: "
                + ", ".join(f"fig{number}.png (t = {figures[number]:g} s)" for number in left)
                + f", paper_psi.png (t = {PAPER_TIMES[-1]:g} s)")
    finer = f" and the finer grid (--check-n {check_n}) not run" if check_n else ""
    return f"every figure drawn from the whole run; its numbers not printed{finer}"


def psi_step(dt):
    """psi's sampling step for leap-frog's ``dt``: the multiple of ``dt`` nearest :data:`PSI_STEP` (``dt`` itself when it
    is longer), so that every sample is a time leap-frog lands on (``--dt 5e-5`` was refused, naming ``times``)."""
    return dt * max(1, round(PSI_STEP / dt))


def psi_times(t_end, step=PSI_STEP):
    """psi's saved times: every ``step`` from 0 up to ``t_end``, as typed (9 decimals)."""
    return np.round(np.arange(int(t_end / step * (1 + 1e-12)) + 1) * step, 9)


def psi_peak(psi):
    """The frequency (Hz) of the largest FFT amplitude of ``psi`` (a DataArray on evenly spaced ``time``)."""
    values = psi.values - psi.values.mean()
    return float(np.fft.rfftfreq(values.size, float(psi.time[1] - psi.time[0]))[np.argmax(np.abs(np.fft.rfft(values)))])


def sampled_times(dt, t_end=PAPER_TIMES[-1]):
    """The run's saved times: every :func:`psi_step` of ``dt``, and the paper's times on leap-frog's steps."""
    paper = [round(round(t / dt) * dt, 9) for t in PAPER_TIMES if t <= t_end]  # on leap-frog's steps (figures: nearest)
    return np.unique(np.r_[psi_times(t_end, psi_step(dt)), paper])


def check_fits(name, n, dt, fields, zero=""):
    """Refuse, naming the script's option ``name`` (``--n``, ``--check-n``: a grid of ``n`` nodes), a run that would
    not fit in memory with the saved times the script takes (:func:`sampled_times`, which no option sets): before
    any work (``--check-n 4000`` was refused after the whole paper run, naming ``times`` and ``--times``, which the
    script has not). ``zero``: what 0 means, which the range says too."""
    times = sampled_times(dt)
    est = resources.estimate(n, len(times), times[-1], fields=fields, dt=dt)
    try:
        resources.check_memory(est, times_name=None, n_name=name, what=f"the run on {n:,} nodes",
                               kept=f"saved times (psi every {psi_step(dt) * 1e6:g} us)",
                               fewer_nodes=f"use fewer nodes ({name})")
    except ParameterError as exc:
        if not zero:
            raise
        raise ParameterError(name, n, f"0 ({zero}) or {exc.allowed}", hint=exc.hint) from None


def _simulate_sampled(scene, n, dt, t_end=PAPER_TIMES[-1]):
    """The run saved at :func:`sampled_times`, without stresses (:func:`_fields` adds them); a run that Ctrl-C stopped
    raises :class:`~mol_shell.cli.scripts.Stopped` with it. leap-frog's bound refuses ``dt`` naming ``--dt``, the
    option typed."""
    times = sampled_times(dt, t_end)
    try:
        return simulate(scene, n=n, times=times, dt=dt, progress=False, stresses=False)
    except ParameterError as exc:
        if exc.name != "dt":
            raise
        raise ParameterError("--dt", exc.value, exc.allowed, exc.hint) from None


def reached(run, t, dt):
    """Whether ``run`` reached the paper's time ``t`` (saved at the leap-frog step nearest it, within ``dt / 2``)."""
    return t <= float(run.time[-1]) + dt / 2


def _fields(run, dt):
    """The run at every :data:`FIELD_STEP` and at the paper's times it reached (an interrupted run: up to its end, each
    time once), with its stresses: the netCDF's and the figures'."""
    paper = [t for t in PAPER_TIMES if reached(run, t, dt)]
    times = np.r_[np.arange(0.0, float(run.time[-1]) + FIELD_STEP / 2, FIELD_STEP), paper]
    nearest = np.unique(run.indexes["time"].get_indexer(np.round(times, 9), method="nearest"))  # each saved time once
    return mol_shell.add_stresses(run.isel(time=nearest))


def _plot_psi(ds, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.4))
    for frac in (0.0, 0.25, 0.5):
        i = int(round(frac * (ds.sizes["s"] - 1)))
        axes[0].plot(ds.time, ds.psi.isel(s=i), lw=0.8, label=f"s = {float(ds.s[i]):.2f} m")
    axes[0].set_xlabel("t [s]")
    step = float(ds.time[1] - ds.time[0])
    axes[0].set_ylabel(rf"$\psi$ [rad] ({step * 1e6:.3g} $\mu$s samples)")
    axes[0].legend(fontsize=8)
    axes[1].plot(ds.s, ds.psi.sel(time=0.143, method="nearest"), "k.-", ms=3)
    axes[1].set_xlabel("s [m]")
    axes[1].set_ylabel(r"$\psi$ at t = 0.143 s [rad]")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)  # written whole or not at all, and said after a Ctrl-C (interrupts.wrote)


if __name__ == "__main__":
    run_script(main)
