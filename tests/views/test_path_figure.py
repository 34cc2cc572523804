"""The path figure: the path split at its critical points (solid up to the point, dashed past it), one label for
points at nearly one place, the modes' legend outside the meridian, and the response named for what it is.

Drawn from a small hand-made path file (steps, counts of negative eigenvalues and critical points set here), so
what each piece must be is known without a continuation."""

import matplotlib
import numpy as np
import pytest
import xarray as xr
from matplotlib.text import Text

from mol_shell.views.path_plot import _pieces, critical_response, path_figure

matplotlib.use("Agg")


def path_file(loads, negatives, points):
    """A path in ``pressure`` with conjugate ``4 - load/1000``; ``points``: ``(kind, step, load)``."""
    loads = np.asarray(loads, float)
    s = np.linspace(0.0, np.pi, 9)
    r0, z0 = np.sin(s), -np.cos(s)
    count = len(points)
    mode = np.tile(np.sin(2 * s), (count, 1))
    ds = xr.Dataset(
        {"parameter": ("step", loads, {"units": "Pa"}),
         "load_conjugate": ("step", 4.0 - loads / 1000.0, {"units": "m3"}),
         "negative_eigenvalues": ("step", np.asarray(negatives)),
         "point_kind": ("point", [p[0] for p in points]), "point_step": ("point", [p[1] for p in points]),
         "point_parameter": ("point", [float(p[2]) for p in points], {"units": "Pa"}),
         "point_family": ("point", ["axisymmetric"] * count),
         "r0": ("s", r0), "z0": ("s", z0),  # a path's states along it (the figure checks it is given a path)
         "r": (("step", "s"), np.tile(r0, (len(loads), 1))), "z": (("step", "s"), np.tile(z0, (len(loads), 1))),
         "point_r": (("point", "s"), np.tile(r0, (count, 1))), "point_z": (("point", "s"), np.tile(z0, (count, 1))),
         "point_mode_r": (("point", "s"), mode), "point_mode_z": (("point", "s"), 0.5 * mode)},
        coords={"s": s}, attrs={"parameter": "pressure", "scene": "sphere"})
    return ds


def test_a_step_that_crosses_a_critical_point_is_solid_up_to_it_and_dashed_past_it():
    ds = path_file([0, -100, -200, -300], [0, 0, 1, 1], [("bifurcation", 1, -150.0)])
    x = ds.load_conjugate.values
    marks = [(critical_response(ds, x, 0), -150.0)]
    assert marks[0][0] == pytest.approx(4.15)  # interpolated in the load between steps 1 and 2
    pieces = [(tuple(xs), tuple(loads), ok) for xs, loads, ok in _pieces(ds, x, marks)]
    assert pieces == [((4.0, 4.1), (0.0, -100.0), True), ((4.1, pytest.approx(4.15)), (-100.0, -150.0), True),
                      ((pytest.approx(4.15), 4.2), (-150.0, -200.0), False), ((4.2, 4.3), (-200.0, -300.0), False)]


def test_between_two_critical_points_of_one_step_the_path_is_unstable():
    ds = path_file([0, -100, -200], [0, 0, 0], [("bifurcation", 1, -120.0), ("bifurcation", 1, -180.0)])
    x = ds.load_conjugate.values
    marks = [(critical_response(ds, x, m), ds.point_parameter.values[m]) for m in range(2)]
    oks = [ok for _, _, ok in _pieces(ds, x, marks)]
    assert oks == [True, True, False, True]  # one eigenvalue crosses down at -120 Pa and back at -180 Pa


def test_the_figure_draws_those_pieces_labels_close_points_once_and_keeps_the_legend_off_the_modes():
    ds = path_file([0, -100, -200, -300, -1000], [0, 0, 1, 1, 3],
                   [("bifurcation", 1, -150.0), ("bifurcation", 1, -155.0), ("bifurcation", 1, -158.0),
                    ("limit", 3, -900.0)])
    fig = path_figure(ds)
    left, right = fig.axes
    dashed = [line for line in left.get_lines() if line.get_linestyle() == "--"]
    solid = [line for line in left.get_lines() if line.get_linestyle() == "-"]
    assert max(float(np.max(line.get_ydata())) for line in dashed) == pytest.approx(-150.0)  # dashed from point 0
    assert min(float(np.min(line.get_ydata())) for line in solid) == pytest.approx(-150.0)  # solid up to it
    labels = sorted(t.get_text() for t in left.texts)
    assert labels == ["0-2", "3"]  # three points within 4 % of the axes: one label; the limit far from them: its own
    assert left.get_xlabel() == "enclosed volume (load_conjugate) [m3]" and "enclosed volume" in left.get_title()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend = right.get_legend().get_window_extent(renderer)
    axes = right.get_window_extent(renderer)
    assert legend.y1 <= axes.y0 and len(right.get_legend().get_texts()) == 5  # below the meridian, all modes listed
    assert legend.y0 >= 0  # and inside the figure


def test_labels_of_critical_points_close_together_stand_apart():
    """Three bifurcations within 1.3 % of the load, the middle one 5 % of the response off the other two (which share
    the label "0, 2"), and a limit point far off: three labels, none on another (the middle one's "1" stood on
    "0, 2"), each joined to its point when moved off its place beside it."""
    loads = [0, -400, -800, -1200, -1210, -1220, -1600]
    ds = path_file(loads, [0, 0, 0, 0, 1, 2, 3], [("bifurcation", 3, -1200.0), ("bifurcation", 4, -1210.0),
                                                   ("bifurcation", 5, -1220.0), ("limit", 1, -400.0)])
    ds["load_conjugate"].values[:] = [4.0, 3.6, 3.2, 2.8, 2.88, 2.8, 2.4]  # the response turns back and forth
    fig = path_figure(ds)
    left = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = {t.get_text(): Text.get_window_extent(t, renderer) for t in left.texts}  # the words, not the lines
    assert sorted(texts) == ["0, 2", "1", "3"]
    boxes = list(texts.values())
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:]), texts
