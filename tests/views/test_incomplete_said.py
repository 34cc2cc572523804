"""Every view of a run that stopped early says so, as the paper's figures did alone: the history and fibres figures,
the frames and printed line of ``animate``, the printed line and the files of ``export``; a path that ended at
``max_steps`` short of its range says it in its figure and printed line, and a study of paths marks its cases that
did."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from PIL import Image

import mol_shell
from mol_shell.analysis.path_study import path_study
from mol_shell.cli.main import main
from mol_shell.views.fibres import fibres_figure
from mol_shell.views.figures import path_note
from mol_shell.views.history import history_figure
from mol_shell.views.path_plot import path_figure
from mol_shell.views.path_study_plot import path_study_figure

MESSAGE = "delta = r beta1 cos(psi) reached 0 at t = 2e-06 s, s = 1 m (cell centre): a limit of the model"
SMALL = ["--n-phi", "6", "--fibres", "2", "--width", "160"]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """A run of the paper's scene (6 nodes, 3 saved times) as it stopped at a limit, and complete."""
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=6, times=[0.0, 1e-6, 2e-6], progress=False,
                            stresses=False)
    folder = tmp_path_factory.mktemp("incomplete")
    stopped = ds.copy()
    stopped.attrs.update(status="limit", complete=0, message=MESSAGE)
    mol_shell.write_netcdf(stopped, folder / "stopped.nc")
    mol_shell.write_netcdf(ds, folder / "complete.nc")
    return folder / "stopped.nc", folder / "complete.nc"


def _title(fig):
    import matplotlib.pyplot as plt

    text = fig._suptitle.get_text() if fig._suptitle is not None else ""
    plt.close(fig)
    return " ".join(text.split())  # the lines and the no-break spaces that keep "name = value" whole


def test_the_history_and_fibres_figures_say_it(runs):
    stopped, complete = runs
    for figure in (history_figure, fibres_figure):
        said = _title(figure(stopped))
        assert "[INCOMPLETE: delta = r beta1 cos(psi) reached 0" in said, (figure.__name__, said)
        assert "INCOMPLETE" not in _title(figure(complete)), figure.__name__


