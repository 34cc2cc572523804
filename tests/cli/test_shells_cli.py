"""Command line for shells of revolution: scenes listing, runs and plots of a sphere, modes and their refusals."""

import dataclasses

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main


def test_scenes_lists_every_registered_scene_and_a_scenes_parameters(capsys):
    from mol_shell.scenes import SCENES

    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in SCENES)
    assert main(["scenes", "torus"]) == 0
    head, columns, *rows = capsys.readouterr().out.splitlines()
    assert head.startswith("torus: ") and columns.split()[:3] == ["parameter", "default", "units"]
    torus = SCENES["torus"]()
    rows = rows[: len(dataclasses.fields(torus))]  # then a note on auto and ''
    shown = {row.split()[0]: row.split()[1] for row in rows}  # name, default, unit, description
    assert shown == {f.name: "auto" if getattr(torus, f.name) is None else "''" if getattr(torus, f.name) == "" else
                     str(getattr(torus, f.name)) for f in dataclasses.fields(torus)}  # '': an empty string shown
    assert main(["scenes", "drum"]) == 2
    assert "scene = 'drum' is outside" in capsys.readouterr().err


def test_sphere_run_plot_and_modes(tmp_path, capsys):
    run = tmp_path / "sphere.nc"
    assert main(["run", "sphere", "--set", "R=1.01", "--n", "21", "--t-end", "0.002", "-o", str(run)]) == 0
    ds = xr.open_dataset(run, decode_times=False)
    assert ds.attrs["edge_s0"] == "pole" and ds.attrs["edge_sL"] == "pole"
    assert float(abs(ds.r.isel(s=0)).max()) == 0.0 and float(abs(ds.r.isel(s=-1)).max()) == 0.0  # poles stay on the axis
    assert float(ds.r0.isel(s=10)) == 1.0  # the equator of the unit sphere (s = pi/2 at n = 21)
    ds.close()
    png = tmp_path / "sphere.png"
    assert main(["plot", str(run), "-o", str(png)]) == 0 and png.stat().st_size > 10_000
    out = tmp_path / "modes.nc"
    assert main(["modes", "sphere", "--n", "21", "--count", "4", "-o", str(out)]) == 0
    modes = xr.open_dataset(out)
    assert modes.attrs["zero_modes"] == 2 and modes.sizes["mode"] == 4
    assert (modes.frequency.diff("mode") >= 0).all()
    modes.close()
    assert (tmp_path / "modes.png").stat().st_size > 10_000


def test_modes_and_edges_refuse_with_one_line(tmp_path, capsys):
    # the paper's twisted cylinder between magnets untwists: not an equilibrium
    with pytest.raises(ParameterError) as refused:
        mol_shell.modes(mol_shell.TwistedCylinder(), n=11)
    assert "equilibrium" in str(refused.value) and "chi" in str(refused.value)
    assert main(["modes", "twisted-cylinder", "--n", "11", "-o", str(tmp_path / "m.nc")]) == 2
    assert capsys.readouterr().err.splitlines() == [f"mol-shell: error: {refused.value}"]  # all of stderr
    # a pole cannot be clamped; an open edge cannot be a pole
    assert main(["run", "sphere", "--set", "end1=clamped", "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]) == 2
    assert "end1 = 'clamped' is outside {pole, auto}" in capsys.readouterr().err
    assert main(["run", "cone", "--set", "end2=pole", "--t-end", "1e-5", "-o", str(tmp_path / "x.nc")]) == 2
    assert "end2 = 'pole' is outside" in capsys.readouterr().err


def test_modes_lists_every_mode_it_counts(tmp_path, capsys):
    """``--count 12`` said "12 modes" and listed modes 1-10: every mode of the file is listed."""
    out = tmp_path / "m.nc"
    assert main(["modes", "sphere", "--n", "11", "--count", "12", "-o", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert ": 12 modes, 2 rigid motions; lowest" in lines[0]
    assert [line.split(":")[0].split()[-1] for line in lines[1:]] == [str(m) for m in range(1, 13)]
    assert main(["modes", "sphere", "--n", "11", "--count", "1", "-o", str(out)]) == 0
    first, *listed = capsys.readouterr().out.splitlines()
    assert ": 1 mode, 2 rigid motions;" in first and len(listed) == 1


def test_scene_summaries_are_plain_whole_clauses(capsys):
    """``mol-shell scenes`` cut the vessel's line in a parenthesis ("torispherical heads (crown") and showed the
    double backticks of reStructuredText: each summary is plain text with its parentheses closed. ``mol-shell scenes
    NAME`` shows the whole description, which the summary begins."""
    from mol_shell.scenes import SCENES, description

    assert main(["scenes"]) == 0
    lines = capsys.readouterr().out.splitlines()[: len(SCENES)]
    for name, line in zip(SCENES, lines):
        assert main(["scenes", name]) == 0
        out = capsys.readouterr().out.splitlines()
        head = " ".join(x.strip() for x in out[: next(i for i, x in enumerate(out) if x.split()[:1] == ["parameter"])])
        text = line[18:].strip()
        assert head == f"{name}: {description(SCENES[name])}"  # the whole description, wrapped
        assert head.startswith(f"{name}: {text.removesuffix(' ...')}")
        assert "``" not in line and line.count("(") == line.count(")") and len(text) <= 100, line
        assert text.endswith((".", " ...")), line
    vessel = dict(zip(SCENES, lines))["vessel"]
    assert "(crown" not in vessel and "two torispherical heads" in vessel
    assert dict(zip(SCENES, lines))["sphere"].endswith("A spherical shell of natural radius a: closed (default), a "
                                                        "cap or a zone.")


def test_each_listed_frequency_reads_back_as_the_files_to_8_digits(tmp_path, capsys):
    """A soft Mooney-Rivlin wall (c10 = 1e-300 Pa) has modes near 4e-152 rad/s: the list printed each as
    0.000000 (six decimals), under a summary saying 4.38e-152. Each line reads back as the file's value."""
    out = tmp_path / "m.nc"
    assert main(["modes", "sphere", "--set", "material=mooney-rivlin", "--set", "c10=1e-300", "--n", "10",
                 "--count", "3", "-o", str(out)]) == 0
    listed = [float(line.split(":")[1].split()[0]) for line in capsys.readouterr().out.splitlines()[1:]]
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(listed, ds.frequency.values, rtol=1e-7)
        assert 0 < ds.frequency.values[0] < 1e-100  # the soft wall's, not a rounding
