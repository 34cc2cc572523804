"""Layered walls: layers through the thickness, each with its law, parameters and fibres, integrated layer by layer.

The scene parameter ``layers`` lists them from the lower face ``zeta1`` upwards, as a string
``"T1 MATERIAL key=value ...; T2 MATERIAL ..."`` (``T`` the layer's full thickness, m; ``MATERIAL`` a value of
``material``; keys ``E, nu, c10, c01, fibre_E, fibre_angle, fibre_families, fibre_compression``, the scene's
values where left out), or as a Python list of dicts (``thickness``, ``material`` and those keys), or ``[[layer]]``
tables in a scene file. The thicknesses add up to the wall, ``2h``. Each layer gets the scene's ``n_quad``
Gauss-Legendre points on its own interval: the energy is integrated layer by layer (a kink of the stress at an
interface is never inside a Gauss rule).
"""

from __future__ import annotations

import contextvars
from dataclasses import dataclass

import numpy as np

from mol_shell._core.errors import ParameterError

#: the most layers a wall may have. Every layer adds its own Gauss points to every cell's kernel, and the generated
#: C grows with them: a sphere at n = 8 of N svk-plane-stress layers, measured on a 2-core machine shared with
#: other jobs (graph build, gcc -O3, the run and its stresses, from an empty kernel cache): N = 1 in 5.7 s,
#: N = 10 in 19 s (333 kB of C, gcc 9.7 s), N = 20 in 50 s (582 kB, gcc 34 s), N = 30 in 102 s (853 kB,
#: gcc 77 s); N = 1000 built its graph for 4 min (2.4 GB) and gcc did not finish in 5 min. 20 keeps a run
#: within about a minute.
MAX_LAYERS = 20
#: the keys a layer may set (the rest are the scene's)
#: True while :func:`mol_shell.model.laws.layer_scenes` makes a layered scene's layers: a check of the whole wall (the
#: axisymmetric scene's balance of helical fibres) is made on the layered scene, not on each layer's
MAKING_LAYERS = contextvars.ContextVar("making_layers", default=False)
LAYER_KEYS = ("E", "nu", "c10", "c01", "fibre_E", "fibre_angle", "fibre_families", "fibre_compression")
#: the keys whose value is a number (a dict's strings are refused, as a scene's are)
NUMERIC_KEYS = tuple(key for key in LAYER_KEYS if key != "fibre_compression")
_ALLOWED = ("'T MATERIAL key=value ...; ...' (T the layer's thickness, m; keys " + ", ".join(LAYER_KEYS)
            + "), or a list of dicts with thickness, material and those keys")


def layer_word(value):
    """A layer's value in the string form: a bool as ``true``/``false`` (the words the flags take), else as it is."""
    return ("true" if value else "false") if isinstance(value, (bool, np.bool_)) else value


def layers_text(value):
    """A list of dicts (Python, or a scene file's ``[[layer]]`` tables) as the string form; a string as it is."""
    if isinstance(value, str):
        return value
    if not isinstance(value, (list, tuple)) or not all(isinstance(x, dict) for x in value):
        raise ParameterError.not_a("layers", value, "a list of layers", _ALLOWED)
    parts = []
    for layer in value:
        layer = dict(layer)
        missing = [key for key in ("thickness", "material") if key not in layer]
        if missing:
            raise ParameterError("layers", value, _ALLOWED, hint=f"layer {len(parts) + 1} has no {missing[0]}")
        number = len(parts) + 1
        try:
            if isinstance(layer["thickness"], (str, bool)):  # a number, as every numeric parameter of a scene
                raise TypeError
            head = f"{float(layer.pop('thickness'))!r} {layer.pop('material')}"
        except (TypeError, ValueError):
            raise ParameterError("layers", value, _ALLOWED, hint=f"layer {number}: its thickness is not a "
                                 "number") from None
        text = [k for k, v in layer.items() if k in NUMERIC_KEYS and isinstance(v, (str, bool))]
        if text:
            raise ParameterError("layers", value, _ALLOWED, hint=f"layer {number}: {text[0]} = {layer[text[0]]!r} is "
                                 "not a number")
        parts.append(" ".join([head] + [f"{k}={layer_word(v)}" for k, v in layer.items()]))
    return "; ".join(parts)


