"""The azimuthally unshearable shell of section 4 (a spinning shell with a bulge): its scene.

Run by :func:`mol_shell.simulate` with ``"ida"`` (the constrained DAE of :mod:`mol_shell.runs.unshearable`) or
``"leapfrog"`` (the free shell from the same initial state).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from mol_shell._core.constants import NF
from mol_shell._core.ranges import Interval, finite
from mol_shell.scenes.base import _check, refuse_loads, zeta1_used
from mol_shell.scenes.cylinder import CylinderScene

#: integrators of the unshearable scene: the constrained DAE (ida) or the free shell (leapfrog)
UNSHEARABLE_INTEGRATORS = ("ida", "leapfrog")
#: the options of its constrained DAE (``"ida"`` on this scene; the free shell's are leap-frog's): the names of
#: :data:`mol_shell.runs.unshearable.DAE_OPTIONS`
UNSHEARABLE_DAE_OPTIONS = ("rtol", "atol", "max_step")


@dataclass(frozen=True)
class Unshearable(CylinderScene):
    """A spinning shell with a bulge: the initial state that tells unshearable from free shells.

    Initial data: ``z = s``, ``r = R + dR cos(2 pi s / L)``, ``theta = arctan(r_s)`` (the
    generator is initially shear-free, ``beta2 = 0``, so the fast transverse-shear mode is
    not excited; ``theta = 0`` at the ends), ``chi = psi = 0``, uniform spin ``chi_t = omega``,
    the other rates zero. Ends as :class:`~mol_shell.scenes.TwistedCylinder`.

    Parameters
    ----------
    L, a : float
        Length and natural radius, m (defaults 4 and 1), as :class:`~mol_shell.scenes.CylinderScene`.
    R : float or None
        Mean initial radius, m (default 1), with the thinnest section's inner face ``R - |dR| + zeta1`` at a
        positive radius; ``None`` (``"auto"``): the natural radius ``a`` (the radial equilibrium of the
        untwisted, unloaded cylinder).
    dR : float
        Amplitude of the initial radius variation, m, in (-0.2, 0.2) (default 0.01).
    omega : float
        Initial spin rate, rad/s (default 20).
    """

    defaults_mean = MappingProxyType({"R": "a, the radial equilibrium of the untwisted, unloaded cylinder"})

    R: float | None = 1.0
    dR: float = 0.01
    omega: float = 20.0

    name = "unshearable"
    gamma = psi0 = 0.0
    initial = ("R", "dR", "omega")
    #: solved by its own formulation (the constrained DAE), not by the shell's integrators
    own_formulation = True

    def _validate(self):
        super()._validate()
        _check("dR", self.dR, Interval(-0.2, 0.2, unit="m"))
        if self.R is not None:  # the thinnest section, R - |dR|, keeps its inner face at a positive radius
            low = -zeta1_used(self.h, self.zeta1, self.a) + abs(self.dR)
            _check("R", self.R, Interval(low, math.inf, unit="m", shown=f"({low:.4g}, inf) m: the inner face "
                                         f"R - |dR| + zeta1 must be at a positive radius (dR = {self.dR:g} m)"))
        _check("omega", self.omega, finite("rad/s"))
        refuse_loads(self, "the unshearable DAE")

    def auto_values(self, initial, reference):
        return {"R": self.a} if self.R is None else {}  # as initial_fields takes it

    def initial_fields(self, s, reference=None):
        """``(Q, V)``, each ``5 x len(s)``: fields and rates of the initial data at nodes ``s``."""
        s = np.asarray(s, dtype=float)
        k = 2 * math.pi / self.L
        R = self.a if self.R is None else self.R
        Q, V = np.zeros((NF, s.size)), np.zeros((NF, s.size))
        Q[0] = s
        Q[1] = R + self.dR * np.cos(k * s)
        Q[3] = np.arctan(-self.dR * k * np.sin(k * s))
        Q[3][[0, -1]] = 0.0
        V[2] = self.omega
        return Q, V
