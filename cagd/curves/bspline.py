"""B-spline and NURBS curves (seed 000, 5.3; Piegl & Tiller, The NURBS Book, ch. 2-5).

Non-periodic: n control points, full knot vector u_0..u_{n+p}, domain [u_p, u_n].
Periodic: n distinct control points and one period t_0..t_n; the curve is the
B-spline with control points P_0..P_{n-1}, P_0..P_{p-1} on the unwrapped knots
(see :func:`cagd.knots.periodic_extend`), C^(p-1) at the seam for simple knots.
Rational curves work in homogeneous coordinates (w P, w) throughout.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from ..basis.bernstein import elevation_matrix
from ..errors import CagdError
from ..knots import vectors as kv
from .base import Curve, rational_derivatives
from .bezier_spans import BernsteinSpans, bezier_spans, bezier_spans_many
from .ppform import PP_MAX_DEGREE, PPForm

if TYPE_CHECKING:
    from ..knots.removal import KnotRemoval
    from ..knots.reduction import DegreeReduction
    from .bezier import BezierCurve

#: Values of the de Boor levels (and blossom arguments) held at once by the blossom evaluation (8 MiB).
_ELEVATE_VALUES = 1 << 20


class OccForm(NamedTuple):
    """Exactly the arguments of OCCT's ``Geom_BSplineCurve`` constructor."""
    poles: np.ndarray              # (n, 3)
    weights: Optional[np.ndarray]  # (n,) or None
    knots: np.ndarray              # distinct knots
    multiplicities: np.ndarray     # int
    degree: int
    periodic: bool


