"""True/false parameters of the Python API are checked as bools, and options that a run does not use are refused.

``simulate_unshearable(constrained="no")`` ran the constrained DAE (any non-empty string is true), as
``load_scene(with_run="no")`` returned the ``[run]`` table; ``simulate_unshearable(dt=...)`` of the constrained run
(IDA) was ignored silently, as ``rtol`` of the free one (leap-frog) was, where ``simulate`` refuses an option its
integrator does not take. A study's refusal of a case named by part of its parameters showed
``e.g. gamma=np.float64(0.05)``; docs/python.md named a case of a study of gamma and nu by gamma alone."""

import re
from pathlib import Path

import pytest

import mol_shell
from mol_shell import ParameterError
from mol_shell.results.study_dataset import study_case

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("call, words", [
    (lambda: mol_shell.simulate_unshearable("unshearable", n=8, t_end=1e-4, constrained="no"),
     "constrained = 'no' is not a bool; allowed: True or False"),
    (lambda: mol_shell.simulate_unshearable("unshearable", n=8, t_end=1e-4, dt=1e-5),
     "dt is not an option of the constrained DAE (ida) (its options: atol, max_step, rtol)"),
    (lambda: mol_shell.simulate_unshearable("unshearable", n=8, t_end=1e-4, constrained=False, rtol=1e-6),
     "rtol is not an option of the free shell (leapfrog) (its options: chunk, dt, restart)"),
    (lambda: mol_shell.load_scene(ROOT / "examples" / "pressurised_sphere.toml", with_run="no"),
     "with_run = 'no' is not a bool; allowed: True or False"),
    (lambda: mol_shell.load_scene(ROOT / "examples" / "pressurised_sphere.toml", together=1),
     "together = 1 is not a bool; allowed: True or False"),
])
def test_a_flag_that_is_not_a_bool_and_an_option_the_run_does_not_take_are_refused(call, words):
    with pytest.raises(ParameterError) as err:
        call()
    assert str(err.value) == words


def test_a_case_named_by_part_of_its_parameters_is_refused_with_plain_numbers():
    st = mol_shell.study(mol_shell.TwistedCylinder(material="svk-plane-stress"), {"gamma": [0.05, 0.1],
                         "nu": [0.3, 0.4]}, n=8, t_end=1e-5, scheduler="serial", progress=False)
    with pytest.raises(ParameterError, match=r"\(e\.g\. gamma=0\.05, nu=0\.3\)$"):
        study_case(st, gamma=0.1)
    assert study_case(st, gamma=0.1, nu=0.3).attrs["gamma"] == 0.1


def test_the_python_pages_case_of_a_study_names_each_varied_parameter():
    text = (ROOT / "docs" / "python.md").read_text()
    varied = set(re.findall(r'"(\w+)": \[', re.search(r"mol_shell\.study\(scene, (\{[^}]*\})", text).group(1)))
    named = re.search(r"study_case\(st, ([^)]*)\)", text).group(1)
    assert varied == {"gamma", "nu"} and set(re.findall(r"(\w+)=", named)) == varied, named
