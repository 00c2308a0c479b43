"""Piecewise-polynomial evaluation core shared by every curve family.

Each span [b_j, b_{j+1}] holds the power coefficients of the curve in the
centred local variable x = (t - m_j) / h_j in [-1, 1] (m_j the midpoint, h_j the
half width): p(t) = sum_k c[k, j] x^k. The coefficients are the Taylor
coefficients at the midpoint, c_k = C^(k)(m_j) h_j^k / k!, which keeps the power
form well conditioned. Evaluation is a span lookup (O(1) arithmetic for uniform
breaks, ``searchsorted`` otherwise) and a vectorized Horner scheme, done in
cache-sized chunks. This is the "per-span polynomial coefficients and vectorized
Horner" design; its results equal de Boor's algorithm to rounding.
"""
from __future__ import annotations

from math import factorial
from typing import Dict, Tuple

import numpy as np

from .._checks import frozen
from .._value import Value
from ..basis.bspline import basis_derivatives

_CHUNK = 1 << 15
FEW_POINTS = 16          # up to this many parameters are evaluated all coordinates at once
#: sorted parameters, at least this many per span on average, are evaluated span by span
#: (each span's run of parameters with its coefficients as scalars: no gathers; 10^6
#: sorted parameters on 97 spans: 44 -> 9 ms); fewer per span would pay a Python
#: iteration per span for little
RUN_POINTS = 4096

#: Highest degree evaluated in the power form. Measured (issue 14): random Bezier curves
#: in the unit cube against exact (Fraction) de Casteljau, worst of 7 parameters in
#: [0.001, 0.999]: degree 10: 1e-15, 15: 3e-15, 20: 1.7e-14, 25: 1.3e-13, 30: 6e-13,
#: 35: 2.7e-12, 40: 2e-11, 50: 5e-10, 55: 4e-9, 60: 0.87 (the centred power basis loses
#: about a factor 2.5 per degree). 20 keeps a margin of 60 below 1e-12; above it the
#: curves evaluate by the Bernstein sum on Bezier spans
#: (:class:`cagd.curves.bezier_spans.BernsteinSpans`).
PP_MAX_DEGREE = 20
#: |local knot| cap of from_bspline (knots that far from a span act as at infinity)
LOCAL_KNOT_MAX = 1e300