def parse_layers(text):
    """``[(thickness, material, {key: text})]`` of the string form; a ParameterError naming ``layers`` and the layer
    (counted from 1 at the lower face) otherwise."""
    out = []
    for number, part in enumerate(text.split(";"), start=1):
        words = part.split()
        try:
            thickness = float(words[0])
            material = words[1]
            changes = dict(w.split("=", 1) for w in words[2:])
        except (IndexError, ValueError):
            raise ParameterError("layers", text, _ALLOWED, hint=f"layer {number}: cannot read {part.strip()!r}") from None
        keys = [w.split("=", 1)[0] for w in words[2:]]
        if len(set(keys)) < len(keys):
            twice = next(k for k in keys if keys.count(k) > 1)
            raise ParameterError("layers", text, _ALLOWED, hint=f"layer {number}: {twice} given twice")
        unknown = [k for k in changes if k not in LAYER_KEYS]
        if unknown or not (np.isfinite(thickness) and thickness > 0):
            raise ParameterError("layers", text, _ALLOWED, hint=f"layer {number}: unknown key {unknown[0]!r}" if unknown
                                 else f"layer {number}: a thickness {thickness:g}, not a positive finite number")
        out.append((thickness, material, changes))
    return out


def layer_value(key, text):
    """A layer's ``key=text`` as the scene field takes it: a number (``fibre_families`` an int when it is a whole
    number, else the float, which the scene's check refuses), the flag's word as it is; a ParameterError naming the
    key for text that is not a number (the caller adds the layer)."""
    if key == "fibre_compression":  # 1/0 as the scene's own flag takes them (a layer dict's fibre_compression=0)
        return {"1": "true", "0": "false", "1.0": "true", "0.0": "false"}.get(text.strip(), text)
    try:
        value = float(text)
    except ValueError:
        raise ParameterError.not_a(key, text, "a number", "a number in the key's range") from None
    if key == "fibre_families" and value.is_integer():
        return int(value)
    return value


@dataclass(frozen=True)
class LayeredThickness:
    """The thickness rule of a layered wall: ``n_quad`` Gauss points on each layer (``bounds``: its faces).

    Quacks like :class:`~mol_shell.model.material.Thickness` (``zeta1``, ``h``, ``n_quad`` = all the points,
    ``nodes_weights``); ``per_layer`` points belong to each layer in turn.
    """

    zeta1: float
    h: float
    per_layer: int
    bounds: tuple

    @property
    def n_quad(self):
        return self.per_layer * (len(self.bounds) - 1)

    @property
    def nodes_weights(self):
        x, w = np.polynomial.legendre.leggauss(self.per_layer)
        nodes, weights = [], []
        for lo, hi in zip(self.bounds[:-1], self.bounds[1:]):
            half = (hi - lo) / 2
            nodes += list((lo + hi) / 2 + half * x)
            weights += list(half * w)
        return tuple(nodes), tuple(weights)


def layered_thickness(zeta1, h, n_quad, thicknesses):
    """The :class:`LayeredThickness` of layers of ``thicknesses`` from ``zeta1``, scaled to add up to ``2h`` exactly
    (the scene accepts them to 1e-6 of it; equal layers stay equal halves of the wall to round-off)."""
    thicknesses = np.asarray(thicknesses, dtype=float)
    thicknesses = thicknesses * (2 * h / np.sum(thicknesses))
    bounds = tuple(float(b) for b in zeta1 + np.concatenate([[0.0], np.cumsum(thicknesses)]))
    return LayeredThickness(float(zeta1), float(h), int(n_quad), bounds[:-1] + (float(zeta1 + 2 * h),))
