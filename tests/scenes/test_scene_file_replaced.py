"""What a scene file's values become where something else replaces them: ``study --vary`` over a ``[run]`` option
(replaced), ``--integrator`` over the file's (its options the other does not take left out with a note, the shared
kept), a vessel's ``segments`` over ``a``, ``Lc``, ``crown``, ``knuckle`` (each said unused), and ``[[layer]]``
tables that do not add up to the wall (said by the tables, or by the ``--set h`` that made them disagree)."""

import pytest

from mol_shell._core.errors import ParameterError
from mol_shell.cli import study as study_cli
from mol_shell.cli.main import make_parser
from mol_shell.scenes.files import load_scene
from mol_shell.scenes.scene_warnings import scene_warnings


class _Ran(Exception):
    """Raised in place of running the study: its keywords, as the command gave them."""


@pytest.fixture
def captured_study(monkeypatch):
    def fake(scene, vary, integrator, **kwargs):
        raise _Ran(dict(vary=vary, integrator=integrator, **kwargs))

    monkeypatch.setattr(study_cli, "study", fake)

    def run(argv):
        args = make_parser().parse_args(argv)
        with pytest.raises(_Ran) as info:
            args.func(args)
        return info.value.args[0]

    return run


BDF = ('scene = "sphere"\n[initial]\nR = 1.01\n[run]\nintegrator = "cvode-bdf"\nn = 11\nt_end = 0.002\n'
       'rtol = 1e-6\njac_every = 30\n')


def test_study_vary_replaces_the_files_run_option(tmp_path, captured_study, capsys):
    """``study st.toml --vary rtol=...`` was refused ("rtol = 1e-06 is set while vary['rtol'] varies it"), naming
    neither the file nor [run], though the docs say the file's value is replaced; the command line's own beside
    --vary stays refused."""
    path = tmp_path / "st.toml"
    path.write_text(BDF)
    out = str(tmp_path / "s.nc")
    got = captured_study(["study", str(path), "--vary", "rtol=1e-5,1e-7", "-o", out])
    assert got["vary"] == {"rtol": [1e-5, 1e-7]} and "rtol" not in got and got["jac_every"] == 30
    got = captured_study(["study", str(path), "--vary", "jac_every=10,20", "-o", out])
    assert got["vary"] == {"jac_every": [10, 20]} and "jac_every" not in got and got["rtol"] == 1e-6
    args = make_parser().parse_args(["study", str(path), "--vary", "rtol=1e-5,1e-7", "--rtol", "1e-6", "-o", out])
    with pytest.raises(ParameterError, match=r"^--rtol = 1e-06 sets rtol, which --vary varies"):
        args.func(args)


def test_study_integrator_leaves_out_the_files_options_it_does_not_take(tmp_path, captured_study, capsys):
    """``--integrator cvode-bdf`` on a file for ida: jac_reuse (ida's) left out with a note naming it; max_order and
    linsolver, which both take, kept."""
    path = tmp_path / "rt_ida.toml"
    path.write_text('scene = "sphere"\n[initial]\nR = 1.01\n[run]\nintegrator = "ida"\nn = 11\nt_end = 0.0005\n'
                    'jac_reuse = 5\nmax_order = 3\nlinsolver = "lapack-dense"\n')
    got = captured_study(["study", str(path), "--vary", "rtol=1e-5,1e-7", "--integrator", "cvode-bdf",
                          "-o", str(tmp_path / "s.nc")])
    assert got["integrator"] == "cvode-bdf" and "jac_reuse" not in got
    assert got["max_order"] == 3 and got["linsolver"] == "lapack-dense"
    assert ("note: the scene file's [run] jac_reuse = 5 is not an option of cvode-bdf (--integrator): left out"
            in capsys.readouterr().err)


def test_segments_say_the_vessel_parameters_they_replace_unused(tmp_path):
    """``segments`` beside ``a = 2``, ``Lc = 7``, ``crown = 5``, ``knuckle = 0.3`` ran without a word (the run's
    attrs saying a = 2 of a shell of radius 1)."""
    path = tmp_path / "v.toml"
    path.write_text('scene = "vessel"\n[geometry]\nsegments = "arc 1 -90, line 2, arc 1 -90"\na = 2\nLc = 7\n'
                    'crown = 5\nknuckle = 0.3\n')
    lines = scene_warnings(load_scene(path))["scene_warning"]
    assert lines == [f"{key} is unused: segments draw the meridian"
                     for key in ("a = 2", "Lc = 7", "crown = 5", "knuckle = 0.3")]
    path.write_text('scene = "vessel"\n[geometry]\nsegments = "arc 1 -90, line 2, arc 1 -90"\n')
    assert scene_warnings(load_scene(path))["scene_warning"] == []  # the defaults: nothing set beside them
    path.write_text('scene = "vessel"\n[geometry]\na = 2\nLc = 7\n')
    assert scene_warnings(load_scene(path))["scene_warning"] == []  # no segments: a and Lc draw it


LAYERS = ('scene = "sphere"\n[material]\nh = {h}\n[[layer]]\nthickness = {t1}\nmaterial = "neo-hookean-incompressible"'
          '\n[[layer]]\nthickness = {t2}\nmaterial = "svk-plane-stress"\n')


def test_layer_tables_not_adding_up_to_the_wall_are_said_by_the_tables(tmp_path):
    """Said as ``[layer] layers = '0.012 neo-hookean-incompressible; ...'``, a table and key never written."""
    path = tmp_path / "e4.toml"
    path.write_text(LAYERS.format(h=0.01, t1=0.012, t2=0.009))
    with pytest.raises(ParameterError) as info:
        load_scene(path)
    assert str(info.value) == (f"{path}: [[layer]] thicknesses 0.012 + 0.009 = 0.021 m; allowed: thicknesses adding "
                               "up to the wall, 2h = 0.02 m ([material] h = 0.01), to 1e-06 of it")


def test_set_h_that_makes_the_layers_disagree_is_named(tmp_path):
    """``--set h=0.011`` on layers adding up to 2 x 0.01 m blamed the file's layers, not the --set that did it."""
    path = tmp_path / "lay.toml"
    path.write_text(LAYERS.format(h=0.01, t1=0.01, t2=0.01))
    with pytest.raises(ParameterError) as info:
        load_scene(path, overrides={"h": "0.011"})
    assert str(info.value).startswith(f"--set h = 0.011 makes the wall 2h = 0.022 m, which {path}'s [[layer]] "
                                      "thicknesses 0.01 + 0.01 = 0.02 m do not add up to; allowed: h = half")
    assert info.value.name == "h"
    assert load_scene(path, overrides={"h": "0.01"}).h == 0.01  # the same h: they add up


def test_a_number_for_a_history_is_refused_with_the_inline_table_forms(tmp_path):
    path = tmp_path / "ph.toml"
    path.write_text('scene = "sphere"\n[loads]\npressure = 100\npressure_history = 5\n')
    with pytest.raises(ParameterError) as info:
        load_scene(path)
    said = str(info.value)
    assert said.startswith(f"{path}: [loads] pressure_history = 5 is not a string or an inline table; allowed: ")
    assert '{kind = "ramp", t1 = T1}' in said and "'ramp T1'" in said
