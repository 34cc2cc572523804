"""The ranges of the integrators' options are the true ones, on every route (Python, ``--option``, a scene file's
``[run]``): an integer option is bounded by what it is stored or passed as (``chunk = 99999999999999999999`` was
accepted and lost the run in write_netcdf; ``jac_every`` of that size overflowed the driver's C long), a float option
takes a big integer as its float value (``first_step = 99999999999999999999`` failed in ``np.isfinite``), the
leap-frog's ``restart`` works over its whole range (1e308 overflowed ``round``; inf is "never" as 0 is)."""

import math

import numpy as np
import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.loop import INT64_MAX, declared
from mol_shell.integrators.sundials_c import FREQUENCY_MAX
from mol_shell.results.dataset import read_netcdf

BIG = 99999999999999999999  # 1e20: beyond int64, inside the floats
#: the integer options without a small bound of their own, and the largest value each takes
TOPS = {"chunk": INT64_MAX, "max_steps": INT64_MAX, "jac_every": FREQUENCY_MAX, "setup_every": FREQUENCY_MAX}


@pytest.mark.parametrize("name", sorted(n for n, cls in INTEGRATORS.items() if set(TOPS) & set(declared(cls))))
def test_integer_options_are_bounded_by_what_they_are_stored_as(name):
    cls = INTEGRATORS[name]
    newton = {"iteration": "newton"} if "iteration" in declared(cls) else {}  # jac_every is Newton's
    options = {k: top for k, top in TOPS.items() if k in declared(cls)}
    for option, top in options.items():
        method = cls(**{option: top}, **newton)  # the top of the stated range is taken, as a Python int
        assert getattr(method, option) == top and type(getattr(method, option)) is int
        assert str(top) in declared(cls)[option].allowed
        for bad in (top + 1, BIG, 2**64):
            with pytest.raises(ParameterError) as info:
                cls(**{option: bad}, **newton)
            assert info.value.name == option and str(top) in str(info.value)
    assert cls(**{k: np.int64(5) for k in options}, **newton) is not None  # NumPy integers are integers


@pytest.mark.parametrize(("name", "option"), [("leapfrog", "restart"), ("leapfrog", "dt"), ("cvode-bdf", "first_step"),
                                              ("ida", "max_step"), ("dop853-c", "atol")])
def test_a_float_option_takes_a_big_integer_as_its_float_value(name, option):
    method = INTEGRATORS[name](**{option: BIG})
    assert getattr(method, option) == 1e20 and type(getattr(method, option)) is float


def test_restart_anywhere_in_its_range_works_and_beyond_any_run_is_never():
    leapfrog = INTEGRATORS["leapfrog"]
    assert leapfrog(restart=1.0, dt=1e-6).restart_steps() == 10**6
    for never in (0, 0.0, 1e300, 1e308, math.inf, BIG, 10**400, 2**53 * 1e-6 * 1.01):
        assert leapfrog(restart=never, dt=1e-6).restart_steps() == 0, never
    for bad in (-1, -math.inf, math.nan, "1", True):
        with pytest.raises(ParameterError, match=r"^restart = .* \[0, inf\] s; 0 or inf: never"):
            leapfrog(restart=bad)


INT64_RANGE = "integers in [1, 9223372036854775807]"


@pytest.mark.parametrize(("integrator", "option", "said"), [
    ("leapfrog", "chunk=99999999999999999999", f"--option chunk = 99999999999999999999 is outside {INT64_RANGE}"),
    ("dop853-c", "max_steps=99999999999999999999",
     f"--option max_steps = 99999999999999999999 is outside {INT64_RANGE}"),
    ("cvode-bdf", "jac_every=99999999999999999999",
     "--option jac_every = 99999999999999999999 is outside integers in [0, 2147483647] (0: SUNDIALS' 51)"),
])
def test_an_option_beyond_its_bounds_is_refused_by_name_on_the_command_line(integrator, option, said, tmp_path,
                                                                            capsys):
    out = tmp_path / "x.nc"
    assert main(["run", "sphere", "--n", "8", "--t-end", "1e-5", "--integrator", integrator, "--option", option,
                 "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == f"mol-shell: error: {said}"
    assert not out.exists()


@pytest.mark.parametrize("restart", ["1e308", "99999999999999999999", "inf"])
def test_a_restart_beyond_the_run_runs_from_a_scene_file_and_the_command_line(restart, tmp_path, capsys):
    """``restart = 1e308`` ended in an OverflowError after the run's set-up; a big integer in ``np.isfinite``."""
    scene, out = tmp_path / "s.toml", tmp_path / "x.nc"
    scene.write_text(f'scene = "sphere"\n[run]\nn = 8\nt_end = 1e-5\nrestart = {restart}\n')
    assert main(["run", str(scene), "-o", str(out)]) == 0, capsys.readouterr().err
    ds = read_netcdf(out)
    assert ds.attrs["complete"] == 1 and ds.attrs["n_restarts"] == 0 and ds.attrs["restart"] == float(restart)
    assert main(["run", "sphere", "--n", "8", "--t-end", "1e-5", "--option", f"restart={restart}", "-o", str(out)]) == 0
    assert read_netcdf(out).attrs["restart"] == float(restart)
