"""Results are values: frozen dataclasses whose numpy arrays are read-only."""
from __future__ import annotations

import dataclasses
from typing import TypeVar

import numpy as np

_T = TypeVar("_T")


def readonly(value: _T) -> _T:
    """``value`` with its write flag cleared when it is a numpy array, or with the arrays
    in it when it is a tuple (the one place results make their arrays read-only);
    anything else is returned unchanged."""
    if isinstance(value, np.ndarray):
        value.setflags(write=False)
    elif isinstance(value, tuple):
        for item in value:
            readonly(item)
    return value


class ReadOnlyArrays:
    """Mixin for frozen dataclasses: every array field (and array in a tuple field) is
    made read-only on creation, and again when unpickled (a result sent back by a
    worker process or a Dask task: pickle restores writable arrays)."""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            readonly(getattr(self, f.name))

    def __setstate__(self, state: dict) -> None:
        for name, value in state.items():
            object.__setattr__(self, name, value)
        self.__post_init__()
