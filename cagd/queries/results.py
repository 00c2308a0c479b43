"""The result types of the queries, in one module (issue 16, layout): closest points,
deviations, minimum distances, intersection points, curves and overlaps. Each is a
frozen dataclass; array fields are read-only (:class:`cagd._results.ReadOnlyArrays`).
The functions that make them live in :mod:`cagd.queries.closest`,
:mod:`~cagd.queries.deviation`, :mod:`~cagd.queries.distance` and
:mod:`~cagd.queries.intersect`."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .._deprecation import deprecated
from .._periodic import wrap
from .._results import ReadOnlyArrays
from ._numerics import DEFAULT_TOL

if TYPE_CHECKING:
    from ..curves.bspline import BSplineCurve

__all__ = ["ClosestPoints", "Deviation", "DistanceResult", "IntersectionPoint", "IntersectionResult", "Overlap",
           "IntersectionCurve", "SurfaceOverlap", "Domain"]

Domain = Tuple[np.ndarray, np.ndarray, np.ndarray]   # (lo, hi, closed) of a surface's parameters


@dataclass(frozen=True)
class ClosestPoints(ReadOnlyArrays):
    """Result of :func:`closest_point` for N points (or N local minima of one point).

    params: (N,) curve parameters or (N, 2) surface parameters; feet: (N, dim) closest
    points (the feet of the perpendiculars); distances: (N,); point_converged: (N,)
    the local Newton refinement met ``tol`` (or ``param_tol``) within
    ``max_iterations`` at that point and the search proved the foot global (its lower
    bound within 1e-9 of the distance below it, ``closest.WIN_GAP_RTOL``, or rounding
    of the object's size; False where the search stopped at its work bound with the
    certificate open: the distance is then the nearest found, an upper bound);
    converged: at every point, and ``message`` names
    the points where it did not; lower_bounds: (N,) certified lower bounds on the true
    distance from the point to the whole object (``lower_bounds <= distances``, whether
    or not Newton converged); isolated (``all_minima`` only, else None): (N,) False
    where the minimum is not
    isolated: the Hessian of the squared distance has a zero eigenvalue (relative 1e-6)
    along the free parameters, so the minima form a curve or a region through it (the
    centre of a sphere, a point on the axis of a surface of revolution); the rows are
    then samples of that continuum, one per Bezier cell. A foot at a collapsed edge (a
    pole) is one row, isolated when the distance grows away from it. owner (a list of
    objects only, else None): (N,) the index of the nearest object, the first of equally
    near ones; params are on it (curve parameters repeated in both columns among
    surfaces)."""
    params: np.ndarray
    feet: np.ndarray
    distances: np.ndarray
    point_converged: np.ndarray
    lower_bounds: np.ndarray
    isolated: Optional[np.ndarray] = None
    converged: bool = True
    message: str = ""
    owner: Optional[np.ndarray] = None


@dataclass(frozen=True)
class Deviation(ReadOnlyArrays):
    """Signed deviations of N points from an object, with their statistics.

    distances: (N,) signed (or unsigned, see ``signed``) distances; params, feet: the
    closest points (as :class:`cagd.queries.ClosestPoints`); lower_bounds: certified
    lower bounds of the unsigned distances; signed: whether a side was defined; max,
    min, mean, rms, max_abs of the distances; percentiles: {p: value} of the distances;
    owner: the nearest object's index; converged: the closest points converged at every
    point (``message`` says where not)."""
    distances: np.ndarray
    params: np.ndarray
    feet: np.ndarray
    lower_bounds: np.ndarray
    signed: bool
    max: float
    min: float
    mean: float
    rms: float
    max_abs: float
    percentiles: Dict[float, float]
    owner: Optional[np.ndarray] = None     # (N,) index of the nearest object, for a list of objects
    converged: bool = True
    message: str = ""

    def table(self) -> str:
        """The statistics as a Markdown table."""
        rows = [("points", f"{len(self.distances)}"), ("signed", "yes" if self.signed else "no")]
        rows += [(k, f"{getattr(self, k):.6g}") for k in ("max", "min", "mean", "rms", "max_abs")]
        rows += [(f"percentile {p:g}", f"{v:.6g}") for p, v in self.percentiles.items()]
        return "\n".join(["| statistic | value |", "|---|---|"] + [f"| {a} | {b} |" for a, b in rows])


@dataclass(frozen=True)
class DistanceResult:
    """``distance`` attained at ``params`` = (parameter on a, parameter on b) and
    ``points`` = (a point, b point); the global minimum is certified to be at least
    ``lower_bound``. ``tol`` is the absolute distance (model units) the gap
    ``distance - lower_bound`` was to reach; ``converged`` is False when it did not
    within the depth/pair limits (``message`` says which).

    ``isolated`` is False when the minimum found is not isolated to second order: along
    some direction of the free parameters (those along which the distance is
    stationary, so not held at a domain bound or a C0 seam, less the directions that
    move neither point, along a pole) |A(s) - B(t)|^2 grows by at most ISOLATION_RTOL
    (1e-6) of what the curvature terms alone would give, plus HESSIAN_FLOOR (1e-12)
    times |dA|^2 + |dB|^2, the squared lengths the two points move; that is, the
    Hessian of |A - B|^2 / 2 over those parameters, in the metric of the points'
    displacements, has a zero eigenvalue. The minimum distance is then attained along a
    curve or a region of parameter pairs through ``params``, which is one of them:
    concentric spheres or arcs, coaxial cylinders, parallel planes, a torus and a
    sphere at its centre (or a nearly concentric case that the test cannot tell apart
    at that precision). Where the objects touch (distance <= TOUCH_RTOL = 1e-12 of
    their size) and that Hessian is flat, the order of contact decides, with the domain
    bounds left out: a touch at one point (a sphere on a plane or on a sphere) is
    isolated, a line of contact (a cylinder on a plane) or surfaces crossing along a
    curve are not (nor is an edge resting on a surface). Separate minima of equal
    distance (two spheres placed symmetrically about a third, a circle inside a
    concentric ellipse) are isolated: each is a strict local minimum, and ``params`` is
    one of them."""
    distance: float
    params: tuple
    points: tuple
    lower_bound: float
    tol: float
    converged: bool
    isolated: bool = True
    message: str = ""

    @property
    def gap(self) -> float:
        """distance - lower_bound: how far the true minimum may lie below ``distance``."""
        return self.distance - self.lower_bound


@dataclass(frozen=True)
class IntersectionPoint(ReadOnlyArrays):
    """One intersection: parameters on a and b (floats for curves, (u, v) arrays for
    surfaces), the point (midpoint of a(x) and b(y)), the residual |a(x) - b(y)| and
    whether the contact is tangential (the angle between the tangents, or between the
    curve and the tangent plane, or between the tangent planes, is at most angle_tol);
    ``converged``: the residual is within tol and the point is isolated (``message``
    says why not)."""
    param_a: object
    param_b: object
    point: np.ndarray
    tangential: bool
    residual: float
    converged: bool = True
    message: str = ""


@dataclass(frozen=True)
class IntersectionResult:
    """Points, overlaps and (surface queries) intersection curves, as tuples; ``tol`` the
    distance asked for; ``converged`` is False when the subdivision hit
    ``max_depth``/``max_pairs`` with pairs still open, a candidate's Newton solve did
    not settle, or a branch or point did not converge (``message`` says which)."""
    points: Tuple[IntersectionPoint, ...]
    overlaps: tuple
    curves: tuple = ()
    tol: float = DEFAULT_TOL
    converged: bool = True
    message: str = ""

    def __post_init__(self) -> None:
        for name in ("points", "overlaps", "curves"):
            object.__setattr__(self, name, tuple(getattr(self, name)))

    @property
    def params_a(self) -> np.ndarray:
        return np.array([p.param_a for p in self.points], dtype=float)

    @property
    def params_b(self) -> np.ndarray:
        return np.array([p.param_b for p in self.points], dtype=float)

    @property
    def coordinates(self) -> np.ndarray:
        return np.array([p.point for p in self.points], dtype=float)

    def __len__(self) -> int:
        return len(self.points)


@dataclass(frozen=True)
class Overlap(ReadOnlyArrays):
    """Coincident pieces: ``param_a`` = (s0, s1) on a with s0 < s1, ``param_b`` the
    parameters on b matching s0 and s1 (decreasing when the directions are opposite).
    For a curve lying in a surface, ``param_b`` holds the surface's (u, v) arrays at
    s0 and s1 (with the curve given second, the two fields are swapped). The ends are
    where the distance to the other object reaches tol (``converged``; ``message`` says
    otherwise)."""
    param_a: Tuple[float, float]
    param_b: Tuple[object, object]
    converged: bool = True
    message: str = ""


@dataclass(frozen=True)
class IntersectionCurve(ReadOnlyArrays):
    """One branch of a surface–surface or surface–plane intersection.

    curve: 3-D BSplineCurve through the marched points (chord-length parameters);
    params_a, params_b: 2-D BSplineCurves (same parameter) on a and b (None for a
    plane); closed: the branch is a loop; max_distance: the largest distance of
    the curve from both surfaces (Newton projection), measured at 9 samples per span
    and at the parabolic vertex of each span's largest (within 0.1% of 20,000 samples
    per branch on 72 test branches); params_max_distance: the largest
    |A(params_a(t)) - curve(t)|, |B(params_b(t)) - curve(t)|, measured the same way
    (within 1%); converged: the march and the fit met their bounds (both distances
    <= tol), ``message`` says why not; ends: how each end stopped ('boundary',
    'singular', 'closed', 'stalled', 'limit'). ``tolerance`` and
    ``params_tolerance`` are the deprecated names of the two distances (one release).

    params_a and params_b live in the covering space of closed directions: after
    crossing a seam (periodic or closed u or v) their values run on past the domain
    (e.g. v = 1.3 on a domain [0, 1] means v = 0.3); use :meth:`surface_params` for
    parameters reduced into the domains. Through a collapsed edge (a pole, an apex) the
    parameter curves run along the edge on a parameter interval of width <= 0.1 tol /
    length, where the 3-D curve is within 0.1 tol of the degenerate point."""
    curve: BSplineCurve
    params_a: Optional[BSplineCurve]          # None for a plane (intersect(plane, surface))
    params_b: Optional[BSplineCurve]
    closed: bool
    max_distance: float
    params_max_distance: float = 0.0
    converged: bool = True
    ends: Tuple[str, str] = ("closed", "closed")
    domains: Tuple[Optional[Domain], Optional[Domain]] = (None, None)
    message: str = ""

    @property
    def tolerance(self) -> float:
        """Deprecated name of :attr:`max_distance`."""
        deprecated("IntersectionCurve.tolerance", "use max_distance (the same value: the largest distance "
                                                  "of the curve from the surfaces)")
        return self.max_distance

    @property
    def params_tolerance(self) -> float:
        """Deprecated name of :attr:`params_max_distance`."""
        deprecated("IntersectionCurve.params_tolerance", "use params_max_distance (the same value)")
        return self.params_max_distance

    def surface_params(self, t: ArrayLike) -> Tuple[np.ndarray, Optional[np.ndarray]]:
        """(uv on a (N, 2), st on b (N, 2) or None for a plane) at curve parameters t,
        reduced into the surfaces' domains: u -> u0 + (u - u0) mod (u1 - u0) in closed
        directions, clipped to the domain otherwise."""
        t = np.atleast_1d(np.asarray(t, float))
        out: List[Optional[np.ndarray]] = []
        for pc, dom in zip((self.params_a, self.params_b), self.domains):
            if pc is None:
                out.append(None)
                continue
            x = pc(t)
            if dom is not None:
                lo, hi, closed = dom
                x = np.where(closed, wrap(x, lo, hi - lo), np.clip(x, lo, hi))
            out.append(x)
        assert out[0] is not None                   # params_a is always there
        return out[0], out[1]


@dataclass(frozen=True)
class SurfaceOverlap:
    """Coincident pieces of two surfaces: ``box_a`` = ((u0, u1), (v0, v1)) on a where
    a lies on b within tol, ``box_b`` the parameter box of the same piece on b (the
    bounding box of the projected samples); the box of a plane is None (``box_b``, or
    ``box_a`` for intersect(plane, surface), whose cells are then on b). The boxes are grown until
    the distance reaches tol (``converged``; ``message`` says otherwise).

    Clipped to trimmed faces (:func:`cagd.queries.trimmed.clip_to_trims`), the region is
    the box's part inside both trims, as parameter cells of a: ``cells_a`` (K, 4) rows
    (u0, v0, u1, v1) inside both trims, ``edge_cells_a`` those a trim boundary crosses
    (at the smallest cell size), ``area`` its area on a (inside cells plus half the edge
    cells) within ``area_error`` (half the edge cells' area); the boxes are then the
    region's bounding boxes. None for an overlap of untrimmed surfaces."""
    box_a: Optional[Tuple[Tuple[float, float], Tuple[float, float]]]     # None for a plane
    box_b: Optional[Tuple[Tuple[float, float], Tuple[float, float]]]
    converged: bool = True
    message: str = ""
    cells_a: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    edge_cells_a: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    area: Optional[float] = None
    area_error: float = 0.0
