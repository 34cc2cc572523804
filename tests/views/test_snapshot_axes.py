"""The snapshot figure (r, theta, chi against s): axis ranges that show small motions, and a title clear of the panels.

The paper's axis ranges (chi in -0.2 to 0.2 rad, r in 0.985 to 1.005 m) were used whenever the data fit inside
them, so a twist of gamma = 0.001 rad/m (chi within +-0.002 rad) was drawn as flat lines; they are now used only
where the data fill a fair share of them, as the paper's own twist gamma = 0.1 rad/m does (chi = gamma (s - L/2)
spans all of -0.2 to 0.2 rad at L = 4 m). And the figure's title, placed 2 % of the figure's height below its top
edge, overprinted the top panels' titles once more than 12 times (three rows of panels a time) were drawn.
"""

import matplotlib.pyplot as plt
import pytest

import mol_shell
from mol_shell.views.plotting import PAPER_LIMITS, snapshot_figure

L = 4.0  # the cylinder's length (m)


def _run(gamma, times):
    return mol_shell.simulate(mol_shell.TwistedCylinder(gamma=gamma), n=10, t_end=times[-1], times=times,
                              progress=False, stresses=False)


def _ylims(fig):
    """``{field: (bottom, top)}`` of the first column's panels, which carry the field's label."""
    labels = {"r [m]": "r", r"$\theta$ [rad]": "theta", r"$\chi$ [rad]": "chi"}
    return {labels[ax.get_ylabel()]: ax.get_ylim() for ax in fig.axes if ax.get_ylabel() in labels}


def test_a_small_twist_is_drawn_on_axes_fitted_to_it():
    """chi = gamma (s - L/2) at t = 0 spans gamma L = 0.004 rad (1 % of the paper's 0.4 rad), and the twist only
    relaxes afterwards: the chi axis spans that, give or take its margin, not the paper's 0.4 rad."""
    gamma = 0.001
    ds = _run(gamma, [0.0, 0.005, 0.01])
    fig = snapshot_figure(ds)
    try:
        limits = _ylims(fig)
        bottom, top = limits["chi"]
        assert bottom <= -gamma * L / 2 and top >= gamma * L / 2  # the data inside
        assert top - bottom <= 1.2 * gamma * L, (bottom, top)  # was 0.4 rad, 100 times the data's 0.004
        for name in ("r", "theta"):  # both move by far less than a micrometre, a microradian: fitted too
            bottom, top = limits[name]
            span = float(ds[name].max() - ds[name].min())
            assert 0 < span <= top - bottom <= 1.2 * span, (name, bottom, top, span)
    finally:
        plt.close(fig)


def test_the_paper_s_twist_keeps_the_paper_s_chi_axis():
    """The paper's gamma = 0.1 rad/m: chi spans -gamma L/2 to gamma L/2 = -0.2 to 0.2 rad, all of the paper's
    range; at t = 0 alone r and theta are constant (a flat line) and keep the paper's ranges as well."""
    assert PAPER_LIMITS["chi"] == (-0.1 * L / 2, 0.1 * L / 2)
    ds = _run(0.1, [0.0, 0.005, 0.01])
    for times in ([0], [0, 1, 2]):
        fig = snapshot_figure(ds.isel(time=times))
        try:
            limits = _ylims(fig)
            assert limits["chi"] == PAPER_LIMITS["chi"], (times, limits)
            if len(times) == 1:
                assert limits == PAPER_LIMITS
        finally:
            plt.close(fig)


@pytest.fixture(scope="module")
def thirty_times():
    return _run(0.1, [k * 1e-4 for k in range(30)])


@pytest.mark.parametrize(("count", "note"), [(14, False), (30, True)])  # 30: 24 drawn, a second line says so
def test_the_title_clears_the_top_panels_titles(thirty_times, tmp_path, count, note):
    """Before, at 14 times the title's one line lay over "t = 0.0002 s" and "t = 0.0003 s", at 30 its two lines
    (the second "24 of 30 saved times shown") over two or three top panels' titles."""
    fig = snapshot_figure(thirty_times.isel(time=slice(0, count)))
    try:
        fig.savefig(tmp_path / "snapshots.png", dpi=120)  # as plot_snapshots saves it
        renderer = fig.canvas.get_renderer()
        title = fig._suptitle.get_window_extent(renderer)
        assert ("24 of 30 saved times shown" in fig._suptitle.get_text()) == note
        panels = [ax.title.get_window_extent(renderer) for ax in fig.axes if ax.get_visible() and ax.get_title()]
        assert len(panels) == min(count, 24)
        assert not [box for box in panels if box.overlaps(title)], (title, panels[:6])
        assert title.y0 > max(box.y1 for box in panels)  # above them all
        assert title.y1 <= fig.bbox.y1  # and inside the figure
    finally:
        plt.close(fig)
