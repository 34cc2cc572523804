"""Studies of paths (``path_study``, ``mol-shell study --path``): one path per case, the critical points gathered."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import xarray as xr
from reference_cap import cap_angle, cap_params, p_classical

from mol_shell import ParameterError, Sphere, path
from mol_shell.analysis.path_study import path_study
from mol_shell.cli.main import main

path_study_module = importlib.import_module("mol_shell.analysis.path_study")

STOP = -1.0 * p_classical()
ANGLES = [cap_angle(4.5), cap_angle(5.5)]


@pytest.fixture(scope="module")
def studied(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "caps.nc"
    ds = path_study(Sphere(**cap_params(5.0)), {"alpha2": ANGLES}, "pressure", 0.0, STOP, n=21, max_steps=30,
                    scheduler="serial", output=out)
    return out, ds


def test_each_case_has_the_critical_points_of_its_own_path(studied):
    _, ds = studied
    assert ds.point_parameter.dims == ("alpha2", "point") and ds.attrs["n_cases"] == 2
    for k, angle in enumerate(ANGLES):
        own = path(Sphere(**{**cap_params(5.0), "alpha2": angle}), "pressure", 0.0, STOP, n=21, max_steps=30)
        m = own.sizes["point"]
        assert np.array_equal(ds.point_parameter.values[k, :m], own.point_parameter.values)
        assert list(ds.point_kind.values[k, :m]) == list(own.point_kind.values)
        assert np.array_equal(ds.point_grid_mode_share.values[k, :m], own.point_grid_mode_share.values)
        assert ds.sizes["near"] == own.sizes["near"] == 0 or np.array_equal(
            ds.near_parameter.values[k, :own.sizes["near"]], own.near_parameter.values)
        assert ds.first_critical.values[k] == own.point_parameter.values[0]
        assert ds.steps.values[k] == own.sizes["step"] - 1  # steps as mol-shell path counts them (it held states)
        assert np.all(np.isnan(ds.point_parameter.values[k, m:]))
        held = [v for v in own.data_vars if v.startswith("point_end")]  # the rim's reactions at the points
        assert held and all(np.array_equal(ds[v].values[k, :m], own[v].values) for v in held)
    # a deeper cap (larger lambda) carries a larger pressure before it snaps (shallow-shell theory: the snap
    # pressure grows with the rise)
    assert ds.first_critical.values[1] < ds.first_critical.values[0] < 0


def test_a_rerun_reuses_the_finished_paths(studied):
    out, first = studied
    again = path_study(Sphere(**cap_params(5.0)), {"alpha2": ANGLES}, "pressure", 0.0, STOP, n=21, max_steps=30,
                       scheduler="serial", output=out)
    assert again.attrs["n_reused"] == 2 and again.attrs["n_executed"] == 0
    assert np.array_equal(again.point_parameter.values, first.point_parameter.values, equal_nan=True)


def test_the_command(tmp_path, capsys):
    out = tmp_path / "s.nc"
    argv = ["study", "sphere", "--vary", f"alpha2={ANGLES[0]!r},{ANGLES[1]!r}", "--path", f"pressure=0:{STOP:.6g}",
            "--n", "21", "--max-steps", "30", "--scheduler", "serial"]
    for k, v in cap_params(5.0).items():
        if k != "alpha2":
            argv += ["--set", f"{k}={v}"]
    assert main([*argv, "-o", str(out)]) == 0, capsys.readouterr().err
    assert "first critical pressure" in capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        assert ds.sizes["alpha2"] == 2 and ds.first_critical.attrs["units"] == "Pa"
        assert ds.alpha2.attrs["long_name"].endswith("(varied)")  # it had none
        # the scene's parameters as the paths used them, as a path file has them (the file had none: the wall could
        # not be told from the default one), the varied one a coordinate only; the path's range with its units
        for name, value in cap_params(5.0).items():
            if name != "alpha2":
                assert ds.attrs[name] == value and ds.attrs[f"units_{name}"] in ("m", "Pa", "1"), name
        assert "alpha2" not in ds.attrs and "units_alpha2" not in ds.attrs and ds.attrs["edge_sL"] == "clamped"
        assert ds.attrs["units_path_start"] == ds.attrs["units_path_stop"] == "Pa"
    assert main([*argv, "--t-end", "1", "-o", str(tmp_path / "x.nc")]) == 2
    assert "--t-end is an option of a study of runs" in capsys.readouterr().err
    assert main([*argv, "--option", "foo=bar", "-o", str(tmp_path / "x.nc")]) == 2  # was ignored, exit 0
    assert "--option is an option of a study of runs, not of one of paths" in capsys.readouterr().err


def test_the_study_s_figure_draws_each_case_s_critical_loads(studied, tmp_path, capsys):
    """``mol-shell plot`` of a study of paths: the first critical load of each case joined against the varied
    angle, every critical point marked; a run figure's option is refused by name."""
    import matplotlib

    matplotlib.use("Agg")
    from mol_shell.views.path_study_plot import is_path_study, path_study_figure

    out, ds = studied
    assert is_path_study(ds)
    fig = path_study_figure(ds)
    ax = fig.axes[0]
    first = ax.lines[0]
    np.testing.assert_array_equal(first.get_ydata(), ds.first_critical.values)
    np.testing.assert_array_equal(first.get_xdata(), ds.alpha2.values)
    marked = np.concatenate([line.get_ydata() for line in ax.lines[1:] if len(line.get_ydata())])
    located = ds.point_parameter.values[np.isfinite(ds.point_parameter.values)]
    assert sorted(marked) == sorted(located)
    assert "pressure" in ax.get_ylabel() and "Pa" in ax.get_ylabel()
    png = tmp_path / "study.png"
    assert main(["plot", str(out), "-o", str(png)]) == 0 and png.stat().st_size > 1000
    assert main(["plot", str(out), "--time", "0.1", "-o", str(png)]) == 2
    assert "--time" in capsys.readouterr().err


