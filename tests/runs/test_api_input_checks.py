"""The Python API's input checks met by a new user's probe: a study's ``n`` taken by ``int(n)``, saved times that took
bools and strings and a grid tolerance unlike ``t_end``'s, float32 ``initial`` fields refused at a pole, a
``pathlib.Path`` of points refused, and simulate's keywords refused by a study as options of the integrator."""

import math
import pathlib
import re

import numpy as np
import pytest

import mol_shell
from mol_shell import ParameterError
from mol_shell._core.errors import show
from mol_shell.integrators.leapfrog import Leapfrog
from mol_shell.runs.simulate import steps_to

C = mol_shell.TwistedCylinder


@pytest.mark.parametrize("n", [2, -5, 2.5, 20.9, True, "40"])
def test_a_study_refuses_n_before_any_case(n):
    """``int(n)`` ran 20.9 at n = 20 and "40" at 40; n = 2 came back as a Dataset of refused cases, 2.5 refused as
    "n = 2", True as "n = 1". Now refused up front as simulate refuses it."""
    with pytest.raises(ParameterError, match=rf"^n = {re.escape(show(n))} is outside integers >= 3$"):
        mol_shell.study(C(), {"gamma": [0.1]}, t_end=1e-4, n=n, scheduler="serial", progress=False)


@pytest.mark.parametrize("times, odd", [(["0", True], r"'0' \(str\)"), ([0, True], r"True \(bool\)"),
                                        ([0.0, None], r"None \(NoneType\)")])
def test_saved_times_are_numbers_as_t_end_is(times, odd):
    """``times=['0', True]`` ran to t = 1 s (True as 1.0), though ``t_end="0.001"`` and ``t_end=True`` are refused."""
    with pytest.raises(ParameterError, match=rf"^times = .* is not a list of numbers; allowed: .* \({odd} is not a "
                       r"number\)$"):
        mol_shell.simulate(C(), n=11, times=times, progress=False)


@pytest.mark.parametrize("t, on_grid", [
    (1.000000005e-4, True),  # 5e-13 s = 5e-7 steps off: t_end was refused (1e-9 of it), times snapped
    (2000.0000004, False),  # 0.4 steps off: t_end was taken (1e-9 of 2000 s is 2 steps), times refused
    (np.float32(1e-4), False),  # 9.999999747e-05: 2.5e-6 steps off at its double value; t_end ran in float32 sums
])
def test_t_end_and_saved_times_are_on_the_step_grid_by_one_rule(t, on_grid):
    """One rule for leap-frog's grid, ``|k dt - t| <= 1e-6 dt + 1e-12 t``, at double precision, for t_end (what
    ``steps_to`` accepts) and saved times (``step_counts``) alike."""
    dt = 1e-6
    k = round(float(t) / dt)
    assert (abs(k * dt - float(t)) <= 1e-6 * dt + 1e-12 * float(t)) == on_grid  # the rule, as the docstring says
    assert steps_to(t, dt) == (k if on_grid else 0)
    if on_grid:
        assert Leapfrog(dt=dt).step_counts(np.array([0.0, float(t)])).tolist() == [0, k]
    else:
        with pytest.raises(ParameterError, match=r"^times = .* is outside multiples of dt = 1e-06 s"):
            Leapfrog(dt=dt).step_counts(np.array([0.0, float(t)]))


def test_a_float32_t_end_or_times_is_refused_saying_its_precision():
    """``t_end=np.float32(1e-4)`` ran while ``times=np.array([0, 1e-4], np.float32)`` was refused: both are now
    refused at their double value, saying that the single precision is the cause."""
    with pytest.raises(ParameterError, match=r"^t_end = 9.999999747378752e-05 is outside positive multiples of dt = "
                       r"1e-06 s .*2.53e-12 s from step 100 at 0.0001 s; a single-precision \(float32\) value"):
        mol_shell.simulate(C(), n=11, t_end=np.float32(1e-4), progress=False)
    with pytest.raises(ParameterError, match=r"^times = 9.999999747378752e-05 is outside multiples of dt = 1e-06 s "
                       r".*single-precision \(float32\)"):
        Leapfrog(dt=1e-6).step_counts(np.array([0, 1e-4], np.float32))


