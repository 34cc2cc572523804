"""Material laws as stored energies ``W(C)``, the built-in ones, and what a scene's ``material`` makes of them.

``svk`` and ``svk-plane-stress`` keep their own route (:mod:`mol_shell.model.material`: the Lame pair, exact
per-cell thickness moments). Every other law is a :class:`Law`, integrated through the thickness point by point
(:mod:`mol_shell.model.hyperelastic`) with its stresses and tangents by automatic differentiation:

- ``neo-hookean``: ``W = mu/2 (I1 - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J)``, ``J = sqrt(det C)``, the Lame
  pair of ``E, nu`` (Ciarlet and Geymonat's volumetric term: convex in ``J``, so the law is polyconvex); plane
  stress in closed form (:func:`neo_hookean_condense`, the energy then written with that ``det C``,
  :func:`neo_hookean_held`);
- ``neo-hookean-log``: ``W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2`` (the volumetric term of Bonet and Wood,
  FEBio and COMSOL; its ``J``-dependent part is not convex beyond ``J = e^(1 + mu/lambda)``), the same Lame pair;
  plane stress by its own scalar Halley solve (:func:`neo_hookean_log_solve`, the energy then written with its ``ln det C``,
  :func:`neo_hookean_log_held`);
- ``neo-hookean-incompressible``: ``W = mu/2 (I1 - 3)``, ``mu = E/3``, ``det C = 1``;
- ``mooney-rivlin``: ``W = c10 (I1 - 3) + c01 (I2 - 3)``, ``det C = 1`` (``c10, c01`` in Pa; small-strain shear
  modulus ``2 (c10 + c01)``).

The parameters enter the graphs as numbers: a law's parameters are absent from a scene that uses another law.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import re
import sys

from mol_shell._core.errors import ParameterError
from mol_shell._core.ranges import Choice
from mol_shell.model.fibres import (
    fibre_thickness_energy,
    scene_fibres,
)
from mol_shell.model.hyperelastic import (  # noqa: F401  (Law, TREATMENTS: where the laws are)
    NEWTON_STEPS,
    TREATMENTS,
    Law,
    determinant,
    invariants,
    law_shell_energy,
    law_thickness_energy,
    with_thickness,
)
from mol_shell.model.law_energies import (  # noqa: F401  (the energies, by their names here too)
    HALLEY_STEPS,
    START_DEGREE,
    START_RANGE,
    mooney_rivlin,
    neo_hookean,
    neo_hookean_condense,
    neo_hookean_held,
    neo_hookean_incompressible,
    neo_hookean_log,
    neo_hookean_log_held,
    neo_hookean_log_solve,
    neo_hookean_log_start,
    neo_hookean_log_thickness,
    svk,
)
from mol_shell.model.layers import MAKING_LAYERS, layer_value, layered_thickness, parse_layers
from mol_shell.model.material import MATERIALS as SVK_MATERIALS
from mol_shell.model.material import condensed, effective_lame, lame, quadrature_factors, shell_energy
from mol_shell.model.user_laws import (
    RESERVED,
    Material,
    parameter_text,
    parameter_values,
)

#: the built-in laws beyond SVK, by the scene parameter ``material``
LAWS = {
    "neo-hookean": Law("neo-hookean", neo_hookean, ("lambda", "mu"), "plane-stress", neo_hookean_condense,
                       neo_hookean_held),
    "neo-hookean-log": Law("neo-hookean-log", neo_hookean_log, ("lambda", "mu"), "plane-stress",
                           neo_hookean_log_solve, neo_hookean_log_held),
    "neo-hookean-incompressible": Law("neo-hookean-incompressible", neo_hookean_incompressible, ("mu",),
                                      "incompressible"),
    "mooney-rivlin": Law("mooney-rivlin", mooney_rivlin, ("c10", "c01"), "incompressible"),
}
#: every value of the scene parameter ``material``
MATERIALS = tuple(SVK_MATERIALS) + tuple(LAWS)
RESERVED.update(MATERIALS)
#: the compressible laws beyond SVK (the Lame pair of ``E, nu``, plane stress) and why each takes ``0 <= nu < 0.5``
#: (said when a scene's ``nu`` is refused)
COMPRESSIBLE_WHY = {
    "neo-hookean": "its thickness stretch in plane stress is positive at every stretch for 0 <= nu < 0.5",
    "neo-hookean-log": "its thickness stretch is condensed by 2 Halley steps, checked converged for 0 <= nu < 0.5",
}
COMPRESSIBLE = tuple(COMPRESSIBLE_WHY)
#: scene parameters read by one law only
LAW_PARAMETERS = {"mooney-rivlin": ("c10", "c01")}


#: ``(material, mol_shell_version) -> the law's name now``: files of versions whose ``neo-hookean`` was the
#: ``(ln J)^2`` law (the development code wrote ``0.5.0`` until its version was set; 0.5.0 itself had SVK only)
RENAMED = {("neo-hookean", "0.5.0"): "neo-hookean-log", ("neo-hookean", "0.6.0.dev0"): "neo-hookean-log"}


def renamed_law(material, version):
    """The name now of the law a file of ``version`` calls ``material`` (:data:`RENAMED`)."""
    return RENAMED.get((str(material), str(version)), material)


def renamed_layers(text, version):
    """A file's ``layers`` string with each layer's law by its name now (:func:`renamed_law`)."""
    if not any((material, str(version)) in RENAMED for material in re.split(r"[;\s]+", str(text))):
        return text
    parts = []
    for part in str(text).split(";"):
        words = part.split()
        if len(words) > 1:
            words[1] = renamed_law(words[1], version)
        parts.append(" ".join(words))
    return "; ".join(parts)


#: the laws of one's own (:class:`~mol_shell.model.user_laws.Material`) of this process, by the ``material`` a
#: scene stores, its key: the law's name (the first law made under it), ``name@digest`` for another law of the same
#: name (:func:`law_key`), or the import path it came by. A key names one law: two Materials of one name with other
#: energies, parameters or thickness treatments were one law to the scenes and caches, the last one made
REGISTRY = {}
#: what runs when a key is registered again for another law (a persistent worker process of a study restoring a
#: law of another session, :func:`mol_shell.runs.study.restore_materials`): the caches of the layers above, keyed
#: by scenes, which store the key only (each adds its own ``cache_clear``)
ON_REDEFINED = []


def register(key, material):
    """``REGISTRY[key] = material``; the caches keyed by scenes are cleared when the key held another law."""
    previous = REGISTRY.get(key)
    REGISTRY[key] = material
    if previous is not None and previous is not material and previous.fingerprint() != material.fingerprint():
        for clear in ON_REDEFINED:
            clear()


def law_key(material):
    """The key of a :class:`~mol_shell.model.user_laws.Material` in :data:`REGISTRY`: its name if the name is free
    or is this law's (the same energy, parameters and thickness treatment: a cell run again), else the key already
    given to this law, else ``name@`` and the first 8 hex digits of its fingerprint."""
    digest = material.fingerprint()
    keys = (material.name, f"{material.name}@{digest[:8]}")
    for key in keys:
        held = REGISTRY.get(key)
        if held is None or held is material or held.fingerprint() == digest:
            return key
    return f"{material.name}@{digest}"  # (8 digits of another law of the name: not in a lifetime)


def resolve_material(value):
    """The string a scene stores as ``material``: a built-in name as it is; a
    :class:`~mol_shell.model.user_laws.Material` registered under its key (:func:`law_key`); a key (so a name
    given as a string is the first law a scene was made with under it in this process); an import path
    ``package.module:attr`` of a Material (imported, registered under the path). ParameterError otherwise."""
    if isinstance(value, Material):
        if value.name in MATERIALS:
            raise ParameterError("name", value.name, "a name of its own, not a built-in law's ("
                                 + ", ".join(MATERIALS) + ")", hint="the name of a mol_shell.Material")
        key = law_key(value)
        if REGISTRY.get(key) is None:
            register(key, value)
        value.import_path()  # looked for here, kept with the law: a study's workers get a copy, bound nowhere
        return key
    if isinstance(value, str) and (value in MATERIALS or value in REGISTRY):
        return value
    if isinstance(value, str) and ":" in value:
        module, _, attr = value.partition(":")
        try:
            found = getattr(_import(module.strip()), attr.strip())
        except (Exception, SystemExit) as exc:  # noqa: BLE001 - the user's module may raise anything on import
            raise ParameterError("material", value, _allowed(),
                                 hint=f"cannot import it ({type(exc).__name__}: {exc})") from None
        if not isinstance(found, Material):
            raise ParameterError("material", value, _allowed(), hint=f"it is a {type(found).__name__}, not a "
                                 "mol_shell.Material")
        register(value, found)
        found.keep_import_path(f"{module.strip()}:{attr.strip()}")
        return value
    raise ParameterError("material", value, _allowed(),
                         hint="or a mol_shell.Material, or its import path 'package.module:attr'")


def _import(module):
    """``importlib.import_module(module)``, looked up in the working directory too when it is not on the path:
    ``python -m mol_shell`` puts it there, the ``mol-shell`` script does not, and the two are one command."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        here = os.getcwd()
        if exc.name != module.split(".")[0] or "" in sys.path or here in sys.path:
            raise
        sys.path.append(here)
        return importlib.import_module(module)


