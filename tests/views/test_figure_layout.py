"""Figures whose text stood on the figure's edge or on itself: the fibres figure had no axis labels or units (its x
label fell off the bottom), the time ticks of the history panels ran together ("0.00000.00050.0010..."), and the
modes figure labelled its scaled shapes "[m]" and "[rad]" and its s axis "s (m)" where every other figure says
"s [m]"."""

from __future__ import annotations

import itertools

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

import mol_shell
from mol_shell.views.fibres import fibres_figure
from mol_shell.views.history import history_figure
from mol_shell.views.modes import modes_figure
from mol_shell.views.plotting import meridian_figure

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def run():
    """The paper's scene on 6 nodes saved every 0.5 ms to 4 ms: nine time ticks' worth of milliseconds."""
    return mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=np.arange(9) * 5e-4, progress=False,
                              stresses=False)


def _inside(fig, text):
    """Whether ``text`` (an artist) is drawn whole inside the figure."""
    box, frame = text.get_window_extent(), fig.bbox
    return frame.x0 - 0.5 <= box.x0 and box.x1 <= frame.x1 + 0.5 and frame.y0 - 0.5 <= box.y0 and box.y1 <= frame.y1 + 0.5


@pytest.mark.parametrize("reinforced", [False, True])
def test_the_fibres_figure_has_its_axes_labelled_in_metres_inside_it_and_drawn_to_scale(run, reinforced):
    ds = run.copy()
    if reinforced:  # a third panel: the reinforcing fibres seen from the side
        ds.attrs.update(fibre_E=1e6, fibre_angle=0.5, fibre_families=2)
    fig = fibres_figure(ds)
    fig.canvas.draw()
    assert len(fig.axes) == (3 if reinforced else 2)
    for ax in fig.axes:
        for label in (ax.xaxis.label, ax.yaxis.label):
            assert "[m]" in label.get_text() and _inside(fig, label), (label.get_text(), label.get_window_extent())
        box = ax.get_window_extent()
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        assert (x1 - x0) / box.width == pytest.approx((y1 - y0) / box.height, rel=1e-6)  # a circle drawn round
    panels = sorted((ax.get_tightbbox() for ax in fig.axes), key=lambda b: b.x0)
    assert all(a.x1 <= b.x0 for a, b in itertools.pairwise(panels))  # no panel's text on its neighbour
    plt.close(fig)


@pytest.mark.parametrize("figure", [history_figure, meridian_figure])
def test_time_tick_labels_stand_apart(run, figure):
    fig = figure(run)
    fig.canvas.draw()
    checked = 0
    for ax in fig.axes:
        if ax.get_xlabel() != "t [s]":
            continue
        boxes = sorted((t.get_window_extent() for t in ax.get_xticklabels() if t.get_visible() and t.get_text()),
                       key=lambda b: b.x0)
        assert len(boxes) >= 3
        assert all(a.x1 + 2 <= b.x0 for a, b in itertools.pairwise(boxes)), [(b.x0, b.x1) for b in boxes]
        checked += 1
    plt.close(fig)
    assert checked == 2


def test_the_mode_shapes_are_labelled_as_scaled_shapes_along_s_in_metres():
    ds = mol_shell.modes(mol_shell.Sphere(), n=9, count=3)
    fig = modes_figure(ds, count=3)
    labels = {ax.get_ylabel().replace("\n", " ") for ax in fig.axes if ax.get_ylabel()}
    assert labels == {"shape of z, r (scaled)", "shape of chi, theta, psi (scaled)"}
    assert {ax.get_xlabel() for ax in fig.axes if ax.get_xlabel()} == {"s [m]"}
    plt.close(fig)
