"""Stresses of any law (and of fibres) from its stored energy, by automatic differentiation.

:mod:`mol_shell.results.stresses` computes the St Venant-Kirchhoff stresses from the Lame pair; this module gives
the same kernel (inputs ``e, e_t, ref, par``; the same resultants and face stresses) for every other material:
a law of :mod:`mol_shell.model.laws`, and any law with fibres (:mod:`mol_shell.model.fibres`).

The shell's energy at a thickness point is ``W^(C')``: the law's ``W`` at ``C'`` (the kinematic ``C = F^T F`` of
eq. 7.4, whose thickness component is 1) with the thickness component set by the law's treatment
(:func:`~mol_shell.model.hyperelastic.condensed_energy`), plus the fibres' energy. Its second Piola-Kirchhoff
stress is

    S = 2 dW^/dC'     (S_ij = dW^/dC'_ij for i != j, C'_ij = C'_ji one variable),

so that ``T = F S`` integrated through the thickness gives resultants that are exactly the derivatives of the
integrated energy, as SVK's are (eq. 7.7). For a plane-stress law ``S_22 = 0`` by the condensation
(``dW/dC_22 = 0``, the envelope theorem); for an incompressible law the substituted ``C_22(C')`` carries the
pressure: ``S = 2 dW/dC - p C^-1`` with ``p`` such that ``S_22 = 0``; under the director constraint ``S_22`` is the
reaction of the inextensible director, which the energy does not give: the resultants (of ``T e1`` and ``T e3``)
do not use it, and at the faces ``S_22`` is the one that makes the face's
normal Cauchy stress its traction (``-p`` on the face a pressure acts on, 0 on a free face;
:func:`~mol_shell.results.stress_samples.held_thickness_stress`). ``svk-plane-stress`` with fibres keeps SVK's
convention ``S_22 = 0``.

The Cauchy stress at the faces is ``F_l S F_l^T / det F_l`` with ``F_l`` the kinematic ``F`` whose director column is
multiplied by the law's thickness stretch ``sqrt(C_22)`` (1 under the director constraint; ``svk-plane-stress``'s
from the 3-D law's ``S_22 = 0``, :func:`~mol_shell.model.material.plane_stress_thickness`, as SVK's own kernel has
it): ``det F_l`` is the law's ``J`` (1 for an incompressible law), so a stretched rubber wall shows its true
stress. The transverse shears keep their kinematic values in ``C`` (the thickness stretch changes them by a factor
``sqrt(C_22)`` in the true configuration: a difference of the order of the transverse shear strain times the
thickness strain).
"""

from __future__ import annotations

import casadi as ca

from mol_shell._core.errors import ParameterError
from mol_shell.model.fibres import Fibres, fibre_energy
from mol_shell.model.hyperelastic import condensed_energy, thickness_component
from mol_shell.model.laws import (
    COMPRESSIBLE,
    LAWS,
    SVK_LAW,
    own_parameters,
    parameter_text,
    parameter_values,
    renamed_law,
    scene_material,
    thickness_treatment,
    user_material,
)
from mol_shell.model.layers import layer_value, parse_layers
from mol_shell.model.material import MATERIALS as SVK_MATERIALS
from mol_shell.model.material import condensed, lame, plane_stress_thickness


def law_of_attrs(attrs):
    """The stress route of a run: ``None`` for an SVK law without fibres (SVK's own kernel), else the hashable
    ``(law name, params as sorted items, fibres, plane)``; ``plane``: ``S_22 = 0`` imposed after the fact
    (``svk-plane-stress``, SVK's convention). A material this version does not know gives ``None`` params; a law
    renamed since the file was written (:func:`~mol_shell.model.laws.renamed_law`) is read by its name now.
    """
    material = renamed_law(str(attrs.get("material", "svk")), attrs.get("mol_shell_version", ""))
    if str(attrs.get("layers", "") or "") not in ("", "none"):  # ("layers", ((thickness, route of the layer), ...),
        return "layers", tuple((t, _layer_route(attrs, m, changes))  # plane): each layer as a run of its own
                               for t, m, changes in parse_layers(str(attrs["layers"]))), \
            thickness_treatment(material) != "director"
    fibre_E = float(attrs.get("fibre_E", 0.0))
    fibres = None
    if fibre_E > 0:
        fibres = Fibres(fibre_E, float(attrs.get("fibre_angle", 0.0)), int(layer_value("fibre_families", str(attrs.get("fibre_families", 1)))),
                        _flag(attrs.get("fibre_compression", 1)))
    if material in SVK_MATERIALS:
        if fibres is None:
            return None
        lam, mu = condensed(*lame(float(attrs["E"]), float(attrs["nu"])), material)
        return "svk", (("lambda", lam), ("mu", mu)), fibres, material == "svk-plane-stress"
    if material not in LAWS:  # a law of one's own (registered here, or by its import path), else unknown
        try:
            user = scene_material(material, str(attrs.get("material_parameters", "") or ""))
        except ParameterError:
            return material, None, fibres, False
        return material, tuple(sorted(user.parameters.items())), fibres, False
    E, nu = float(attrs["E"]), float(attrs["nu"])
    if material in COMPRESSIBLE:
        lam, mu = lame(E, nu)
        params = {"lambda": lam, "mu": mu}
    elif material == "neo-hookean-incompressible":
        params = {"mu": E / 3.0}
    else:
        params = {"c10": float(attrs["c10"]), "c01": float(attrs["c01"])}
    return material, tuple(sorted(params.items())), fibres, False