def _half_width(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(b - a) / 2, at least the smallest subnormal (a span 5e-324 wide halves to 0)."""
    return np.maximum(0.5 * (b - a), _TINY)


_TINY = float(np.nextafter(0.0, 1.0))


class PPForm(Value):
    """Piecewise polynomial with ``breaks`` (s+1,) and ``coefficients`` (p+1, s, dim),
    a value like the curves it caches for (read-only arrays)."""

    def __init__(self, breaks: np.ndarray, coefficients: np.ndarray):
        self.breaks = frozen(np.ascontiguousarray(breaks, dtype=np.float64))
        self.coefficients = frozen(np.ascontiguousarray(coefficients, dtype=np.float64))
        self.degree = self.coefficients.shape[0] - 1
        self.dim = self.coefficients.shape[2]
        b = self.breaks
        self._mid = frozen(0.5 * (b[1:] + b[:-1]))
        with np.errstate(over="ignore", divide="ignore"):
            self._inv_half = frozen(2.0 / (b[1:] - b[:-1]))
        self._half = frozen(_half_width(b[:-1], b[1:]))
        # a span narrower than 2 / 1.8e308 (subnormal) has no finite 1/half: divide there
        self._subnormal = bool(not np.all(np.isfinite(self._inv_half)))
        nspan = len(b) - 1
        width = b[-1] - b[0]
        self._uniform = bool(np.allclose(np.diff(b), width / nspan, rtol=1e-13, atol=0.0))
        self._inv_h = nspan / width
        # per-dimension contiguous 1-D tables: take() on 1-D arrays is the fastest gather
        self._tables = [[frozen(self.coefficients[k, :, d]) for d in range(self.dim)]
                        for k in range(self.degree + 1)]
        self._derived: Dict[int, "PPForm"] = {}

    # --- construction -------------------------------------------------------------
    @classmethod
    def from_bspline(cls, knots: np.ndarray, degree: int, control_points: np.ndarray) -> "PPForm":
        """Taylor coefficients at the midpoints of the non-empty spans of a B-spline
        (derivatives by Piegl & Tiller A2.3)."""
        n = control_points.shape[0]
        p = degree
        span = np.flatnonzero(knots[p:n] < knots[p + 1:n + 1]) + p
        a, b = knots[span], knots[span + 1]
        mid, half = 0.5 * (a + b), _half_width(a, b)
        # each span's knot window u_{i-p}..u_{i+p+1} in its own centred variable
        # x = (u - mid)/half, so the x-derivatives are the Taylor coefficients times k!
        # without forming (1/h)^k (no overflow on narrow spans, no loss at large offsets)
        window = span[:, None] + np.arange(-p, p + 2)
        with np.errstate(over="ignore"):
            local = (knots[window] - mid[:, None]) / half[:, None]
        # neighbours of a subnormal span land beyond the float range: far away is far away
        # (the basis on [-1, 1] changes by ~1/LOCAL_KNOT_MAX), so clip them
        np.clip(local, -LOCAL_KNOT_MAX, LOCAL_KNOT_MAX, out=local)
        width = 2 * p + 2
        ders = basis_derivatives(local.ravel(), p, np.zeros(len(span)), np.arange(len(span)) * width + p, p)
        idx = span[:, None] - p + np.arange(p + 1)                   # (s, p+1)
        coef = np.einsum("ksr,srd->ksd", ders, control_points[idx])
        coef /= np.array([factorial(k) for k in range(p + 1)], dtype=np.float64)[:, None, None]
        breaks = np.concatenate([a, b[-1:]])
        return cls(breaks, coef)

    @classmethod
    def from_unit_power(cls, breaks: np.ndarray, coefficients: np.ndarray) -> "PPForm":
        """From coefficients in u = (t - b_j)/(b_{j+1} - b_j) in [0, 1] per span,
        shape (p+1, s, dim): substitute u = (x + 1)/2."""
        p = coefficients.shape[0] - 1
        # u^k = 2^-k (x+1)^k = sum_i C(k,i) 2^-k x^i
        S = np.zeros((p + 1, p + 1))
        for k in range(p + 1):
            for i in range(k + 1):
                S[i, k] = factorial(k) / (factorial(i) * factorial(k - i)) / 2.0 ** k
        return cls(breaks, np.einsum("ik,ksd->isd", S, coefficients))

    # --- evaluation -----------------------------------------------------------------
    @property
    def domain(self) -> Tuple[float, float]:
        return float(self.breaks[0]), float(self.breaks[-1])

    def span_of(self, t: np.ndarray) -> np.ndarray:
        """Index j of the span with b_j <= t < b_{j+1} (last span closed at the end)."""
        last = len(self.breaks) - 2
        if self._uniform and t.shape[0] > FEW_POINTS:      # (a few: one searchsorted is cheaper, same j)
            j = ((t - self.breaks[0]) * self._inv_h).astype(np.intp)
            np.minimum(j, last, out=j)
            np.maximum(j, 0, out=j)
            # rounding in the division can land one span off at a break: fix exactly
            j -= (t < self.breaks[j]) & (j > 0)
            j += (t >= self.breaks[np.minimum(j + 1, last + 1)]) & (j < last)
            return j
        j = np.searchsorted(self.breaks, t, side="right") - 1
        np.minimum(j, last, out=j)              # np.clip's dispatch costs more on a few points
        np.maximum(j, 0, out=j)
        return j

    def derived(self, order: int) -> "PPForm":
        """The pp form of the ``order``-th derivative (cached)."""
        if order == 0:
            return self
        if order not in self._derived:
            c = self.coefficients
            p = self.degree
            if order > p:
                new = np.zeros((1,) + c.shape[1:])
            else:
                k = np.arange(order, p + 1)
                fall = np.array([factorial(i) / factorial(i - order) for i in k])
                new = c[order:] * fall[:, None, None] * (self._inv_half ** order)[None, :, None]
            self._derived[order] = PPForm(self.breaks, new)
        return self._derived[order]

    def __call__(self, t: np.ndarray, order: int = 0) -> np.ndarray:
        """Values (order 0) or derivatives at the flat parameter array ``t``: (len(t), dim)."""
        pp = self.derived(order)
        t = np.asarray(t, dtype=np.float64).ravel()
        out = np.empty((t.shape[0], pp.dim))
        if not pp._by_runs(t, out, pp.dim, False):
            for s in range(0, t.shape[0], _CHUNK):
                pp._horner(t[s:s + _CHUNK], out[s:s + _CHUNK], pp.dim)
        return out

    def projected(self, t: np.ndarray) -> np.ndarray:
        """Values of a homogeneous (rational) form divided by its last coordinate,
        (len(t), dim-1); the division happens chunk by chunk while in cache."""
        t = np.asarray(t, dtype=np.float64).ravel()
        out = np.empty((t.shape[0], self.dim - 1))
        if not self._by_runs(t, out, self.dim - 1, True):
            for s in range(0, t.shape[0], _CHUNK):
                self._horner(t[s:s + _CHUNK], out[s:s + _CHUNK], self.dim - 1, project=True)
        return out

    def _by_runs(self, t: np.ndarray, out: np.ndarray, ndim: int, project: bool) -> bool:
        """:meth:`_horner` on sorted parameters, RUN_POINTS or more per span: the run of
        each span (the same spans as :meth:`span_of`, clamped at the ends) by Horner with
        that span's coefficients as scalars, the same operations on every number (the
        same bits). False, nothing done, when t is not sorted or too short."""
        n, spans = t.shape[0], len(self.breaks) - 1
        if n < RUN_POINTS * spans or not bool(np.all(t[1:] >= t[:-1])):
            return False
        ends = np.concatenate([[0], np.searchsorted(t, self.breaks[1:-1], side="left"), [n]])
        p, tables = self.degree, self._tables
        for j in np.flatnonzero(ends[1:] > ends[:-1]):
            run = slice(ends[j], ends[j + 1])
            x = (t[run] - self._mid[j]) / self._half[j] if self._subnormal else (t[run] - self._mid[j]) * \
                self._inv_half[j]

            def horner(d: int) -> np.ndarray:
                if p == 0:
                    return np.full(x.shape[0], tables[0][d][j])
                acc = tables[p][d][j] * x
                for k in range(p - 1, -1, -1):
                    acc += tables[k][d][j]
                    if k:
                        acc *= x
                return acc
            inv_w = 1.0 / horner(self.dim - 1) if project else None
            for d in range(ndim):
                acc = horner(d)
                if inv_w is not None:
                    acc *= inv_w
                out[run, d] = acc
        return True

    def _horner(self, t: np.ndarray, out: np.ndarray, ndim: int, project: bool = False) -> None:
        j = self.span_of(t)
        x = self.local(t, j)
        if t.shape[0] <= FEW_POINTS:         # one gather of every coordinate: fewer numpy calls
            self._horner_few(j, x, out, ndim, project)
            return
        inv_w = 1.0 / self._horner_1d(j, x, self.dim - 1) if project else None
        for d in range(ndim):
            acc = self._horner_1d(j, x, d)
            if project:
                acc *= inv_w
            out[:, d] = acc

    def _horner_few(self, j: np.ndarray, x: np.ndarray, out: np.ndarray, ndim: int, project: bool) -> None:
        """:meth:`_horner` on a few points, all coordinates at once (the same operations
        on every number as the per-coordinate path, so the same bits)."""
        c = self.coefficients[:, j]                   # (p+1, n, dim)
        acc = c[self.degree].copy()
        xc = x[:, None]
        for k in range(self.degree - 1, -1, -1):
            acc *= xc
            acc += c[k]
        if project:
            out[:] = acc[:, :ndim] * (1.0 / acc[:, ndim:ndim + 1])
        else:
            out[:] = acc[:, :ndim]

    def local(self, t: np.ndarray, j: np.ndarray) -> np.ndarray:
        """x = (t - m_j) / h_j of parameters t in spans j."""
        if self._subnormal:
            return (t - self._mid.take(j)) / self._half.take(j)
        return (t - self._mid.take(j)) * self._inv_half.take(j)

    def _horner_1d(self, j: np.ndarray, x: np.ndarray, d: int) -> np.ndarray:
        p = self.degree
        acc = self._tables[p][d].take(j)
        for k in range(p - 1, -1, -1):
            acc *= x
            acc += self._tables[k][d].take(j)
        return acc
