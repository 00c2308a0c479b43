"""Knot vector algorithms (Piegl & Tiller ch. 2, 9; seed 000, 5.3.2 knot types)."""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .._checks import MAX_SAMPLES, degree as _degree, finite_array, integer, scalar
from .._deprecation import renamed
from ..errors import CagdError


def _count_degree(count: int, degree: int, start: float, end: float) -> Tuple[int, int, float, float]:
    p = _degree(degree, "degree", 0)
    n = integer(count, "count", p + 1, MAX_SAMPLES)
    a, b = scalar(start, "start"), scalar(end, "end")
    if not a < b:
        raise CagdError(f"start, end: need start < end, got [{a}, {b}]")
    return n, p, a, b


def _vector(knots: ArrayLike, name: str, min_size: int = 1) -> np.ndarray:
    u = finite_array(knots, name, ndim=1)
    if u.shape[0] < min_size:
        raise CagdError(f"{name}: need at least {min_size} values, got {u.shape[0]}")
    return u


def clamped_uniform(count: int, degree: int, start: float = 0.0, end: float = 1.0) -> np.ndarray:
    """Open uniform (clamped) knots: degree+1 copies of ``start`` and ``end``,
    equally spaced interior knots (seed 000, 5.3.2 "open uniform").

    Raises:
        CagdError: count not in [degree + 1, MAX_SAMPLES], a bad degree, start >= end."""
    count, degree, start, end = _count_degree(count, degree, start, end)
    inner = np.linspace(start, end, count - degree + 1)
    return np.concatenate([np.full(degree, start), inner, np.full(degree, end)])


def uniform(count: int, degree: int, start: float = 0.0, end: float = 1.0) -> np.ndarray:
    """Floating uniform knots with domain [u_p, u_n] = [start, end] (seed 000, 5.3.2).

    Raises:
        CagdError: count not in [degree + 1, MAX_SAMPLES], a bad degree, start >= end."""
    count, degree, start, end = _count_degree(count, degree, start, end)
    h = (end - start) / (count - degree)
    return start + h * np.arange(-degree, count + 1, dtype=np.float64)


def averaged(params: ArrayLike, degree: int) -> np.ndarray:
    """Clamped knots by averaging parameters (Piegl & Tiller eq. 9.8).

    Raises:
        CagdError: parameters not a finite 1-D array of at least degree + 1 values."""
    degree = _degree(degree, "degree", 1)
    params = _vector(params, "params", degree + 1)
    n = len(params)
    c = np.cumsum(np.concatenate([[0.0], params]))
    inner = (c[1 + degree:n] - c[1:n - degree]) / degree
    return np.concatenate([np.full(degree + 1, params[0]), inner, np.full(degree + 1, params[-1])])


def from_multiplicities(distinct: ArrayLike, multiplicities: ArrayLike) -> np.ndarray:
    """Expand distinct knots and multiplicities into the full (flat) knot vector.

    Raises:
        CagdError: shapes that differ, multiplicities not integers >= 0, more than
            MAX_SAMPLES knots in all."""
    t = finite_array(distinct, "distinct", ndim=1)
    m = finite_array(multiplicities, "multiplicities", ndim=1)
    if m.shape != t.shape:
        raise CagdError(f"multiplicities: need one per distinct knot ({t.size}), got shape {m.shape}")
    if np.any(m < 0) or np.any(m != np.round(m)) or m.sum() > MAX_SAMPLES:
        raise CagdError(f"multiplicities: must be integers >= 0, at most MAX_SAMPLES = {MAX_SAMPLES} in all")
    return np.repeat(t, m.astype(np.intp))


KNOT_TOL = 0.0      # default of distinct_with_multiplicities: only equal knots merge