def unloadable_law(attrs):
    """Why the run's own law (``material = my_laws:rubber``) cannot be loaded in this process (its module is not
    importable here, a Material made in another session), or ``None``: the stresses need the law's energy."""
    material = renamed_law(str(attrs.get("material", "svk")), attrs.get("mol_shell_version", ""))
    if material in SVK_MATERIALS or material in LAWS or ":" not in material:  # a name, not an import path: unknown
        return None
    try:  # with the parameters it has (a layered run's may be its layers' laws')
        values = parameter_values(str(attrs.get("material_parameters", "") or ""))
        scene_material(material, own_parameters(material, values))
    except ParameterError as exc:
        return str(exc)
    return None


def _flag(value):
    """A checked true/false parameter as the attrs hold it: 0/1 (the run's own), or ``true``/``false`` (a layer's key
    in the ``layers`` string)."""
    if isinstance(value, str):  # a file written before the layers were stored canonically may hold 1/0
        return {"true": True, "false": False}[layer_value("fibre_compression", value).strip().lower()]
    return bool(int(value))


def _layer_route(attrs, material, changes):
    """The route of one layer: the run's attrs with the layer's material and keys (SVK without fibres included), and
    those of the run's ``material_parameters`` the layer's law has (:func:`~mol_shell.model.laws.own_parameters`)."""
    sub = {**attrs, "layers": "", "material": material, **changes}
    try:
        values = parameter_values(str(attrs.get("material_parameters", "") or ""))
        sub["material_parameters"] = parameter_text(own_parameters(renamed_law(material, attrs.get(
            "mol_shell_version", "")), values))
    except ParameterError:  # a law not loadable here, or parameters not read: the route says it (an unknown law)
        pass
    route = law_of_attrs(sub)
    if route is None:
        lam, mu = condensed(*lame(float(sub["E"]), float(sub["nu"])), material)
        route = "svk", (("lambda", lam), ("mu", mu)), None, material == "svk-plane-stress"
    return route


def route_law(route):
    """The :class:`~mol_shell.model.laws.Law` of a route of :func:`law_of_attrs`."""
    if route[0] == "svk":
        return SVK_LAW
    return LAWS[route[0]] if route[0] in LAWS else user_material(route[0]).law()


def route_stress(route):
    """:func:`energy_stress` of a route of :func:`law_of_attrs`."""
    return energy_stress(route_law(route), dict(route[1]), route[2], route[3])


def energy_stress(law, params, fibres=None, plane=False):
    """``C' -> (S, lambda_3)``: the second Piola-Kirchhoff stress ``2 dW^/dC'`` (nested 3x3) and the thickness stretch.

    ``C'`` nested 3x3 (symmetric) of CasADi expressions. See the module's docstring. Its attribute ``held``: the
    director holds the thickness, so ``S_22`` is the constraint's reaction (the faces take theirs from the
    tractions, :func:`~mol_shell.results.stress_samples.held_thickness_stress`).
    """
    sym = {(i, j): ca.SX.sym(f"c{i}{j}") for i in range(3) for j in range(i, 3)}

    def C_of(sym):
        return tuple(tuple(sym[min(i, j), max(i, j)] for j in range(3)) for i in range(3))

    C = C_of(sym)
    W = condensed_energy(law, C, params)
    if fibres is not None:
        W = W + fibre_energy(C, fibres)
    keys = list(sym)
    grad = ca.gradient(W, ca.vertcat(*[sym[k] for k in keys]))
    S_of = {k: (2.0 if k[0] == k[1] else 1.0) * grad[n] for n, k in enumerate(keys)}
    if law.thickness != "director":
        stretch = ca.sqrt(thickness_component(law, C, params))
    elif plane:  # svk-plane-stress (with fibres, or a layer): SVK's own thickness stretch, as its kernel's
        stretch = ca.sqrt(plane_stress_thickness((C[0][0] - 1) / 2, (C[2][2] - 1) / 2, params["lambda"], params["mu"]))
    else:
        stretch = ca.SX(1.0)
    f = ca.Function("law_stress", [ca.vertcat(*[sym[k] for k in keys])], [ca.vertcat(*[S_of[k] for k in keys]), stretch])

    def stress(Cp):
        S_flat, lam3 = f(ca.vertcat(*[Cp[i][j] for i, j in keys]))
        S = [[S_flat[keys.index((min(i, j), max(i, j)))] for j in range(3)] for i in range(3)]
        if plane:
            S[1][1] = 0.0
        return tuple(tuple(row) for row in S), lam3

    stress.held = law.thickness == "director" and not plane  # S_22 the constraint's reaction: the faces' from traction
    return stress
