"""Knot and degree edits of the pole edit mode (issue 19), free of GUI code: insert a
knot at the parameter nearest a picked pole, elevate the degree, remove knots within a
tolerance, on the B-spline curve and surface objects (their poles, knots, degrees and
weights are properties). Each edit builds the object's engine geometry from its
properties, lets the engine change it (Boehm's insertion, Piegl & Tiller A5.1/A5.3;
degree elevation, P&T 5.5; Tiller's knot removal, P&T A5.8: insertion and elevation
keep the shape exactly) and writes the result back through :func:`properties`, the
one mapping engine object -> feature properties, in one transaction (one undo step).
The pole editor's panel and context menu (editpoles.py) call :func:`run`.
"""
from __future__ import annotations

from typing import Callable, Optional, Tuple

import numpy as np

from . import conversion, curves, fitting, surfaces
from .conversion import cagd

DIRECTIONS = fitting.DIRECTIONS          # a surface's direction(s) of an edit: Both, U, V
REMOVE_TOL = 1e-3                        # the panel's default tolerance of Remove knots (mm)
KNOT_SNAP = 1e-9                         # a parameter this close (relative to the domain) to a knot is that knot


def refusal(obj) -> Optional[str]:
    """Why the knot and degree edits do not apply to ``obj`` (not a B-spline curve or
    surface object, poles following linked vertices, an interpolating surface), or None."""
    proxy = getattr(obj, "Proxy", None)
    if not isinstance(proxy, (curves.BSplineCurve, surfaces.BSplineSurface)):
        return f"{obj.Label}: knots and degree are edited on B-spline curve and surface objects only"
    if getattr(obj, "Vertices", None):
        return "Vertices: the poles follow linked vertices (unlink them to insert knots or change the degree)"
    if getattr(obj, "Interpolate", False):
        return "Interpolate: the poles are points the surface passes through (turn Interpolate off first)"
    return None


def engine_of(obj):
    """The engine curve or surface of the object's properties (local coordinates);
    CagdError with :func:`refusal`'s reason for other objects."""
    reason = refusal(obj)
    if reason:
        raise cagd.CagdError(reason)
    return obj.Proxy.build(obj)


def properties(geometry) -> dict:
    """The feature properties {name: value} that describe the engine ``geometry`` (a
    cagd.BSplineCurve: Poles, Degree, Knots, Weights, Periodic; a cagd.BSplineSurface:
    Poles row-major, CountU, DegreeU/V, KnotsU/V, Weights row-major, PeriodicU/V). Knots
    are the engine's: the full vector, or one period of a periodic direction (the
    properties' convention); Weights are empty for a polynomial one."""
    W = geometry.weights
    weights = [] if W is None else [float(w) for w in np.asarray(W).ravel()]
    if isinstance(geometry, cagd.BSplineCurve):
        return {"Poles": conversion.vectors(geometry.control_points), "Degree": int(geometry.degree),
                "Knots": [float(k) for k in geometry.knots], "Weights": weights,
                "Periodic": bool(geometry.periodic)}
    if isinstance(geometry, cagd.BSplineSurface):
        P = np.asarray(geometry.control_points)
        return {"Poles": conversion.vectors(P.reshape(-1, P.shape[-1])), "CountU": int(P.shape[0]),
                "DegreeU": int(geometry.degree_u), "DegreeV": int(geometry.degree_v),
                "KnotsU": [float(k) for k in geometry.knots_u], "KnotsV": [float(k) for k in geometry.knots_v],
                "Weights": weights, "PeriodicU": bool(geometry.periodic_u), "PeriodicV": bool(geometry.periodic_v)}
    raise cagd.CagdError(f"geometry: a BSplineCurve or BSplineSurface, got {type(geometry).__name__}")


def _steps(geometry, direction: str) -> Tuple[Optional[str], ...]:
    """The engine directions of an edit: (None,) for a curve; 'u', 'v' or both."""
    if isinstance(geometry, cagd.BSplineCurve):
        return (None,)
    if direction not in DIRECTIONS:
        raise cagd.CagdError(f"direction: one of {', '.join(DIRECTIONS)}, got {direction!r}")
    return ("u", "v") if direction == "Both" else (direction.lower(),)


