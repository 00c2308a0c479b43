"""Hypothesis strategies for hostile input (issue 14): the classes of value a user or a
file can hand the toolkit. Each strategy mixes well-formed values with the bad ones
(non-finite, empty, wrong shape, wrong type, extreme scale, huge counts), so a test
over it exercises both the answers and the refusals."""
from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

#: scales from the smallest normal double to near the largest (coordinates 1e-300 to 1e300)
SCALES = st.sampled_from([1.0, 1.0, 1.0, 1e-300, 1e-100, 1e-12, 1e-3, 1e3, 1e12, 1e100, 1e155, 1e300])
#: translations of a well-formed object far from the origin
OFFSETS = st.sampled_from([0.0, 0.0, 1e6, -1e12, 1e155])

finite = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False, width=64)
special = st.sampled_from([np.nan, np.inf, -np.inf, 1e308, -1e308, 5e-324, 0.0, -0.0])

#: values that are not numbers at all, or numbers Python cannot turn into a float64
non_numbers = st.sampled_from([None, "1.0", "abc", b"\x00", [], {}, object(), 1j, 10 ** 400, -10 ** 400,
                               float("nan"), True])

#: integers for counts, degrees and orders: small, zero, negative, huge, and non-integers
counts = st.one_of(st.integers(0, 12), st.sampled_from([-1, -10 ** 18, 25, 26, 60, 100, 171, 1000, 10 ** 6,
                                                        10 ** 18, 10 ** 400]),
                   st.sampled_from([1.5, "3", None, np.nan, np.int64(2), np.float64(3.0)]))

#: tolerances (a distance): normal, tiny, zero, negative, non-finite, the wrong type
tolerances = st.one_of(st.sampled_from([None, 1e-6, 1e-9, 1e-3]),
                       st.sampled_from([0.0, -1e-6, 1e-300, 1e-17, np.nan, np.inf, "1e-6", 10 ** 400]))


@st.composite
def point_arrays(draw, min_count: int = 0, max_count: int = 8, dims=(0, 1, 2, 3, 4)):
    """(n, d) arrays, mostly well formed, sometimes with a non-finite entry, a wrong
    shape (1-D, 3-D, ragged) or at an extreme scale."""
    kind = draw(st.sampled_from(["good"] * 6 + ["special", "flat", "deep", "ragged", "empty", "object",
                                                "integer"]))
    n = draw(st.integers(min_count, max_count))
    d = draw(st.sampled_from(dims))
    base = np.array(draw(st.lists(finite, min_size=n * d, max_size=n * d)), dtype=float).reshape(n, d)
    base = base * draw(SCALES) + draw(OFFSETS)
    if kind == "special" and base.size:
        flat = base.ravel()
        flat[draw(st.integers(0, flat.size - 1))] = draw(special)
        return flat.reshape(base.shape)
    if kind == "flat":
        return base.ravel()
    if kind == "deep":
        return base[None]
    if kind == "ragged":
        return [list(row) for row in base] + [[1.0]]
    if kind == "empty":
        return np.empty((0, d))
    if kind == "object":
        return [["x"] * d for _ in range(n)]
    if kind == "integer":
        return [[10 ** 400] * d for _ in range(n)]
    return base


@st.composite
def knot_vectors(draw, count: int):
    """Knot vectors of ``count`` entries: clamped and increasing, or hostile (decreasing,
    non-finite, spans 1e-300 wide, values near 1e300)."""
    kind = draw(st.sampled_from(["good"] * 4 + ["tiny", "huge", "decreasing", "special", "short"]))
    inner = np.sort(np.array(draw(st.lists(st.floats(0.0, 1.0), min_size=count, max_size=count))))
    if kind == "tiny":
        return inner * 1e-300
    if kind == "huge":
        return inner * 1e300
    if kind == "decreasing":
        return inner[::-1]
    if kind == "special" and count:
        inner[draw(st.integers(0, count - 1))] = draw(special)
    if kind == "short":
        return inner[: max(count - 2, 0)]
    return inner
