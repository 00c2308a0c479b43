"""Ranks within groups laid end to end: the one implementation of a gather-offset idiom
(pairs of a list with each member's list, strips of segments, children of boxes)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def ranks(counts: ArrayLike) -> np.ndarray:
    """For groups of ``counts`` elements laid end to end, each element's index within its
    group: [2, 0, 3] -> [0, 1, 0, 1, 2] (counts >= 0, integers)."""
    c = np.asarray(counts, dtype=np.intp)
    return np.arange(int(c.sum())) - np.repeat(np.cumsum(c) - c, c)
