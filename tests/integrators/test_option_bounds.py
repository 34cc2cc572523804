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
from mol_shell.integrators.tolerances import smallest_max_step
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


def test_an_explicit_restart_of_one_second_is_checked_as_any_other():
    """At dt = 20 ms, 100 steps are 2 s: restart = 1.5 was refused but an explicit 1.0 was taken as 2 s unsaid (it was
    the default's value). The default is None: 1 s where that is 100 steps or more (dt = 1e-6: 10^6 steps), else 100
    steps (2 s), recorded; a restart given, 1.0 too, is refused below 100 steps."""
    leapfrog = INTEGRATORS["leapfrog"]
    for given in (1.0, 1.5):
        with pytest.raises(ParameterError, match=rf"^restart = {given} is outside 0 or inf \(never\), or \[2, inf\] s at "
                                                 r"dt = 0\.02 s"):
            leapfrog(dt=0.02, restart=given)
    assert leapfrog(dt=0.02).restart is None and leapfrog(dt=0.02).restart_steps() == 100
    assert leapfrog(dt=0.02).settings()["restart"] == leapfrog(dt=0.02, restart=2.0).settings()["restart"] == 2.0
    assert leapfrog(dt=1e-6).restart_steps() == 10**6 and leapfrog(dt=1e-6).settings()["restart"] == 1.0


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


# -- a new user's findings: what the messages say about rtol, max_step, None and integers ---------------------------
#: SciPy's least relative tolerance (``scipy.integrate._ivp.common.validate_tol`` raises a smaller one to it)
SCIPY_FLOOR = float(100 * np.finfo(float).eps)


@pytest.mark.parametrize("name", ["scipy-rk45", "scipy-dop853", "scipy-radau", "scipy-bdf"])
def test_the_scipy_peers_refuse_an_rtol_below_scipys_floor(name):
    """``--rtol 1e-14`` ran with SciPy's warning passed through: SciPy raised it to 2.22e-14 and the file recorded
    1e-14. Refused below the floor, stated to 4 digits rounded up (2.221e-14: the least stated value is taken)."""
    allowed = "[2.221e-14, 1) (SciPy's floor: 100 x machine epsilon)"
    assert 2.221e-14 >= SCIPY_FLOOR > 2.220e-14
    for bad in (1e-14, 2.22e-14, SCIPY_FLOOR * (1 - 1e-15)):
        with pytest.raises(ParameterError) as info:
            INTEGRATORS[name](rtol=bad)
        assert str(info.value) == f"rtol = {bad!r} is outside {allowed}"
    assert INTEGRATORS[name](rtol=2.221e-14).rtol == 2.221e-14
    with pytest.raises(ParameterError, match=r"^rtol = 1e-14 is outside \[2.221e-14, 1\) \(SciPy's floor"):
        mol_shell.simulate("sphere", name, n=8, t_end=1e-5, rtol=1e-14, progress=False)  # check_options says the same
    assert INTEGRATORS["dop853-c"](rtol=1e-14).rtol == 1e-14  # the others take the whole RTOL_RANGE as given


def test_scipy_rk45_at_scipys_floor_runs_at_the_rtol_it_records_without_scipys_warning(tmp_path, capsys):
    out = tmp_path / "x.nc"
    assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "scipy-rk45", "--rtol", "1e-14",
                 "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == ("mol-shell: error: --rtol = 1e-14 is outside [2.221e-14, 1) (SciPy's "
                                               "floor: 100 x machine epsilon)")
    assert not out.exists()
    scene = tmp_path / "s.toml"
    scene.write_text('scene = "sphere"\n[run]\nintegrator = "scipy-rk45"\nn = 5\nt_end = 1e-6\nrtol = 1e-14\n')
    assert main(["run", str(scene), "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip().endswith("s.toml: [run] rtol = 1e-14 is outside [2.221e-14, 1) (SciPy's "
                                                    "floor: 100 x machine epsilon)")
    assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "scipy-rk45", "--rtol", "2.221e-14",
                 "-o", str(out)]) == 0
    assert "rtol" not in capsys.readouterr().err  # SciPy's "rtol is too small" is not passed through
    ds = read_netcdf(out)
    assert ds.attrs["complete"] == 1 and ds.attrs["rtol"] == 2.221e-14


