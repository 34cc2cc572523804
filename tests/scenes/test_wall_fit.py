"""The wall fits its meridian exactly (a short sharp arc is not missed between samples), an edge's "none" is refused
(free or auto?), and the cone's conditional range for H shows the bound it excludes."""

import numpy as np
import pytest
import xarray as xr

from mol_shell._core.errors import ParameterError
from mol_shell.analysis.path_start import scene_params
from mol_shell.cli.main import main
from mol_shell.scenes import Cone, MeridianShell, Torus, Vessel
from mol_shell.scenes.files import scene_from_dict
from mol_shell.scenes.setting import with_params

SHARP = "line 1, arc 0.001 -90, line 1, arc 0.001 -90, line 1"


@pytest.mark.parametrize("given, name", [({"knuckle": 1e-3}, "knuckle"), ({"knuckle": 1e-9}, "knuckle"),
                                         ({"segments": SHARP}, "segments")])
def test_a_wall_past_a_short_sharp_arcs_centre_is_refused_naming_the_arc(given, name):
    """h = 6.28 mm inside a 1 mm arc: the inner face passes its centre of curvature (201 samples missed it)."""
    with pytest.raises(ParameterError, match="centre of curvature of radius") as info:
        Vessel(**given)
    assert info.value.name == name


def test_the_knuckle_the_wall_fits_exactly():
    """The inner face at zeta1 = -6.306 mm: a knuckle of 6.4 mm holds it, one of 6.3 mm does not."""
    assert Vessel(knuckle=6.4e-3).knuckle == 6.4e-3
    with pytest.raises(ParameterError, match="knuckle"):
        Vessel(knuckle=6.3e-3)


@pytest.mark.parametrize("n", ["21", "81"])
def test_the_command_line_refuses_the_sharp_knuckle_at_every_n(n, tmp_path, capsys):
    assert main(["run", "vessel", "--set", "knuckle=1e-3", "--n", n, "-o", str(tmp_path / "v.nc")]) == 2
    err = capsys.readouterr().err
    assert "knuckle = 0.001 is outside" in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("given", [{"knuckle": 1e-3}, {"segments": SHARP}])
def test_a_graded_wall_past_a_short_sharp_arcs_centre_is_refused(given):
    with pytest.raises(ParameterError, match="h_profile"):
        Vessel(h_profile="0.002", **given)
    assert Vessel(h_profile="0.0009", **given).h_profile == "0.0009"  # inside the 1 mm arcs


def test_curvature_extremes_and_turning_points_of_the_meridians():
    """A points meridian's curvature extremes (roots of a polynomial per spline piece) bound a dense sampling and
    are reached to round-off; a torus segment turns (tangent along the axis) at its outer equator."""
    from mol_shell.model.wall_fit import curvature_pieces, turning_points  # the module this fix adds

    mer = MeridianShell().meridian()
    pieces = np.array(curvature_pieces(mer))
    k = mer.at(np.linspace(0.0, mer.length, 20001))[3]
    assert pieces[:, 2].min() <= k.min() + 1e-12 and pieces[:, 3].max() >= k.max() - 1e-12
    assert pieces[:, 2].min() == pytest.approx(k.min(), rel=1e-3)
    torus = Torus()
    assert turning_points(torus.meridian()) == pytest.approx([torus.a * (np.pi / 2 - torus.alpha1)])
    vessel = Vessel(segments="arc 1 -90, line 2, arc 1 -90").meridian()
    assert turning_points(vessel) == pytest.approx([np.pi / 2, np.pi / 2 + 2.0])


@pytest.mark.parametrize("value", ["none", "None", " NONE "])
def test_an_edges_none_is_refused_saying_free_or_auto(value):
    """"none" read as the set of imposed fields is free, as no choice auto: refused, not silently auto (magnet)."""
    for make in (lambda: Cone(end1=value), lambda: with_params(Cone(), {"end1": value}),
                 lambda: scene_from_dict({"scene": "cone", "edges": {"end2": value}})):
        with pytest.raises(ParameterError, match="write free for an edge that imposes no field, or auto") as info:
            make()
        assert info.value.name in ("end1", "end2")
    assert Cone(end1="auto").end1 is None and Cone(end1=None).end1 is None and Cone(end1="free").end1 == "free"
    assert with_params(Cone(), {"dilation": "none"}).dilation is None  # other parameters' none: auto


def test_an_old_files_none_edges_are_auto_again():
    """0.5.0 stored end1 = end2 = "none" for auto: a file read back runs its scene as before."""
    ds = xr.Dataset(attrs={"scene": "cone", "end1": "none", "end2": "free"})
    assert scene_params(ds)["end1"] is None and scene_params(ds)["end2"] == "free"


def test_the_listing_explains_auto_and_has_no_none(capsys):
    assert main(["scenes", "cone"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.strip().startswith("end1 "))
    assert "auto (a pole on the axis, magnet elsewhere)" in line and "none" not in line


def test_a_flat_rings_refusal_shows_the_open_bound():
    with pytest.raises(ParameterError) as info:
        Cone(r1=1.0, r2=1.0, H=0.0)
    assert str(info.value) == "H = 0.0 is outside (0, inf) m where r1 = r2 (a flat ring needs r1 != r2)"
    assert Cone(r1=1.0, r2=0.5, H=0.0).H == 0.0
