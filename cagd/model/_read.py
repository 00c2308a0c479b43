"""Typed readers for the JSON model format: every failure is a :class:`ModelError`
whose ``path`` is the JSON path of the offending value (``$.objects[2].knots[4]``)."""
from __future__ import annotations

import difflib
import json
import re
from typing import Any, Iterable, Optional, Sequence, Tuple

import numpy as np

from .._validate import check_name
from ..errors import CagdError

MAX_DEPTH = 100          # nesting limit of a document (models need about 10 levels)
MAX_INT_DIGITS = 4300    # digits of a JSON integer (Python's int/str conversion limit, sys.int_info)
_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class ModelError(CagdError):
    """An invalid model document. ``path`` is the JSON path of the bad value
    (``$`` for the whole document), ``reason`` the problem; ``str(error)`` is
    ``"<path>: <reason>"``."""

    def __init__(self, path: str, reason: str):
        self.path, self.reason = path, reason
        super().__init__(f"{path}: {reason}")

    def __reduce__(self):
        return type(self), (self.path, self.reason)


class NonFinite:
    """What ``parse_constant`` makes of the non-JSON literals NaN, Infinity, -Infinity;
    rejected with its path by :func:`check_tree`."""

    def __init__(self, literal: str):
        self.literal = literal

    def __repr__(self) -> str:
        return self.literal


class HugeInteger:
    """What ``parse_int`` makes of an integer literal of more than MAX_INT_DIGITS digits
    (Python refuses to convert it: a ValueError); rejected with its path by :func:`check_tree`."""

    def __init__(self, literal: str):
        self.digits = len(literal.lstrip("-"))

    def __repr__(self) -> str:
        return f"<integer of {self.digits} digits>"


def parse_int(literal: str) -> Any:
    """A JSON integer literal as an int, or a HugeInteger marker when too long."""
    if len(literal.lstrip("-")) > MAX_INT_DIGITS:
        return HugeInteger(literal)
    return int(literal)


class JsonObject(dict):
    """A parsed JSON object remembering keys that occurred more than once."""
    duplicates: Tuple[str, ...] = ()


def object_pairs(pairs) -> JsonObject:
    obj = JsonObject()
    dups = []
    for key, value in pairs:
        if key in obj and key not in dups:
            dups.append(key)
        obj[key] = value
    obj.duplicates = tuple(dups)
    return obj


def key_path(path: str, key: str) -> str:
    return f"{path}.{key}" if _IDENT.match(key) else f"{path}[{json.dumps(key)}]"


def show(value: Any, limit: int = 40) -> str:
    """A short JSON rendering of ``value`` for messages."""
    if isinstance(value, (NonFinite, HugeInteger)):
        return repr(value)
    try:
        text = json.dumps(value, allow_nan=True, default=repr)
    except (TypeError, ValueError, RecursionError):
        text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def kind(value: Any) -> str:
    """The JSON type name of ``value``."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, (list, tuple)):
        return "an array"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def check_tree(value: Any, path: str = "$") -> None:
    """Reject what is not plain JSON data, depth first in document order: NaN/Infinity
    literals or non-finite floats, duplicate keys, non-string keys, other Python
    types, nesting deeper than MAX_DEPTH (which also stops cyclic containers)."""
    stack = [(value, path, 0)]
    while stack:
        v, p, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise ModelError(p, f"nested more than {MAX_DEPTH} levels deep")
        if isinstance(v, HugeInteger):
            raise ModelError(p, f"an integer of {v.digits} digits; at most {MAX_INT_DIGITS} are read")
        if isinstance(v, NonFinite) or (isinstance(v, float) and not np.isfinite(v)):
            raise ModelError(p, f"{show(v)} is not allowed: numbers must be finite "
                                f"(NaN and Infinity are not JSON)")
        if isinstance(v, dict):
            for key in v:
                if not isinstance(key, str):
                    raise ModelError(p, f"object keys must be strings, got {key!r}")
            for key in getattr(v, "duplicates", ()):
                raise ModelError(key_path(p, key), "duplicate key (a JSON object names each key once)")
            stack.extend((v[k], key_path(p, k), depth + 1) for k in reversed(list(v)))
        elif isinstance(v, (list, tuple)):
            stack.extend((x, f"{p}[{i}]", depth + 1) for i, x in reversed(list(enumerate(v))))
        elif not (v is None or isinstance(v, (str, bool, int, float))):
            raise ModelError(p, f"not a JSON value (a Python {type(v).__name__})")


def suggest(word: str, options: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


# --- scalars ------------------------------------------------------------------------------
def number(value: Any, path: str, what: str = "a number") -> float:
    """A finite JSON number (not a boolean) as a float."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(path, f"must be {what}, got {show(value)}")
    try:
        x = float(value)
    except OverflowError:
        raise ModelError(path, f"number too large for float64: {show(value)}") from None
    if not np.isfinite(x):
        raise ModelError(path, f"must be finite, got {show(value)}")
    return x


def positive(value: Any, path: str) -> float:
    x = number(value, path, "a positive number")
    if not x > 0.0:
        raise ModelError(path, f"must be a positive number, got {show(value)}")
    return x


def integer(value: Any, path: str, minimum: int = 1) -> int:
    """A JSON integer >= minimum (3.0 and true are not integers here)."""
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ModelError(path, f"must be an integer >= {minimum}, got {show(value)}")
    return int(value)


def boolean(value: Any, path: str) -> bool:
    if not isinstance(value, bool):
        raise ModelError(path, f"must be true or false, got {show(value)}")
    return value


