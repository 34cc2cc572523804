"""A meridian's self-intersection check and its wall fit on long tables: the same answers as the definitions,
in time near linear in the table's rows."""

import time

import numpy as np
import pytest

import mol_shell
from mol_shell.model import polyline
from mol_shell.model.polyline import segments_meet, self_intersects
from mol_shell.model.wall_fit import curvature_pieces, turning_points


def brute_force(points):
    """Every pair of non-adjacent segments (the first and last of a closed polyline are adjacent), no boxes."""
    points = np.asarray(points, dtype=float)
    a, b = points[:-1], points[1:]
    n = len(a)
    tol = 1e-12 * float(np.max(np.abs(points)))
    closed = n > 2 and float(np.max(np.abs(points[0] - points[-1]))) <= tol
    i, j = np.triu_indices(n, 2)
    keep = ~(closed & (i == 0) & (j == n - 1))
    return bool(keep.any()) and segments_meet(a[i[keep]], b[i[keep]], a[j[keep]], b[j[keep]], tol)


@pytest.mark.parametrize("chunk", [1 << 18, 1])
def test_the_sweep_finds_what_every_pair_finds(chunk, monkeypatch):
    """Random polylines (scattered points, arcs that may wind past a full turn, points on a coarse grid that touch
    and overlap collinearly, closed loops): the sweep's answer is the pairwise definition's, also when each block
    holds one candidate pair."""
    monkeypatch.setattr(polyline, "CHUNK", chunk)
    rng = np.random.default_rng(7)
    answers = set()
    for trial in range(400):
        m = int(rng.integers(2, 25))
        kind = trial % 4
        if kind == 0:
            pts = rng.random((m, 2))
        elif kind == 1:
            t = np.sort(rng.random(m)) * rng.uniform(1.0, 8.0)
            pts = np.column_stack([1.0 + 0.5 * np.cos(t), np.sin(t)])
        elif kind == 2:
            pts = np.round(rng.random((m, 2)) * 3.0) / 3.0
        else:
            t = np.linspace(0.0, 2.0 * np.pi, m)
            pts = np.column_stack([2.0 + np.cos(t), np.sin(t)])
        expected = brute_force(pts)
        assert self_intersects(pts) == expected, (trial, pts)
        answers.add(expected)
    assert answers == {True, False}


def test_a_long_straight_or_curved_table_is_checked_in_linear_time():
    """200,000 segments along a cylinder's generator (every box overlapping in r) or a half circle: the sweep runs
    along the larger spread, so each segment has a handful of candidates; pairwise, 2e10 comparisons."""
    n = 200_000
    t = np.linspace(0.0, np.pi, n)
    for pts in (np.column_stack([np.ones(n), np.linspace(0.0, 1.0, n)]), np.column_stack([np.sin(t), -np.cos(t)])):
        start = time.perf_counter()
        assert not self_intersects(pts)
        assert time.perf_counter() - start < 10.0
    folded = np.concatenate([pts, pts[-2:n // 2:-1] + [1e-3, 0.0]])  # back alongside itself, then across
    folded = np.concatenate([folded, [[0.5, 0.5], [1.5, -0.5]]])
    assert self_intersects(folded)


def test_a_five_thousand_row_table_gives_its_exact_curvature_pieces(tmp_path):
    """A dome of 5,000 rows: each spline piece's curvature extremes and the turning points of r, found for all pieces
    at once, are those of each piece's own polynomials (numpy's poly1d and roots, piece by piece, on 200 pieces);
    the table's scene is made in seconds (it took minutes)."""
    t = np.linspace(0.05, np.pi - 0.05, 5000)
    path = tmp_path / "dome.txt"
    np.savetxt(path, np.column_stack([np.sin(t), -np.cos(t)]))
    start = time.perf_counter()
    meridian = mol_shell.get_scene("meridian", points=str(path)).meridian()
    assert time.perf_counter() - start < 8.0  # 15 s before the pieces were found together
    pieces = curvature_pieces(meridian)
    spline, u = meridian._spline, meridian._u
    for i in range(0, len(u) - 1, 25):
        r, z = (np.poly1d(spline.c[:, i, j]) for j in (0, 1))
        dr, dz = r.deriv(), z.deriv()
        N, S = dz * dr.deriv() - dr * dz.deriv(), dr * dr + dz * dz
        span = u[i + 1] - u[i]
        cand = [0.0, span] + [x.real for x in np.roots((N.deriv() * S - 1.5 * N * S.deriv()).coeffs)
                              if abs(x.imag) < 1e-12 and 0 < x.real < span]
        k = [N(x) / S(x) ** 1.5 for x in cand]
        assert pieces[i][2:] == pytest.approx((min(k), max(k)), rel=1e-12)
        assert pieces[i][2] == pytest.approx(-1.0, rel=1e-6)  # the unit circle's curvature, to the spline's error
    # r = sin(t) turns at the equator only, where the tangent is along the axis: s = pi/2 - 0.05 from the first row
    assert turning_points(meridian) == pytest.approx([np.pi / 2 - 0.05], abs=1e-6)
