"""A layer's law keys its law does not read are said, naming the layer; a run of the Python API with a law of one's own
is written back as a scene file by the law's import path, without importing it."""

import sys
import textwrap

import casadi as ca
import numpy as np
import pytest

import mol_shell
from mol_shell.analysis.run_scene import read_run_toml
from mol_shell.cli.main import main
from mol_shell.model.law_warnings import unused_law_parameters
from mol_shell.scenes import Sphere
from mol_shell.scenes.scene_warnings import scene_warnings

TIMES = np.linspace(0.0, 4e-3, 3)
MODULE = "laws_of_a_script"
#: the law of test_user_laws.py's import-path test (its graphs, by the same name, energy and parameters)
SOURCE = '''
    import casadi as ca
    import mol_shell

    rubber = mol_shell.Material("rubber", energy=lambda C, p: p["mu"] / 2 * (ca.trace(C) - 3),
                                parameters={"mu": 1e6 / 3}, thickness="incompressible")
'''


def test_a_layer_s_law_keys_it_does_not_read_are_said_naming_the_layer():
    """``0.006 mooney-rivlin E=5e7 nu=0.1`` ran unsaid, its E and nu dropped, while the same keys at the scene's
    level are said. Mooney-Rivlin reads c10 and c01 only, the compressible neo-Hookean E and nu, the incompressible one
    E, a Material its own parameters: each key a layer sets that its law does not read is one line naming the layer
    (its number from the lower face, its thickness) and the law; the scene's own keys, which the layers take, are not
    said of a layered wall."""
    scene = Sphere(h=0.01, material="neo-hookean", nu=0.3, c01=7.0,
                   layers="0.006 mooney-rivlin E=5e7 nu=0.1 c10=2e5; 0.008 neo-hookean c10=5e5 E=2e6; "
                          "0.006 neo-hookean-incompressible nu=0.1 E=3e6")
    reads_c = "material = 'mooney-rivlin' reads c10 and c01 only"
    assert unused_law_parameters(scene) == [
        f"layer 1 (0.006 m): E = 5e+07 is unused: {reads_c}", f"layer 1 (0.006 m): nu = 0.1 is unused: {reads_c}",
        "layer 2 (0.008 m): c10 = 500000 is unused: material = 'neo-hookean' reads E and nu, not c10 and c01",
        "layer 3 (0.006 m): nu = 0.1 is unused: material = 'neo-hookean-incompressible' reads E only"]
    assert scene_warnings(scene)["scene_warning"] == unused_law_parameters(scene)  # said once, by every command
    law = mol_shell.Material("layer-law", energy=lambda C, p: p["mu"] / 2 * (ca.trace(C) - 3),
                             parameters={"mu": 1e5}, thickness="incompressible")
    own = Sphere(h=0.01, layers=[{"thickness": 0.01, "material": law, "E": 5e7}, {"thickness": 0.01,
                                                                                 "material": "svk", "nu": 0.2}])
    assert unused_law_parameters(own) == [("layer 1 (0.01 m): E = 5e+07 is unused: material = 'layer-law' is a law "
                                           "of one's own: it reads its parameters (material_parameters)")]


@pytest.fixture(scope="module")
def imported_run(tmp_path_factory):
    """A run of the Python API whose law comes from an importable module (``from laws_of_a_script import rubber``),
    written to a file; the module then forgotten (not importable, not imported)."""
    where = tmp_path_factory.mktemp("laws")
    (where / f"{MODULE}.py").write_text(textwrap.dedent(SOURCE))
    sys.path.insert(0, str(where))
    try:
        rubber = __import__(MODULE).rubber
        ds = mol_shell.simulate(Sphere(h=0.01, material=rubber, R=1.2), "leapfrog", n=8, times=TIMES, progress=False,
                                stresses=False)
    finally:
        sys.path.remove(str(where))
        sys.modules.pop(MODULE, None)
    mol_shell.write_netcdf(ds, where / "py.nc")
    return ds, where


def test_a_python_run_of_an_imported_law_is_written_back_by_its_import_path(imported_run, tmp_path, monkeypatch):
    """``scenes RUN.nc --toml`` of such a run was refused, "by this version" (the one that wrote it): the run kept
    the law's name, which no other process knows. The run records the law's import path (``material_imports``), the
    scene file names the law by it, written without importing the module (where it is not importable), and runs the
    same run again to the bit where it is."""
    ds, where = imported_run
    key = ds.attrs["material"]  # "rubber" (or rubber@digest, another law of the name made in this process)
    assert key.startswith("rubber") and ds.attrs["material_imports"] == f"{key}={MODULE}:rubber"
    monkeypatch.chdir(tmp_path)
    text = read_run_toml(str(where / "py.nc"))
    assert MODULE not in sys.modules
    assert f'\nmaterial = "{MODULE}:rubber"' in text and "no import path" not in text
    (tmp_path / "again.toml").write_text(text)
    monkeypatch.syspath_prepend(str(where))
    assert main(["run", str(tmp_path / "again.toml"), "-o", str(tmp_path / "again.nc")]) == 0
    again = mol_shell.read_netcdf(tmp_path / "again.nc")
    np.testing.assert_array_equal(again.r.values, ds.r.values)
    np.testing.assert_array_equal(again.psi.values, ds.psi.values)


def test_a_law_without_an_import_path_is_written_by_its_name_and_said_so(imported_run, tmp_path, monkeypatch):
    """A law made in a script's ``__main__`` (or a notebook) has no import path: the scene file names it by its name
    and says it must be given as ``module:attr``. A layer's law is written by its import path as the wall's is."""
    ds, _ = imported_run
    monkeypatch.delitem(sys.modules, MODULE, raising=False)
    key = ds.attrs["material"]
    law = mol_shell.Material("local-law", energy=lambda C, p: p["mu"] / 2 * (ca.trace(C) - 3),
                             parameters={"mu": 1e5}, thickness="incompressible")
    assert law.import_path() is None  # bound in no module
    ds = ds.copy()
    ds.attrs.pop("material_imports")
    name = tmp_path / "main.nc"
    mol_shell.write_netcdf(ds, name)
    text = read_run_toml(str(name))
    assert f'\nmaterial = "{key}"' in text
    assert f"# material {key!r} is a law of one's own the run recorded no import path for" in text
    ds.attrs.update(material_imports=f"{key}={MODULE}:rubber", layers=f"0.01 {key}; 0.01 svk-plane-stress nu=0.2")
    mol_shell.write_netcdf(ds, name)
    text = read_run_toml(str(name))
    assert f'\nlayers = "0.01 {MODULE}:rubber; 0.01 svk-plane-stress nu=0.2"' in text
    assert MODULE not in sys.modules
