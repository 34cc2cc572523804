"""File names in lists and words of a file (bytes that are not UTF-8, newlines), and the files a command writes beside
an output that is a symbolic link: beside the link, as the user typed it, whatever the link points to."""

import os
from types import SimpleNamespace

import numpy as np
import xarray as xr

from mol_shell.results.dataset import read_netcdf, write_netcdf
from mol_shell.results.study_store import Store

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
