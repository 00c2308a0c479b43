"""Periodic (closed) parameter directions: one implementation of the seam arithmetic.

A periodic direction with domain [a, a + T) is a circle: t and t + k T name the same
point for every integer k. :func:`wrap` reduces parameters into one period and
:func:`wrapped_difference` gives the shortest signed step between two of them across
the seam. Both are vectorized (numpy broadcasting over t, a and the period).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def wrap(t: ArrayLike, a: ArrayLike, period: ArrayLike) -> np.ndarray:
    """t reduced into [a, a + period): a + mod(t - a, period).

    In floating point mod(t - a, period) rounds to ``period`` for t just below a (and
    a + mod(...) may round up to a + period for t just below the seam); that value is
    the seam itself, so it is returned as a (the same point). Integer input stays
    integer (e.g. parameter bins).
    """
    a = np.asarray(a)
    end = a + period
    out = a + np.mod(np.subtract(t, a), period)
    return np.where(out >= end, a, out)


def wrapped_difference(t1: ArrayLike, t0: ArrayLike, period: ArrayLike) -> np.ndarray:
    """The step from t0 to t1 across the seam: t1 - t0 + k period in [-period/2, period/2]
    (the shortest of the equivalent steps; the sign says the direction)."""
    half = 0.5 * np.asarray(period, dtype=np.float64)
    return np.mod(np.subtract(t1, t0) + half, period) - half


def clamped(t: ArrayLike, lo: ArrayLike, hi: ArrayLike, periodic: ArrayLike) -> np.ndarray:
    """Parameters t (..., k) clamped into [lo, hi], or wrapped into [lo, hi) in the
    directions flagged ``periodic`` (k,); the wrap is computed only when one is."""
    inside = np.minimum(np.maximum(t, lo), hi)           # (np.clip costs 6 us a call)
    if not np.any(periodic):
        return inside
    return np.where(periodic, wrap(t, lo, np.subtract(hi, lo)), inside)


def step_across(t1: ArrayLike, t0: ArrayLike, period: ArrayLike, periodic: ArrayLike) -> np.ndarray:
    """t1 - t0, across the seam (:func:`wrapped_difference`) in the directions flagged
    ``periodic``; computed plainly when none is."""
    if not np.any(periodic):
        return np.subtract(t1, t0)
    return np.where(periodic, wrapped_difference(t1, t0, period), np.subtract(t1, t0))
