"""Constants of the model shared by every layer: the fields, the dense-matrix threshold and the limits of double
precision the integrators' inputs keep to."""

import math
import sys

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
#: the least absolute tolerance (m or rad; a momentum's is this times its mass): the integrators' error norms sum
#: squares of each entry over its tolerance, ``sqrt(mean((v_i / atol_i)^2))``, which overflow once ``v_i / atol_i``
#: passes 1.3e154 (and ``1 / atol_i``, SUNDIALS' weight of an entry at 0, once ``atol_i`` is subnormal). Measured on the
#: sphere (n = 8, 0.1 ms): CVODE's BDF failed at t = 0 from 1e-142 on (on and off down to 1e-160), IDA from 1e-170
#: (SUNDIALS' status -22), DOP853 in C divided by zero from 1e-154 on the twisted cylinder. 1e-100 leaves 40 decades
#: for the magnitudes of the states, rates and masses; no length or angle is meaningful at 1e-100 m anyway. A tolerance
#: above it can still ask more of a motion than its steps can give (an entry crossing 0 held to 1e-100 m): such a run
#: stops, saying so (the integrator's step or its step count)
ATOL_MIN = 1e-100
#: the shortest step an adaptive integrator is asked to take (s): sqrt of the smallest normal double, 1.49e-154 s.
#: Step-size selection squares the step (``h^2 y''``); below it that underflows and SUNDIALS refuses to start
#: (CV_ILL_INPUT, measured from 1e-161 s on with IDA) or its Newton iteration fails at t = 0 (CVODE's BDF from a
#: first step of 1e-290 s). The shortest interval between saved times, and the least ``first_step``
MIN_STEP = math.sqrt(sys.float_info.min)


def stated_up(value, digits=4):
    """``value`` rounded up to ``digits`` significant digits: a lower bound a message states with that many digits
    and that is then the bound applied (a bound rounded down would state values the check refuses)."""
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    if float(f"{mantissa}e{exponent}") < value:  # rounded down: one unit of the last digit up
        mantissa = f"{float(mantissa) + 10.0 ** (1 - digits):.{digits - 1}f}"
    return float(f"{mantissa}e{exponent}")


def stated_down(value, digits=4):
    """``value`` rounded down to ``digits`` significant digits: an upper bound a message states with that many digits
    and that is then the bound applied (one rounded up stated as refused values the check took: ``dt < 1/omega_max``
    said ``(0, 0.0001889)`` and ran ``dt = 0.0001889``)."""
    return -stated_up(-value, digits)

#: intervals between the saved times of a run given ``t_end`` alone (``DEFAULT_INTERVALS + 1`` evenly spaced times)
DEFAULT_INTERVALS = 10