def _allowed():
    return Choice(tuple(MATERIALS))


def user_material(name):
    """The :class:`~mol_shell.model.user_laws.Material` a scene's ``material`` names, or ``None`` for a built-in."""
    if name in MATERIALS:
        return None
    if name not in REGISTRY:
        resolve_material(name)  # an import path made in another process; a bare name unknown here is refused
    return REGISTRY[name]


def scene_material(material, parameters=""):
    """The :class:`~mol_shell.model.user_laws.Material` named by ``material`` with a scene's ``material_parameters``
    applied (:func:`~mol_shell.model.user_laws.parameter_values`); ``None`` for a built-in law."""
    user = user_material(material)
    if user is None:
        return None
    return user.with_parameters(parameter_values(parameters or ""))


def law_parameters(scene):
    """``(law, params)`` of a scene's material, or ``(None, None)`` for ``svk``/``svk-plane-stress`` (own route)."""
    name = scene.material
    if name in SVK_MATERIALS:
        return None, None
    if name not in LAWS:
        material = own_material(scene)
        return material.law(), dict(material.parameters)
    law = LAWS[name]
    if name in COMPRESSIBLE:
        lam, mu = lame(scene.E, scene.nu)
        return law, {"lambda": lam, "mu": mu}
    if name == "neo-hookean-incompressible":
        return law, {"mu": scene.E / 3.0}
    return law, {"c10": scene.c10, "c01": scene.c01}


