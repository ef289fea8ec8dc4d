"""parametric."""
