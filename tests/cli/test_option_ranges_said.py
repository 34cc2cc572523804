"""Command-line option ranges (probe of December 7): ``restart=none`` refused (it restarted every 1 s), "not an
option of X" said before a value's range, the bounds stated to 4 digits on the side they are applied, and a
refusal of a value the command line set naming its option."""

import re
import types

import numpy as np
import pytest

import mol_shell
from mol_shell._core.constants import stated_down, stated_up
from mol_shell._core.errors import ParameterError
from mol_shell.cli.main import main
from mol_shell.runs.simulate import _check_max_step
from mol_shell.views.animate import animate

RUN = ["run", "twisted-cylinder", "--n", "9"]


def _refusal(argv, tmp_path, capsys):
    code = main([*argv, "-o", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert not (tmp_path / "x.nc").exists()
    return err.removeprefix("mol-shell: error: ")


@pytest.mark.parametrize("word", ["none", "auto", "None"])
def test_restart_takes_no_none_word(word, tmp_path, capsys):
    # None is leap-frog's default restart (1 s), not "never": the word was read as it and restarted every second
    said = _refusal([*RUN, "--times", "0:2:1", "--option", f"restart={word}"], tmp_path, capsys)
    assert said.startswith(f"--option restart = '{word}' is not a number; allowed: [0, inf] s; 0 or inf: never"), said
    assert mol_shell.integrators.INTEGRATORS["leapfrog"]().restart_s() == 1.0  # Python's None: the default still


@pytest.mark.parametrize("first,then", [("jac_reuse=5000", "jac_reuse=5"), ("max_steps=0", "max_steps=5"),
                                        ("linsolver=bogus", "linsolver=band")])
def test_not_an_option_is_said_before_the_range(first, then, tmp_path, capsys):
    argv = ["run", "unshearable", "--n", "9", "--t-end", "1e-4", "--integrator", "ida", "--option"]
    name = first.partition("=")[0]
    expected = f"--option {name} is not an option of ida (its options: atol, max_step, rtol)"
    assert _refusal([*argv, first], tmp_path, capsys) == expected
    assert _refusal([*argv, then], tmp_path, capsys) == expected


def test_rtol_on_leapfrog_is_not_an_option_whatever_its_value(tmp_path, capsys):
    for value in ("5", "1e-6"):
        said = _refusal([*RUN, "--t-end", "1e-4", "--rtol", value], tmp_path, capsys)
        assert said.startswith("rtol is not an option of leapfrog"), said
    # on an integrator that takes it, the range, with the value as typed
    said = _refusal([*RUN, "--t-end", "1e-4", "--integrator", "cvode-bdf", "--rtol", "5"], tmp_path, capsys)
    assert said == "--rtol = 5 is outside [1e-14, 1)"


def test_stated_bounds_round_towards_the_inside():
    assert stated_down(1.88945e-4) == 1.889e-4 and stated_down(1.88955e-4) == 1.889e-4
    assert stated_down(1.889e-4) == 1.889e-4 and stated_up(1.01045e-10) == 1.011e-10


@pytest.mark.parametrize("scene,n", [("twisted-cylinder", 9), ("twisted-cylinder", 11), ("twisted-cylinder", 21),
                                     ("unshearable", 9)])
def test_the_stated_dt_bound_is_the_one_applied(scene, n):
    # the open bound (0, B) stated: dt = B refused (B rounded up from 1/omega_max ran at n = 21: dt = 0.0001889)
    with pytest.raises(ParameterError) as info:
        mol_shell.simulate(scene, "leapfrog", n=n, dt=1.0, times=[0, 1.0])
    bound = float(re.search(r"outside \(0, ([0-9.e+-]+)\) s", str(info.value)).group(1))
    with pytest.raises(ParameterError, match=re.escape(f"is outside (0, {bound:.4g}) s")):
        mol_shell.simulate(scene, "leapfrog", n=n, dt=bound, times=[0, bound])
    below = bound * (1 - 1e-6)
    assert mol_shell.simulate(scene, "leapfrog", n=n, dt=below, times=[0, below]).sizes["time"] == 2


def test_the_stated_max_step_bound_is_the_one_applied():
    # [B, inf) stated: B taken, the double below it refused (1.0105e-10 ran under [1.011e-10, inf))
    times = np.linspace(0.0, 1e-4, 11)
    method = types.SimpleNamespace(name="dop853-c", max_steps=1_000_000, max_step=1e-300)
    with pytest.raises(ParameterError) as info:
        _check_max_step(method, times)
    bound = float(re.search(r"outside \[([0-9.e+-]+), inf\) s", str(info.value)).group(1))
    assert bound == 1.011e-10  # t_end / (0.99 max_steps - 10), rounded up to 4 digits (docs/integrators.md)
    _check_max_step(types.SimpleNamespace(name="dop853-c", max_steps=1_000_000, max_step=bound), times)
    for below in (np.nextafter(bound, 0.0), 1.0105e-10):
        with pytest.raises(ParameterError, match=re.escape("max_step = ")):
            _check_max_step(types.SimpleNamespace(name="dop853-c", max_steps=1_000_000, max_step=below), times)


@pytest.mark.parametrize("argv,said", [
    ([*RUN, "--t-end", "1e-300"], "--t-end = 1e-300 is outside [1.5e-153, inf) s"),
    ([*RUN, "--t-end", "1e-4", "--integrator", "dop853-c", "--max-step", "1e-300"],
     "--max-step = 1e-300 is outside [1.011e-10, inf) s, or 0 (unbounded)"),
    (["run", "twisted-cylinder", "--n", "99999999999", "--t-end", "1e-4"], "--n = 99999999999 is outside integers 3..")])
def test_a_refusal_names_the_option_typed(argv, said, tmp_path, capsys):
    err = _refusal(argv, tmp_path, capsys)
    assert err.startswith(said), err


def test_fps_is_shown_as_given(tmp_path):
    ds = mol_shell.simulate("twisted-cylinder", n=9, dt=1e-5, times=[0, 1e-5])
    with pytest.raises(ParameterError, match=re.escape("fps = 50.00000000000001 is outside [0.002, 50]")):
        animate(ds, tmp_path / "a.gif", fps=50.00000000000001)
    with pytest.raises(ParameterError, match=re.escape("fps = 60 is outside [0.002, 50]")):
        animate(ds, tmp_path / "a.gif", fps=60.0)
