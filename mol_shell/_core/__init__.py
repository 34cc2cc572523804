"""Layer 0: what every layer shares. Errors, allowed ranges, constants (the fields), the version, atomic writes."""