def test_max_step_0_is_no_bound_on_every_route_and_every_message_says_so(tmp_path, capsys):
    """``--max-step 0`` was refused as outside (0, inf) s, while the refusal of a too small max_step offered "0
    (none)", and 0 is the integrators' default (no bound). 0 is taken everywhere; the ranges say what it means."""
    out, scene = tmp_path / "x.nc", tmp_path / "s.toml"
    allowed = "[0, inf) s (0: unbounded)"
    assert declared(INTEGRATORS["cvode-bdf"])["max_step"].allowed == allowed
    assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "cvode-bdf", "--max-step", "0",
                 "-o", str(out)]) == 0
    assert read_netcdf(out).attrs["max_step"] == 0.0
    scene.write_text('scene = "sphere"\n[run]\nintegrator = "dop853-c"\nn = 5\nt_end = 1e-6\nmax_step = 0\n')
    assert main(["run", str(scene), "-o", str(out)]) == 0
    assert read_netcdf(out).attrs["max_step"] == 0.0
    capsys.readouterr()
    assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "cvode-bdf", "--max-step", "-1",
                 "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == f"mol-shell: error: --max-step = -1 is outside {allowed}"
    scene.write_text('scene = "sphere"\n[run]\nintegrator = "dop853-c"\nn = 5\nt_end = 1e-6\nmax_step = -1\n')
    assert main(["run", str(scene), "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip().endswith(f"[run] max_step = -1 is outside {allowed}")
    with pytest.raises(ParameterError, match=r"^max_step = -1 is outside \[0, inf\) s \(0: unbounded\)$"):
        INTEGRATORS["ida"](max_step=-1)
    # too small for max_steps to reach t_end: the least value, or 0, which the command line takes
    # (1e-6 s / (99 - 10): one more step per saved interval, 1 % of max_steps for the start)
    with pytest.raises(ParameterError, match=r"^max_step = 1e-12 is outside \[1\.124e-08, inf\) s, or 0 \(unbounded\)"):
        mol_shell.simulate("sphere", "dop853-c", n=5, t_end=1e-6, max_step=1e-12, max_steps=100, progress=False)


@pytest.mark.parametrize(("integrator", "option"), [("cvode-bdf", "max_order"), ("sksundae-cvode-adams", "max_order"),
                                                    ("ida", "max_newton")])
def test_none_spelt_on_the_command_line_or_in_a_scene_file_is_none(integrator, option, tmp_path, capsys):
    """``max_order``'s range ends "or None", but ``--option max_order=None`` was refused as the string 'None' (TOML
    has no null). none or auto, in any case, is None where the option takes None, as scene parameters take them.
    The paper's cylinder on 8 nodes: test_sundials_c's atol test runs these three integrators on it, so their kernels
    (the scikit-sundae route's compiled Jacobian the costliest) are built once for both."""
    out, scene = tmp_path / "x.nc", tmp_path / "s.toml"
    for word in ("None", "none", "AUTO"):
        assert main(["run", "twisted-cylinder", "--n", "8", "--t-end", "1e-6", "--integrator", integrator, "--option",
                     f"{option}={word}", "-o", str(out)]) == 0, capsys.readouterr().err
        assert read_netcdf(out).attrs["complete"] == 1
    scene.write_text(f'scene = "twisted-cylinder"\n[run]\nintegrator = "{integrator}"\nn = 8\nt_end = 1e-6\n'
                     f'{option} = "none"\n')
    assert main(["run", str(scene), "-o", str(out)]) == 0, capsys.readouterr().err
    capsys.readouterr()
    # a word that is not None's stays refused; so does none where the option does not take None
    for given in (f"{option}=nothing", "jac_every=none"):
        assert main(["run", "twisted-cylinder", "--n", "8", "--t-end", "1e-6", "--integrator", integrator,
                     "--option", given, "-o", str(out)]) == 2
        assert capsys.readouterr().err.startswith(f"mol-shell: error: --option {given.split('=')[0]}")


def test_a_float_for_an_integer_option_is_said_to_be_no_integer(tmp_path, capsys):
    """``--option chunk=1e12`` (TOML's float) said "outside integers in [1, 9223372036854775807]", which 10^12 is not
    outside: it is not an integer. As ``--n 1e12`` says it."""
    allowed = f"allowed: {INT64_RANGE}"
    out, scene = tmp_path / "x.nc", tmp_path / "s.toml"
    for text, said in (("1e12", f"1e12 is not an integer; {allowed} (a float: write it as the integer 1000000000000)"),
                       ("2.5", f"2.5 is not an integer; {allowed}"),
                       ("'many'", f"'many' is not an integer; {allowed}")):
        assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "dop853-c", "--option",
                     f"chunk={text}", "-o", str(out)]) == 2
        assert capsys.readouterr().err.strip() == f"mol-shell: error: --option chunk = {said}"
    scene.write_text('scene = "sphere"\n[run]\nintegrator = "dop853-c"\nn = 5\nt_end = 1e-6\nchunk = 1e12\n')
    assert main(["run", str(scene), "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip().endswith(f"[run] chunk = 1e12 is not an integer; {allowed} "
                                                    "(a float: write it as the integer 1000000000000)")
    with pytest.raises(ParameterError, match=r"^max_steps = 1000000000000.0 is not an integer; allowed: integers in"):
        INTEGRATORS["rk45-c"](max_steps=1e12)
    with pytest.raises(ParameterError, match=r"^jac_every = 50.0 is not an integer; allowed: integers in \[0, "):
        INTEGRATORS["cvode-bdf"](jac_every=50.0)
    assert main(["run", "sphere", "--n", "5", "--t-end", "1e-6", "--integrator", "dop853-c", "--option",
                 "chunk=1000000000000", "-o", str(out)]) == 0  # the integer itself is inside the range
    assert read_netcdf(out).attrs["chunk"] == 10**12
    assert not any(tmp_path.glob("*.png"))


def test_a_per_field_atol_is_recorded_to_the_last_digit():
    """A run file recorded a per-field ``atol`` to 6 digits (``:g``), so a scene file written back from it
    (``mol-shell scenes RUN.nc --toml``) ran with other tolerances than the run it came from."""
    atol = {"z": 1.23456789e-9, "r": 2.0000001e-9, "chi": 1e-10, "theta": 3.14159265e-10, "psi": 1e-10}
    method = mol_shell.INTEGRATORS["dop853-c"](rtol=1e-6, atol=atol)
    recorded = dict(item.split("=") for item in method.tolerances()["atol"].split(","))
    assert {k: float(v) for k, v in recorded.items()} == atol, recorded


def test_the_smallest_max_step_a_refusal_names_reaches_t_end():
    """Refused below ``t_end / max_steps`` alone, a ``max_step`` at that bound took all its steps short of ``t_end``
    (1e6 steps of 1e-8 s reached 0.00999992 of 0.01 s: steps shortened to land on the saved times are more steps).
    The bound counts one more step per saved interval and leaves 1 % of ``max_steps`` for the start:
    ``t_end / (0.99 max_steps - intervals)``; at 1,000 steps, 10 intervals to 1e-5 s, 1e-5 / 980 = 1.0204e-8 s."""
    assert math.isclose(smallest_max_step(1e-5, 10, 1000), 1e-5 / 980, rel_tol=1e-12)
    assert smallest_max_step(1e-5, 990, 1000) == math.inf
    for name in ("rk45-c", "cvode-adams"):
        with pytest.raises(ParameterError, match=r"^max_step = 1e-08 is outside \[1\.021e-08, inf\) s, or 0 \(unbounded\) "
                                                 r"\(max_steps = 1000 steps of at most max_step, one more per saved "
                                                 r"interval \(10\)"):
            mol_shell.simulate("twisted-cylinder", name, n=11, t_end=1e-5, max_step=1e-8, max_steps=1000)
        ds = mol_shell.simulate("twisted-cylinder", name, n=11, t_end=1e-5, max_step=1.021e-8, max_steps=1000,
                                progress=False, stresses=False)
        assert ds.attrs["complete"] == 1 and ds.attrs["n_steps"] <= 1000