def thickness_treatment(material):
    """``director``, ``plane-stress`` or ``incompressible``: how ``material`` sets the thickness stretch."""
    if material in SVK_MATERIALS:
        return "director" if material == "svk" else "plane-stress"
    if material not in LAWS:
        return user_material(material).thickness
    return LAWS[material].thickness


def small_strain_lame(scene):
    """The Lame pair ``(lambda*, mu)`` of the material at small strain, thickness stress condensed as the law does.

    The SVK materials: :func:`~mol_shell.model.material.effective_lame` (the pair their kernels use). The others:
    ``lambda* + 2 mu`` is their small-strain in-plane modulus (compressible neo-Hookean: ``E/(1 - nu^2)``;
    incompressible: ``lambda* = 2 mu``, so ``4 mu``), used for scales (tolerances, wave speeds), not in the energy.
    """
    name = scene.material
    if name in SVK_MATERIALS:
        return effective_lame(scene.E, scene.nu, name)
    if name in COMPRESSIBLE:
        return condensed(*lame(scene.E, scene.nu), "svk-plane-stress")
    if name not in LAWS:
        return own_material(scene).small_strain_pair()
    mu = scene.E / 3.0 if name == "neo-hookean-incompressible" else 2.0 * (scene.c10 + scene.c01)
    return 2.0 * mu, mu


def viscosities(scene):
    """The Kelvin-Voigt pair of :func:`~mol_shell.model.material.thickness_dissipation`, condensed like the elastic part
    (:func:`~mol_shell.model.material.condensed`) but under the director constraint; not for a single incompressible
    law, whose ``eta_mu`` acts alone (:func:`~mol_shell.model.hyperelastic.incompressible_dissipation`)."""
    how = "svk" if thickness_treatment(scene.material) == "director" else "svk-plane-stress"
    return condensed(scene.eta_lambda, scene.eta_mu, how)


