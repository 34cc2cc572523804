"""Layer 2: the semi-discrete system. Cells and nodes on the meridian, edge and load terms, the CasADi graphs of the
right-hand side, the DAE residual and their exact Jacobians, compiled to C and cached; the leap-frog stencil."""
