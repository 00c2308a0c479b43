"""Adaptive Gauss-Legendre quadrature on many intervals at once: the one halving rule of
the engine (arc length, trimmed-face areas and volumes).

Every interval is split in halves; an interval is done when its two halves agree with
the whole within its share of the bound (its length over the total length), and the
whole integral is done as soon as the error estimates of all intervals, done and live,
sum to the bound (a global criterion: intervals whose halves differ by rounding only
no longer keep the rule going). Numerical Recipes 4.6; Piessens et al., QUADPACK
(1983), 2.2 (the global error test).
"""
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

#: the rule on (lo, hi, tags): the integral over each interval (tags: an integer per
#: interval, carried to its halves, e.g. which curve it lies on)
Rule = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Quadrature:
    """The integral ``value``, its ``error`` estimate (sum of |halves - whole| over the
    final intervals), ``converged`` (the estimate is within the bound), a ``message``
    and the number of ``intervals`` evaluated."""
    value: float
    error: float
    converged: bool
    message: str
    intervals: int


def adaptive(rule: Rule, lo: np.ndarray, hi: np.ndarray, tags: Optional[np.ndarray], bound: Optional[float],
             rel_tol: float, max_levels: int, max_intervals: int, what: str = "", floor: float = 0.0) -> Quadrature:
    """Integrate by halving (see the module docstring) from the intervals ``lo`` to ``hi``.

    ``bound`` is the absolute error goal; None: ``rel_tol`` times the sum of |rule| over
    the starting intervals, at least ``floor`` (an integrand that vanishes: no goal of
    rounding size). At most ``max_levels`` halvings and ``max_intervals`` live
    intervals: beyond them the value comes back unconverged with the estimate reached
    (``what``: the names of those two bounds, "LEVELS_NAME, INTERVALS_NAME")."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    tags = np.zeros(len(lo), dtype=int) if tags is None else np.asarray(tags)
    if not len(lo):
        return Quadrature(0.0, 0.0, True, "no interval", 0)
    whole = rule(lo, hi, tags)
    if bound is None:
        bound = max(rel_tol * float(np.abs(whole).sum()), floor)
    span = float((hi - lo).sum())
    if not bound > 0.0 or not span > 0.0:               # a zero integrand: nothing to resolve
        return Quadrature(float(whole.sum()), 0.0, True, "a zero integral", len(lo))
    total, err, pending, evaluated = 0.0, 0.0, 0.0, len(lo)
    names = what.split(", ") + ["", ""] if what else ["", ""]
    why = f"after {max_levels} halvings{names[0] and ' (' + names[0] + ')'}"
    for _ in range(max_levels):
        mid = 0.5 * (lo + hi)
        left, right = rule(lo, mid, tags), rule(mid, hi, tags)
        evaluated += 2 * len(lo)
        pair = left + right
        diff = np.abs(pair - whole)
        if err + float(diff.sum()) <= bound:               # the global test
            value, error = total + float(pair.sum()), err + float(diff.sum())
            return Quadrature(value, error, True, f"within {bound:.3g}", evaluated)
        done = diff <= bound * (hi - lo) / span
        total += float(pair[done].sum())
        err += float(diff[done].sum())
        keep = ~done
        if not keep.any():                                # every share met (rounding in the sum)
            return Quadrature(total, err, True, f"within {bound:.3g}", evaluated)
        pending = float(diff[keep].sum())
        if 2 * int(keep.sum()) > max_intervals:
            whole = pair[keep]
            why = f"after {evaluated} intervals{names[1] and ' (' + names[1] + ')'}"
            break
        lo, hi, tags = np.concatenate([lo[keep], mid[keep]]), np.concatenate([mid[keep], hi[keep]]), \
            np.concatenate([tags[keep], tags[keep]])
        whole = np.concatenate([left[keep], right[keep]])
    estimate = err + pending
    return Quadrature(total + float(whole.sum()), estimate, False,
                      f"not within {bound:.3g} {why}; error estimate {estimate:.3g}", evaluated)


__all__ = ["Quadrature", "adaptive"]