def distinct_with_multiplicities(knots: ArrayLike, param_tol: float = KNOT_TOL, *,
                                 tol: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray]:
    """Distinct knot values and their multiplicities: consecutive values at most
    ``param_tol`` apart (absolute, in parameter units) merge. ``tol`` is the deprecated
    name of ``param_tol`` (one release; ``tol`` is a distance in model units in cagd)."""
    if tol is not None:
        param_tol = renamed("distinct_with_multiplicities", "tol", "param_tol", tol, param_tol, KNOT_TOL,
                            "a knot tolerance is in parameter space")
    knots = _vector(knots, "knots")
    param_tol = scalar(param_tol, "param_tol")
    if param_tol < 0:
        raise CagdError(f"param_tol: must be >= 0, got {param_tol}")
    new = np.concatenate([[True], np.diff(knots) > param_tol])
    starts = np.flatnonzero(new)
    mults = np.diff(np.append(starts, len(knots)))
    return knots[starts].copy(), mults


def validate(knots: ArrayLike, degree: int, count: int, name: str = "knots") -> np.ndarray:
    """Check a full non-periodic knot vector for ``count`` control points.

    Raises CagdError for a wrong length, NaN/inf, decreasing values, an end
    multiplicity above degree+1, an interior multiplicity above degree, or an
    empty domain [u_p, u_n].
    """
    degree = _degree(degree, "degree", 0)
    count = integer(count, "count", 1)
    u = finite_array(knots, name, ndim=1)
    expected = count + degree + 1
    if u.shape[0] != expected:
        raise CagdError(f"{name}: expected {expected} values (len(control_points) + degree + 1 = "
                        f"{count} + {degree} + 1), got {u.shape[0]}")
    if (u[1:] < u[:-1]).any():
        _non_decreasing(u, name)
    if not u[degree] < u[count]:
        raise CagdError(f"{name}: empty domain [knots[{degree}], knots[{count}]] = [{u[degree]}, {u[count]}]")
    # a run of degree + 2 equal knots anywhere, or of degree + 1 strictly inside the domain
    head = u[:count + 1]                     # u[i] starts a run of degree + 1 equal knots if u[i] == u[i + degree]
    if (u[degree + 1:] == head[:-1]).any() or \
            ((u[degree:] == head) & (head > u[degree]) & (head < u[count])).any():
        _multiplicity_error(u, degree, count, name)
    return u


def validate_period(knots: ArrayLike, count: int, degree: int, name: str = "knots") -> np.ndarray:
    """Check one period t_0..t_n of a periodic knot vector (n = ``count``)."""
    degree = _degree(degree, "degree", 0)
    count = integer(count, "count", 1)
    t = finite_array(knots, name, ndim=1)
    if t.shape[0] != count + 1:
        raise CagdError(f"{name}: a periodic curve with {count} control points takes one period of "
                        f"{count + 1} knots, got {t.shape[0]}")
    _non_decreasing(t, name)
    if not t[0] < t[-1]:
        raise CagdError(f"{name}: the period is empty (knots[0] == knots[-1] = {t[0]})")
    # multiplicity of the seam counts knots at both ends of the period once
    d, m = distinct_with_multiplicities(t)
    m = m.copy()
    if len(m) > 1:
        m[0] += m[-1] - 1
        m[-1] = m[0]
    if m.max() > degree:
        raise CagdError(f"{name}: a knot has multiplicity {m.max()} > degree = {degree} in a periodic curve")
    return t


def reflected(knots: np.ndarray, start: float, end: float) -> np.ndarray:
    """The knots of C(start + end - t), the curve traversed backwards: t -> start + end - t
    in reverse order, the domain ends mapped exactly (seed 000, 5.2.2 symmetry)."""
    old = knots[::-1]
    out = (start + end) - old
    out[old == start], out[old == end] = end, start
    return out


