"""Animations draw no more bands along s than the frame has pixels: a frame of 5,000 nodes x 48 azimuths drew 240,000
quads (3 s a frame, 35 s for 11 frames of a 480 px GIF); the bands between the drawn nodes show the mean of the cells
they span."""

from __future__ import annotations

import numpy as np
import pytest

import mol_shell
from mol_shell.views import animate as animate_module
from mol_shell.views.fields import drawn_rows, row_means


@pytest.mark.parametrize("count,most", [(5, 10), (11, 10), (12, 10), (5000, 480), (2001, 480)])
def test_drawn_rows_keep_both_ends_and_at_most_the_room(count, most):
    rows = drawn_rows(count, most)
    assert rows[0] == 0 and rows[-1] == count - 1 and np.all(np.diff(rows) > 0)
    assert len(rows) == min(count, most + 1)
    if count > most + 1:  # nearly even: no band more than one node wider than another
        assert np.diff(rows).max() - np.diff(rows).min() <= 1


def test_a_band_shows_the_mean_of_the_cells_it_spans():
    values = np.arange(10.0) ** 2  # 10 cells between 11 nodes
    rows = np.array([0, 3, 7, 10])
    np.testing.assert_array_equal(row_means(values, rows), [np.mean(values[0:3]), np.mean(values[3:7]),
                                                            np.mean(values[7:10])])
    np.testing.assert_array_equal(row_means(values, np.arange(11)), values)  # every node drawn: the cells as they are


def test_an_animation_of_more_nodes_than_pixels_draws_a_band_per_pixel(tmp_path, monkeypatch):
    ds = mol_shell.simulate("twisted-cylinder", "dop853-c", n=161, times=[0.0, 1e-3])
    drawn = []
    surface = animate_module._surface
    monkeypatch.setattr(animate_module, "_surface", lambda points, colours: drawn.append(points.shape) or
                        surface(points, colours))
    assert animate_module.animate(ds, str(tmp_path / "a.gif"), width=100, progress=False) == 2
    # a 100 x 90 px frame: 101 drawn nodes of the 161 (both ends), n_phi + 1 = 49 azimuths closing the surface
    assert drawn and set(drawn) == {(101, 49, 3)}  # each frame drawn (the palette's and the written ones)