@pytest.mark.parametrize("figure", ["history", "fibres", "snapshots"])
def test_plot_says_it_in_its_line(runs, tmp_path, capsys, figure):
    stopped, complete = runs
    assert main(["plot", str(stopped), "--figure", figure, "-o", str(tmp_path / "f.png")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("wrote ") and "[INCOMPLETE: delta = r beta1 cos(psi) reached 0" in out, out
    assert main(["plot", str(complete), "--figure", figure, "-o", str(tmp_path / "g.png")]) == 0
    assert "INCOMPLETE" not in capsys.readouterr().out


def _foot(gif):
    """Dark pixels in the lower left corner of a GIF's first frame (where a stopped run's frames carry the note,
    left of the shell)."""
    with Image.open(gif) as image:
        rgb = np.asarray(image.convert("RGB"), dtype=int)
    return int((rgb[-rgb.shape[0] // 6:, : rgb.shape[1] // 8].max(axis=-1) < 100).sum())


def test_animate_says_it_in_each_frame_and_in_its_line(runs, tmp_path, capsys):
    stopped, complete = runs
    assert main(["animate", str(stopped), *SMALL, "-o", str(tmp_path / "s.gif")]) == 0
    out = capsys.readouterr().out
    assert "3 frames" in out and "[INCOMPLETE: delta = r beta1 cos(psi) reached 0" in out, out
    assert main(["animate", str(complete), *SMALL, "-o", str(tmp_path / "c.gif")]) == 0
    assert "INCOMPLETE" not in capsys.readouterr().out
    assert _foot(tmp_path / "s.gif") > 50 and _foot(tmp_path / "c.gif") == 0


@pytest.mark.parametrize("suffix", ["xdmf", "pvd"])
def test_export_says_it_in_its_line_and_its_file(runs, tmp_path, capsys, suffix):
    stopped, complete = runs
    assert main(["export", str(stopped), "--n-phi", "4", "-o", str(tmp_path / f"s.{suffix}")]) == 0
    assert "[INCOMPLETE: delta = r beta1 cos(psi) reached 0" in capsys.readouterr().out
    text = (tmp_path / f"s.{suffix}").read_text()
    assert "<!-- mol_shell run of scene twisted-cylinder [INCOMPLETE: delta = r beta1" in text
    assert main(["export", str(complete), "--n-phi", "4", "-o", str(tmp_path / f"c.{suffix}")]) == 0
    assert "INCOMPLETE" not in capsys.readouterr().out + (tmp_path / f"c.{suffix}").read_text()
    if suffix == "xdmf":  # still a series its readers take
        import meshio

        with meshio.xdmf.TimeSeriesReader(tmp_path / "s.xdmf") as reader:
            reader.read_points_cells()
            assert reader.num_steps == 3


@pytest.fixture(scope="module")
def short_path(tmp_path_factory):
    """A sphere's path in pressure stopped by max_steps = 2 far short of -1000 Pa."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, -1000.0, n=11, max_steps=2)
    path = tmp_path_factory.mktemp("short_path") / "p.nc"
    mol_shell.write_netcdf(ds, path)
    return path, ds


def test_a_path_that_ended_short_says_where(short_path, tmp_path, capsys):
    path, ds = short_path
    assert ds.attrs["status"] == "max_steps" and ds.sizes["step"] == 3
    last = float(ds.parameter.values[-1])
    assert -1000.0 < last < 0.0
    said = _title(path_figure(path))
    assert said.startswith("[ENDED SHORT: stopped after max_steps = 2 steps") and f"pressure = {last:.6g}" in said
    assert "of its range 0 to -1000 Pa" in said, said
    assert main(["plot", str(path), "-o", str(tmp_path / "p.png")]) == 0
    assert "[ENDED SHORT: stopped after max_steps = 2 steps" in capsys.readouterr().out


def test_a_study_of_paths_marks_the_cases_that_ended_short():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = path_study(mol_shell.Sphere(), {"nu": [0.3, 0.35]}, "pressure", 0.0, -1000.0, n=11, max_steps=2,
                        scheduler="serial")
    assert ds.status.values.tolist() == ["max_steps", "max_steps"]
    fig = path_study_figure(ds)
    ax = fig.axes[0]
    title = " ".join(ax.get_title().split())
    marks = [segment for c in ax.collections if c.get_gid() == "ended short" for segment in c.get_segments()]
    labels = [text.get_text() for text in ax.texts]
    import matplotlib.pyplot as plt

    plt.close(fig)
    got = [f"{v:.6g} Pa" for v in ds.reached.values]  # and where each ended
    assert (f"[ENDED SHORT of pressure = -1000 Pa: nu = 0.3 (max_steps at {got[0]}); nu = 0.35 (max_steps at "
            f"{got[1]})]") in title, title
    assert sorted(float(segment[0][0]) for segment in marks) == [0.3, 0.35]  # a dotted line at each case
    assert labels.count("max_steps") == 2


def test_an_interrupted_path_s_note_says_where_it_stopped_once():
    """The interrupt's message says where already: the figure's title said it twice ("... at pressure = -744.21 Pa
    at pressure = -744.21 of its range ..."). A path that ran out of steps says where from the last state."""
    attrs = {"complete": 0, "status": "interrupted", "parameter": "pressure", "parameter_units": "Pa", "start": 0.0,
             "stop": -1000.0, "message": "interrupted by the user at pressure = -744.21 Pa"}
    assert path_note(attrs, -744.21) == ("ENDED SHORT: interrupted by the user at pressure = -744.21 Pa of its range "
                                         "0 to -1000 Pa")
    attrs.update(status="max_steps", message="stopped after max_steps = 2 steps")
    assert path_note(attrs, -744.21) == ("ENDED SHORT: stopped after max_steps = 2 steps at pressure = -744.21 of its "
                                         "range 0 to -1000 Pa")
