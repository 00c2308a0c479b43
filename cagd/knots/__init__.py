"""Knot vectors: construction, validation, multiplicities, periodic extension, spans.

Conventions (seed 000, 5.3.1-5.3.2; Piegl & Tiller, The NURBS Book, ch. 2):
a non-periodic B-spline of degree p with n control points has the full knot
vector u_0..u_{n+p} and domain [u_p, u_n]; a periodic one is given by one period
t_0..t_n (n distinct control points) and is unwrapped by :func:`periodic_extend`.
"""
from .vectors import (
    clamped_uniform,
    distinct_with_multiplicities,
    find_span,
    greville,
    periodic_extend,
    uniform,
    validate,
    validate_period,
    from_multiplicities,
    averaged,
    occ_knots,
    is_clamped,
    from_occ_knots,
)

__all__ = [
    "clamped_uniform", "distinct_with_multiplicities", "find_span", "greville",
    "periodic_extend", "uniform", "validate", "validate_period",
    "from_multiplicities", "averaged", "occ_knots", "from_occ_knots", "is_clamped",
]
