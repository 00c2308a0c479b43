"""Argument validation shared by every family; every failure is a CagdError."""
from __future__ import annotations

import numbers
from typing import Any, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from .errors import CagdError

#: Highest polynomial degree accepted anywhere (curves, surfaces, elevation, fitting).
#: Every degree up to it evaluates within 1e-12 of de Casteljau relative to the control
#: net (the power form up to :data:`cagd.curves.ppform.PP_MAX_DEGREE`, the Bernstein sum
#: on Bezier spans above); binomials C(n, i) stay far from overflow (C(1029, 514) is the
#: last finite one) and t^i (1-t)^(n-i) C(n, i) of a subnormal t^i stays below
#: 2^n * 2.2e-308 (negligible). 128 is also where evaluation stays fast: 1e5 points of a
#: degree-128 curve in ~0.2 s once its Bezier spans are extracted (O(s p^3), once per
#: curve: ~2 s for 400 poles), a degree-128 surface 1e4 points in ~1 s. Note: OCCT's own maximum is 25
#: (``Geom_BSplineCurve::MaxDegree()``); degrees above 25 do not convert to OCCT.
MAX_DEGREE = 128
#: Highest derivative order accepted (curves and surfaces, each direction): derivatives
#: above the degree are zero, and orders beyond MAX_DEGREE only cost memory.
MAX_ORDER = MAX_DEGREE
#: Largest number of samples a count argument may ask for (comb teeth, sample counts):
#: 10^7 points of 3 float64 coordinates are 240 MB per array.
MAX_SAMPLES = 10_000_000
#: OCCT's maximum B-spline degree (``Geom_BSplineCurve::MaxDegree()``), for the converters.
OCC_MAX_DEGREE = 25


def finite_array(value: ArrayLike, name: str, ndim: Optional[int] = None, copy: bool = True) -> np.ndarray:
    """``value`` as a float64 array, rejecting NaN/inf and a wrong number of dimensions;
    ``copy`` False: ``value`` itself where it already is a float64 array (read by the
    caller only)."""
    try:
        arr = np.array(value, dtype=np.float64) if copy else np.asarray(value, dtype=np.float64)
    except OverflowError:
        raise CagdError(f"{name}: a value is beyond the floating-point range (|x| > 1.8e308)") from None
    except (TypeError, ValueError) as exc:
        raise CagdError(f"{name}: not a numeric array ({exc})") from None
    if ndim is not None and arr.ndim != ndim:
        raise CagdError(f"{name}: expected a {ndim}-D array, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        bad = np.argwhere(~np.isfinite(arr))[0]
        raise CagdError(f"{name}: contains NaN or inf (at index {tuple(int(i) for i in bad)})")
    return arr


def points(value: ArrayLike, name: str = "control_points", min_count: int = 1) -> np.ndarray:
    """An (n, dim) array of finite points, dim >= 1; a 1-D input is n points of dim 1."""
    arr = finite_array(value, name)
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] < 1:
        raise CagdError(f"{name}: expected shape (n, dim), got {arr.shape}")
    if arr.shape[0] < min_count:
        raise CagdError(f"{name}: need at least {min_count} points, got {arr.shape[0]}")
    return arr


def weights(value: Optional[ArrayLike], count: int, name: str = "weights") -> Optional[np.ndarray]:
    """Positive finite weights, one per control point, or None."""
    if value is None:
        return None
    w = finite_array(value, name, ndim=1)
    if w.shape[0] != count:
        raise CagdError(f"{name}: got {w.shape[0]} weights for {count} control points")
    if np.any(w <= 0):
        i = int(np.argmax(w <= 0))
        raise CagdError(f"{name}: must be positive (weights[{i}]={w[i]!r})")
    return w


def integer(value: Any, name: str, minimum: int = 0, maximum: Optional[int] = None) -> int:
    """An int in [minimum, maximum]; bools and non-integral floats are rejected."""
    if type(value) is int and value >= minimum and (maximum is None or value <= maximum):
        return value                         # the common case, without the ABC checks below
    if isinstance(value, bool) or not isinstance(value, (numbers.Integral, np.integer)):
        if isinstance(value, (float, np.floating)) and float(value).is_integer():
            value = int(value)
        else:
            raise CagdError(f"{name}: must be an integer, got {value!r}")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        hi = "" if maximum is None else f", at most {maximum}"
        raise CagdError(f"{name}: out of range ({value}); must be at least {minimum}{hi}")
    return value


def degree(value: Any, name: str = "degree", minimum: int = 1, maximum: Optional[int] = None) -> int:
    """A polynomial degree: an int in [minimum, maximum] and at most :data:`MAX_DEGREE`."""
    d = integer(value, name, minimum)
    if d > MAX_DEGREE:
        raise CagdError(f"{name}: degree {d} exceeds the maximum degree cagd.MAX_DEGREE = {MAX_DEGREE}")
    return integer(d, name, minimum, maximum)


def order(value: Any, name: str = "order") -> int:
    """A derivative order: an int in [0, :data:`MAX_ORDER`]."""
    k = integer(value, name, 0)
    if k > MAX_ORDER:
        raise CagdError(f"{name}: derivative order {k} exceeds cagd.MAX_ORDER = {MAX_ORDER} "
                        f"(derivatives above the degree are zero)")
    return k


def elevation(value: Any, current: int, name: str = "times") -> int:
    """How many times to raise a degree ``current``: an int >= 0 with current + times <=
    :data:`MAX_DEGREE`."""
    r = integer(value, name, 0)
    if current + r > MAX_DEGREE:
        raise CagdError(f"{name}: raising degree {current} by {r} exceeds the maximum degree "
                        f"cagd.MAX_DEGREE = {MAX_DEGREE}")
    return r


