"""One policy for what a scene says about itself: the warnings of :func:`mol_shell.simulate`, :func:`mol_shell.modes`,
:func:`mol_shell.path` and the studies of both.

Two kinds, each a list of one-line texts, each kept in its Dataset's attribute of the same name:
``material_warning`` (:class:`~mol_shell.MaterialWarning`: the director law's locking at ``nu >= 0.45``, fibre keys
that ``fibre_E = 0`` leaves unused) and ``scene_warning`` (:class:`~mol_shell.SceneWarning`: a load's history without
the load, a law parameter the law does not read). A run, a path or a mode analysis says them (the warnings module:
once per command on the command line) and records them; a study says each distinct one once, itself, and its cases
record their own.
"""

from __future__ import annotations

import dataclasses
import warnings

from mol_shell._core.errors import MaterialWarning, MolShellWarning, SceneWarning
from mol_shell.model.law_warnings import locking_warnings, unused_fibres_warnings, unused_law_parameters
from mol_shell.scenes.setting import unused_histories

#: the parameters of a scene's own meridian that its ``segments`` (a vessel's) replace
SEGMENT_REPLACED = ("a", "Lc", "crown", "knuckle")


def unused_by_segments(scene):
    """One line for each parameter of :data:`SEGMENT_REPLACED` set (not its default) beside ``segments``, which draw
    the meridian in its place: ``a = 2 is unused: segments draw the meridian`` (it was dropped silently, the run's
    attrs still saying ``a = 2``)."""
    if not (dataclasses.is_dataclass(scene) and str(getattr(scene, "segments", "") or "").strip()):
        return []
    defaults = {f.name: f.default for f in dataclasses.fields(scene)}
    return [f"{key} = {getattr(scene, key):g} is unused: segments draw the meridian" for key in SEGMENT_REPLACED
            if key in defaults and getattr(scene, key) is not None and getattr(scene, key) != defaults[key]]


#: the attribute that records each kind, and the category it is said as
KINDS = {"material_warning": MaterialWarning, "scene_warning": SceneWarning}


def scene_warnings(scene, parameter=None):
    """``{"material_warning": [lines], "scene_warning": [lines]}`` for ``scene``. ``parameter``: the load a path
    continues, whose history the path replaces (a constant load): not said as unused."""
    histories = [line for line in unused_histories(scene) if parameter is None
                 or not line.startswith(f"{parameter}_history ")]
    return {"material_warning": [*locking_warnings(scene), *unused_fibres_warnings(scene)],
            "scene_warning": [*histories, *unused_law_parameters(scene), *unused_by_segments(scene)]}


def say_scene_warnings(scene, attrs=None, *, parameter=None, stacklevel=2):
    """Say each of :func:`scene_warnings` (``stacklevel`` as for :func:`warnings.warn`, counted from the caller) and
    record each kind in ``attrs`` (a dict: a Dataset's attrs), its lines joined by ``"; "``. Returns ``attrs``."""
    for kind, lines in scene_warnings(scene, parameter).items():
        for line in lines:
            warnings.warn(line, KINDS[kind], stacklevel=stacklevel + 1)
        if lines and attrs is not None:
            attrs[kind] = "; ".join(lines)
    return attrs


def say_once(scenes, *, parameter=None, stacklevel=2):
    """A study's: each distinct line of :func:`scene_warnings` over ``scenes`` said once (not once per case)."""
    said = {}
    for scene in scenes:
        for kind, lines in scene_warnings(scene, parameter).items():
            said.update(dict.fromkeys((line, KINDS[kind]) for line in lines))
    for line, category in said:
        warnings.warn(line, category, stacklevel=stacklevel + 1)


#: what a run says and records about its own course (not its scene's): a study's case records it without saying it
#: (:func:`hush_in_case`); the study says it, each case's once, naming the case (:func:`say_case_warnings`)
CASE_WARNINGS = {"ellipticity_warning": MaterialWarning, "stability_warning": MolShellWarning}


def say_case_warnings(cases, *, stacklevel=2):
    """A study's: for each ``(label, attrs)`` of its cases (a case's Dataset's attrs), each of
    :data:`CASE_WARNINGS` it recorded, said once as ``case LABEL: TEXT``."""
    said = {}
    for label, attrs in cases:
        for kind, category in CASE_WARNINGS.items():
            if str(attrs.get(kind, "")).strip():
                said.setdefault((f"case {label}: {attrs[kind]}", category))
    for line, category in said:
        warnings.warn(line, category, stacklevel=stacklevel + 1)


def hush_in_case():
    """In a study's case (inside :func:`warnings.catch_warnings`): ignore what :func:`say_once` said for the study,
    the material's warnings (and the state's, ellipticity and slack fibres, as before: the case's Dataset records
    them) and the scene's unused parameters (each line ``... is unused: ...``), and the start's stability (the
    study says it and the ellipticity's, naming the case: :func:`say_case_warnings`); a case's other warnings stay."""
    warnings.simplefilter("ignore", MaterialWarning)
    warnings.filterwarnings("ignore", message=r".* is unused: ", category=SceneWarning)
    warnings.filterwarnings("ignore", message=r"the (start computed as a static equilibrium|stability of the start) ",
                            category=MolShellWarning)  # its stability_warning: said by the study (CASE_WARNINGS)


__all__ = ["CASE_WARNINGS", "KINDS", "hush_in_case", "say_case_warnings", "say_once", "say_scene_warnings",
           "scene_warnings", "unused_by_segments"]