class BSplineCurve(Curve):
    """B-spline curve, NURBS when ``weights`` are given.

    Args:
        control_points: (n, dim) points; for a periodic curve the n distinct ones.
        degree: polynomial degree p >= 1 (p <= n - 1; periodic: p <= n).
        knots: full non-decreasing vector of n + p + 1 values (default clamped
            uniform on [0, 1]); periodic: one period of n + 1 values (default uniform).
        weights: n positive weights, or None for a polynomial B-spline.
        periodic: closed curve, C^(p-1) at the seam.

    Raises:
        CagdError: mismatched counts, non-monotone knots, bad multiplicities,
            non-positive weights, NaN/inf, degree out of range.
    """

    #: the attributes that define the object (equal ones give equal geometry): the
    #: closest-point projectors are cached by them (cagd.queries.closest.content_key)
    _content_fields = ("periodic", "degree", "knots", "control_points", "weights")

    _modified_copy = "use with_control_points(P), moved_pole(index, point) or with_weights(w)"

    def __init__(self, control_points: ArrayLike, degree: int, knots: Optional[ArrayLike] = None,
                 weights: Optional[ArrayLike] = None, periodic: bool = False):
        P = _checks.points(control_points, "control_points", min_count=2)
        n = P.shape[0]
        periodic = bool(periodic)
        p = _checks.degree(degree, "degree", 1, n if periodic else n - 1)
        w = _checks.weights(weights, n)
        if periodic:
            t = np.linspace(0.0, 1.0, n + 1) if knots is None else kv.validate_period(knots, n, p)
            full_u = kv.periodic_extend(t, p)
        else:
            t = kv.clamped_uniform(n, p) if knots is None else kv.validate(knots, p, n)
            full_u = None
        self._fill(P, w, p, t, full_u, periodic)

    def _fill(self, P: np.ndarray, w: Optional[np.ndarray], p: int, knots: np.ndarray,
              full_u: Optional[np.ndarray], periodic: bool) -> None:
        """Bind validated parts, frozen; ``full_u`` is the unwrapped vector of a periodic curve."""
        self.periodic = periodic
        self.control_points, self.degree, self.knots = _checks.frozen(P), p, _checks.frozen(knots)
        self.weights = None if w is None else _checks.frozen(w)
        self.dim = P.shape[1]
        self._u = _checks.frozen(full_u) if periodic and full_u is not None else self.knots   # full knots
        if w is None and not periodic:
            self._hom = self.control_points                               # matching (homogeneous) points
        else:
            hom = P if w is None else _checks.finite_homogeneous(np.hstack([P * w[:, None], w[:, None]]))
            self._hom = _checks.frozen(hom[kv.unwrapped_index(len(P), p, periodic)])
        self._pp: Optional[PPForm] = None
        self._derivative_pp: Dict[int, PPForm] = {}
        self._spans: Dict[int, BernsteinSpans] = {}
        self._pp_overflows: Optional[bool] = None

    # --- modified copies (the object itself never changes) --------------------------------
    def _with(self, P: np.ndarray, w: Optional[np.ndarray]) -> "BSplineCurve":
        return BSplineCurve._unchecked(P, w, self.degree, self.knots, self._u, self.periodic)

    def with_control_points(self, control_points: ArrayLike) -> "BSplineCurve":
        """The curve with the same degree, knots, weights and periodicity on new control
        points of the same shape (checked as in the constructor).

        Raises:
            CagdError: NaN/inf, a shape other than ``control_points.shape``."""
        P = _checks.points(control_points, "control_points", min_count=2)
        return self._with(_checks.same_shape(P, self.control_points.shape, "control_points"), self.weights)

    def moved_pole(self, index: int, point: ArrayLike) -> "BSplineCurve":
        """The curve with control point ``index`` (an int, negative from the end; for a
        periodic curve an index of the distinct points) moved to ``point``, all else
        kept: the cheap edit for dragging a pole (no knot checks, O(n) copies, the pp
        form rebuilt on the next evaluation).

        Raises:
            CagdError: an index out of range, a point of the wrong dimension or NaN/inf."""
        (i,) = _checks.pole_index(index, self.control_points.shape[:1])
        P = self.control_points.copy()
        P[i] = _checks.point(point, self.dim)
        return self._with(P, self.weights)

    def with_weights(self, weights: Optional[ArrayLike]) -> "BSplineCurve":
        """The same control points, degree and knots with new weights (None: polynomial).

        Raises:
            CagdError: a count other than one per control point, weights not positive."""
        return self._with(self.control_points, _checks.weights(weights, len(self.control_points)))

    # --- basic properties ------------------------------------------------------------
    @property
    def is_rational(self) -> bool:
        return self.weights is not None

    @property
    def domain(self) -> Tuple[float, float]:
        u, p = self._u, self.degree
        return float(u[p]), float(u[len(self._hom)])

    @property
    def full_knots(self) -> np.ndarray:
        """The full knot vector (unwrapped for a periodic curve), read-only."""
        return self._u

    def __repr__(self) -> str:
        kind = "NURBS" if self.is_rational else "B-spline"
        per = ", periodic" if self.periodic else ""
        return (f"<{kind} curve degree {self.degree}, {len(self.control_points)} control points{per}, "
                f"domain {self.domain}>")

    # --- evaluation ------------------------------------------------------------------
    @property
    def ppform(self) -> PPForm:
        """The per-span power form (cached): accurate to ~1e-14 of the net up to degree
        PP_MAX_DEGREE = 20 and losing digits fast above it, where evaluation uses the
        Bernstein sums on the Bezier spans instead (see :mod:`cagd.curves.ppform`)."""
        if self._pp is None:
            self._pp = PPForm.from_bspline(self._u, self.degree, self._hom)
        return self._pp

    def _bernstein_spans(self, order: int) -> BernsteinSpans:
        """The Bezier nets of the spans (and of their ``order``-th hodographs), cached."""
        if order not in self._spans:
            if 0 not in self._spans:
                self._spans[0] = BernsteinSpans(*bezier_spans(self._u, self.degree, self._hom))
            self._spans[order] = self._spans[0].derived(order)
        return self._spans[order]

    @property
    def _by_bernstein(self) -> bool:
        """Evaluate by the Bernstein sums: above PP_MAX_DEGREE, and where the power
        coefficients (binomial multiples of the net) leave the float range (a degree-13
        net at 1e300 gave NaN points)."""
        if self._pp_overflows is None:
            self._pp_overflows = self.degree > PP_MAX_DEGREE or not np.isfinite(self.ppform.coefficients).all()
        return self._pp_overflows

    def _evaluate(self, t: np.ndarray, order: int) -> np.ndarray:
        """Derivatives 0..order: the power form up to degree PP_MAX_DEGREE, the Bernstein
        sum on the Bezier spans above it (accurate to ~p ulps of the net at any degree)."""
        if self._by_bernstein:
            hom = np.stack([self._bernstein_spans(k)(t) for k in range(order + 1)])
            if order == 0 and self.is_rational:
                return self._clamped_ends(t, hom[0, :, :-1] / hom[0, :, -1:])[None]
            if order == 0:
                return self._clamped_ends(t, hom[0])[None]
            return rational_derivatives(hom) if self.is_rational else hom
        pp = self.ppform
        if order == 0:
            pts = pp.projected(t) if self.is_rational else pp(t)
            return self._clamped_ends(t, pts)[None]
        hom = np.stack([pp(t)] + [self._derivative_ppform(k)(t) for k in range(1, order + 1)])
        return rational_derivatives(hom) if self.is_rational else hom

    def _clamped_ends(self, t: np.ndarray, pts: np.ndarray) -> np.ndarray:
        """Points with clamped ends set to their control points bit for bit."""
        u, p, n = self._u, self.degree, len(self._hom)
        if u[0] == u[p]:
            pts[np.flatnonzero(t == u[p])] = self.control_points[0]      # (an index array: a boolean
        if u[-1] == u[n]:                                               # mask assignment scans 5x slower)
            pts[np.flatnonzero(t == u[n])] = self.control_points[-1]
        return pts

    def _derivative_ppform(self, order: int) -> PPForm:
        """pp form of the ``order``-th derivative built from the derivative curve's own
        control points Q_i = p (P_{i+1} - P_i) / (u_{i+p+1} - u_{i+1}) (seed 000, 5.3.1
        derivative formula; Piegl & Tiller eq. 3.4), applied ``order`` times. Unlike
        differentiating the curve's power form this keeps full relative precision of
        high derivatives on very short spans."""
        if order not in self._derivative_pp:
            u, P, p = self._u, self._hom, self.degree
            if order > p:
                pp = self.ppform.derived(order)               # identically zero
            else:
                for _ in range(order):
                    denom = (u[p + 1:len(P) + p] - u[1:len(P)])[:, None]
                    with np.errstate(divide="ignore", invalid="ignore"):
                        P = np.where(denom > 0, p * (P[1:] - P[:-1]) / np.where(denom > 0, denom, 1.0), 0.0)
                    u, p = u[1:-1], p - 1
                pp = PPForm.from_bspline(u, p, P)
            self._derivative_pp[order] = pp
        return self._derivative_pp[order]

    def _breaks_within(self, start: float, end: float) -> np.ndarray:
        u = np.unique(self._u)
        return u[(u > start) & (u < end)]

    def to_nurbs(self) -> "BSplineCurve":
        return self

    def _rebuild(self, hom: np.ndarray, knots: np.ndarray, degree: Optional[int] = None) -> "BSplineCurve":
        """A non-periodic curve from homogeneous control points and full knots."""
        if self.is_rational:
            w = hom[:, -1]
            return BSplineCurve(hom[:, :-1] / w[:, None], degree or self.degree, knots, w)
        return BSplineCurve(hom, degree or self.degree, knots)

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "BSplineCurve":
        return BSplineCurve(self.control_points @ A.T + b, self.degree, self.knots, self.weights, self.periodic)

    @property
    def homogeneous_control_points(self) -> np.ndarray:
        """(w P, w) for NURBS, P otherwise; the unwrapped sequence for periodic curves
        (read-only)."""
        return self._hom

    # --- knot insertion ----------------------------------------------------------------
    def insert_knot(self, t: float, times: int = 1) -> "BSplineCurve":
        """Insert the knot ``t`` ``times`` times (Boehm's algorithm, Piegl & Tiller A5.1);
        the curve is unchanged. A periodic curve stays periodic."""
        t = _checks.scalar(t, "t")
        times = _checks.integer(times, "times", 0)
        a, b = self.domain
        if not a <= t <= b:
            raise CagdError(f"t: knot {t} is outside the domain [{a}, {b}]")
        if self.periodic:
            return self._insert_periodic(t, times)
        u, hom = self._u, self._hom
        p = self.degree
        have = int(np.count_nonzero(u == t))
        if have + times > p + (1 if t in (a, b) else 0):
            raise CagdError(f"times: knot {t} would reach multiplicity {have + times} > degree = {p}")
        for _ in range(times):
            u, hom = _boehm(u, hom, p, t)
        return self._rebuild(hom, u)

    def _insert_periodic(self, t: float, times: int) -> "BSplineCurve":
        """Boehm's algorithm on the bi-infinite periodic sequence: control point and
        knot indices are taken modulo the period (knots continued by T = t_n - t_0)."""
        p, period = self.degree, self.knots.copy()
        T = period[-1] - period[0]
        if t == period[-1]:
            t = float(period[0])
        have = int(np.count_nonzero(period[:-1] == t))
        if t == period[0]:
            have += int(np.count_nonzero(period == period[-1])) - 1
        if have + times > p:
            raise CagdError(f"times: knot {t} would reach multiplicity {have + times} > degree = {p}")
        P = self._hom[:len(self.control_points)]
        for s in range(have, have + times):
            n = len(period) - 1
            k = min(int(np.searchsorted(period, t, side="right")) - 1, n - 1)
            # standard index i has knots u_i = t_{i-p}: affected i = k+1 .. k+p-s
            i = np.arange(k + 1, k + p - s + 1)

            def knot(j: np.ndarray) -> np.ndarray:
                return period[j % n] + (j // n) * T

            alpha = ((t - knot(i - p)) / (knot(i) - knot(i - p)))[:, None]
            j = np.arange(n + 1)
            Q = np.where((j <= k)[:, None], P[np.minimum(j, n - 1)], P[(j - 1) % n])
            Q[i % (n + 1)] = alpha * P[i % n] + (1.0 - alpha) * P[(i - 1) % n]
            P, period = Q, np.insert(period, k + 1, t)
        if self.is_rational:
            w = P[:, -1]
            return BSplineCurve(P[:, :-1] / w[:, None], p, period, w, periodic=True)
        return BSplineCurve(P, p, period, periodic=True)

    def refine(self, new_knots: ArrayLike) -> "BSplineCurve":
        """Insert all ``new_knots`` at once (knot refinement, Piegl & Tiller 5.3): each new
        control point is a blossom value of the curve
        (:func:`_blossoms`: convex combinations at any degree), O((n + r) p^2) for r knots.
        A periodic curve inserts them one by one (Boehm on the periodic sequence).

        Raises:
            CagdError: knots NaN/inf or outside the domain, a multiplicity above the degree."""
        ks = np.sort(_checks.finite_array(new_knots, "new_knots", ndim=1))
        if ks.size == 0:
            return self
        a, b = self.domain
        if ks[0] < a or ks[-1] > b:
            bad = ks[(ks < a) | (ks > b)][0]
            raise CagdError(f"new_knots: knot {bad} is outside the domain [{a}, {b}]")
        if self.periodic:
            return self._insert_each(ks)
        p = self.degree
        merged = np.sort(np.concatenate([self._u, ks]))
        count = len(self._hom) + len(ks)
        vals, mults = kv.distinct_with_multiplicities(merged)
        inner = (vals > a) & (vals < b)
        if np.any(mults[inner] > p) or np.any(mults[~inner] > p + 1):
            i = int(np.argmax(np.where(inner, mults > p, mults > p + 1)))
            raise CagdError(f"new_knots: knot {vals[i]} would reach multiplicity {mults[i]} > degree = {p}")
        u, n = self._u, len(self._hom)
        if u[0] != u[p] or u[n] != u[n + p]:
            # an unclamped end: a row f(x^p) at a knot of multiplicity p + 1 is a control
            # point of the piece on either side, which its values alone do not tell
            return self._insert_each(ks)
        rows = merged[np.arange(count)[:, None] + 1 + np.arange(p)]      # Q_j = f(v_(j+1), ..., v_(j+p))
        hom = _blossoms(u, p, self._hom, rows)
        if hom is None:
            return self._insert_each(ks)
        return self._rebuild(hom, kv.validate(merged, p, count))

    def _insert_each(self, ks: np.ndarray) -> "BSplineCurve":
        """Insert the sorted knots one by one (Boehm)."""
        c = self
        for k in ks:
            c = c.insert_knot(k)
        return c

    # --- restriction, Bezier decomposition, split ----------------------------------------
    def _with_multiplicity(self, values: np.ndarray, mult: int) -> Tuple[np.ndarray, np.ndarray]:
        """Full knots and homogeneous points after raising each of ``values`` to at
        least ``mult`` (non-periodic unwrapped form)."""
        u, hom, p = self._u, self._hom, self.degree
        for v in values:
            for _ in range(mult - int(np.count_nonzero(u == v))):
                u, hom = _boehm(u, hom, p, v)
        return u, hom

    def segment(self, start: float, end: float) -> "BSplineCurve":
        """The part of the curve on [start, end] as a clamped, non-periodic curve
        with the same parametrisation."""
        a, b = self.domain
        start, end = _checks.scalar(start, "start"), _checks.scalar(end, "end")
        if not (a <= start < end <= b):
            raise CagdError(f"start, end: need {a} <= start < end <= {b}, got [{start}, {end}]")
        p = self.degree
        u, hom = self._with_multiplicity(np.array([start, end]), p)
        k = int(np.searchsorted(u, start, side="right")) - 1   # last index with u_k = start
        l = int(np.searchsorted(u, end, side="left"))          # first index with u_l = end
        knots = np.concatenate([np.full(p + 1, start), u[k + 1:l], np.full(p + 1, end)])
        return self._rebuild(hom[k - p:l], knots)

    def clamped(self) -> "BSplineCurve":
        """The same curve with clamped (open) end knots, non-periodic."""
        return self.segment(*self.domain)

    def split(self, t: float) -> Tuple["BSplineCurve", "BSplineCurve"]:
        """Two clamped curves on [a, t] and [t, b]."""
        a, b = self.domain
        t = _checks.scalar(t, "t")
        if not a < t < b:
            raise CagdError(f"t: split parameter {t} must lie strictly inside the domain ({a}, {b})")
        return self.segment(a, t), self.segment(t, b)

    def bezier_net(self) -> Tuple[np.ndarray, np.ndarray]:
        """Breakpoints (m + 1,) and the homogeneous Bezier control points (m, p + 1, D)
        of the m pieces ((w P, w) when rational), as arrays: no curve objects. Each span
        on its own (:func:`cagd.curves.bezier_spans.bezier_spans`: the blossom values
        f(a^(p-j), b^j), what knot insertion to multiplicity p gives, Piegl & Tiller
        A5.6), vectorized over the spans: O(n p^3) work, O(n p) memory."""
        if 0 in self._spans:
            return self._spans[0].breaks, self._spans[0].nets
        return bezier_spans(self._u, self.degree, self._hom)

    def bezier_segments(self) -> Tuple[np.ndarray, List["BSplineCurve"]]:
        """Breakpoints and the Bezier pieces (each a clamped single-span curve on its
        own interval), from :meth:`bezier_net`."""
        values, nets = self.bezier_net()
        p = self.degree
        pieces = [self._piece(net, np.concatenate([np.full(p + 1, lo), np.full(p + 1, hi)]))
                  for net, lo, hi in zip(nets, values[:-1], values[1:])]
        return values, pieces

    def _piece(self, hom: np.ndarray, knots: np.ndarray) -> "BSplineCurve":
        """A clamped single-span piece from a homogeneous net, without re-validation
        (the net and knots come from this valid curve)."""
        if self.is_rational:
            w = hom[:, -1]
            return BSplineCurve._unchecked(hom[:, :-1] / w[:, None], w, self.degree, knots, None, False)
        return BSplineCurve._unchecked(hom, None, self.degree, knots, None, False)

    def to_bezier(self) -> List[BezierCurve]:
        """Bezier decomposition: a list of :class:`cagd.BezierCurve` on [0, 1] each
        (from :meth:`bezier_net`; O(n) memory)."""
        from .bezier import BezierCurve
        _, nets = self.bezier_net()
        p = self.degree
        knots = np.concatenate([np.zeros(p + 1), np.ones(p + 1)])
        return [BezierCurve._unchecked(self._piece(net, knots)) for net in nets]

    # --- degree elevation, reversal, reparametrisation ----------------------------------
    def elevate(self, times: int = 1) -> "BSplineCurve":
        """Raise the degree by ``times`` (p + times at most :data:`cagd.MAX_DEGREE`);
        every distinct knot's multiplicity grows by ``times`` so the continuity
        C^(p-m) at a knot of multiplicity m is kept (Piegl & Tiller 5.5, A5.9). A
        periodic curve comes back clamped.

        A curve in Bezier form (every interior knot of multiplicity p) is elevated
        exactly segment by segment with the Bernstein elevation matrix (Farin 6.1;
        Piegl & Tiller eq. 5.36). Otherwise the new control points are blossom values,
        one degree at a time (:func:`_elevated_by_blossom`: Prautzsch's averages of
        convex Oslo-type blossoms): no linear solve, accurate to a few ulps of the net
        at every accepted degree, O(n q t^2) work and O(n) memory. (It replaced a
        Greville collocation solve, whose condition grows like 2^q: above degree 20
        that fell back to C^0 knots.)

        Raises:
            CagdError: ``times`` not an integer >= 0, p + times > MAX_DEGREE."""
        times = _checks.elevation(times, self.degree)
        if times == 0:
            return self
        c = self.clamped()
        _, mults = kv.distinct_with_multiplicities(c._u, 0.0)
        if np.all(mults[1:-1] >= c.degree):
            return c._elevate_segments(times)
        u, p, hom = c._u, c.degree, c._hom
        for _ in range(times):
            u, hom = _elevated_by_blossom(u, p, hom)
            p += 1
        return c._rebuild(hom, u, p)

    def remove_knots(self, tol: float) -> "KnotRemoval":
        """Remove as many interior knots as keep the curve within ``tol`` of itself at
        equal parameters: Tiller's knot removal with its error bound (Piegl & Tiller 5.4,
        A5.8, and 9.4.4; :mod:`cagd.knots.removal`; the seeds do not treat it). A rational
        curve works in homogeneous coordinates with eq. 5.30's tolerance. A periodic
        curve comes back clamped (as :meth:`elevate`).

        Returns a :class:`cagd.knots.removal.KnotRemoval`: the new curve (``result``),
        the number of knots removed, the certified ``error_bound`` (<= tol) and the
        ``deviation`` measured at DEVIATION_SAMPLES parameters per knot span.

        Raises:
            CagdError: ``tol`` not a finite number >= 0."""
        from ..knots import removal as rm
        tol = _checks.nonnegative(tol, "tol")
        c = self.clamped()
        hom = c._hom
        htol = rm.homogeneous_tol(hom, tol) if c.is_rational else tol
        u, P, removed, bound = rm.remove_knots(c._u, hom[:, None, :], c.degree, htol)
        out = c._rebuild(P[:, 0, :], u)
        dev = self._deviation_from(c, out)
        bound = tol * bound / htol if htol > 0 else 0.0
        left = len(kv.distinct_with_multiplicities(out._u[c.degree:len(out._u) - c.degree], 0.0)[0]) - 2
        msg = f"{removed} knot(s) removed, {left} interior knot value(s) left"
        if self.periodic:
            msg += "; the periodic curve came back clamped"
        return rm.KnotRemoval(out, removed, min(bound, tol), dev, True, msg)

    def reduce_degree(self, tol: float) -> "DegreeReduction":
        """The curve one degree lower, within ``tol`` of this one at equal parameters if
        the shape allows: each Bezier piece reduced with its ends held and its convex-hull
        error bound, then Tiller's knot removal on the rest of the tolerance (Piegl &
        Tiller 5.6, A5.11; :mod:`cagd.knots.reduction`). A rational curve works in
        homogeneous coordinates (eq. 5.30's tolerance); a periodic one comes back clamped.

        Returns a :class:`cagd.knots.reduction.DegreeReduction`: ``result`` (degree p - 1),
        the certified ``error_bound``, the measured ``deviation``, ``converged`` when the
        bound is within tol (the reduced curve is returned either way).

        Raises:
            CagdError: ``tol`` not a finite number >= 0, degree 1 (nothing below it), a
                rational curve whose reduced weights would not be positive (its shape
                needs the degree)."""
        from ..knots import reduction as rd
        from ..knots import removal as rm
        tol = _checks.nonnegative(tol, "tol")
        if self.degree < 2:
            raise CagdError("degree: a degree-1 curve cannot be reduced further")
        c = self.clamped()
        breaks, nets = c.bezier_net()
        unit = rm.homogeneous_tol(c._hom, 1.0) if c.is_rational else 1.0   # homogeneous per model unit
        u, P, q, bound = rd.reduce_degree(breaks, nets[:, :, None, :], tol * unit)
        rd.check_weights(P, c.is_rational, c.degree)
        out = c._rebuild(P[:, 0, :], u, q)
        bound /= unit
        dev = self._deviation_from(c, out)
        ok = bool(bound <= tol)
        msg = (f"degree {c.degree} -> {q}, {len(out.control_points)} control points, within {bound:.3g}"
               if ok else f"degree {c.degree} -> {q}: the bound {bound:.3g} exceeds tol {tol:g} (measured "
               f"deviation {dev:.3g}); the shape needs degree {c.degree} there")
        return rd.DegreeReduction(out, float(bound), dev, ok, msg)

    def _deviation_from(self, c: "BSplineCurve", out: "BSplineCurve") -> float:
        """Largest |self(t) - out(t)| at DEVIATION_SAMPLES parameters per knot span of c
        (this curve clamped)."""
        from ..knots import removal as rm
        t = rm._span_samples(c._u, c.degree)
        return float(np.sqrt(((self(t) - out(t)) ** 2).sum(-1)).max())

    def _elevate_segments(self, times: int) -> "BSplineCurve":
        """Exact elevation of a clamped curve segment by segment: elevated Bezier nets
        joined at knots of multiplicity p + times."""
        p, q = self.degree, self.degree + times
        breaks, nets = self.bezier_net()
        E = elevation_matrix(p, times)
        up = np.einsum("ij,sjd->sid", E, nets)                       # (s, q+1, D)
        hom = np.concatenate([up[0, :1], up[:, 1:].reshape(-1, up.shape[2])])  # neighbours share an end
        mults = np.full(len(breaks), q)
        mults[0] = mults[-1] = q + 1
        return self._rebuild(hom, kv.from_multiplicities(breaks, mults), q)

    def reversed(self) -> "BSplineCurve":
        """The same point set traversed backwards: C_r(t) = C(a + b - t) (seed 000, 5.2.2
        symmetry, for B-splines with reflected knots)."""
        P, w = self.control_points[::-1], None if self.weights is None else self.weights[::-1]
        if self.periodic:
            p = self.degree
            P = np.roll(P, p, axis=0)
            w = None if w is None else np.roll(w, p)
        knots = kv.reflected(self.knots, *self.domain)
        if not self.periodic:
            lead, trail = kv.collapsed_ends(knots, self.degree)
            if lead or trail:
                stop = len(P) - trail
                knots, P = knots[lead:len(knots) - trail], P[lead:stop]
                w = None if w is None else w[lead:stop]
        return BSplineCurve(P, self.degree, knots, w, self.periodic)

    def reparametrized(self, start: float, end: float) -> "BSplineCurve":
        """Affine reparametrisation onto [start, end] (seed 004, 1.7): the knots are
        mapped, the control points kept."""
        start, end = _checks.scalar(start, "start"), _checks.scalar(end, "end")
        if not start < end:
            raise CagdError(f"start, end: need start < end, got [{start}, {end}]")
        a, b = self.domain
        knots = start + (self.knots - a) * ((end - start) / (b - a))
        knots[self.knots == a] = start      # the domain ends map exactly, not an ulp off
        knots[self.knots == b] = end
        return BSplineCurve(self.control_points, self.degree, knots, self.weights, self.periodic)

    # --- OCCT form ----------------------------------------------------------------------
    def occ_form(self) -> OccForm:
        """Poles (n, 3), weights, distinct knots, multiplicities, degree, periodic — what
        ``Geom_BSplineCurve`` takes. 2-D curves get z = 0. For a periodic curve the
        poles are the distinct control points, rolled by the seam shift of
        :func:`cagd.knots.occ_knots`, and the knots one period. Degrees above 25 (OCCT's
        maximum) raise CagdError: such curves do not convert to OCCT."""
        if self.dim > 3:
            raise CagdError(f"control_points: OCCT curves are 3-D at most, this one is {self.dim}-D")
        if self.degree > _checks.OCC_MAX_DEGREE:
            raise CagdError(f"degree: OCCT's maximum B-spline degree is {_checks.OCC_MAX_DEGREE} "
                            f"(Geom_BSplineCurve::MaxDegree()); this curve has degree {self.degree}")
        poles = np.zeros((len(self.control_points), 3))
        poles[:, :self.dim] = self.control_points
        w = None if self.weights is None else self.weights.copy()
        knots, mults, shift = kv.occ_knots(self.knots, self.periodic)
        if shift:
            poles = np.roll(poles, -shift, axis=0)
            w = None if w is None else np.roll(w, -shift)
        return OccForm(poles, w, knots, mults, self.degree, self.periodic)

    @classmethod
    def from_occ_form(cls, poles: ArrayLike, weights: Optional[ArrayLike], knots: ArrayLike,
                      multiplicities: ArrayLike, degree: int, periodic: bool = False,
                      dim: Optional[int] = None) -> "BSplineCurve":
        """The inverse of :meth:`occ_form`: the same curve from OCCT's poles, weights,
        distinct knots and multiplicities (``dim`` = 2 drops z). Weights all equal
        give a polynomial B-spline (the same curve). Raises CagdError on bad input."""
        P = _checks.points(poles, "poles", min_count=2)
        if dim is not None:
            P = P[:, :_checks.integer(dim, "dim", 1, P.shape[1])]
        degree = _checks.degree(degree, "degree", 1)
        t = kv.from_occ_knots(knots, multiplicities, degree, periodic)
        w = None if weights is None else _checks.weights(weights, len(P))
        if w is not None and np.all(w == w[0]):
            w = None
        return cls(P, degree, t, w, periodic)


def _boehm(u: np.ndarray, hom: np.ndarray, p: int, t: float) -> Tuple[np.ndarray, np.ndarray]:
    """One insertion of knot t (Boehm 1980; Piegl & Tiller A5.1 with r = 1),
    vectorized over the affected control points."""
    n = hom.shape[0]
    k = max(int(np.searchsorted(u, t, side="right")) - 1, p)   # u_k <= t < u_{k+1}
    s = int(np.count_nonzero(u == t))
    i = np.arange(k - p + 1, k - s + 1)
    alpha = ((t - u[i]) / (u[i + p] - u[i]))[:, None]
    new = np.empty((n + 1, hom.shape[1]))
    new[:k - p + 1] = hom[:k - p + 1]
    new[i] = alpha * hom[i] + (1.0 - alpha) * hom[i - 1]
    new[k - s + 1:] = hom[k - s:]
    return np.insert(u, k + 1, t), new


def _blossoms(knots: np.ndarray, degree: int, points: np.ndarray, args: np.ndarray) -> Optional[np.ndarray]:
    """Blossom values f(x_1, ..., x_p) (M, D) of the B-spline (knots, degree, points)
    at the sorted rows of ``args`` (M, p), each row p consecutive knots of some
    refinement of ``knots`` (then f(row) is a control point of the same curve on that
    refinement: knot insertion, Piegl & Tiller 5.3; Ramshaw's blossoming, seed 003,
    2.2.4).

    A row's old knots are consecutive old knots u_(a+1), ..., u_(a+p-t) and only its t
    new values y_1..y_t need work: with E^0_c = P_(a-t+c), c = 0..t, de Boor's step
    E^r_c = (1 - alpha) E^(r-1)_c + alpha E^(r-1)_(c+1),
    alpha = (y_r - u_(a-t+r+c)) / (u_(a-t+c+p+1) - u_(a-t+r+c)),
    gives E^t_0 = f(y_1..y_t, u_(a+1)..u_(a+p-t)). Every y lies in [u_a, u_(a+p-t+1)]
    (the old knots around the row), so every alpha is in [0, 1]: convex combinations
    only, as in Boehm's insertion (Oslo algorithm; Cohen, Lyche & Riesenfeld 1980),
    at any degree. Rows of p equal values at a knot of multiplicity p + 1 (a
    discontinuity) are ambiguous, either piece's control point: callers give clamped
    knots, where that happens only at the ends (the first and the last point). A de
    Boor triangle over all p arguments on one span extrapolates
    by up to (spread of the arguments / span width)^p instead: a degree-20 refinement
    by one knot was off by 1e-3. Vectorized over the rows with the same t; memory
    bounded by _ELEVATE_VALUES per chunk; wide points (surface rows, D > t + 1) go
    through the (t + 1)-wide coefficient rows. None when a row's neighbourhood leaves
    the control points (repeated knots at an unclamped end)."""
    u = np.asarray(knots, dtype=np.float64)
    P = np.asarray(points, dtype=np.float64)
    S = np.asarray(args, dtype=np.float64)
    n, p = P.shape[0], degree
    M = S.shape[0]
    out = np.empty((M, P.shape[1]))
    if M == 0:
        return out
    col = np.arange(p)
    new_value = np.ones((M, p), dtype=bool)
    new_value[:, 1:] = S[:, 1:] != S[:, :-1]
    occurrence = col - np.maximum.accumulate(np.where(new_value, col, 0), axis=1)
    left, right = np.searchsorted(u, S, side="left"), np.searchsorted(u, S, side="right")
    old = occurrence < right - left                         # a copy the old knot vector holds
    t = p - old.sum(axis=1)
    rows = np.arange(M)
    first = np.argmax(old, axis=1)                          # the first old argument (if any)
    last = p - 1 - np.argmax(old[:, ::-1], axis=1)          # the last one
    x0 = S[rows, first]
    old_x0 = np.count_nonzero(old & (S == x0[:, None]), axis=1)
    # the old part u_(a+1).. starts with the last old_x0 copies of x0 when it goes on
    # past x0 or new values follow it; with the first copies when new values precede a
    # single old value (or when the last copies would pass the last control point)
    a = right[rows, first] - old_x0 - 1
    single = x0 == S[rows, last]
    a = np.where(single & ((first > 0) | (a > n - 1)), left[rows, first] - 1, a)
    a = np.where(t < p, a, right[:, 0] - 1)                 # no old argument: the span holding all
    if np.any((a < t) | (a > n - 1)):
        # a row whose old neighbours are no control points of the curve (repeated knots
        # at a floating, unclamped end): the caller inserts one knot at a time
        return None
    for tg in np.unique(t):
        sel = np.flatnonzero(t == tg)
        if tg == 0:
            out[sel] = P[a[sel]]
            continue
        wide = P.shape[1] > tg + 1
        D = tg + 1 if wide else P.shape[1]
        step = max(1, _ELEVATE_VALUES // ((tg + 1) * D))
        for c0 in range(0, len(sel), step):
            rc = sel[c0:c0 + step]
            ac = a[rc]
            Y = S[rc][~old[rc]].reshape(len(rc), tg)
            base = ac[:, None] - tg
            local = P[base + np.arange(tg + 1)]                              # (c, t+1, D)
            level = np.broadcast_to(np.eye(tg + 1), (len(rc), tg + 1, tg + 1)) if wide else local
            for r in range(1, tg + 1):
                cc = np.arange(tg + 1 - r)
                lo, hi = u[base + r + cc], u[base + cc + p + 1]
                width = hi - lo
                alpha = np.where(width > 0, (Y[:, r - 1:r] - lo) / np.where(width > 0, width, 1.0), 0.0)
                level = (1.0 - alpha[..., None]) * level[:, :-1] + alpha[..., None] * level[:, 1:]
            out[rc] = np.einsum("ck,ckd->cd", level[:, 0], local) if wide else level[:, 0]
    return out


def _elevated_by_blossom(knots: np.ndarray, degree: int, points: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Full knots and control points of the clamped B-spline (knots, degree, points)
    raised to degree q = p + 1 with every distinct knot's multiplicity + 1, so the
    continuity C^(p-m) at a knot of multiplicity m is kept (Piegl & Tiller 5.5, A5.9).

    The degree-q blossom of a degree-p polynomial f is the symmetric average
    F(x_1, ..., x_q) = (1/q) sum_j f(x_1, ..., x_(j-1), x_(j+1), ..., x_q), and the
    elevated control points are Q_i = F(v_(i+1), ..., v_(i+q)) on the new knots v
    (Ramshaw; Prautzsch 1984, "Degree elevation of B-spline curves", CAGD 1). Dropping
    v_(i+1+j) leaves p consecutive knots of w_r = v without the indices = r (mod q),
    r = (i+1+j) mod q, a refinement of the old knots (each knot loses at most one of
    its m + 1 <= q copies), so every term is a convex blossom value
    (:func:`_blossoms`). No linear solve: a few ulps of the net per level at any
    degree, where Greville collocation's condition grows like 2^q. O(m q t^2 D) work
    for m new points and t <= p new arguments per term, memory bounded per chunk."""
    u = np.asarray(knots, dtype=np.float64)
    P = np.asarray(points, dtype=np.float64)
    p = degree
    q = p + 1
    vals, mults = kv.distinct_with_multiplicities(u, 0.0)
    v = np.repeat(vals, mults + 1)
    m = len(v) - q - 1
    keep = np.array([np.delete(np.arange(q), j) for j in range(q)])        # (q, p)
    step = max(1, _ELEVATE_VALUES // (q * p))
    out = np.empty((m, P.shape[1]))
    for c0 in range(0, m, step):
        idx = np.arange(c0, min(c0 + step, m))[:, None, None] + 1 + keep[None]   # (c, q, p) into v
        args = v[idx].reshape(-1, p)
        terms = _blossoms(u, p, P, args)
        if terms is None:       # cannot happen on clamped knots (every row is inside)
            raise CagdError("knots: degree elevation needs clamped knots")
        out[c0:c0 + step] = terms.reshape(-1, q, P.shape[1]).mean(axis=1)
    return v, out


def prime_bezier_nets(curves: Sequence[BSplineCurve]) -> None:
    """Compute and cache the Bezier nets (:meth:`BSplineCurve.bezier_net`) of many curves
    at once: one de Boor pass per degree and dimension (the same numbers as one curve at
    a time; :func:`cagd.curves.bezier_spans.bezier_spans_many`)."""
    groups: Dict[Tuple[int, int], List[BSplineCurve]] = {}
    for c in curves:
        if 0 not in c._spans and c._hom.shape[1] <= c.degree + 1:
            groups.setdefault((c.degree, c._hom.shape[1]), []).append(c)
    for (p, _), cs in groups.items():
        unique = list({id(c): c for c in cs}.values())
        for c, (breaks, nets) in zip(unique, bezier_spans_many([c._u for c in unique], p, [c._hom for c in unique])):
            c._spans[0] = BernsteinSpans(breaks, nets)
