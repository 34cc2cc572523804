"""Layer 7: analyses that run or linearise many systems: natural modes, stability reports, work-precision."""
