"""The ranges of the integrators' options are the true ones, on every route (Python, ``--option``, a scene file's
``[run]``): an integer option is bounded by what it is stored or passed as (``chunk = 99999999999999999999`` was
accepted and lost the run in write_netcdf; ``jac_every`` of that size overflowed the driver's C long), a float option
takes a big integer as its float value (``first_step = 99999999999999999999`` failed in ``np.isfinite``), the
leap-frog's ``restart`` works over its whole range (1e308 overflowed ``round``; inf is "never" as 0 is), and
``atol`` and ``first_step`` stop where SUNDIALS' and SciPy's norms do (1e-320 failed at t = 0 with status -22)."""

import math

import numpy as np
import pytest

import mol_shell
from mol_shell._core.constants import ATOL_MIN, MIN_STEP
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.integrators import INTEGRATORS
from mol_shell.integrators.loop import INT64_MAX, declared
from mol_shell.integrators.sundials import FIRST_STEP_MIN
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
        held = {"jac_every": top} if option == "setup_every" else {}  # setup_every is held at most jac_every (51 at 0)
        method = cls(**{option: top}, **held, **newton)  # the top of the stated range is taken, as a Python int
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


def test_atol_and_first_step_bounds_are_refused_below_and_taken_at(tmp_path):
    assert ATOL_MIN == 1e-100 and FIRST_STEP_MIN == 1.492e-154 >= MIN_STEP
    cvode = INTEGRATORS["cvode-bdf"]
    assert cvode(atol=ATOL_MIN, first_step=FIRST_STEP_MIN).first_step == FIRST_STEP_MIN
    assert cvode(atol={"r": ATOL_MIN}).field_atol()[1] == ATOL_MIN
    for bad in (1e-320, 5e-324, ATOL_MIN * (1 - 1e-15), {"r": 1e-300}, [1e-9, 1e-9, 1e-101, 1e-9, 1e-9]):
        with pytest.raises(ParameterError, match=r"^atol = .* is outside \[1e-100, inf\)"):
            cvode(atol=bad)
    for bad in (1e-300, 1e-320, 1.4916e-154, -1.0):
        with pytest.raises(ParameterError, match=r"^first_step = .* is outside 0 \(SUNDIALS estimates it\) or "
                                                 r"\[1.492e-154, inf\) s$"):
            INTEGRATORS["ida"](first_step=bad)


@pytest.mark.parametrize("integrator", ["cvode-bdf", "ida"])
def test_atol_and_first_step_are_refused_just_below_their_bounds_and_run_at_them(integrator):
    """At the bounds the runs complete; below them (cvode-bdf failed at t = 0 from atol = 1e-142 and from a first step
    of 1e-290 s, IDA with status -22 from atol = 1e-170) the values are refused before anything is built."""
    for option, bound in (("atol", ATOL_MIN), ("first_step", FIRST_STEP_MIN)):
        with pytest.raises(ParameterError) as info:
            mol_shell.simulate("sphere", integrator, n=8, t_end=1e-5, progress=False, **{option: bound * (1 - 1e-15)})
        assert info.value.name == option
    ds = mol_shell.simulate("sphere", integrator, n=8, t_end=1e-5, atol=ATOL_MIN, first_step=FIRST_STEP_MIN,
                            progress=False, stresses=False)
    assert ds.attrs["complete"] == 1 and ds.attrs["atol"] == ATOL_MIN and ds.attrs["first_step"] == FIRST_STEP_MIN


INT64_RANGE = "integers in [1, 9223372036854775807]"


@pytest.mark.parametrize(("integrator", "option", "said"), [
    ("leapfrog", "chunk=99999999999999999999", f"--option chunk = 99999999999999999999 is outside {INT64_RANGE}"),
    ("dop853-c", "max_steps=99999999999999999999",
     f"--option max_steps = 99999999999999999999 is outside {INT64_RANGE}"),
    ("cvode-bdf", "jac_every=99999999999999999999",
     "--option jac_every = 99999999999999999999 is outside integers in [0, 2147483647] (0: SUNDIALS' 51)"),
    ("ida", "first_step=1e-320",
     "--option first_step = 1e-320 is outside 0 (SUNDIALS estimates it) or [1.492e-154, inf) s"),
])
def test_an_option_beyond_its_bounds_is_refused_by_name_on_the_command_line(integrator, option, said, tmp_path,
                                                                            capsys):
    out = tmp_path / "x.nc"
    assert main(["run", "sphere", "--n", "8", "--t-end", "1e-5", "--integrator", integrator, "--option", option,
                 "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == f"mol-shell: error: {said}"
    assert not out.exists()


def test_atol_below_its_bound_is_refused_on_the_command_line_and_in_a_scene_file(tmp_path, capsys):
    out = tmp_path / "x.nc"
    assert main(["run", "sphere", "--n", "8", "--t-end", "1e-5", "--integrator", "cvode-bdf", "--atol", "1e-320",
                 "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip().startswith("mol-shell: error: --atol = 1e-320 is outside [1e-100, inf)")
    scene = tmp_path / "s.toml"
    scene.write_text('scene = "sphere"\n[run]\nintegrator = "ida"\nn = 8\nt_end = 1e-5\natol = {r = 1e-320}\n')
    assert main(["run", str(scene), "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip().endswith("[run] atol.r = 1e-320 is outside [1e-100, inf)")
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
