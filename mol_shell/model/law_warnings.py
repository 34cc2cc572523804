"""What a scene's law says about the scene before it runs: parameters it does not read, locking under the director
constraint, fibres that carry nothing. Lines of text, said once by :func:`mol_shell.simulate`, ``modes``, ``path`` and
the studies (``SceneWarning``, ``MaterialWarning``: :mod:`mol_shell.scenes.scene_warnings`) and stored in their
Datasets' attributes."""

from __future__ import annotations

import dataclasses

from mol_shell.model.fibres import FIBRE_DEFAULTS, FIBRE_PARAMETERS, unused_fibres_warning
from mol_shell.model.laws import COMPRESSIBLE, LAWS, layer_scenes, thickness_treatment
from mol_shell.model.layers import parse_layers
from mol_shell.model.material import MATERIALS as SVK_MATERIALS
from mol_shell.model.material import locking_warning


def _reads(name):
    """``(keys, why)``: which of ``E, nu, c10, c01`` the law ``name`` reads, and the clause that says so."""
    if name in LAWS and name not in COMPRESSIBLE:
        reads = ("c10", "c01") if name == "mooney-rivlin" else ("E",)
        return reads, f"material = {name!r} reads {' and '.join(reads)} only"
    if name in LAWS or name in SVK_MATERIALS:
        return ("E", "nu"), f"material = {name!r} reads E and nu, not c10 and c01"
    return (), f"material = {name!r} is a law of one's own: it reads its parameters (material_parameters)"


def unused_law_parameters(scene):
    """One line for each of ``E, nu, c10, c01`` set away from the scene's default that its law does not read (a law
    of one's own reads its own parameters, Mooney-Rivlin ``c10, c01`` alone, the incompressible neo-Hookean ``E``,
    the others ``E, nu``), and for ``eta_lambda > 0`` on an incompressible law. A layered wall: one line for each of
    those keys a layer sets itself that its law does not read, naming the layer (its number from the lower face and
    its thickness; until December 7 a layer's were not looked at: ``0.006 mooney-rivlin E=5e7`` ran unsaid)."""
    name, defaults = scene.material, {f.name: f.default for f in dataclasses.fields(scene)}
    if getattr(scene, "layers", ""):
        return unused_layer_parameters(scene)
    if not isinstance(name, str):
        return []
    reads, why = _reads(name)
    lines = [f"{key} = {getattr(scene, key):g} is unused: {why}" for key in ("E", "nu", "c10", "c01")
             if key in defaults and key not in reads and getattr(scene, key) != defaults[key]]
    if getattr(scene, "eta_lambda", 0.0) > 0 and thickness_treatment(name) == "incompressible":
        lines.append(f"eta_lambda = {scene.eta_lambda:g} is unused: material = {name!r} is incompressible (det C = 1), "
                     "its Kelvin-Voigt stress has eta_mu alone")
    return lines


def unused_layer_parameters(scene):
    """The lines of :func:`unused_law_parameters` for a layered wall: each of ``E, nu, c10, c01`` a layer sets itself
    (in ``layers``) that its law does not read, as ``layer K (T m): KEY = VALUE is unused: material = ...``. The
    scene's own keys, which every layer takes where it sets none, are not said (the wall's ``material`` sets the run's
    scales with them)."""
    lines = []
    for k, ((t, sub), (_, material, own)) in enumerate(zip(layer_scenes(scene), parse_layers(scene.layers)), 1):
        reads, why = _reads(material)
        lines += [f"layer {k} ({t:g} m): {key} = {getattr(sub, key):g} is unused: {why}"
                  for key in ("E", "nu", "c10", "c01") if key in own and key not in reads]
    return lines


def locking_warnings(scene):
    """The lines of :func:`~mol_shell.model.material.locking_warning` for ``scene``: its law's; for a layered wall one
    per layer that is ``svk`` at ``nu >= 0.45`` (named by its place and thickness), and none for the scene-level
    ``material``/``nu`` the layers replace."""
    if not getattr(scene, "layers", ""):
        note = locking_warning(scene.material, scene.nu)
        return [note] if note else []
    notes = [(k, t, locking_warning(sub.material, sub.nu)) for k, (t, sub) in enumerate(layer_scenes(scene), 1)]
    return [f"layer {k} ({t:g} m): {note}" for k, t, note in notes if note]


def unused_fibres_warnings(scene):
    """The lines of :func:`~mol_shell.model.fibres.unused_fibres_warning` for ``scene``: its own; for a layered wall
    one per layer whose fibre parameters ``fibre_E = 0`` leaves unused (named by its place and thickness), or one
    for all when every layer has the same (the scene's fibre keys, which each layer takes)."""
    if not getattr(scene, "layers", ""):
        note = unused_fibres_warning(scene)
        return [note] if note else []
    notes = []
    for k, ((t, sub), (_, _, own)) in enumerate(zip(layer_scenes(scene), parse_layers(scene.layers)), 1):
        if "fibre_E" in own:  # a layer that turns its fibres off itself: the scene's fibre keys it takes are moot
            sub = dataclasses.replace(sub, **{name: FIBRE_DEFAULTS[name] for name in FIBRE_PARAMETERS[1:]
                                              if name not in own})
        notes.append((k, t, unused_fibres_warning(sub)))
    if len(notes) > 1 and all(note == notes[0][2] for _, _, note in notes) and notes[0][2]:
        return [f"every layer: {notes[0][2]}"]
    return [f"layer {k} ({t:g} m): {note}" for k, t, note in notes if note]
