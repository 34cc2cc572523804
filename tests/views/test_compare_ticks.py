"""The compare figure's wall-time axis: its tick labels do not overlap (matplotlib labelled the minor ticks of an axis
spanning up to about a decade and a half, 2, 3, 4, 6 x 10^e, and "3x10^-3 4x10^-3" ran into each other)."""

import itertools

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from mol_shell.views.workprecision import figure


def _comparison(lo, hi):
    """Two integrators, three levels each, wall times from ``lo`` to ``hi`` s."""
    wall = np.array([[lo, (lo * hi) ** 0.5, hi], [lo * 1.1, hi * 0.9, hi * 0.95]])
    error = np.array([[1e-4, 1e-6, 1e-8], [1e-5, 1e-7, 1e-9]])
    dims = ("integrator", "level")
    ds = xr.Dataset({"wall_time_s": (dims, wall), "error": (dims, error), "status": (dims, np.full((2, 3), "complete"))},
                    coords={"integrator": ["cvode-bdf", "scipy-radau"]})
    ds.attrs.update(reference_error=1e-10, scene="twisted-cylinder", n=11, times="0,0.01")
    return ds


def _labels(fig):
    """The x tick labels drawn inside the axis, as (text, bounding box in pixels), left to right."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    lo, hi = sorted(ax.get_xlim())
    ticks = [t for t in ax.xaxis.get_major_ticks() + ax.xaxis.get_minor_ticks()
             if lo <= t.get_loc() <= hi and t.label1.get_visible() and t.label1.get_text()]
    return sorted(((t.label1.get_text(), t.label1.get_window_extent(renderer)) for t in ticks), key=lambda x: x[1].x0)


@pytest.mark.parametrize("lo, decades", [(2.2e-3, 1.3), (2.7e-3, 1.2), (1.7e-3, 1.5), (2.5e-3, 0.3), (1.3e-3, 0.1),
                                         (1e-4, 6.0)])
def test_the_wall_time_labels_do_not_overlap(lo, decades):
    """A span of 1.2 to 1.5 decades (each overlapped before), a third of a decade, a tenth (matplotlib's own fallback
    crowded 1.3, 1.35, 1.4 ... x 10^-3) and six decades: at least two labels, each box clear of the next one."""
    fig = figure(_comparison(lo, lo * 10**decades))
    try:
        labels = _labels(fig)
        assert len(labels) >= 2, labels
        for (left, a), (right, b) in itertools.pairwise(labels):
            assert a.x1 < b.x0, (left, right)
    finally:
        plt.close(fig)
