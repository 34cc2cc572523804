"""The snapshot figure's title stays inside the figure, however narrow the figure and long the title.

A run stopped at its first saved time has one column of panels (3.4 in wide) and a title of its parameters and
the limit's message (about 150 characters): both ends were cut off. Long titles are now wrapped to the figure's
width, and the panels leave room for the lines.
"""

import numpy as np
import pytest

import mol_shell
from mol_shell.views.plotting import snapshot_figure


@pytest.fixture(scope="module")
def stopped_at_start():
    """gamma = 20 rad/m at R = 1 m compresses a cell past SVK's turning point at t = 0: one saved time, stopped."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(gamma=20.0, R=1.0, material="svk-plane-stress"), n=12,
                            times=[0.0, 0.1], progress=False)
    assert ds.sizes["time"] == 1 and ds.attrs["status"] == "limit", ds.attrs.get("status")
    return ds


def _inside(fig):
    fig.canvas.draw()
    box, frame = fig._suptitle.get_window_extent(), fig.bbox
    return box.x0 >= frame.x0 - 0.5 and box.x1 <= frame.x1 + 0.5 and box.y1 <= frame.y1 + 0.5


def test_a_one_column_figure_of_a_stopped_run_shows_its_whole_title(stopped_at_start):
    import matplotlib.pyplot as plt

    fig = snapshot_figure(stopped_at_start)
    try:
        assert _inside(fig), fig._suptitle.get_text()
        text = fig._suptitle.get_text().replace("\xa0", " ")  # kept together: name = value
        assert "INCOMPLETE" in text and "gamma = 20 rad/m" in text
        words = " ".join(text.split())  # nothing lost in the wrapping
        assert stopped_at_start.attrs["message"].split()[-1] in words
        title_bottom = fig._suptitle.get_window_extent().y0
        tops = [ax.get_window_extent().y1 for ax in fig.axes if ax.get_visible()]
        assert max(np.array(tops)) < title_bottom  # the panels (their titles aside) stay below it
    finally:
        plt.close(fig)