def scalar(value: Any, name: str) -> float:
    """A finite float (bools are rejected: ``tol=True`` is a mistake, not 1.0)."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, np.ndarray) and value.dtype == bool):
        raise CagdError(f"{name}: must be a number, got {value!r}")
    try:
        x = float(value)
    except OverflowError:
        raise CagdError(f"{name}: beyond the floating-point range (|x| > 1.8e308)") from None
    except (TypeError, ValueError):
        raise CagdError(f"{name}: must be a number, got {value!r}") from None
    if not np.isfinite(x):
        raise CagdError(f"{name}: must be finite, got {x!r}")
    return x


def positive(value: Any, name: str) -> float:
    """A finite float > 0 (tolerances, radii)."""
    x = scalar(value, name)
    if not x > 0.0:
        raise CagdError(f"{name}: must be positive, got {x!r}")
    return x


def nonnegative(value: Any, name: str) -> float:
    """A finite float >= 0 (a distance tolerance that may be zero)."""
    x = scalar(value, name)
    if not x >= 0.0:
        raise CagdError(f"{name}: must be >= 0, got {x!r}")
    return x


def angle(value: Any, name: str = "angle_tol") -> float:
    """An angle tolerance in radians: a finite float >= 0."""
    x = scalar(value, name)
    if x < 0.0:
        raise CagdError(f"{name}: an angle in radians >= 0, got {x!r}")
    return x


def parameters(t: ArrayLike, name: str = "t") -> np.ndarray:
    """Finite float64 parameters of any shape, a read-only view (no copy of a float64
    array: 10^6 parameters took 1.6 ms of a 13 ms evaluation)."""
    view = finite_array(t, name, copy=False).view()
    view.flags.writeable = False
    return view


def affine_map(matrix: ArrayLike, offset: Optional[ArrayLike], dim: int, what: str) -> Tuple[np.ndarray, np.ndarray]:
    """(A, b) of an affine map x -> A x + b acting on ``dim``-D points of a ``what``."""
    A = finite_array(matrix, "matrix", ndim=2)
    if A.shape[1] != dim:
        raise CagdError(f"matrix: expected {dim} columns for a {dim}-D {what}, got {A.shape}")
    b = np.zeros(A.shape[0]) if offset is None else finite_array(offset, "offset", ndim=1)
    if b.shape[0] != A.shape[0]:
        raise CagdError(f"offset: expected {A.shape[0]} values, got {b.shape[0]}")
    return A, b


def increasing(value: ArrayLike, count: int, name: str = "parameters") -> np.ndarray:
    """``count`` finite, strictly increasing values (one parameter per point)."""
    t = finite_array(value, name, ndim=1)
    if t.shape[0] != count:
        raise CagdError(f"{name}: expected {count} values (one per point), got {t.shape[0]}")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = int(bad[0])
        raise CagdError(f"{name}: must be strictly increasing ({name}[{i + 1}]={t[i + 1]} <= {name}[{i}]={t[i]})")
    return t


def finite_homogeneous(hom: np.ndarray) -> np.ndarray:
    """The homogeneous control points w P must stay finite (w and P finite can overflow)."""
    if not np.all(np.isfinite(hom)):
        raise CagdError("control_points, weights: the products w * P overflow (weights or coordinates "
                        "too large); scale the model or the weights")
    return hom


def frozen(value: ArrayLike, dtype: Optional[DTypeLike] = None) -> np.ndarray:
    """A read-only array that owns its data (objects are values, issue 13): ``value``
    itself when it already is one (frozen arrays are shared between values), else a
    read-only copy (as ``dtype`` if given), so that the caller's array is neither
    frozen nor aliased."""
    if isinstance(value, np.ndarray) and not value.flags.writeable and value.flags.owndata \
            and (dtype is None or value.dtype == dtype):
        return value
    arr = np.array(value, dtype=dtype)
    arr.setflags(write=False)
    return arr


def pole_index(index: Any, shape: Tuple[int, ...], name: str = "index") -> Tuple[int, ...]:
    """A control point's position in a net of ``shape``: an int for a sequence (shape
    (n,)), a tuple of len(shape) ints for a net; negative values count from the end."""
    if len(shape) == 1 and not isinstance(index, (tuple, list)) and np.ndim(index) == 0:
        index = (index,)
    try:
        parts = tuple(index)
    except TypeError:
        parts = ()
    if len(parts) != len(shape):
        want = "an int" if len(shape) == 1 else f"a tuple of {len(shape)} ints"
        raise CagdError(f"{name}: expected {want} for a net of shape {tuple(shape)}, got {index!r}")
    return tuple(integer(i, name, -n, n - 1) % n for i, n in zip(parts, shape))


def point(value: ArrayLike, dim: int, name: str = "point") -> np.ndarray:
    """One finite point of ``dim`` coordinates (a scalar for dim 1)."""
    p = finite_array(value, name)
    if p.ndim == 0:
        p = p[None]
    if p.shape != (dim,):
        raise CagdError(f"{name}: expected {dim} coordinates, got shape {p.shape}")
    return p


def same_shape(arr: np.ndarray, expected: Tuple[int, ...], name: str) -> np.ndarray:
    """``arr`` unless its shape differs from ``expected`` (a modified copy keeps the layout)."""
    if arr.shape != tuple(expected):
        raise CagdError(f"{name}: expected shape {tuple(expected)} like the original, got {arr.shape}")
    return arr
