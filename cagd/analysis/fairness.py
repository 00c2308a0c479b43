"""Fairness read-out of a curve: curvature plot, curvature-variation energy, inflections
and curvature jumps at knots (Farin, Curves and Surfaces for CAGD, 23.1-23.2: curvature
plots and fairing; the curvature formulas, Farin 10.1-10.2).

With C', C'', C''' the parameter derivatives and c = C' x C'' (2-D curves lifted to
z = 0):

- kappa and the curvature vector kappa N, from :func:`cagd.analysis.comb.curvature_comb`
  (Farin 10.1; the same per-span samples);
- d kappa / dt = c.(C' x C''') / (|c| |C'|^3) - 3 kappa (C'.C'') / |C'|^2 (where c = 0,
  the first term is |C' x C'''| / |C'|^3, its one-sided limit up to sign: only its
  square is used);
- energy E = integral of (d kappa / ds)^2 ds = integral of (d kappa / dt)^2 / |C'| dt,
  by composite Gauss-Legendre quadrature (QUAD_POINTS nodes on each interval between
  two curvature samples of a knot span; the integrand is smooth inside a span);
- signed curvature kappa_s = (c . m) / |C'|^3 for the plane normal m: z for 2-D curves,
  for 3-D curves the normal of the best-fitting plane of the samples (the least
  singular vector of the centred sample points). The inflections counted are the sign
  changes of kappa_s along the samples (values within INFLECTION_TOL of the largest
  |kappa| count as zero and are skipped): exact for planar curves; for twisted 3-D
  curves, the inflections of the projection onto that plane.

Samples are placed per knot span (Bezier piece of the exact NURBS form), the span's
ends included, as :func:`cagd.analysis.comb.curvature_comb` does: an interior knot is
sampled twice (left and right limit), so a curvature jump shows as a jump.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._results import ReadOnlyArrays
from ..curves.base import Curve
from ..errors import CagdError
from .comb import curvature_comb

QUAD_POINTS = 8           # Gauss-Legendre nodes per sample interval (energy and arc length)
MAX_NODES = 500_000       # quadrature nodes at most (spans x samples_per_span x QUAD_POINTS; process peak 220 MB)
INFLECTION_TOL = 1e-9     # |kappa_s| below this fraction of max |kappa|: zero (no sign)
_SINGULAR = 1e-12         # |C'| below this fraction of its largest sample: a singular point


@dataclass(frozen=True)
class Fairness(ReadOnlyArrays):
    """Fairness metrics of a curve (see the module doc for the formulas).

    energy: integral of (d kappa / ds)^2 ds; inflections: sign changes of the signed
    curvature; max_knot_jump: the largest |kappa N (left) - kappa N (right)| over the
    interior knots (and the seam of a periodic curve), 0 if none; jump_parameter: the
    knot where it occurs (NaN if none); knots, knot_jumps: every such knot and its jump.
    Curvature plot: params, span, arc_length s (from the start), curvature kappa >= 0,
    signed_curvature kappa_s, per sample; length: the total arc length."""
    energy: float
    inflections: int
    max_knot_jump: float
    jump_parameter: float
    knots: np.ndarray
    knot_jumps: np.ndarray
    params: np.ndarray
    span: np.ndarray
    arc_length: np.ndarray
    curvature: np.ndarray
    signed_curvature: np.ndarray
    length: float


def _lift(d: np.ndarray) -> np.ndarray:
    if d.shape[-1] == 2:
        return np.concatenate([d, np.zeros(d.shape[:-1] + (1,))], axis=-1)
    return d


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def fairness(curve: Curve, samples_per_span: int = 16) -> Fairness:
    """Curvature plot and fairness metrics of ``curve`` (a 2-D or 3-D engine curve).

    Args:
        curve: the curve.
        samples_per_span: curvature samples per knot span, at least 2 (both span ends
            included); the inflection count sees sign changes at this resolution.

    Returns:
        :class:`Fairness`.

    Raises:
        CagdError: not a curve, not 2-D or 3-D, samples_per_span < 2 or too many samples
            (more than MAX_NODES quadrature nodes), a singular point (C' = 0), values beyond the floating-point range.
    """
    if not isinstance(curve, Curve):
        raise CagdError(f"curve: expected a cagd Curve, got {type(curve).__name__}")
    if curve.dim not in (2, 3):
        raise CagdError(f"curve: fairness is defined for 2-D and 3-D curves, this one is {curve.dim}-D")
    from ..queries.bounds import bezier_pieces
    per = _checks.integer(samples_per_span, "samples_per_span", 2, _checks.MAX_SAMPLES)
    pieces = bezier_pieces(curve)
    b = pieces.breaks[0]
    h = np.diff(b)
    m = len(h)
    if per * m * QUAD_POINTS > MAX_NODES:
        raise CagdError(f"samples_per_span: {per} samples on each of {m} spans need more than MAX_NODES = "
                        f"{MAX_NODES} quadrature nodes ({QUAD_POINTS} per sample interval)")
    # kappa and kappa N at the samples from the comb (the same per-span sampling, one formula)
    comb = curvature_comb(curve, samples_per_span=per, scale=0.0)
    t, span = comb.params, comb.span
    kappa = comb.curvature
    kvec = _lift(-kappa[:, None] * comb.normals)
    d1 = _lift(pieces.derivatives(span, t[:, None], 1)[1])
    # Gauss-Legendre nodes on each of the per - 1 intervals between samples of a span
    x, wq = np.polynomial.legendre.leggauss(QUAD_POINTS)
    lo = t.reshape(m, per)[:, :-1].ravel()
    hi = t.reshape(m, per)[:, 1:].ravel()
    half = 0.5 * (hi - lo)
    tq = (0.5 * (hi + lo))[:, None] + half[:, None] * x[None, :]
    dq = _lift(pieces.derivatives(np.repeat(span.reshape(m, per)[:, :-1].ravel(), QUAD_POINTS),
                                  tq.ravel()[:, None], 3))
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        speed = np.linalg.norm(d1, axis=-1)
        top = float(speed.max())
        if not top > 0.0 or np.any(speed <= _SINGULAR * top):
            raise CagdError("curve: singular point (C' = 0): curvature is undefined there")
        # plane normal m: z in 2-D, least singular vector of the centred samples in 3-D
        if curve.dim == 2:
            normal = np.array([0.0, 0.0, 1.0])
        else:
            base = comb.base
            normal = np.linalg.svd(base - base.mean(axis=0), full_matrices=False)[2][-1]
        # kappa_s = (c.m) / |C'|^3 = kappa sign((C' x kappa N).m), c = C' x C''
        signed = kappa * np.sign(_dot(np.cross(d1, kvec), normal))
        # energy and arc length by composite Gauss-Legendre, in the arc-length-rate frame
        # D_k = d_k / a^k, a = |C'| (a reparametrisation t' = a t: |D_1| = 1, no over/underflow
        # of |C'|^5): d kappa / dt = a d kappa / dt', integrand (d kappa / dt)^2 / a = a (d kappa / dt')^2
        sq = np.linalg.norm(dq[1], axis=-1)
        a = np.where(sq > 0, sq, 1.0)[:, None]
        D1, D2, D3 = dq[1] / a, dq[2] / a / a, dq[3] / a / a / a
        cq = np.cross(D1, D2)
        cn = np.linalg.norm(cq, axis=-1)
        c3 = np.cross(D1, D3)
        tiny = cn <= _SINGULAR * np.linalg.norm(D2, axis=-1)
        first = np.where(tiny, np.linalg.norm(c3, axis=-1), _dot(cq, c3) / np.where(tiny, 1.0, cn))
        dk = first - 3.0 * cn * _dot(D1, D2)
        wts = (half[:, None] * wq[None, :]).ravel()
        energy = float(np.sum(wts * sq * dk * dk))
        pieces_len = np.sum((wts * sq).reshape(-1, QUAD_POINTS), axis=1).reshape(m, per - 1)
    s = np.concatenate([np.zeros((m, 1)), np.cumsum(pieces_len, axis=1)], axis=1)
    s = (s + np.concatenate([[0.0], np.cumsum(s[:, -1])[:-1]])[:, None]).ravel()
    if not (np.isfinite(energy) and np.all(np.isfinite(s)) and np.all(np.isfinite(kvec))):
        raise CagdError("curve: its curvature exceeds the floating-point range (the curve is too small or large)")
    # inflections: sign changes of kappa_s, near-zero values skipped
    kmax = float(kappa.max())
    signs = np.sign(signed[np.abs(signed) > INFLECTION_TOL * kmax]) if kmax > 0.0 else np.zeros(0)
    inflections = int(np.count_nonzero(np.diff(signs)))
    # curvature-vector jumps at interior knots (and the seam of a periodic curve)
    ends = kvec.reshape(m, per, 3)
    left, right, knots = ends[:-1, -1], ends[1:, 0], b[1:-1]
    if pieces.periodic[0] and m >= 1:
        left, right = np.vstack([left, ends[-1, -1]]), np.vstack([right, ends[0, 0]])
        knots = np.append(knots, b[-1])
    jumps = np.linalg.norm(left - right, axis=-1)
    worst = int(np.argmax(jumps)) if jumps.size else -1
    return Fairness(energy, inflections, float(jumps[worst]) if jumps.size else 0.0,
                    float(knots[worst]) if jumps.size else float("nan"), np.array(knots, dtype=np.float64),
                    jumps, t, span, s, kappa, signed, float(s[-1]))