#: the SVK energy as a law, under the director constraint (the Lame pair condensed as the scene's material asks)
SVK_LAW = Law("svk", svk, ("lambda", "mu"), "director")


def own_parameters(material, values):
    """The part of ``values`` (``{name: number}``, a scene's ``material_parameters``) that the law ``material`` has
    (``{}`` for a built-in law): a layered wall's parameters go to the layers whose law has each, and its own
    ``material`` (the run's scales) takes those it has."""
    user = user_material(material)
    return {k: v for k, v in values.items() if user is not None and k in user.parameters}


def own_material(scene):
    """:func:`scene_material` of the scene's ``material`` with those of its ``material_parameters`` it has (a single
    wall's are its law's, checked; a layered wall's may be its layers' laws' alone)."""
    values = parameter_values(getattr(scene, "material_parameters", "") or "")
    return scene_material(scene.material, own_parameters(scene.material, values))


def layer_scenes(scene):
    """``[(thickness, scene of the layer)]`` of a layered scene: the scene with the layer's material and keys (its
    checks run on them), without layers, and with those of the scene's ``material_parameters`` its law has (every
    layer was given all of them, and a built-in layer refused them)."""
    out = []
    values = parameter_values(getattr(scene, "material_parameters", "") or "")
    token = MAKING_LAYERS.set(True)
    try:
        for number, (thickness, material, changes) in enumerate(parse_layers(scene.layers), start=1):
            try:
                typed = {k: layer_value(k, v) for k, v in changes.items()}
                if values:
                    typed["material_parameters"] = parameter_text(own_parameters(material, values))
                out.append((thickness, dataclasses.replace(scene, layers="", material=material, **typed)))
            except ParameterError as exc:
                raise ParameterError(exc.name, exc.value, exc.allowed, message=f"layer {number}: {exc}") from None
    finally:
        MAKING_LAYERS.reset(token)
    return out


def layer_laws(scene):
    """``(thickness rule, [(law, params, fibres) per layer])`` of a layered scene (every layer by its law's route:
    the SVK laws as :data:`SVK_LAW` with their condensed Lame pair)."""
    layers = layer_scenes(scene)
    out = []
    for _, sub in layers:
        law, params = law_parameters(sub)
        if law is None:
            lam, mu = effective_lame(sub.E, sub.nu, sub.material)
            law, params = SVK_LAW, {"lambda": lam, "mu": mu}
        out.append((law, params, scene_fibres(sub)))
    zeta1 = -scene.h if getattr(scene, "h_profile", "") else scene.zeta1_used()  # graded: about the mid-surface
    rule = layered_thickness(zeta1, scene.h, scene.n_quad, [t for t, _ in layers])
    return rule, out


def scene_shell_energy(scene, strains, thickness, r0=1.0, theta0=0.0, theta0_s=0.0, beta1_0=1.0, beta2_0=0.0):
    """Stored energy per unit reference area of the scene's material (SVK's own route or the law's), fibres included;
    a layered wall layer by layer (``thickness`` then only places the wall: its ``zeta1``)."""
    if getattr(scene, "layers", ""):
        rule, laws = layer_laws(scene)
        factors = quadrature_factors(rule, r0, theta0, theta0_s, beta1_0)
        nq, total = scene.n_quad, 0.0
        for k, (law, params, fibres) in enumerate(laws):
            part = factors[k * nq:(k + 1) * nq]
            total = total + law_thickness_energy(strains, law, params, part, beta2_0)
            if fibres is not None:
                total = total + fibre_thickness_energy(strains, fibres, part, beta2_0)
        return total / r0
    law, params = law_parameters(scene)
    if law is None:
        lam, mu = effective_lame(scene.E, scene.nu, scene.material)
        energy = shell_energy(strains, lam, mu, thickness, r0, theta0, theta0_s, beta1_0, beta2_0)
    else:
        energy = law_shell_energy(strains, law, params, thickness, r0, theta0, theta0_s, beta1_0, beta2_0)
    fibres = scene_fibres(scene)
    if fibres is None:
        return energy
    factors = quadrature_factors(thickness, r0, theta0, theta0_s, beta1_0)
    return energy + fibre_thickness_energy(strains, fibres, factors, beta2_0) / r0