@pytest.fixture(scope="module")
def sphere_start():
    """A sphere's own fields at t = 0 (its poles: r = 0, theta = +-pi/2)."""
    ds = mol_shell.simulate(mol_shell.Sphere(), n=12, t_end=2e-4, progress=False, stresses=False)
    return np.stack([ds[f].isel(time=0).values for f in ("z", "r", "chi", "theta", "psi")])


def test_float32_initial_fields_are_taken_at_the_values_a_pole_imposes(sphere_start):
    """float32 rounds theta = pi/2 at the pole by 4.4e-8 rad, beyond the 1e-9 tolerance: refused as "theta = 1.5708
    rad ... is outside ... theta = 1.5708 rad there". Taken now, the pole's values set to the ones it imposes."""
    single = sphere_start.astype(np.float32)
    assert 0 < abs(float(single[3, 0]) - math.pi / 2) < 1e-7
    ds = mol_shell.simulate(mol_shell.Sphere(), n=12, t_end=2e-4, initial=single, progress=False, stresses=False)
    assert ds.attrs["status"] == "complete"
    start = ds.isel(time=0)
    assert float(start.theta[0]) == math.pi / 2 and float(start.theta[-1]) == -math.pi / 2
    assert float(start.r[0]) == 0.0 and float(start.r[-1]) == 0.0
    off = sphere_start.astype(np.float32)
    off[3, 0] += np.float32(1e-4)  # beyond single precision: refused, saying how far and what its precision allows
    with pytest.raises(ParameterError, match=r"theta = 1.5708 rad there \(end1 is 'pole'\) \(0.0001 rad off; fields "
                       r"given in float32 may be [\d.e-]+ rad off\)$"):
        mol_shell.simulate(mol_shell.Sphere(), n=12, t_end=2e-4, initial=off, progress=False)


def test_points_take_a_path_kept_as_its_text(tmp_path):
    """``MeridianShell(points=pathlib.Path(...))`` was refused as "not a file name"."""
    t = np.linspace(0.0, np.pi / 2, 9)
    f = tmp_path / "dome.txt"
    np.savetxt(f, np.column_stack([np.cos(t), 0.6 * np.sin(t)]))
    scene = mol_shell.MeridianShell(points=pathlib.Path(f))
    assert scene.points == str(f) and isinstance(scene.points, str)
    assert scene == mol_shell.MeridianShell(points=str(f))


@pytest.mark.parametrize("keyword, value", [("threads", 2), ("stresses", False), ("initial", None)])
def test_a_study_names_simulates_keywords_it_sets_itself(keyword, value):
    """``study(..., threads=2)`` was refused as "threads is not an option of leapfrog"."""
    with pytest.raises(ParameterError, match=rf"^{keyword} = {value} is a keyword of simulate that a study sets "
                       r"itself; allowed: study's keywords vary, integrator, n, times, t_end, scheduler, workers, "
                       r"output, progress and the options of leapfrog \(chunk, dt, restart\) \(each case "):
        mol_shell.study(C(), {"gamma": [0.1]}, t_end=1e-4, n=11, scheduler="serial", progress=False,
                        **{keyword: value})


@pytest.mark.parametrize("threads", [0, 10**6, True, 2.0])
def test_a_thread_count_is_refused_before_anything_is_built(threads, no_build):
    """``simulate(threads=10**6)`` was refused only after the graphs were built and compiled (seconds to minutes at a
    large n): now with the other inputs, before a build (``no_build`` raises where one would start)."""
    with pytest.raises(ParameterError, match=r"^threads = \S+ is outside integers 1 \.\. "):
        mol_shell.simulate(mol_shell.TwistedCylinder(), n=777, t_end=1e-4, threads=threads, progress=False)