def parameter_near(geometry, pole: int):
    """The parameter (a surface: (u, v)) of the point of ``geometry`` nearest its pole
    ``pole`` (a flat, row-major index as the Poles property): the engine's certified
    closest point."""
    P = np.asarray(geometry.control_points)
    flat = P.reshape(-1, P.shape[-1])
    if not 0 <= pole < len(flat):
        raise cagd.CagdError(f"Poles: index {pole} out of range (0..{len(flat) - 1})")
    return np.asarray(cagd.closest_point(geometry, flat[pole]).params[0], dtype=float)


def insert_knot(geometry, pole: int, direction: str = "Both") -> Tuple[object, str]:
    """(geometry with a knot inserted at the parameter nearest pole ``pole``, message).
    A surface gets it in ``direction`` (U, V or Both). A parameter within KNOT_SNAP
    (relative) of a knot is that knot (its multiplicity grows: no sliver span); one at
    a clamped end has no knot to insert: CagdError naming Poles."""
    at = np.atleast_1d(parameter_near(geometry, pole))
    out, done = geometry, []
    for step in _steps(geometry, direction):
        k = 0 if step in (None, "u") else 1
        periodic = geometry.periodic if step is None else getattr(geometry, f"periodic_{step}")
        a, b = geometry.domain if step is None else geometry.domain[k]
        knots = np.asarray(geometry.knots if step is None else getattr(geometry, f"knots_{step}"))
        near = np.abs(knots - at[k]) <= KNOT_SNAP * (b - a)
        t = float(knots[near][0]) if near.any() else float(at[k])
        if not periodic and not a < t < b:
            raise cagd.CagdError(f"Poles: the point nearest pole {pole} is at the end {step or 't'} = {t:g} "
                                 "of the domain: no knot to insert there (pick an inner pole)")
        out = out.insert_knot(t) if step is None else out.insert_knot(step, t)
        done.append(f"{step or 't'} = {t:.6g}")
    return out, f"knot inserted at {', '.join(done)} (nearest pole {pole})"


def elevate(geometry, direction: str = "Both") -> Tuple[object, str]:
    """(geometry one degree higher, message); a surface in ``direction`` (U, V or Both)."""
    out, done = geometry, []
    for step in _steps(geometry, direction):
        before = geometry.degree if step is None else getattr(geometry, f"degree_{step}")
        out = out.elevate(1) if step is None else out.elevate(step, 1)
        done.append(f"{'degree' if step is None else 'degree in ' + step} {before} -> {before + 1}")
    return out, "; ".join(done)


def remove_knots(geometry, tol: float, direction: str = "Both") -> Tuple[object, str, int, float]:
    """(geometry with as many knots removed as keep it within ``tol``, message, knots
    removed, deviation): the engine's removal (fitting.remove_knots_within) and the
    deviation it measured at equal parameters."""
    out, removed, bound, dev = fitting.remove_knots_within(geometry, tol, direction)
    return out, (f"{removed} knot(s) removed, deviation {dev:.3g} mm (bound {bound:.3g} mm, "
                 f"tolerance {tol:.3g} mm)"), removed, dev


def apply(obj, new_geometry) -> None:
    """Write ``new_geometry`` into the object's properties (only those that change)."""
    for name, value in properties(new_geometry).items():
        if getattr(obj, name) != value:
            setattr(obj, name, value)


def run(obj, title: str, edit: Callable[[object], tuple]) -> tuple:
    """``edit(geometry)`` -> (new geometry, message, ...) applied to ``obj`` and
    recomputed in one transaction titled ``title`` (one undo step); returns what
    ``edit`` returned. An error (the engine's, or an invalid object after the
    recompute) aborts the transaction, so nothing changes, and raises CagdError."""
    doc = obj.Document
    result = edit(engine_of(obj))
    doc.openTransaction(f"{title} of {obj.Label}")
    try:
        apply(obj, result[0])
        doc.recompute()
        if "Invalid" in obj.State:
            raise cagd.CagdError(f"{obj.Label}: {obj.Message}")
    except Exception:
        doc.abortTransaction()
        doc.recompute()
        raise
    doc.commitTransaction()
    return result
