"""The parameters of laws of one's own on a wall: which laws a scene's ``material_parameters`` (and ``material.NAME``)
set. A single wall's are its ``material``'s; a layered wall's go to each layer whose law has the parameter (they were
given to every layer, and a built-in layer refused them), and one that no layer's law has is refused by name."""

from __future__ import annotations

from mol_shell._core.errors import ParameterError
from mol_shell.model.laws import own_parameters, parameter_text, parameter_values, user_material
from mol_shell.model.layers import parse_layers


def wall_laws(scene):
    """The laws whose parameters ``scene``'s ``material_parameters`` set: a layered wall's layers' (from the lower
    face), else its ``material``."""
    if getattr(scene, "layers", ""):
        return [material for _, material, _ in parse_layers(scene.layers)]
    return [scene.material]


def wall_parameter_names(scene):
    """``{name: [numbers of the laws of wall_laws(scene), from 1]}`` of the parameters of its laws of one's own."""
    out = {}
    for number, material in enumerate(wall_laws(scene), start=1):
        user = user_material(material)
        for name in (user.parameters if user is not None else ()):
            out.setdefault(name, []).append(number)
    return out


def wall_parameter(scene, name):
    """The value of parameter ``name`` in ``scene``: its ``material_parameters``', else that of the first of its laws
    (:func:`wall_laws`) that has it."""
    values = parameter_values(getattr(scene, "material_parameters", "") or "")
    if name in values:
        return values[name]
    return next(user.parameters[name] for user in map(user_material, wall_laws(scene))
                if user is not None and name in user.parameters)


def check_layer_parameters(scene):
    """A ParameterError naming ``material_parameters`` for a parameter of a layered ``scene`` that no layer's law has
    (its own ``material`` sets only the run's scales): its allowed range the parameters the layers' laws have, each
    with the layers that take it."""
    values = parameter_values(getattr(scene, "material_parameters", "") or "")
    taken = wall_parameter_names(scene)
    unused = [k for k in values if k not in taken]
    if not getattr(scene, "layers", "") or not unused:
        return
    shown = " ".join(f"{k}={values[k]:g}" for k in unused)
    if not taken:
        raise ParameterError("material_parameters", shown, "the parameters of the layers' laws, none here", hint=(
            "no layer's law is a mol_shell.Material; a built-in layer takes E, nu, c10, c01 in the layers string: "
            "'0.01 svk-plane-stress E=2e6; ...'"))
    allowed = "{" + ", ".join(f"{k} (layer{'s' if len(v) > 1 else ''} {', '.join(map(str, v))})"
                              for k, v in sorted(taken.items())) + "}, the parameters of the layers' laws"
    raise ParameterError("material_parameters", shown, allowed, hint=f"no layer's law has {', '.join(unused)}; each "
                         "parameter goes to the layers whose law has it")


def checked_material_parameters(scene):
    """``scene.material_parameters`` in its string form (a dict read too), checked against the scene's law of one's
    own: refused for a single wall of a built-in law; a layered wall's own ``material`` takes those it has here, the
    names are checked against its layers' laws by :func:`check_layer_parameters`."""
    values = parameter_values(scene.material_parameters)
    layered = bool(scene.layers.strip() if isinstance(scene.layers, str) else scene.layers)
    user = user_material(scene.material)
    if values and user is None and not layered:
        raise ParameterError("material_parameters", scene.material_parameters, "'' (a built-in law)",
                             hint=f"material = {scene.material} takes its parameters as scene parameters "
                             "(E, nu, c10, c01)")
    if values and user is not None:
        user.with_parameters(own_parameters(scene.material, values) if layered else values)
    return parameter_text(values)


def law_attrs(scene):
    """``{"material_laws": ...}`` for a run's attrs where ``scene`` has laws of one's own (else ``{}``): each law's
    key (``material``, or a layer's), its thickness treatment, the parameters it ran with (the ``Material``'s with
    the scene's ``material_parameters`` applied) and the ``Material``'s fingerprint
    (:meth:`~mol_shell.model.user_laws.Material.fingerprint`, before those changes). The attrs said
    ``material = 'rubber'`` and ``material_parameters = ''`` for every law of that name. And ``{"material_imports":
    "KEY=module:attr; ..."}`` for each law stored by its name that has an import path
    (:meth:`~mol_shell.model.user_laws.Material.import_path`): what a scene file names it by
    (:func:`mol_shell.analysis.run_scene.run_toml`)."""
    if not hasattr(scene, "material_parameters"):
        return {}
    values = parameter_values(scene.material_parameters or "")
    said, paths = [], []
    for key in dict.fromkeys([scene.material, *wall_laws(scene)]):
        user = user_material(key)
        if user is not None:
            used = {**user.parameters, **own_parameters(key, values)}
            said.append(f"{key}: {user.thickness}, {parameter_text(used) or 'no parameters'}, "
                        f"fingerprint {user.fingerprint()}")
            path = user.import_path() if ":" not in key else None
            paths += [f"{key}={path}"] if path else []
    out = {"material_laws": "; ".join(said)} if said else {}
    return {**out, "material_imports": "; ".join(paths)} if paths else out
