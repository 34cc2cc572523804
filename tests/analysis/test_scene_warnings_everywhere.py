"""The scene's warnings (the director law's locking, parameters without effect) are said by ``path``, ``modes`` and
the studies as by ``simulate``: each once, and recorded in the Dataset's attrs (``material_warning``,
``scene_warning``). ``mol-shell path`` said none of them (a path past twice the classical buckling pressure of a
locking ``svk`` wall found no critical point without a hint why), ``modes`` only the locking one, a study of runs
never the unused fibre keys."""

from __future__ import annotations

import warnings

import mol_shell
from mol_shell import MaterialWarning, SceneWarning, Sphere
from mol_shell.analysis.path_study import path_study
from mol_shell.cli.main import main

NU = 0.49
#: the director law at nu = 0.49 against a thin wall in plane stress, in a hoop stretch: (1 - nu)^2 / (1 - 2 nu)
#: (lambda + 2 mu against E / (1 - nu^2))
HOOP = (1 - NU) ** 2 / (1 - 2 * NU)
LOCKING = f"{HOOP:.3g} times stiffer in a hoop stretch"
FIBRES = "fibre_angle = 0.5 is unused: fibre_E = 0"
GRAVITY = "gravity_history = 'ramp 1' is unused: gravity = 0"


def _said(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = call()
    return out, [(w.category, str(w.message)) for w in caught if issubclass(w.category, (MaterialWarning, SceneWarning))]


def _count(said, category, text):
    return sum(1 for kind, message in said if kind is category and text in message)


def test_a_path_says_and_records_the_scenes_warnings_once_each():
    """svk at nu = 0.49 (13.0 times stiffer), a fibre angle without fibres, a history without its load: each said once,
    as MaterialWarning or SceneWarning, and in the path's attrs. The continued load's own history is replaced by the
    path's constant values: not said as unused."""
    scene = Sphere(nu=NU, fibre_angle=0.5, gravity_history="ramp 1", pressure_history="ramp 1")
    ds, said = _said(lambda: mol_shell.path(scene, "pressure", 0.0, -100.0, n=11, max_steps=2, progress=False))
    assert LOCKING.startswith("13 times")  # 0.51^2 / 0.02 = 13.005
    assert _count(said, MaterialWarning, LOCKING) == 1 and _count(said, MaterialWarning, FIBRES) == 1
    assert _count(said, SceneWarning, GRAVITY) == 1 and not any("pressure_history" in m for _, m in said)
    assert LOCKING in ds.attrs["material_warning"] and FIBRES in ds.attrs["material_warning"]
    assert ds.attrs["scene_warning"].startswith(GRAVITY)


def test_modes_say_the_unused_parameters_too():
    """Mooney-Rivlin reads c10 and c01, not E; fibre keys without fibre_E: both said and recorded (modes said only the
    locking warning)."""
    scene = Sphere(material="mooney-rivlin", E=5.0, fibre_angle=0.5)
    ds, said = _said(lambda: mol_shell.modes(scene, n=11, count=2))
    assert _count(said, SceneWarning, "E = 5 is unused: material = 'mooney-rivlin' reads c10 and c01 only") == 1
    assert _count(said, MaterialWarning, FIBRES) == 1
    assert "E = 5 is unused" in ds.attrs["scene_warning"] and FIBRES in ds.attrs["material_warning"]


def test_a_study_of_paths_says_each_warning_once_not_once_per_case():
    scene = Sphere(material="neo-hookean-incompressible", nu=0.2, fibre_angle=0.5)
    ds, said = _said(lambda: path_study(scene, {"h": [0.01, 0.0125]}, "pressure", 0.0, -100.0, n=11, max_steps=1,
                                        scheduler="serial"))
    assert _count(said, SceneWarning, "nu = 0.2 is unused: material = 'neo-hookean-incompressible' reads E only") == 1
    assert _count(said, MaterialWarning, FIBRES) == 1 and len(said) == 2
    assert FIBRES in ds.attrs["material_warning"] and "nu = 0.2 is unused" in ds.attrs["scene_warning"]


def test_a_study_of_runs_says_the_unused_fibre_keys_once():
    """A study's cases run with the material's warnings off (the study says them once): it said only the locking
    one, so an unused fibre key was said by nothing."""
    scene = Sphere(material="svk-plane-stress", nu=0.3, fibre_angle=0.5)  # two cases of one kernel: omega is initial
    _, said = _said(lambda: mol_shell.study(scene, {"omega": [0.0, 1.0]}, n=11, t_end=1e-4, scheduler="serial"))
    assert _count(said, MaterialWarning, FIBRES) == 1 and len(said) == 1


def test_the_path_command_says_them_once(tmp_path, capsys):
    out = tmp_path / "w.nc"
    code = main(["path", "sphere", "--param", "pressure=0:-100", "--set", "material=svk-plane-stress", "--set",
                 "nu=0.3", "--set", "c10=7", "--n", "11", "--max-steps", "2", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 0
    assert err.count("mol-shell: warning: c10 = 7 is unused: material = 'svk-plane-stress' reads E and nu") == 1
