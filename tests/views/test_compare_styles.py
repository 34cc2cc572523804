"""The compare figure: each integrator its own colour and marker (14 lines shared matplotlib's 10-colour cycle:
cvode-adams and dop853-c, the two fastest, both solid green in docs/work_precision.png), and the points whose
measured error is at or below the reference's own error level drawn hollow (the figure claimed errors the reference
cannot measure)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.colors as mcolors
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from mol_shell.integrators import INTEGRATORS
from mol_shell.views import workprecision as views
from mol_shell.views.workprecision import figure

LEVEL = 3.8e-11  # the reference's error in the docs' figure


def _comparison(names, levels=6):
    """Every integrator of ``names``: errors from 1e-4 down to 1e-13 (the last two points below :data:`LEVEL`)."""
    k = len(names)
    error = np.tile(np.logspace(-4, -13, levels), (k, 1)) * np.linspace(1, 2, k)[:, None]
    wall = np.tile(np.logspace(-2, 0, levels), (k, 1)) * np.linspace(1, 3, k)[:, None]
    dims = ("integrator", "level")
    ds = xr.Dataset({"wall_time_s": (dims, wall), "error": (dims, error),
                     "status": (dims, np.full((k, levels), "complete"))}, coords={"integrator": names})
    ds.attrs.update(reference_error=LEVEL, scene="twisted-cylinder", n=40, times="0,0.143")
    return ds


def _artist(ax, gid):
    found = [line for line in ax.get_lines() if line.get_gid() == gid]
    assert len(found) <= 1, gid
    return found[0] if found else None


def test_every_integrator_has_its_own_colour_and_marker_in_the_figure_and_its_legend():
    names = list(INTEGRATORS)
    fig = figure(_comparison(names))
    try:
        ax = fig.axes[0]
        legend = {text.get_text(): handle for text, handle in
                  zip(ax.get_legend().get_texts(), ax.get_legend().legend_handles)}
        shown = [(mcolors.to_hex(legend[name].get_color()), legend[name].get_marker()) for name in names]
        assert len({colour for colour, _ in shown}) == len(names), shown  # colours alone (tab20 has 20)
        drawn = [_artist(ax, f"{name}:measured") for name in names]
        assert [(mcolors.to_hex(line.get_color()), line.get_marker()) for line in drawn] == shown
    finally:
        plt.close(fig)
    more = views.styles([*names, *(f"new-{k}" for k in range(8))])  # names without a fixed style: distinct
    assert len({colour for colour, _, _ in more.values()}) == 20  # colours while tab20 has them, then pairs
    assert len({(colour, marker) for colour, marker, _ in more.values()}) == len(names) + 8


def test_points_at_or_below_the_reference_s_error_are_drawn_hollow():
    ds = _comparison(["cvode-adams", "dop853-c"])
    fig = figure(ds)
    try:
        ax = fig.axes[0]
        for name in ("cvode-adams", "dop853-c"):
            error = ds.error.sel(integrator=name).values
            below, measured = _artist(ax, f"{name}:below"), _artist(ax, f"{name}:measured")
            np.testing.assert_array_equal(below.get_ydata(), error[error <= LEVEL])
            np.testing.assert_array_equal(measured.get_ydata(), error[error > LEVEL])
            assert below.get_ydata().size == 2 and below.get_markerfacecolor() == "none"
            assert mcolors.to_hex(measured.get_markerfacecolor()) == mcolors.to_hex(measured.get_color())
        labels = [text.get_text() for text in ax.get_legend().get_texts()]
        assert "reference's error, 3.8e-11" in labels and any(label.startswith("hollow: ") for label in labels)
    finally:
        plt.close(fig)