def collapsed_ends(knots: np.ndarray, degree: int) -> Tuple[int, int]:
    """How many knots beyond degree + 1 equal the first and the last knot: spans shorter
    than a rounding step at an end, which :func:`reflected` rounds onto the end (a span of
    1.2e-16 next to 0 on a domain ending at -3.016, seen in 11752.stp). Their basis
    functions vanish on the domain, so dropping those knots and as many control points at
    that end is exact for the knot vector as rounded."""
    lead = int(np.searchsorted(knots, knots[0], side="right")) - (degree + 1)
    trail = len(knots) - int(np.searchsorted(knots, knots[-1], side="left")) - (degree + 1)
    return max(lead, 0), max(trail, 0)


def _multiplicity_error(u: np.ndarray, degree: int, count: int, name: str) -> None:
    """Raise for the knot of :func:`validate` whose multiplicity is too high."""
    values, mults = distinct_with_multiplicities(u)
    if mults.max() > degree + 1:
        raise CagdError(f"{name}: a knot has multiplicity {mults.max()} > degree + 1 = {degree + 1}")
    interior = (values > u[degree]) & (values < u[count]) & (mults > degree)
    i = int(np.argmax(interior))
    raise CagdError(f"{name}: interior knot {values[i]} has multiplicity {mults[i]} > degree = "
                    f"{degree} (the curve would break apart there)")


def _non_decreasing(u: np.ndarray, name: str) -> None:
    bad = np.flatnonzero(np.diff(u) < 0)
    if bad.size:
        i = int(bad[0])
        raise CagdError(f"{name}: must be non-decreasing ({name}[{i + 1}]={u[i + 1]} < {name}[{i}]={u[i]})")


def periodic_extend(period: np.ndarray, degree: int) -> np.ndarray:
    """Unwrap one period t_0..t_n into the full vector u_k = t_{k-p} (k = 0..n+2p),
    continued by the period T = t_n - t_0 on both sides. With control points
    P_0..P_{n-1}, P_0..P_{p-1} the curve on [t_0, t_n] is the periodic curve; this
    is also OCCT's periodic convention (for a uniform cubic, p(t_0) = (P0+4P1+P2)/6,
    seed 000, 5.3.2).

    Raises:
        CagdError: not a finite non-decreasing period of at least degree + 1 spans' knots."""
    degree = _degree(degree, "degree", 0)
    period = _vector(period, "period", 2)
    _non_decreasing(period, "period")
    n = len(period) - 1
    if n < degree or not period[0] < period[-1]:
        raise CagdError(f"period: need a non-empty period of at least degree + 1 = {degree + 1} knots, "
                        f"got {n + 1}")
    T = period[-1] - period[0]
    left = period[n - degree:n] - T
    right = period[1:degree + 1] + T
    # copies of the seam knot map exactly onto t_0 / t_n, not an ulp away
    left[period[n - degree:n] == period[n]] = period[0]
    right[period[1:degree + 1] == period[0]] = period[n]
    return np.concatenate([left, period, right])


def unwrapped_index(count: int, degree: int, periodic: bool) -> np.ndarray:
    """Which of ``count`` control points stand at each place of the sequence that goes
    with :func:`periodic_extend`: P_0..P_{n-1}, P_0..P_{p-1} when periodic, else
    P_0..P_{n-1}."""
    return np.concatenate([np.arange(count), np.arange(degree)]) if periodic else np.arange(count)


def greville(knots: np.ndarray, degree: int) -> np.ndarray:
    """Greville abscissae: averages of degree consecutive knots (Piegl & Tiller 9.2).

    Raises:
        CagdError: knots not a finite 1-D array of at least degree + 2 values."""
    degree = _degree(degree, "degree", 0)
    knots = _vector(knots, "knots", degree + 2)
    n = len(knots) - degree - 1
    if degree == 0:
        return 0.5 * (knots[:-1] + knots[1:])
    c = np.cumsum(np.concatenate([[0.0], knots[1:]]))
    return (c[degree:degree + n] - c[:n]) / degree


