"""Time integrators. Each is a small frozen dataclass with ``name``, ``order`` and ``integrate``."""

from mol_shell.integrators.base import Monitor, Trajectory
from mol_shell.integrators.explicit import EXPLICIT
from mol_shell.integrators.leapfrog import Leapfrog
from mol_shell.integrators.sundials import CVODEBDF, IDA, CVODEAdams

INTEGRATORS = {cls.name: cls for cls in (Leapfrog, CVODEBDF, CVODEAdams, IDA)}
INTEGRATORS.update(EXPLICIT)

try:  # the comparison's peers (scipy, CasADi's SUNDIALS plugins)
    from mol_shell.integrators.peers import PEERS

    INTEGRATORS.update(PEERS)
except ImportError:  # pragma: no cover - peers are optional
    PEERS = {}

__all__ = ["INTEGRATORS", "CVODEAdams", "CVODEBDF", "IDA", "Leapfrog", "Monitor", "PEERS", "Trajectory"]
