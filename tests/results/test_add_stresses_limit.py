"""``add_stresses(ds, limit=...)``: a limit that is not an integer >= 1 (or None) is refused by name, with its range.

``limit=-5`` was taken silently (every run then skipped, its attrs saying the samples exceeded -5).
"""

import numpy as np
import pytest
import xarray as xr

import mol_shell
from mol_shell._core.errors import ParameterError


@pytest.mark.parametrize("limit", [-5, 0, 0.5, 2.5, float("nan"), float("inf"), True, "1000", [10]])
def test_a_limit_that_is_not_a_positive_integer_is_refused_naming_it(limit):
    with pytest.raises(ParameterError, match=r"^limit = .* integers >= 1, or None \(no limit\)") as info:
        mol_shell.add_stresses(xr.Dataset(), limit=limit)
    assert info.value.name == "limit"


@pytest.mark.parametrize("limit", [None, 1, 4_000_000, 4e6, np.int64(10)])
def test_a_positive_integer_or_none_is_taken(limit):
    """Taken: the call goes on to read the run (here no run, refused naming ``ds``)."""
    with pytest.raises(ParameterError) as info:
        mol_shell.add_stresses(xr.Dataset(), limit=limit)
    assert info.value.name == "ds"
