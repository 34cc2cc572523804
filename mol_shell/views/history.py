"""Figures over time for a breathing or inflated shell: a radius against time, and the energy-work balance.

``mol-shell plot run.nc --figure history [--at-s S]``, and the lower row of the default figure of every
shell that is not the paper's unloaded cylinder. The radius is ``r`` at one node: at ``--at-s``, else at
the equator: the node of largest reference radius ``r0`` or, where several nodes have it (a cylinder, the
cylindrical part of a vessel), the middle one of them. The balance:
the change of the total energy ``E(t) - E(0)`` (kinetic + stored), the work ``W`` done on the shell by
the loads and the energy ``D`` dissipated (viscosity, drag), and what the balance
``E - E(0) - W + D = 0`` leaves, which measures the time integration.
"""

from __future__ import annotations

import textwrap

import numpy as np

from mol_shell.views.fibres import _nearest
from mol_shell.views.fields import run_of
from mol_shell.views.figures import figure_path, incomplete_note, save_figure, wrapped_title

#: what the figures over time read of a run (its reference radius ``r0``, and the work and dissipation, where it has
#: them)
HISTORY = ("r", "energy")
#: nodes whose ``r0`` is within this fraction of the largest are on the widest part (a vessel's cylinder is exact to
#: rounding; a sphere's neighbours of its equator node are 1 - cos(pi / (n - 1)) below it, 1.2e-6 at n = 2000)
WIDEST = 1e-9


def widest_nodes(ds):
    """``(first, last)``: the longest run of consecutive nodes whose ``r0`` is within :data:`WIDEST` of its largest
    value (the first such run of the longest length; every node when the run has no ``r0``)."""
    if "r0" not in ds:
        return 0, ds.sizes["s"] - 1
    r0 = np.asarray(ds["r0"].values, dtype=float)
    top = r0 >= r0.max() - WIDEST * np.abs(r0).max()
    edges = np.flatnonzero(np.diff(np.concatenate([[0], top.astype(int), [0]])))
    starts, stops = edges[::2], edges[1::2] - 1  # runs of True: [starts, stops]
    k = int(np.argmax(stops - starts))
    return int(starts[k]), int(stops[k])


def radius_node(ds, s=None):
    """Index of the node whose radius is drawn: the one nearest ``s`` (m), else the equator: the middle node of
    :func:`widest_nodes` (the one node of largest ``r0`` of a sphere; the middle of a cylinder, or of a vessel's
    cylindrical part, where its knuckle's first node, at the same ``r0``, moves inwards under pressure)."""
    if s is not None:
        return _nearest(ds["s"].values, float(s), "s", "m")
    first, last = widest_nodes(ds)
    if first == 0 and last == ds.sizes["s"] - 1:  # a cylinder (every node): its middle node, upper of two
        return ds.sizes["s"] // 2
    middle = [first + (last - first) // 2, first + (last - first + 1) // 2]  # one node, or the two of an even run
    r0 = ds["r0"].values
    return max(middle, key=lambda i: (r0[i], -i))  # the wider; of two alike (a sphere's even n) the first, as before


#: time ticks along a panel at most: at the default's 9 to 10, labels of a run of milliseconds ran into each other
#: ("0.00000.00050.0010...")
TIME_TICKS = 6


def time_axis(ax):
    """``t [s]`` along ``ax``'s x axis, with at most :data:`TIME_TICKS` ticks and short labels: below 0.001 s or from
    10000 s on, the power of ten once at the axis' end (``0 1 2 3 4`` and ``1e-4``)."""
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(TIME_TICKS, steps=[1, 2, 2.5, 5, 10]))
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4), useOffset=False)
    ax.set_xlabel("t [s]")


#: characters per line of a panel's title (half the figure's width at its font size)
TITLE_WIDTH = 70
#: the label of ``D`` integrated from the saved dissipated power (a viscous run without loads carries no ``dissipated``)
QUADRATURE_LABEL = "D, dissipated (trapezoidal rule on the saved times)"


def cumulative(values, times):
    """The running trapezoid integral of ``values`` over ``times`` (0 at the first time)."""
    values, times = np.asarray(values, dtype=float), np.asarray(times, dtype=float)
    steps = (values[1:] + values[:-1]) / 2 * np.diff(times)
    return np.concatenate([[0.0], np.cumsum(steps)])


