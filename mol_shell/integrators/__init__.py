"""Time integrators. Each is a small frozen dataclass with ``name``, ``order`` and ``integrate``."""

from mol_shell.integrators.base import Monitor, Trajectory
from mol_shell.integrators.explicit import EXPLICIT
from mol_shell.integrators.leapfrog import Leapfrog
from mol_shell.integrators import sundials
from mol_shell.integrators.sundials_c import CVODEBDF, IDA, CVODEAdams

# cvode-bdf, cvode-adams, ida: the loop in compiled C; sksundae-*: scikit-sundae's Python loop (release 0.5.0's)
INTEGRATORS = {cls.name: cls for cls in (Leapfrog, CVODEBDF, CVODEAdams, IDA, sundials.CVODEBDF,
                                         sundials.CVODEAdams, sundials.IDA)}
"""The integrators :func:`mol_shell.simulate` and :func:`mol_shell.study` take by name: name -> its class, a
dataclass whose fields are its options (the keywords ``simulate`` passes on: ``rtol``, ``dt``, ...).
``list(mol_shell.INTEGRATORS)`` gives the names (the ``scipy-*`` and ``casadi-*`` peers where SciPy and CasADi's
plugins load), ``dataclasses.fields(mol_shell.INTEGRATORS["cvode-bdf"])`` one's options. The unshearable scene takes
``ida`` (its constrained DAE) or ``leapfrog``."""
INTEGRATORS.update(EXPLICIT)

try:  # the comparison's peers (scipy, CasADi's SUNDIALS plugins)
    from mol_shell.integrators.casadi_peers import CASADI_PEERS
    from mol_shell.integrators.peers import SCIPY_PEERS

    PEERS = {**SCIPY_PEERS, **CASADI_PEERS}
    INTEGRATORS.update(PEERS)
except ImportError:  # pragma: no cover - peers are optional
    PEERS = {}

__all__ = ["INTEGRATORS", "CVODEAdams", "CVODEBDF", "IDA", "Leapfrog", "Monitor", "PEERS", "Trajectory"]
