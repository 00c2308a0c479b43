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
    from cagd.occ.compat import Array1OfInteger, Array1OfReal

    k = Array1OfReal(1, len(distinct))
    m = Array1OfInteger(1, len(distinct))
    for i, (x, c) in enumerate(zip(distinct, multiplicities), 1):
        k.SetValue(i, float(x))
        m.SetValue(i, int(c))
    return k, m


def report(rows, size: float, width: int = 48, engine_label: str = "engine / peer") -> bool:
    """Print the table of (name, seconds, points, result, reference) rows: throughput in
    M points/s, the first row's rate over each row's, and the max deviation from the
    reference relative to ``size``. Returns whether every deviation is <= 1e-12."""
    engine_rate = rows[0][2] / rows[0][1]
    col = max(len(engine_label), 14)
    print(f"{'implementation':{width}s} {'M points/s':>11s} {engine_label:>{col}s} {'max deviation':>14s}")
    ok = True
    for name, sec, npts, out, reference in rows:
        rate = npts / sec
        dev = ""
        if out is not None and reference is not None:
            d = float(np.abs(np.asarray(out) - reference).max() / size)
            ok &= d <= 1e-12
            dev = f"{d:.1e}"
        print(f"{name:{width}s} {rate / 1e6:11.2f} {engine_rate / rate:{col}.2f} {dev:>14s}")
    return ok
