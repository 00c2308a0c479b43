"""Degree reduction with an error bound (Piegl & Tiller, The NURBS Book, 5.6 and A5.11;
the seeds do not treat it).

A degree-p B-spline is split into its Bezier pieces; each piece P (p + 1 points) is
replaced by the degree-(p-1) piece R with R_0 = P_0, R_(p-1) = P_p (the joints stay C0)
whose elevation E R (E: :func:`cagd.basis.elevation_matrix`) is nearest to P in the least
squares sense (Farin, Curves and Surfaces for CAGD, 6.3, with the end points held). The
difference of the two pieces is the Bezier curve with control points P - E R, so by the
convex hull property the reduced piece is within e = max_i |P_i - (E R)_i| of the
original at equal parameters: that is the bound of the step. The pieces are then joined
with knots of multiplicity p - 1 and Tiller's knot removal (:mod:`cagd.knots.removal`)
takes out as many as the rest of the tolerance allows, restoring the smoothness where the
shape permits (A5.11's order of work). The bound of the whole is the sum of the two.

Arrays are (n, k, D) as in :mod:`cagd.knots.removal`: k curves sharing the knots (the
rows of a surface), reduced together; a rational curve works in homogeneous coordinates
with the caller's homogeneous tolerance.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from ..basis.bernstein import elevation_matrix
from ..errors import CagdError
from ..knots import vectors as kv
from .removal import remove_knots


@dataclass(frozen=True)
class DegreeReduction:
    """The result of ``reduce_degree``: ``result`` of degree p - 1, ``error_bound`` the
    certified bound of its distance from the original at equal parameters (the pieces'
    reduction bound plus the knot removal's), ``deviation`` the largest distance measured
    at DEVIATION_SAMPLES parameters per original knot span; ``converged`` when the bound
    is within tol (else ``result`` is still the reduced object, farther than asked, and
    ``message`` says by how much)."""
    result: object
    error_bound: float
    deviation: float
    converged: bool
    message: str


def reduced_pieces(nets: np.ndarray) -> Tuple[np.ndarray, float]:
    """Degree-(p-1) Bezier nets (s, p, k, D) nearest to the degree-p nets (s, p+1, k, D)
    with the end points held, and the bound max |P - E R| over pieces and rows."""
    p = nets.shape[1] - 1
    E = elevation_matrix(p - 1, 1)                                   # (p + 1, p)
    R = np.empty(nets.shape[:1] + (p,) + nets.shape[2:])
    R[:, 0], R[:, -1] = nets[:, 0], nets[:, -1]
    if p > 2:
        A = E[:, 1:-1]
        rhs = nets - E[None, :, 0, None, None] * nets[:, :1] - E[None, :, -1, None, None] * nets[:, -1:]
        R[:, 1:-1] = np.einsum("ij,sjkd->sikd", np.linalg.pinv(A), rhs)
    diff = nets - np.einsum("ij,sjkd->sikd", E, R)
    return R, float(np.sqrt((diff * diff).sum(-1)).max(initial=0.0))


def reduce_degree(breaks: np.ndarray, nets: np.ndarray, tol: float
                  ) -> Tuple[np.ndarray, np.ndarray, int, float]:
    """(knots, control points (n, k, D), degree p - 1, bound) of the reduced curve(s)
    from the Bezier decomposition (breaks (s + 1,), nets (s, p + 1, k, D)); the knot
    removal runs only when the pieces' bound leaves room within tol."""
    R, bound = reduced_pieces(nets)
    q = R.shape[1] - 1
    P = np.concatenate([R[:1, 0], R[:, 1:].reshape((-1,) + R.shape[2:])])    # neighbours share an end
    mults = np.full(len(breaks), q)
    mults[0] = mults[-1] = q + 1
    U = kv.from_multiplicities(breaks, mults)
    if bound < tol and len(breaks) > 2:
        U2, P2, _, removal = remove_knots(U, P, q, tol - bound)
        return U2, P2, q, bound + removal
    return U, P, q, bound


def check_weights(P: np.ndarray, rational: bool, p: int) -> None:
    """CagdError when a reduced rational net (n, k, D + 1) has a weight <= 0: the
    homogeneous reduction moved a weight past zero, so no degree-(p-1) rational curve
    near the original exists on this path."""
    if rational and not np.all(P[..., -1] > 0.0):
        raise CagdError(f"tol: reducing this rational degree-{p} shape by one degree makes a weight "
                        f"non-positive (the homogeneous error exceeds a weight); its shape needs degree {p} "
                        f"at this tolerance")