def balance_terms(ds):
    """``{label: values over time}`` of the energy balance (J): ``E - E(0)``, ``W``, ``D`` (when the run has them)
    and the residual ``E - E(0) - W + D``. A viscous run without loads has its ``D`` integrated from the
    dissipated power."""
    times = ds["time"].values
    change = ds["energy"].values - ds["energy"].values[0]
    work = ds["work"].values if "work" in ds else np.zeros_like(change)
    if "dissipated" in ds:
        dissipated = ds["dissipated"].values
    elif "dissipation" in ds:
        dissipated = cumulative(ds["dissipation"].values, times)
    else:
        dissipated = np.zeros_like(change)
    terms = {"E - E(0), kinetic + stored": change}
    if "work" in ds:
        terms["W, work of the loads"] = work
    if "dissipated" in ds:
        terms["D, dissipated"] = dissipated
    elif "dissipation" in ds:  # no accumulator in the run (no loads): the balance measures this quadrature
        terms[QUADRATURE_LABEL] = dissipated
    terms["E - E(0) - W + D (balance)"] = change - work + dissipated
    return terms


def draw_radius(ax, ds, node):
    """``r`` at ``node`` against time, with the reference radius there for scale."""
    t = ds["time"].values
    ax.plot(t, ds["r"].values[:, node], "k.-", lw=1, ms=3, label=f"r at s = {float(ds['s'][node]):.4g} m")
    if "r0" in ds:
        ax.axhline(float(ds["r0"].values[node]), color="0.7", lw=0.8, zorder=0, label="reference r0")
    time_axis(ax)
    ax.set_ylabel("r [m]")
    at = f"s = {float(ds['s'][node]):.4g} m"
    first, last = widest_nodes(ds)
    if node != radius_node(ds):
        where = f"the chosen {at}"
    elif first == last:
        where = f"the equator ({at}, the largest r0)"
    else:
        where = (f"the equator ({at}, the middle of the widest part, r0 largest on s = {float(ds['s'][first]):.4g} to "
                 f"{float(ds['s'][last]):.4g} m)")
    ax.set_title(textwrap.fill(f"radius at {where} against time", TITLE_WIDTH), fontsize=9)  # a long one was cut
    ax.legend(fontsize=7)


def draw_balance(ax, ds):
    """The terms of the energy-work balance against time (J)."""
    t = ds["time"].values
    colors = {"E": "tab:blue", "W": "tab:orange", "D": "tab:green"}
    terms = balance_terms(ds)
    for label, values in terms.items():
        last = "balance" in label
        # E - E(0) drawn wide under the others: where the balance holds, W - D lies on it
        ax.plot(t, values, color="k" if last else colors[label[0]], lw=3 if label[0] == "E" else 1.2 if last else 1,
                alpha=0.5 if label[0] == "E" else 1, ls="--" if last else "-", label=label)
    ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    time_axis(ax)
    ax.set_ylabel("energy [J]")
    residual = float(np.max(np.abs(list(terms.values())[-1])))
    title = f"energy-work balance (largest |E - E(0) - W + D| = {residual:.2g} J)"
    if QUADRATURE_LABEL in terms:  # not the run's error: the rule's on the saved times (a 0.067 J "error" of 18 J)
        title += (f"\nD by the trapezoidal rule on {len(t)} saved times: the balance measures that rule, not the run "
                  "(save more times)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def history_figure(ds, s=None):
    """The radius against time and the energy-work balance (a matplotlib ``Figure``, not saved)."""
    import matplotlib.pyplot as plt

    ds = run_of(ds, "plot --figure history", HISTORY)
    node = radius_node(ds, s)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    draw_radius(ax, ds, node)
    draw_balance(bx, ds)
    title = f"{ds.attrs.get('scene', 'run')}: radius and energy over time"
    if incomplete_note(ds.attrs):  # as the paper's figures say it
        title += f"\n[{incomplete_note(ds.attrs)}]"
    fig.suptitle(wrapped_title(fig.get_figwidth(), title), fontsize=10)
    fig.tight_layout()
    return fig


def plot_history(ds, path, s=None):
    """Write :func:`history_figure` to ``path`` (a run's Dataset or file; ``path`` checked before anything is drawn)."""
    ds = run_of(ds, "plot --figure history", HISTORY)
    path = figure_path(path)
    save_figure(history_figure(ds, s), path, dpi=120)
    return path
