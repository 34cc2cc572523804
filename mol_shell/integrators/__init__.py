"""Time integrators. Each is a small frozen dataclass with ``name``, ``order`` and ``integrate``."""

from .base import Monitor, Trajectory
from .explicit import EXPLICIT
from .leapfrog import Leapfrog
from .sundials import IDA, CVODEAdams, CVODEBDF

INTEGRATORS = {cls.name: cls for cls in (Leapfrog, CVODEBDF, CVODEAdams, IDA)}
INTEGRATORS.update(EXPLICIT)

try:  # the comparison's peers (scipy, CasADi's SUNDIALS plugins)
    from .peers import PEERS

    INTEGRATORS.update(PEERS)
except ImportError:  # pragma: no cover - peers are optional
    PEERS = {}

__all__ = ["INTEGRATORS", "CVODEAdams", "CVODEBDF", "IDA", "Leapfrog", "Monitor", "PEERS", "Trajectory"]
