"""A wall whose thickness varies along the meridian: the half-thickness ``h(s)`` from a table or an expression.

The scene parameter ``h_profile`` gives ``h(s)`` (m) as

- ``"table s0:h0 s1:h1 ..."``: linear between the points, which must cover the meridian ``[0, L]``;
- an expression of ``s`` (m) with ``+ - * / **``, numbers, ``pi``, ``sqrt``, ``exp``, ``log``, ``sin``, ``cos``,
  ``tanh``: ``"0.01 * (1 + 0.2 * s)"``.

A graded wall is integrated cell by cell with the cell's own thickness interval ``[-h, h]`` about the base surface
(the mid-surface: ``zeta1 = -h(s)``) and the same Gauss rule; each node's inertia is that of its dual cell with the
node's ``h``. ``h`` of the scene stays the nominal half-thickness (scales, tolerances).
"""

from __future__ import annotations

import ast
import math

import numpy as np

from mol_shell._core.errors import ParameterError
from mol_shell.model.geometry import node_inertias
from mol_shell.model.material import Thickness
from mol_shell.model.wall_fit import piece_samples, turning_points

_FUNCTIONS = {"sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin, "cos": np.cos, "tanh": np.tanh}
_ALLOWED = "'table s0:h0 s1:h1 ...' (m, covering the meridian) or an expression of s such as '0.01 * (1 + 0.2 * s)'"


def _check_expression(text):
    """Only arithmetic, ``s``, ``pi`` and :data:`_FUNCTIONS` (nothing else reaches ``eval``)."""
    tree = ast.parse(text, mode="eval")
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id not in ("s", "pi", *_FUNCTIONS):
            raise ValueError(f"unknown name {node.id!r}")
        if not isinstance(node, (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Load, ast.Constant,
                                 ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)):
            raise ValueError(f"{type(node).__name__} is not allowed")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise ValueError("only numbers")
    return compile(ast.fix_missing_locations(_Doubles().visit(tree)), "<h_profile>", "eval")


class _Doubles(ast.NodeTransformer):
    """Every number as a numpy double: arithmetic of constants alone then overflows to inf, divides by zero to inf
    and takes roots of negatives to NaN (refused as an h that is not positive and finite), where Python's ints and
    floats hung (``9**9**9``), raised (``1/0``, ``10.0**400``) or turned complex (``(-0.01)**0.5``)."""

    def visit_Constant(self, node):
        return ast.Call(ast.Name("_double", ast.Load()), [ast.Constant(float(node.value))], [])


#: a table's first and last ``s`` count as the meridian's ends within this share of its length (the table's ``h``
#: is held beyond its points): ``3.14159`` for a half circle of radius 1 m, 2.7e-6 m short, was refused
TABLE_ENDS = 1e-4


def table_points(text):
    """The ``s`` of a table's points (``"table s0:h0 s1:h1 ..."``), where a piecewise-linear ``h`` has its least and
    greatest values; none for an expression (or a table that does not read: :func:`thickness_function` says why)."""
    words = text.split()
    try:
        return np.array([float(w.split(":")[0]) for w in words[1:]]) if words and words[0] == "table" else np.array([])
    except ValueError:
        return np.array([])


def thickness_function(text, length):
    """``h(s)`` (a function of an array ``s``) from ``text``; a ParameterError naming ``h_profile`` otherwise.

    Refuses a table that does not cover ``[0, length]``, and an ``h`` that is not positive and finite on it.
    """
    words = text.split()
    try:
        if words and words[0] == "table":
            pairs = [tuple(float(x) for x in w.split(":")) for w in words[1:]]
            if len(pairs) < 2 or any(len(p) != 2 for p in pairs):
                raise ValueError("a table needs two or more points s:h")
            s_tab, h_tab = (np.array(x) for x in zip(*pairs))
            if np.any(np.diff(s_tab) <= 0):
                raise ValueError("the table's s must increase")
            tol = TABLE_ENDS * length  # 3.14159 for a half circle's pi m: typed to a few digits, held flat beyond
            if s_tab[0] > tol or s_tab[-1] < length - tol:
                short = max(s_tab[0], 0.0) + max(length - s_tab[-1], 0.0)
                raise ParameterError("h_profile", text, f"a table covering the meridian [0, {length:.12g}] m",
                                     hint=f"it covers [{s_tab[0]:.12g}, {s_tab[-1]:.12g}] m, {short:.3g} m short")

            def h(s):
                return np.interp(np.asarray(s, dtype=float), s_tab, h_tab)
        else:
            code = _check_expression(text)

            def h(s):
                s = np.asarray(s, dtype=float)
                value = eval(code, {"__builtins__": {}}, {"s": s, "pi": np.float64(math.pi), "_double": np.float64,
                                                          **_FUNCTIONS})  # noqa: S307 (checked)
                return np.broadcast_to(np.asarray(value, dtype=float), s.shape).copy()
    except ParameterError:
        raise
    except (ValueError, SyntaxError, TypeError) as exc:
        raise ParameterError("h_profile", text, _ALLOWED, hint=str(exc)) from None
    s = np.linspace(0.0, length, 1001)
    if words and words[0] == "table":  # linear between its points: its least value on [0, L] is at one of them
        s = np.concatenate([s, s_tab[(s_tab > 0) & (s_tab < length)]])
    with np.errstate(all="ignore"):
        values = h(s)
    bad = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
    if bad.size:
        k = bad[np.argmin(s[bad])]
        raise ParameterError("h_profile", text, "a positive, finite h(s) on the meridian",
                             hint=f"h = {values[k]:.4g} m at s = {s[k]:.6g} m")
    return h


def reversed_profile(text, length):
    """``h_profile`` text of ``h(length - s)`` for the profile ``text`` of ``h(s)``: the same wall along a meridian
    traversed from its other end (a vessel drawn down runs backwards: :func:`mol_shell.scenes.segments.upward`). A
    table's points at ``length - s`` in reverse order (their ``h`` as typed), an expression's ``s`` replaced by
    ``(length - s)``; ``text`` itself where it does not read (:func:`thickness_function` then says why) or has no ``s``."""
    words = text.split()
    if words and words[0] == "table":
        pairs = [w.split(":") for w in words[1:]]
        try:
            points = [(length - float(s), h, float(h)) for s, h in pairs]  # (s, h as typed, h read)
        except ValueError:
            return text
        return "table " + " ".join(f"{s!r}:{h}" for s, h, _ in reversed(points))
    try:
        tree = ast.parse(text, mode="eval")
    except (SyntaxError, ValueError):
        return text
    if not any(isinstance(node, ast.Name) and node.id == "s" for node in ast.walk(tree)):
        return text
    return ast.unparse(_Reversed(float(length)).visit(tree))


class _Reversed(ast.NodeTransformer):
    """Every ``s`` of an expression as ``(length - s)``."""

    def __init__(self, length):
        self.length = length

    def visit_Name(self, node):
        if node.id != "s":
            return node
        return ast.BinOp(ast.Constant(self.length), ast.Sub(), ast.Name("s", ast.Load()))


def scene_profile(scene):
    """The ``h_profile`` text the scene runs with: a vessel drawn down runs backwards, its profile as ``h(L - s)`` of
    the one given along the segments (its ``ran_values``); ``""`` for a uniform wall."""
    return getattr(scene, "ran_values", dict)().get("h_profile", getattr(scene, "h_profile", ""))


def check_profile_fits(text, h, meridian, samples=801):
    """Refuse (naming ``h_profile``) an ``h(s)`` that reaches the axis or a centre of curvature on ``meridian``.

    ``det G0 = (1 - zeta theta0_s)(r0 + zeta cos theta0)``: each factor must stay positive on ``[-h, h]`` (past a
    centre of curvature both change sign and their product alone would pass), i.e. ``h(s)`` below the distance to
    the centre of curvature, ``1/|theta0_s|``, and to the axis, ``r0/|cos theta0|`` (off the poles).
    """
    grid = np.concatenate([np.linspace(0.0, meridian.length, samples), turning_points(meridian)])
    ends, k_ends = piece_samples(meridian)  # every curvature piece with its own curvature: a short sharp arc too
    s = np.concatenate([grid, ends])
    r0, _, th0, th0s = meridian.at(s)
    th0s[grid.size:] = k_ends
    keep = r0 > 1e-9 * float(np.max(np.abs(r0)))  # off the poles (their factor is 0 by geometry), at any size
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = np.minimum(np.where(th0s != 0, 1 / np.abs(th0s), np.inf),
                           np.where(keep & (np.cos(th0) != 0), r0 / np.abs(np.cos(th0)), np.inf))
    hs = h(s)
    bad = np.flatnonzero(~(hs < bound))
    if bad.size:
        k = bad[0]
        raise ParameterError("h_profile", text, "values whose h(s) stays below the distance to the axis and to every "
                             f"centre of curvature (at s = {s[k]:.4g} m: below {bound[k]:.4g} m)",
                             hint=f"h = {hs[k]:.4g} m there")


def graded_node_inertias(meridian, s_nodes, rho, h, n_quad):
    """:func:`~mol_shell.model.geometry.node_inertias` of a graded wall: each node's dual cell with the node's own
    interval ``[-h, h]`` (``h`` a function of ``s``)."""
    h_nodes = h(np.asarray(s_nodes, dtype=float))
    return np.array([node_inertias(meridian, s_nodes, rho, Thickness(-h_nodes[i], h_nodes[i], n_quad))[:, i]
                     for i in range(len(h_nodes))]).T