def string(value: Any, path: str) -> str:
    if not isinstance(value, str):
        raise ModelError(path, f"must be a string, got {show(value)}")
    return value


def name(value: Any, path: str) -> str:
    """An entry name as it can go into a STEP/IGES file (:func:`cagd._validate.check_name`)."""
    s = string(value, path)
    try:
        return check_name(s, "name")
    except CagdError as exc:
        raise ModelError(path, str(exc).split(": ", 1)[1]) from None


def choice(value: Any, path: str, options: Sequence[str]) -> str:
    if not isinstance(value, str) or value not in options:
        hint = suggest(value, options) if isinstance(value, str) else ""
        raise ModelError(path, f"must be one of {', '.join(json.dumps(o) for o in options)}, "
                               f"got {show(value)}{hint}")
    return value


# --- arrays -------------------------------------------------------------------------------
def array(value: Any, path: str, what: str, min_count: int = 0) -> list:
    if not isinstance(value, (list, tuple)):
        raise ModelError(path, f"must be an array of {what}, got {show(value)}")
    if len(value) < min_count:
        raise ModelError(path, f"needs at least {min_count} {what}, got {len(value)}")
    return list(value)


def numbers(value: Any, path: str, min_count: int = 0, count: Optional[int] = None,
            what: str = "numbers") -> np.ndarray:
    """An array of finite numbers (exactly ``count`` of them if given)."""
    items = array(value, path, what, min_count)
    if count is not None and len(items) != count:
        raise ModelError(path, f"expected {count} {what}, got {len(items)}")
    return np.array([number(x, f"{path}[{i}]") for i, x in enumerate(items)], dtype=np.float64)


def vector(value: Any, path: str, dims: Sequence[int] = (3,), what: str = "coordinates") -> np.ndarray:
    """One point/vector with a number of coordinates in ``dims``."""
    if not isinstance(value, (list, tuple)):
        raise ModelError(path, f"must be an array of {_dims_text(dims)} {what}, got {show(value)}")
    if len(value) not in dims:
        raise ModelError(path, f"expected {_dims_text(dims)} {what}, got {len(value)}")
    return np.array([number(x, f"{path}[{i}]") for i, x in enumerate(value)], dtype=np.float64)


def _dims_text(dims: Sequence[int]) -> str:
    return " or ".join(str(d) for d in dims)


def points(value: Any, path: str, min_count: int = 1, dims: Sequence[int] = (2, 3),
           count: Optional[int] = None) -> np.ndarray:
    """An (n, d) array of points, every point with the first point's d in ``dims``
    coordinates; the path of a misfit point is reported."""
    items = array(value, path, "points", min_count)
    if count is not None and len(items) != count:
        raise ModelError(path, f"expected {count} points, got {len(items)}")
    if not items:
        return np.empty((0, dims[-1]))
    first = vector(items[0], f"{path}[0]", dims)
    rows = [first]
    for i, p in enumerate(items[1:], 1):
        rows.append(vector(p, f"{path}[{i}]", (len(first),), what=f"coordinates (like {path}[0])"))
    return np.array(rows)


def grid(value: Any, path: str, dims: Sequence[int] = (3,), min_size: int = 2) -> np.ndarray:
    """An (nu, nv, d) net given as rows of points: nu >= min_size rows of one length
    nv >= min_size, all points with one dimension."""
    rows = array(value, path, "rows of points", min_size)
    first = points(rows[0], f"{path}[0]", min_size, dims)
    out = [first]
    for i, r in enumerate(rows[1:], 1):
        rp = f"{path}[{i}]"
        items = array(r, rp, "points")
        if len(items) != len(first):
            raise ModelError(rp, f"expected {len(first)} points (like {path}[0]), got {len(items)}")
        out.append(points(items, rp, dims=(first.shape[1],)))
    return np.array(out)


def number_grid(value: Any, path: str, shape: Tuple[int, int], what: str = "numbers") -> np.ndarray:
    rows = array(value, path, f"rows of {what}")
    if len(rows) != shape[0]:
        raise ModelError(path, f"expected {shape[0]} rows (one per row of control_points), got {len(rows)}")
    return np.array([numbers(r, f"{path}[{i}]", count=shape[1], what=what)
                     for i, r in enumerate(rows)])


def weights(value: Any, path: str, count: int) -> np.ndarray:
    """``count`` positive weights, one per control point."""
    w = numbers(value, path, count=count, what="weights (one per control point)")
    _positive_entries(w, path)
    return w


def weight_grid(value: Any, path: str, shape: Tuple[int, int]) -> np.ndarray:
    w = number_grid(value, path, shape, "weights")
    _positive_entries(w, path)
    return w


def _positive_entries(w: np.ndarray, path: str) -> None:
    bad = np.argwhere(~(w > 0.0))
    if bad.size:
        idx = "".join(f"[{int(i)}]" for i in bad[0])
        raise ModelError(path + idx, f"weights must be positive, got {float(w[tuple(bad[0])])!r}")


def knots(value: Any, path: str) -> np.ndarray:
    """A non-decreasing array of numbers (the engine checks count and multiplicities)."""
    k = numbers(value, path, what="knots")
    drop = np.flatnonzero(np.diff(k) < 0)
    if drop.size:
        i = int(drop[0]) + 1
        raise ModelError(f"{path}[{i}]", f"knots must be non-decreasing, got {float(k[i])!r} after {float(k[i - 1])!r}")
    return k
