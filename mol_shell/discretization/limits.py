"""The model's limits on the discrete state (delta > 0, r > 0 off the axis, |psi| < pi/2, SVK's turning point) as one
CasADi function that must stay positive, with what and where each entry is: a part of
:class:`~mol_shell.discretization.system.ShellSystem`, which the leap-frog checks after every step and CVODE and IDA
hand to SUNDIALS' root finding."""

from __future__ import annotations

import math
from functools import cached_property

import casadi as ca
import numpy as np


class ModelLimits:
    """The limits of a :class:`~mol_shell.discretization.system.ShellSystem` (a mixin: it reads the system's fields,
    edges, cell kernels and grid)."""

    @cached_property
    def limits(self):
        """``y -> g``: the model's limits as functions that must stay positive (:meth:`limit_names` says which).

        ``g = [delta at the samples of each cell; r per node; (pi/2)^2 - psi^2 per node; det(C_t - I/3) at the
        samples of each cell]`` (the third only when ``psi`` is a field; the last for the SVK laws without fibres:
        :func:`~mol_shell.model.material.svk_turning_limit`). Leap-frog checks them after every step (in C),
        CVODE and IDA find their roots. Depends on the field entries only, which sit at the same
        places in ``y = (q, p)`` and in IDA's ``x = (q, v)``.
        """
        f = self.limits_mapped
        return f.expand() if self.n <= self.FLAT_MAX_NODES else f

    @cached_property
    def limits_mapped(self):
        """:attr:`limits` as a map of the cell kernels whatever ``n``: the form to compile (the flat graph of a few
        hundred nodes is tens of thousands of lines of straight C, which gcc -O3 takes a minute over)."""
        n = self.n
        y = ca.MX.sym("y", self.size)
        Q = self.tie(self._fields(ca.reshape(y[: self.ny * n], self.ny, n)))
        g = [ca.vec(self.cell_delta().map(n - 1)(Q[:, :-1], Q[:, 1:], self.cell_data)), Q[1, list(self.radial_nodes)].T]
        if 4 in self.active:
            g.append((math.pi / 2) ** 2 - Q[4, :].T ** 2)
        if self.turning_limit:
            g.append(ca.vec(self.cell_turning().map(n - 1)(Q[:, :-1], Q[:, 1:], self.cell_data)))
        return ca.Function("limits", [y], [ca.vertcat(*g)], ["y"], ["g"])

    def limit_names(self):
        """``(what, where)`` for each entry of :attr:`limits`."""
        cells = (self.s[:-1] + self.s[1:]) / 2
        names = [("delta = r beta1 cos(psi) reached 0", f"s = {s:.6g} m (cell centre)") for s in np.repeat(cells, self.samples_per_cell)]
        names += [("r reached 0", f"s = {self.s[i]:.6g} m") for i in self.radial_nodes]
        if 4 in self.active:
            names += [("|psi| reached pi/2", f"s = {s:.6g} m") for s in self.s]
        if self.turning_limit:
            names += [("an in-plane stretch reached 1/sqrt(3) in compression, where the St Venant-Kirchhoff stress "
                       "turns back (a limit of the law)", f"s = {s:.6g} m (cell centre)")
                      for s in np.repeat(cells, self.samples_per_cell)]
        return names

    @property
    def radial_nodes(self):
        """Nodes where ``r > 0`` is a limit of the model: all but the poles (where ``r = 0`` is imposed)."""
        poles = {0 if self.edges[0] == "pole" else -1, self.n - 1 if self.edges[1] == "pole" else -1}
        return np.array([i for i in range(self.n) if i not in poles], dtype=int)


__all__ = ["ModelLimits"]
