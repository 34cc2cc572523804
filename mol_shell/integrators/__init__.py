"""Time integrators. Each is a small frozen dataclass with ``name``, ``order`` and ``integrate``."""

from .base import Monitor, Trajectory
from .leapfrog import Leapfrog

INTEGRATORS = {Leapfrog.name: Leapfrog}

__all__ = ["INTEGRATORS", "Leapfrog", "Monitor", "Trajectory"]