def find_span(knots: np.ndarray, degree: int, t: np.ndarray, count: int) -> np.ndarray:
    """Span index i with u_i <= t < u_{i+1}, restricted to p <= i <= n-1 so that the
    domain end u_n falls into the last non-empty span (Piegl & Tiller A2.1).

    Raises:
        CagdError: knots or t not finite, count and degree not matching len(knots)."""
    degree = _degree(degree, "degree", 0)
    knots = _vector(knots, "knots", 2)
    count = integer(count, "count", degree + 1, len(knots) - degree - 1)
    t = finite_array(t, "t")
    span = np.clip(np.searchsorted(knots, t, side="right") - 1, degree, count - 1)
    # a span must be non-empty: step back over repeated knots at the right end
    last = count - 1
    while last > degree and knots[last] == knots[last + 1]:
        last -= 1
    return np.minimum(span, last)


def is_clamped(knots: ArrayLike, degree: int) -> bool:
    """Whether a full knot vector has degree + 1 equal knots at both ends (open, clamped)."""
    degree = _degree(degree, "degree", 0)
    u = _vector(knots, "knots", degree + 1)
    return bool(np.all(u[:degree + 1] == u[0]) and np.all(u[-degree - 1:] == u[-1]))


def occ_knots(knots: ArrayLike, periodic: bool) -> Tuple[np.ndarray, np.ndarray, int]:
    """Engine knots -> OCCT's (distinct knots, multiplicities, pole shift).

    Non-periodic: the full vector, shift 0. Periodic (one period t_0..t_n): OCCT
    counts the seam multiplicity once over both ends, and reads the period as if
    t_0 were simple with every other seam copy at the end, so its pole 0 is the
    engine's control point ``shift`` = (copies of t_0 at the start) - 1 (checked
    against OCCT's own evaluator in tests/occ)."""
    knots = _vector(knots, "knots")
    distinct, mults = distinct_with_multiplicities(knots)
    mults = mults.astype(int)
    if not periodic:
        return distinct, mults, 0
    mults[0] = mults[-1] = mults[0] + mults[-1] - 1
    return distinct, mults, int(mults.size and np.count_nonzero(knots == knots[0]) - 1)


def from_occ_knots(distinct: ArrayLike, multiplicities: ArrayLike, degree: int, periodic: bool,
                   name: str = "knots", mult_name: str = "multiplicities") -> np.ndarray:
    """OCCT's (distinct knots, multiplicities) -> the engine's knots: the full vector,
    or for a periodic B-spline one period with t_0 simple and the seam's other copies
    at the end, so that OCCT's poles are the engine's control points unshifted
    (the inverse of :func:`occ_knots`). Raises CagdError for mismatched lengths,
    non-increasing distinct knots or multiplicities out of [1, degree + 1]."""
    t = finite_array(distinct, name)
    m = np.asarray(multiplicities)
    if t.ndim != 1 or t.size < 2:
        raise CagdError(f"{name}: need at least 2 distinct knots, got shape {t.shape}")
    if m.shape != t.shape:
        raise CagdError(f"{mult_name}: need one multiplicity per distinct knot ({t.size}), got shape {m.shape}")
    if not (t[1:] > t[:-1]).all():
        raise CagdError(f"{name}: distinct knots must be strictly increasing")
    if m.dtype.kind not in "iuf" or not ((m >= 1) & (m <= degree + 1)).all() or \
            (m.dtype.kind == "f" and not (m == np.round(m)).all()):
        raise CagdError(f"{mult_name}: must be integers in [1, degree + 1 = {degree + 1}], got {m.tolist()}")
    m = m.astype(np.intp)
    if periodic:
        if m[0] != m[-1]:
            raise CagdError(f"{name}: a periodic B-spline needs equal first and last multiplicities, "
                            f"got {m[0]} and {m[-1]}")
        m[0] = 1
    return np.repeat(t, m)          # at most (degree + 1) * len(t) values (from_multiplicities)
