"""File names in lists and words of a file (bytes that are not UTF-8, newlines), and the files a command writes beside
an output that is a symbolic link: beside the link, as the user typed it, whatever the link points to."""

import os
from pathlib import Path
from types import SimpleNamespace

import meshio
import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell._core import paths
from mol_shell.cli.main import main
from mol_shell.cli.scripts import output_file
from mol_shell.results.dataset import read_netcdf, write_netcdf
from mol_shell.results.study_store import Store, cases_folder
from mol_shell.views import workprecision

#: a file name of bytes that are not UTF-8 (as a locale's file names may hold), and one with a newline
NOT_UTF8, NEWLINE = b"lat\xfc.txt", "a\nb.txt"


def test_lists_and_words_holding_file_names_not_utf8_are_written_escaped_and_read_back(tmp_path):
    """A list attribute (``files = [...]``) or a variable of words (a study's ``points`` over the cases) holding a
    name that is not UTF-8: ``UnicodeEncodeError ... surrogates not allowed`` from netCDF4 once the study had run
    (3 cases of a meridian's ``--vary points``), its file not written. Now escaped (``\\xfc``) as a single string
    attribute is; a newline is kept as it is (valid text)."""
    odd = os.fsdecode(bytes(tmp_path) + b"/" + NOT_UTF8)
    escaped = str(tmp_path) + "/lat\\xfc.txt"
    ds = xr.Dataset({"x": ("points", np.arange(3.0), {"sources": [odd, "plain"]})},
                    coords={"points": ("points", np.array([odd, NEWLINE, "plain"], dtype=object))},
                    attrs={"files": [odd, NEWLINE], "names": (odd,), "scene": odd})
    write_netcdf(ds, tmp_path / "s.nc")
    back = read_netcdf(tmp_path / "s.nc")
    assert list(back.attrs["files"]) == [escaped, NEWLINE] and back.attrs["names"] == escaped
    assert back.attrs["scene"] == escaped and list(back["x"].attrs["sources"]) == [escaped, "plain"]
    assert back["points"].values.tolist() == [escaped, NEWLINE, "plain"]
    assert ds["points"].values.tolist() == [odd, NEWLINE, "plain"]  # the caller's Dataset left as it was


def test_a_stored_case_whose_label_holds_a_name_not_utf8_is_reused(tmp_path):
    """A study's case stored with ``case_label = "points=.../lat\\udcfc.txt"``: its checksum was taken of the raw
    name and checked against the escaped one read back, so the case was never reused (ran again at every rerun)."""
    odd = os.fsdecode(bytes(tmp_path) + b"/" + NOT_UTF8)
    store = Store(tmp_path / "st.nc")
    task = SimpleNamespace(key="0" * 20, label=f"points={odd}")
    case = xr.Dataset({"x": ("i", np.arange(2.0))}, coords={"points": ("i", np.array([odd, "b"], dtype=object))},
                      attrs={"points": odd, "files": [odd, NEWLINE]})
    store.save(task, case, {"status": "complete", "message": f"ran {odd}", "worker": "", "case_wall_time_s": 0.1})
    loaded = store.load(task)
    assert store.rejected == [] and loaded is not None and loaded[1]["status"] == "complete"


def test_side_files_go_beside_the_path_typed_not_the_links_target(tmp_path):
    """One rule (:func:`mol_shell._core.paths.beside`): the files a command writes beside ``-o`` go beside the path
    typed, named by its stem, where ``-o`` is a symbolic link into another folder: a study's ``.cases``, compare's and
    stability's ``.png``/``.md``, modes' ``.png``, and a study script's (``output_file`` gave the link's target, so a
    script's ``.md`` and ``.png`` went beside the target while the command line's went beside the link)."""
    (tmp_path / "real").mkdir()
    link = tmp_path / "out.nc"
    link.symlink_to("real/target.nc")
    assert paths.beside(link, ".png") == tmp_path / "out.png"
    assert paths.beside(str(link), ".cases") == cases_folder(link) == tmp_path / "out.cases"
    assert workprecision.companion_files(link) == (str(tmp_path / "out.png"), str(tmp_path / "out.md"))
    assert output_file(str(link)) == str(link)
    assert paths.beside(Path("~") / "x.nc", ".md") == Path.home() / "x.md"
    assert paths.beside(link, ".h5", named_inside=True) == tmp_path / "real" / "target.h5"


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=5, times=[0.0, 1e-6], progress=False, stresses=False)
    path = tmp_path_factory.mktemp("run") / "run.nc"
    write_netcdf(ds, path)
    return path


def test_an_export_to_a_symbolic_link_checks_and_says_the_data_files_it_writes(run_file, tmp_path, capsys):
    """``export -o run:1.xdmf`` where that links to ``real/t.xdmf``: the HDF5 data went to ``real/t.h5`` (beside the
    file that names them, where readers look: they resolve the link), but the command line checked ``run_1.h5``
    beside the link (a directory of that name refused the export, exit 2) and its note said the data were in
    ``run_1.h5``. Now the checks and the note name the files written; the ``.pvd``'s steps likewise."""
    (tmp_path / "real").mkdir()
    (tmp_path / "run_1.h5").mkdir()  # where the data do not go: no reason to refuse
    (tmp_path / "run:1.xdmf").symlink_to("real/t.xdmf")
    (tmp_path / "run.pvd").symlink_to("real/t.pvd")
    for name in ("run:1.xdmf", "run.pvd"):
        assert main(["export", str(run_file), "--n-phi", "3", "-o", str(tmp_path / name)]) == 0
        assert capsys.readouterr().err == ""
        assert (tmp_path / name).is_symlink()
    assert sorted(p.name for p in (tmp_path / "real").iterdir()) == ["t.h5", "t.pvd", "t.xdmf", "t_0000.vtu",
                                                                     "t_0001.vtu"]
    with meshio.xdmf.TimeSeriesReader(tmp_path / "run:1.xdmf") as reader:  # by the link's name
        reader.read_points_cells()
        assert reader.num_steps == 2
    (tmp_path / "real" / "t.h5").unlink()
    (tmp_path / "real" / "t.h5").mkdir()  # where they do go: refused before the work, naming -o
    assert main(["export", str(run_file), "--n-phi", "3", "-o", str(tmp_path / "run:1.xdmf")]) == 2
    assert "real/t.h5 beside it, where a directory stands" in capsys.readouterr().err
