"""Figures over time for a breathing or inflated shell: a radius against time, and the energy-work balance.

``mol-shell plot run.nc --figure history [--at-s S]``, and the lower row of the default figure of every
shell that is not the paper's unloaded cylinder. The radius is ``r`` at one node: at ``--at-s``, else at
the equator (the node of largest reference radius ``r0``; the middle node of a cylinder). The balance:
the change of the total energy ``E(t) - E(0)`` (kinetic + stored), the work ``W`` done on the shell by
the loads and the energy ``D`` dissipated (viscosity, drag), and what the balance
``E - E(0) - W + D = 0`` leaves, which measures the time integration.
"""

from __future__ import annotations

import numpy as np

from mol_shell.views.fibres import _nearest
from mol_shell.views.fields import check_run
from mol_shell.views.figures import save_figure


def radius_node(ds, s=None):
    """Index of the node whose radius is drawn: the one nearest ``s`` (m), else the equator (largest ``r0``)."""
    if s is not None:
        return _nearest(ds["s"].values, float(s), "--at-s", "m")
    if "r0" not in ds:
        return ds.sizes["s"] // 2
    r0 = ds["r0"].values
    if np.ptp(r0) <= 1e-12 * np.abs(r0).max():  # a cylinder: every node is on the equator; the middle one
        return ds.sizes["s"] // 2
    return int(np.argmax(r0))


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
    if "dissipated" in ds or "dissipation" in ds:
        terms["D, dissipated"] = dissipated
    terms["E - E(0) - W + D (balance)"] = change - work + dissipated
    return terms


def draw_radius(ax, ds, node):
    """``r`` at ``node`` against time, with the reference radius there for scale."""
    t = ds["time"].values
    ax.plot(t, ds["r"].values[:, node], "k.-", lw=1, ms=3, label=f"r at s = {float(ds['s'][node]):.4g} m")
    if "r0" in ds:
        ax.axhline(float(ds["r0"].values[node]), color="0.7", lw=0.8, zorder=0, label="reference r0")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("r [m]")
    where = "equator" if node == radius_node(ds) else "chosen s"
    ax.set_title(f"radius at the {where} against time", fontsize=9)
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
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy [J]")
    residual = float(np.max(np.abs(list(terms.values())[-1])))
    ax.set_title(f"energy-work balance (largest |E - E(0) - W + D| = {residual:.2g} J)", fontsize=9)
    ax.legend(fontsize=7)


def history_figure(ds, s=None):
    """The radius against time and the energy-work balance (a matplotlib ``Figure``, not saved)."""
    import matplotlib.pyplot as plt

    check_run(ds)
    node = radius_node(ds, s)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    draw_radius(ax, ds, node)
    draw_balance(bx, ds)
    fig.suptitle(f"{ds.attrs.get('scene', 'run')}: radius and energy over time", fontsize=10)
    fig.tight_layout()
    return fig


def plot_history(ds, path, s=None):
    """Write :func:`history_figure` to ``path``."""
    save_figure(history_figure(ds, s), path, dpi=120)
    return path
