"""The size of a path's range: a tiny range traces like any other, one too small to scale by is refused.

The arclength scales the load by the range ``|stop - start|``; the first tangent's load component is its
reciprocal. At ``1e-200`` the square of that component (``1e400``) overflowed in the tangent's norm, the tangent
came out 0 and every step failed ("Newton did not converge"). A load that small moves the shell linearly: the
free end of a clamped cone turns by ``chi = T / k`` with ``k`` its torsional stiffness, the same at ``T = 1e-6``
and at ``1e-300`` (the ratio, not a run's number, is what is compared). The smallest range taken is the smallest
normal double, ``2.2250738585072014e-308``: below it the range is subnormal and its reciprocal overflows near
``5.6e-309``.
"""

from __future__ import annotations

import numpy as np
import pytest

from mol_shell import Cone, ParameterError, Sphere, path
from mol_shell.cli.main import main

N = 8


@pytest.mark.parametrize("material, stop", [("svk-plane-stress", 1e-200), ("neo-hookean-incompressible", 1e-300),
                                            ("svk-plane-stress", 2.2250738585072014e-308)])
def test_a_tiny_pressure_range_traces_to_its_end(material, stop):
    ds = path(Sphere(material=material), "pressure", 0.0, stop, n=N)
    assert ds.attrs["status"] == "complete" and float(ds.parameter[-1]) == stop
    assert np.all(np.diff(ds.parameter.values) > 0)
    # a response of order 1e-200 of the radius: the sphere stays put to the round-off of Newton's corrections
    assert np.allclose(ds.r.values[-1], ds.r.values[0], rtol=0, atol=1e-14)


@pytest.mark.parametrize("scene", ["sphere", "twisted-cylinder"])
@pytest.mark.parametrize("stop", [1e-3, 1e-7, 1e-9, 1e-12, 1e-16])
def test_small_ranges_trace_on_the_default_scenes_and_the_response_is_linear(scene, stop):
    """The default sphere (SVK with the inextensible director, nu = 0.49) failed from 1e-7 Pa down ("the corrector
    left the predictor's neighbourhood" after one step: the displacements, weighed by a response of 1e-12 of the
    size, were mostly the solves' round-off), the free twisted tube below about 1 Pa (its start equilibrium, left at
    Newton's tolerance, was 1e-8 rad off along its softest mode). Both trace now, and the response is linear: the
    last state's change from the start is ``stop`` times the first step's per unit load, to 1e-6 of it (or both are
    below the solves' round-off)."""
    from mol_shell import get_scene

    ds = path(get_scene(scene), "pressure", 0.0, stop, n=21)
    assert ds.attrs["status"] == "complete" and float(ds.parameter[-1]) == stop, ds.attrs["message"]
    p, r = ds.parameter.values, ds.r.values
    first, last = (r[1] - r[0]) / p[1], (r[-1] - r[0]) / p[-1]
    size = np.abs(r[0]).max()
    assert np.abs(last - first).max() * stop <= 1e-6 * np.abs(last).max() * stop + 1e-13 * size


def test_a_tiny_end_torque_turns_the_free_end_as_the_linear_stiffness_says():
    scene = Cone(material="neo-hookean-incompressible", end1="clamped", end2="free")
    tiny = path(scene, "end2_torque", 0.0, 1e-300, n=N)
    small = path(scene, "end2_torque", 0.0, 1e-6, n=N, steps=2)
    assert tiny.attrs["status"] == "complete"
    compliance = float(small.chi[-1, -1]) / 1e-6
    assert compliance > 0
    assert float(tiny.chi[-1, -1]) / 1e-300 == pytest.approx(compliance, rel=1e-6)


@pytest.mark.parametrize("start, stop", [(0.0, 1e-310), (1e-308, -1e-308), (-1e308, 1e308)])
def test_a_range_outside_the_normal_doubles_is_refused_naming_stop(start, stop):
    with pytest.raises(ParameterError) as exc:
        path(Sphere(), "pressure", start, stop, n=N)
    assert exc.value.name == "stop" and "2.2250738585072014e-308 <= |stop - start|" in str(exc.value)


def test_the_command_refuses_it_in_one_line_naming_param(tmp_path, capsys):
    code = main(["path", "sphere", "--param", "pressure=0:1e-310", "--n", "8", "-o", str(tmp_path / "p.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert err.startswith("mol-shell: error: --param") and "2.2250738585072014e-308" in err
    assert not (tmp_path / "p.nc").exists()


SPHERE = Sphere(h=0.01, nu=0.3, material="svk-plane-stress")


def test_a_small_first_step_still_grows_to_the_default_steps():
    """The steps were capped at twice the first one: with ``ds = 1e-3`` (the docs' advice for strongly nonlinear
    ranges) a nearly linear path crept by 0.141 Pa a step and ran out of steps far from stop."""
    ds = path(SPHERE, "pressure", 0.0, 100.0, n=20, ds=1e-3, max_steps=40)
    assert ds.attrs["status"] == "complete" and float(ds.parameter[-1]) == 100.0


@pytest.mark.parametrize("kwargs, name", [
    ({"ds": 1e-300}, "ds"),  # below the corrector's noise: the path came back below start
    ({"start": 100.0, "stop": 100.000000000001}, "stop"),  # 1e-14 of start: an exit 3 ("left the predictor")
])
def test_steps_and_ranges_below_the_resolution_are_refused_by_name(kwargs, name):
    args = {"start": 0.0, "stop": 100.0, **kwargs}
    with pytest.raises(ParameterError, match=rf"^{name} = "):
        path(SPHERE, "pressure", args.pop("start"), args.pop("stop"), n=10, **args)


def test_a_first_step_beyond_the_whole_range_is_taken_as_the_whole_range():
    """``ds = 1e9`` (the scaled arclength of the whole range is about sqrt(2)) ended an easy path as failed at
    pressure = 5 Pa; it is now the first step of ``steps = 1``, and the path is that path."""
    import mol_shell

    big = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, 100.0, n=12, ds=1e9, progress=False)
    one = mol_shell.path(mol_shell.Sphere(), "pressure", 0.0, 100.0, n=12, steps=1, progress=False)
    assert big.attrs["status"] == one.attrs["status"] == "complete"
    np.testing.assert_array_equal(big.r.values, one.r.values)


def test_a_start_newton_misses_from_rest_is_reached_by_continuation_and_is_the_run_s_equilibrium():
    """A sphere at 1e6 Pa (inflated to 2.7 times its radius): Newton from the natural state fails there, and the
    path was refused (start is outside loads at which Newton finds an equilibrium) though a run's ``R = auto``
    reaches that equilibrium by continuation. The path's start now does too: its first state is the run's
    starting state (the static solve of :mod:`mol_shell.runs.statics`, an independent route) to round-off."""
    import mol_shell

    p = mol_shell.path(Sphere(), "pressure", 1e6, 1.000001e6, n=12, max_steps=1, progress=False)
    run = mol_shell.simulate(Sphere(pressure=1e6), "cvode-bdf", n=12, t_end=1e-6, progress=False, stresses=False)
    assert run.attrs["R"] > 2.5  # far from the natural sphere
    for field in ("r", "z"):
        np.testing.assert_allclose(p[field].values[0], run[field].values[0], rtol=0, atol=1e-12)
