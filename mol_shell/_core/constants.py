"""Constants of the model shared by every layer: the fields and the dense-matrix threshold."""

#: the fields of the model, in the order of a node's unknowns (paper, section 2): axial and radial
#: position of the base curve (m), director angle chi and twist theta (rad), shear angle psi (rad)
FIELDS = ("z", "r", "chi", "theta", "psi")
#: fields per node
NF = len(FIELDS)
#: up to this many states a Jacobian is handled as a dense matrix (spectra, dense or banded solvers);
#: above it only sparse methods are used
DENSE_MAX_STATES = 2000
#: relative tolerances every adaptive integrator accepts, ``[low, high)``: below 1e-14 is under round-off,
#: 1 and above controls nothing
RTOL_RANGE = (1e-14, 1.0)
