"""Helpers shared by the benchmarks: best-of-N timing and OCCT arrays through OCP."""
from __future__ import annotations

import time
from typing import Callable, Tuple

import numpy as np


def best(fn: Callable[[], np.ndarray], repeat: int) -> Tuple[float, np.ndarray]:
    """Best wall time of ``repeat`` calls (after one warm-up call) and the last result."""
    out = fn()
    fastest = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        fastest = min(fastest, time.perf_counter() - t0)
    return fastest, out


def occ_knots(distinct, multiplicities):
    """OCCT 1-based knot and multiplicity arrays."""
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal

    k = TColStd_Array1OfReal(1, len(distinct))
    m = TColStd_Array1OfInteger(1, len(distinct))
    for i, (x, c) in enumerate(zip(distinct, multiplicities), 1):
        k.SetValue(i, float(x))
        m.SetValue(i, int(c))
    return k, m
