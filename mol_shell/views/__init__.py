"""Layer 8: what users look at: figures, 3-D export for ParaView, animations. Never switches matplotlib's backend."""
