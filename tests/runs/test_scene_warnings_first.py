"""The scene's warnings (the director law's locking at nu >= 0.45, ...) are said before the build and the run, so a
user can stop and switch laws: at n = 20,000 they came at 66 s of a 68 s run, after "100 %" of a 75 s one. Said once,
and recorded in the run's attributes as before."""

import importlib
import warnings

import mol_shell
from mol_shell import MaterialWarning, TwistedCylinder

simulate_module = importlib.import_module("mol_shell.runs.simulate")


def test_the_locking_warning_precedes_the_build_and_is_said_once(monkeypatch):
    """Before a long build or run (LONG_BUILD_S set to 0 here: every one counts as long); a quick run says it after
    the run as before, so that a refusal stays one line whenever it comes (tests/cli/test_cli.py)."""
    monkeypatch.setattr(simulate_module.resources, "LONG_BUILD_S", 0.0)
    scene = TwistedCylinder(material="svk", nu=0.49)  # locks: 13x stiffer in a hoop stretch than plane stress
    events = []
    original = simulate_module.build

    def spy(*args, **kwargs):
        events.append(("build", len(caught)))
        return original(*args, **kwargs)

    monkeypatch.setattr(simulate_module, "build", spy)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mol_shell.simulate(scene, n=9, t_end=1e-5, progress=False, stresses=False)
    locking = [i for i, w in enumerate(caught) if issubclass(w.category, MaterialWarning)
               and "stiffer in a hoop stretch" in str(w.message)]
    assert len(locking) == 1, [str(w.message) for w in caught]
    assert events == [("build", events[0][1])] and locking[0] < events[0][1]
    assert "stiffer in a hoop stretch" in ds.attrs["material_warning"]


def test_modes_and_paths_say_it_before_their_work_too(monkeypatch):
    """``modes`` said the scene's warnings after its eigen-solve and ``path`` after the whole trace: now once their
    refusals are past (a refusal stays one line), before the eigen-solve and before the trace's steps, once, recorded
    as before."""
    modes_module = importlib.import_module("mol_shell.analysis.modes")
    path_module = importlib.import_module("mol_shell.analysis.path")
    scene = TwistedCylinder(material="svk", nu=0.49, gamma=0.0)
    for module, name, call in ((modes_module, "eigenvalue_scale", lambda: mol_shell.modes(scene, n=9, count=2)),
                               (path_module, "PathRecord",
                                lambda: mol_shell.path(scene, "pressure", 0.0, 100.0, n=9, steps=2, progress=False))):
        events = []
        original = getattr(module, name)

        def spy(*args, _original=original, _events=events, **kwargs):
            _events.append(len(caught))
            return _original(*args, **kwargs)

        monkeypatch.setattr(module, name, spy)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            ds = call()
        locking = [i for i, w in enumerate(caught) if issubclass(w.category, MaterialWarning)
                   and "stiffer in a hoop stretch" in str(w.message)]
        assert len(locking) == 1 and locking[0] < events[0], (name, [str(w.message) for w in caught])
        assert "stiffer in a hoop stretch" in ds.attrs["material_warning"]