def test_on_a_dask_cluster_the_same_critical_points(studied):
    """The same study on a dask cluster (one in-process worker: the back end's submission, gathering and
    bookkeeping, not its processes, which the run studies' fault drills cover) finds the same points as serially."""
    distributed = pytest.importorskip("distributed")
    _, serial = studied
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        ds = path_study(Sphere(**cap_params(5.0)), {"alpha2": ANGLES}, "pressure", 0.0, STOP, n=21, max_steps=30,
                        scheduler=client)
    assert ds.attrs["scheduler"] != "serial" and ds.attrs["n_executed"] == 2
    assert list(ds.status.values) == list(serial.status.values)
    np.testing.assert_array_equal(ds.point_parameter.values, serial.point_parameter.values)


def test_a_study_whose_paths_meet_no_critical_point_says_so_in_the_figure(studied):
    """A study whose paths met no critical point plotted empty axes (every first_critical NaN; its summary line,
    mended too, printed "nan"). The same study with every case's critical points blanked stands in."""
    import matplotlib

    matplotlib.use("Agg")
    from mol_shell.views.path_study_plot import path_study_figure

    _, ds = studied
    none = ds.copy()
    none["first_critical"] = none.first_critical * np.nan
    none["point_parameter"] = none.point_parameter * np.nan
    none["point_kind"] = none.point_kind.where(False, "")
    texts = [t.get_text() for t in path_study_figure(none).axes[0].texts]
    assert any(t.startswith("no path met a critical point of pressure") for t in texts), texts


@pytest.mark.parametrize("start, stop, name", [(0.0, float("nan"), "stop"), (5.0, 5.0, "stop"), ("a", 1.0, "start")])
def test_a_range_every_case_shares_is_refused_up_front(start, stop, name, monkeypatch):
    """A NaN stop returned a Dataset whose every case was "refused" (``mol_shell.path`` raises): the range is checked
    once, before any case."""
    monkeypatch.setattr(path_study_module, "run_path_task", None)  # nothing may run
    with pytest.raises(ParameterError, match=rf"^{name} = "):
        path_study(Sphere(nu=0.3), {"h": [0.01, 0.02]}, "pressure", start, stop, n=10, scheduler="serial")


def test_an_unknown_name_in_a_path_study_lists_scene_parameters_only(tmp_path, capsys):
    """``study --path`` with ``--vary foo=...`` listed the leap-frog's options (chunk, dt) as allowed, which the next
    attempt (``--vary dt=...``) was refused: a study of paths lists its scene's parameters only."""
    from mol_shell.cli.main import main

    for name in ("foo", "dt"):
        assert main(["study", "sphere", "--vary", f"{name}=1,2", "--path", "pressure=0:-100", "--n", "8",
                     "-o", str(tmp_path / "s.nc")]) == 2
        err = capsys.readouterr().err.strip()
        assert f"vary = '{name}' is outside {{" in err and "chunk" not in err and " dt," not in err, err
