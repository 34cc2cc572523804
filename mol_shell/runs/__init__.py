"""Layer 6: running scenes. Building the system, checks before a run, simulate, the unshearable DAE, the ring ODE,
studies and their scheduling, resource estimates, static equilibria that start loaded runs."""
