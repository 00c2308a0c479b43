"""Engine objects <-> OCCT geometry (Geom_BSplineCurve/Surface, Geom_BezierCurve/Surface).

``to_occ`` passes ``obj.to_nurbs().occ_form()`` (exact: the same poles, weights,
knots and multiplicities) to OCCT's constructors; ``from_occ`` reads them back
(:meth:`cagd.BSplineCurve.from_occ_form`) after ``GeomConvert`` has turned any
other bounded curve or surface into a B-spline. OCCT's arrays are filled one
value at a time (OCP has no buffer access); that is the only per-pole loop.
"""
from __future__ import annotations

import warnings
from typing import List, Optional, Tuple, Union

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.Geom import (Geom_BezierCurve, Geom_BezierSurface, Geom_BSplineCurve, Geom_BSplineSurface, Geom_Curve,
                      Geom_OffsetCurve, Geom_OffsetSurface, Geom_RectangularTrimmedSurface, Geom_Surface,
                      Geom_TrimmedCurve)
from OCP.Geom2d import Geom2d_BSplineCurve, Geom2d_Curve, Geom2d_OffsetCurve, Geom2d_TrimmedCurve
from OCP.Geom2dConvert import Geom2dConvert
from OCP.GeomAbs import GeomAbs_C1, GeomAbs_C2
from OCP.GeomConvert import GeomConvert, GeomConvert_ApproxCurve, GeomConvert_ApproxSurface
from OCP.gp import gp_Pnt, gp_Pnt2d
from OCP.Precision import Precision
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED
from OCP.TopoDS import TopoDS_Face, TopoDS_Shape

from .. import _checks
from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bezier import BezierSurface
from ..surfaces.bspline import BSplineSurface
from ..surfaces.trimmed import TrimmedSurface
from .analytic import analytic_form
from .trim import deferred_trim, make_trimmed_face, trimmed_from_face
from .compat import (Array1OfInteger, Array1OfPnt, Array1OfPnt2d, Array1OfReal, Array2OfPnt, Array2OfReal, as_edge,
                     as_face)

PERIOD_SPAN_TOL = 1e-9     # a face spanning this close to a whole period is the full turn
KNOT_SNAP_TOL = 1e-9       # a face box end this close to a knot (relative to the range) ends on it
# the smallest approximate= tolerance for offsets: OCCT's geometric resolution (1e-7 mm);
# from_occ(offset surface, approximate=1e-300) ran over 60 s (issue 14)
APPROXIMATE_MIN_TOL = Precision.Confusion_s()
# OCCT reads coordinates beyond Precision::Infinite() (2e100) as infinite; geometry
# handed to it stays within half of that (measured: a revolution about an axis at 1e300
# raised Standard_ConstructionError, one at 1e100 works)
MAX_COORDINATE = 0.5 * Precision.Infinite_s()


def occt_coordinates(value: np.ndarray, name: str) -> np.ndarray:
    """``value`` (finite coordinates) unless one exceeds MAX_COORDINATE (1e100) in size."""
    arr = np.asarray(value, dtype=np.float64)
    if arr.size and not float(np.abs(arr).max()) <= MAX_COORDINATE:
        raise CagdError(f"{name}: coordinates up to {float(np.abs(arr).max()):.3g} exceed OCCT's range "
                        f"(|x| <= {MAX_COORDINATE:.0e}); scale the model")
    return arr

OccGeometry = Union[Geom_BSplineCurve, Geom_BezierCurve, Geom_BSplineSurface, Geom_BezierSurface]


# --- arrays (OCCT arrays are 1-based) ---------------------------------------------------
def _reals(values) -> Array1OfReal:
    a = Array1OfReal(1, len(values))
    for i, x in enumerate(values, 1):
        a.SetValue(i, float(x))
    return a


def _ints(values) -> Array1OfInteger:
    a = Array1OfInteger(1, len(values))
    for i, x in enumerate(values, 1):
        a.SetValue(i, int(x))
    return a


def _points(poles: np.ndarray):
    occt_coordinates(poles, "obj")
    if poles.shape[1] == 2:
        a = Array1OfPnt2d(1, len(poles))
        for i, (x, y) in enumerate(poles.tolist(), 1):
            a.SetValue(i, gp_Pnt2d(x, y))
        return a
    a = Array1OfPnt(1, len(poles))
    for i, (x, y, z) in enumerate(poles.tolist(), 1):
        a.SetValue(i, gp_Pnt(x, y, z))
    return a


def _net(poles: np.ndarray) -> Array2OfPnt:
    occt_coordinates(poles, "obj")
    nu, nv = poles.shape[:2]
    a = Array2OfPnt(1, nu, 1, nv)
    for i, row in enumerate(poles.tolist(), 1):
        for j, (x, y, z) in enumerate(row, 1):
            a.SetValue(i, j, gp_Pnt(x, y, z))
    return a


def _weight_net(weights: np.ndarray) -> Array2OfReal:
    nu, nv = weights.shape
    a = Array2OfReal(1, nu, 1, nv)
    for i, row in enumerate(weights.tolist(), 1):
        for j, w in enumerate(row, 1):
            a.SetValue(i, j, w)
    return a


def _indexed(get, count: int) -> list:
    """[get(1), ..., get(count)]: OCCT's indexed accessors (Pole(i), Weight(i), Knot(i)).
    The array accessors (Poles(), Weights(), Knots()) are not used: on OCCT 8 they
    return references into the curve that OCP frees a second time (free(): invalid
    pointer, seen with Geom2d_BSplineCurve.Weights())."""
    return [get(i) for i in range(1, count + 1)]


def _xyz(p, dim: int) -> tuple:
    return (p.X(), p.Y()) if dim == 2 else (p.X(), p.Y(), p.Z())


# --- engine -> OCCT -------------------------------------------------------------------------
def to_occ(obj: Union[Curve, Surface], bezier: bool = False, plane: bool = False,
           analytic: bool = False) -> Union[Geom_Curve, Geom2d_Curve, Geom_Surface, TopoDS_Face]:
    """The exact OCCT geometry of an engine curve or surface.

    Curves give ``Geom_BSplineCurve`` (2-D curves with z = 0; ``plane=True`` gives a
    ``Geom2d_BSplineCurve`` instead), surfaces ``Geom_BSplineSurface``: the same
    poles, weights and knots, so the same parametrisation. With ``bezier=True`` a
    BezierCurve/BezierSurface gives ``Geom_BezierCurve/Surface``. A Bezier triangle
    goes through its collapsed-edge NURBS form (a different parametrisation:
    T(u, v) = S(u, v / (1 - u))). With ``analytic=True`` a surface of revolution that
    remembers its construction (:class:`cagd.RevolvedSurface`) gives OCCT's analytic
    surface instead (Geom_SphericalSurface, ..., Geom_SurfaceOfRevolution; trimmed to
    the engine's range by a Geom_RectangularTrimmedSurface unless that is the whole
    surface): the same point set, parametrised by the angle
    (:mod:`cagd.occ.analytic`); every other surface still gives its B-spline. A
    :class:`cagd.TrimmedSurface` gives a ``TopoDS_Face`` (a surface carries no trim in
    OCCT): its B-spline bounded by wires of its pcurves (:mod:`cagd.occ.trim`).

    Raises:
        CagdError: not an engine curve or surface, more than 3 dimensions, or OCCT
            refuses the data (its message is passed on).
    """
    if isinstance(obj, (Curve, Surface)) and obj.dim > 3:
        raise CagdError(f"obj: OCCT geometry is 3-D at most, this {type(obj).__name__} is {obj.dim}-D")
    if isinstance(obj, TrimmedSurface):
        return make_trimmed_face(obj)
    try:
        if isinstance(obj, Curve):
            if bezier and isinstance(obj, BezierCurve) and not plane:
                return _bezier_curve(obj)
            return _bspline_curve(obj.to_nurbs(), plane)
        if isinstance(obj, Surface):
            form = analytic_form(obj) if analytic else None
            if form is not None:
                return form.bounded()
            if bezier and isinstance(obj, BezierSurface):
                return _bezier_surface(obj)
            return _bspline_surface(obj.to_nurbs())
    except CagdError:
        raise
    except Exception as exc:
        if not _is_occt_error(exc):
            raise
        raise CagdError(f"obj: OCCT rejected the geometry: {type(exc).__name__} {exc}") from None
    raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")


def _bspline_curve(c: BSplineCurve, plane: bool):
    f = c.occ_form()
    if plane:
        if c.dim != 2:
            raise CagdError(f"obj: plane=True needs a 2-D curve, this one is {c.dim}-D")
        poles = _points(f.poles[:, :2])
        cls = Geom2d_BSplineCurve
    else:
        poles, cls = _points(f.poles), Geom_BSplineCurve
    knots, mults = _reals(f.knots), _ints(f.multiplicities)
    if f.weights is None:
        return cls(poles, knots, mults, f.degree, f.periodic)
    return cls(poles, _reals(f.weights), knots, mults, f.degree, f.periodic)


def _bezier_curve(c: BezierCurve):
    poles = np.zeros((len(c.control_points), 3))
    poles[:, :c.dim] = c.control_points
    if c.weights is None:
        return Geom_BezierCurve(_points(poles))
    return Geom_BezierCurve(_points(poles), _reals(c.weights))


def _bspline_surface(s: BSplineSurface):
    f = s.occ_form()
    args = (_reals(f.knots_u), _reals(f.knots_v), _ints(f.multiplicities_u), _ints(f.multiplicities_v),
            f.degree_u, f.degree_v, f.periodic_u, f.periodic_v)
    if f.weights is None:
        return Geom_BSplineSurface(_net(f.poles), *args)
    return Geom_BSplineSurface(_net(f.poles), _weight_net(f.weights), *args)


def _bezier_surface(s: BezierSurface):
    poles = np.zeros(s.control_points.shape[:2] + (3,))
    poles[..., :s.dim] = s.control_points
    if s.weights is None:
        return Geom_BezierSurface(_net(poles))
    return Geom_BezierSurface(_net(poles), _weight_net(s.weights))


# --- OCCT -> engine -------------------------------------------------------------------------
def _is_occt_error(exc: Exception) -> bool:
    """OCP raises OCCT's exceptions (Standard_DomainError, StdFail_NotDone, ...) as
    plain Exception subclasses from its own modules."""
    return type(exc).__module__.startswith("OCP")


def from_occ(geom: Union[Geom_Curve, Geom2d_Curve, Geom_Surface, TopoDS_Shape], dim: int = 3,
             oriented: bool = True, approximate: Optional[float] = None, defer_trims: bool = False) -> \
        Union[BSplineCurve, BSplineSurface, TrimmedSurface]:
    """An engine B-spline from OCCT geometry or a shape.

    Accepts any ``Geom_Curve``/``Geom2d_Curve``/``Geom_Surface`` that GeomConvert
    turns into the same B-spline (B-spline, Bezier, trimmed conics and lines,
    trimmed analytic surfaces, surfaces of revolution and extrusion), a
    ``TopoDS_Edge`` (its 3-D curve on the edge's range) or a ``TopoDS_Face`` (its
    surface on the face's UV bounds when its boundary is that box, else a trimmed
    surface, see below).
    With ``oriented`` (default) a REVERSED edge gives the reversed curve (running
    along the edge) and a REVERSED face the surface with u reversed (its normal
    S_u x S_v is the face's); ``oriented=False`` keeps OCCT's parametrisation.
    ``dim=2`` drops z from a curve.

    A face whose boundary is not its UV box gives a :class:`cagd.TrimmedSurface` (its
    pcurves as loops, :mod:`cagd.occ.trim`); one whose wires bound nothing usable (an
    open wire, curves crossing) its surface over the box, with a RuntimeWarning.
    ``defer_trims``: the face's pcurves are converted and checked on first use of the
    trim (``loops``, ``contains``, ``area``, ...; ``TrimmedSurface.deferred`` tells),
    not now; a face whose boundary is its box (one wire of pcurve lines on the box's
    sides, decided on OCCT's pcurves) is still the plain surface. A trim found unusable
    then warns as above and is the box (one loop).

    Offset curves and surfaces have no exact B-spline form: they raise unless
    ``approximate`` gives a tolerance, and are then approximated
    (GeomConvert_ApproxCurve / ApproxSurface) within it (OCCT's measured error must
    not exceed it).

    Raises:
        CagdError: a null shape, an unsupported type, unbounded geometry, an offset
            without ``approximate``, or OCCT failed (its message is passed on).
    """
    try:
        if isinstance(geom, TopoDS_Shape):
            if geom.IsNull():
                raise CagdError("geom: a null shape")
            return _from_shape(geom, dim, oriented, approximate, defer_trims)
        if isinstance(geom, Geom2d_Curve):
            return _curve_from_bspline(_as_bspline2d(geom), 2)
        if isinstance(geom, Geom_Curve):
            return _curve_from_bspline(_as_bspline_curve(geom, approximate), dim)
        if isinstance(geom, Geom_Surface):
            return _surface_from_bspline(_as_bspline_surface(geom, approximate))
    except CagdError:
        raise
    except Exception as exc:
        if not _is_occt_error(exc):
            raise
        raise CagdError(f"geom: OCCT could not convert {type(geom).__name__} to a B-spline: "
                        f"{type(exc).__name__} {exc}") from None
    raise CagdError(f"geom: expected an OCCT Geom curve/surface, edge or face, got {type(geom).__name__}")


def _from_shape(shape: TopoDS_Shape, dim: int, oriented: bool,
                approximate: Optional[float], defer_trims: bool = False) -> \
        Union[BSplineCurve, BSplineSurface, TrimmedSurface]:
    """An edge's curve on the edge's parameter range; a face's surface on the face's
    UV bounding box (the whole surface when that is its natural domain)."""
    reversed_ = oriented and shape.Orientation() == TopAbs_REVERSED
    if shape.ShapeType() == TopAbs_EDGE:
        edge = as_edge(shape)
        if BRep_Tool.Degenerated_s(edge):
            raise CagdError("geom: a degenerated edge has no 3-D curve")
        curve = BRep_Tool.Curve_s(edge, 0.0, 0.0)
        if curve is None:
            raise CagdError("geom: the edge has no 3-D curve")
        adaptor = BRepAdaptor_Curve(edge)
        first, last = adaptor.FirstParameter(), adaptor.LastParameter()
        if max(abs(first), abs(last)) > 1e99:
            raise CagdError(f"geom: the edge is unbounded (range [{first:g}, {last:g}])")
        if isinstance(curve, (Geom_BSplineCurve, Geom_BezierCurve)) and \
                _covers(curve.FirstParameter(), curve.LastParameter(), first, last):
            out = _curve_from_bspline(_as_bspline_curve(curve, approximate), dim)
        else:
            out = _curve_from_bspline(_as_bspline_curve(Geom_TrimmedCurve(curve, first, last), approximate), dim)
        return out.reversed() if reversed_ else out
    if shape.ShapeType() == TopAbs_FACE:
        face = as_face(shape)
        surface = BRep_Tool.Surface_s(face)
        a = BRepAdaptor_Surface(face, True)
        u0, u1, v0, v1 = a.FirstUParameter(), a.LastUParameter(), a.FirstVParameter(), a.LastVParameter()
        if max(abs(u0), abs(u1), abs(v0), abs(v1)) > 1e99:
            raise CagdError("geom: the face is unbounded (no boundary edges limit its surface)")
        boxed = _face_box(surface, u0, u1, v0, v1)
        surf = _surface_from_bspline(_as_bspline_surface(boxed, approximate))
        slack = 2.0 * approximate if approximate is not None and isinstance(_basis(surface), Geom_OffsetSurface) \
            else 0.0
        def plain() -> BSplineSurface:      # the face's surface, oriented like the face
            return surf.reversed("u") if reversed_ else surf

        def trimmed() -> Union[BSplineSurface, TrimmedSurface]:
            try:
                return trimmed_from_face(face, boxed, surf, reversed_, slack)
            except CagdError as exc:        # wires that bound nothing (open, crossing): the box, as before
                warnings.warn(f"geom: the face's trim is unusable ({exc}); its surface over the UV box is "
                              "used untrimmed", RuntimeWarning, stacklevel=4)
                return plain()
        return deferred_trim(face, plain(), surf.domain, trimmed) if defer_trims else trimmed()
    raise CagdError(f"geom: expected an edge or a face, got a shape of type {shape.ShapeType().name}")


def _face_box(surface: Geom_Surface, u0: float, u1: float, v0: float, v1: float) -> Geom_Surface:
    """The face's surface restricted to its UV box, made acceptable to OCCT: files from
    other systems give boxes that overshoot the surface's range by rounding or by their
    own tolerance (1e-16 to 1e-3 of the range seen) and periodic faces spanning a period
    plus 2e-15, which Geom_RectangularTrimmedSurface and the torus conversion refuse. The
    box is taken on the untrimmed basis surface: clamped into its range in a bounded
    direction; in a periodic one, a span of a whole period (to PERIOD_SPAN_TOL) is left
    untrimmed (the face is the full turn), a shorter one is trimmed where it lies (OCCT
    shifts it by periods)."""
    basis = _basis(surface)
    U0, U1, V0, V1 = basis.Bounds()
    box: List[Optional[Tuple[float, float]]] = []
    for lo, hi, A, B, period, knots in ((u0, u1, U0, U1, _period(basis, "U"), _knots(basis, "U")),
                                        (v0, v1, V0, V1, _period(basis, "V"), _knots(basis, "V"))):
        lo, hi = _snapped(lo, knots, period, B - A), _snapped(hi, knots, period, B - A)
        if hi - lo >= period * (1.0 - PERIOD_SPAN_TOL):
            box.append(None)                               # the whole period
        elif np.isfinite(period):
            box.append((lo, hi))
        else:
            lo, hi = min(max(lo, A), B), max(min(hi, B), A)
            if not hi > lo:
                raise CagdError(f"geom: the face's parameter box [{lo:.17g}, {hi:.17g}] lies outside its "
                                f"surface's range [{A:.17g}, {B:.17g}]")
            box.append(None if _covers(A, B, lo, hi) else (lo, hi))
    bu, bv = box
    if bu is None and bv is None:
        return basis
    if bu is None:
        assert bv is not None
        return Geom_RectangularTrimmedSurface(basis, bv[0], bv[1], False)
    if bv is None:
        return Geom_RectangularTrimmedSurface(basis, bu[0], bu[1], True)
    return Geom_RectangularTrimmedSurface(basis, bu[0], bu[1], bv[0], bv[1])


def _knots(surface: Geom_Surface, direction: str) -> np.ndarray:
    """The distinct knots of a B-spline surface in one direction (none for others)."""
    if not isinstance(surface, Geom_BSplineSurface):
        return np.empty(0)
    if direction == "U":
        return np.array(_indexed(surface.UKnot, surface.NbUKnots()))
    return np.array(_indexed(surface.VKnot, surface.NbVKnots()))


def _snapped(x: float, knots: np.ndarray, period: float, length: float) -> float:
    """``x`` moved onto a knot (or a knot shifted by whole periods) within
    KNOT_SNAP_TOL of the range: a face ending 6.6e-10 past a knot (seen) would else be
    cut there by OCCT's segment, which snaps to the knot itself and stretches the
    parametrisation by that much (1.2e-8 mm on the Alias space ship)."""
    if not knots.size or not np.isfinite(length) or length <= 0:
        return x
    shifted = knots if not np.isfinite(period) else knots + period * np.round((x - knots) / period)
    k = int(np.argmin(np.abs(shifted - x)))
    return float(shifted[k]) if abs(shifted[k] - x) <= KNOT_SNAP_TOL * length else x


def _period(surface: Geom_Surface, direction: str) -> float:
    """The period of a periodic direction ("U" or "V"), inf for a bounded one."""
    if direction == "U":
        return float(surface.UPeriod()) if surface.IsUPeriodic() else float("inf")
    return float(surface.VPeriod()) if surface.IsVPeriodic() else float("inf")


def _covers(a: float, b: float, first: float, last: float) -> bool:
    """Whether [first, last] is the whole [a, b] (to 1e-12 of its length)."""
    tol = 1e-12 * max(b - a, 1.0) if abs(a) < 1e99 and abs(b) < 1e99 else 0.0
    return abs(first - a) <= tol and abs(last - b) <= tol


def _basis(geom):
    """The geometry under any trimming (Geom_TrimmedCurve, RectangularTrimmedSurface)."""
    while isinstance(geom, (Geom_TrimmedCurve, Geom_RectangularTrimmedSurface)):
        geom = geom.BasisCurve() if isinstance(geom, Geom_TrimmedCurve) else geom.BasisSurface()
    return geom


def _tolerance(approximate: Optional[float], what: str) -> float:
    if approximate is None:
        raise CagdError(f"geom: {what} has no exact B-spline form; pass approximate=<tolerance> to accept "
                        "an approximation within it")
    tol = _checks.scalar(approximate, "approximate")
    if not tol >= APPROXIMATE_MIN_TOL:
        raise CagdError(f"approximate: the tolerance must be at least {APPROXIMATE_MIN_TOL:g} "
                        f"(OCCT's Precision::Confusion; below it OCCT's approximation runs for minutes), "
                        f"got {approximate!r}")
    return tol


def _checked_approximation(maker, tol: float, what: str):
    if not maker.HasResult() or maker.MaxError() > tol:
        error = maker.MaxError() if maker.HasResult() else float("nan")
        raise CagdError(f"approximate: OCCT could not approximate the {what} within {tol:g} "
                        f"(reached {error:.3g})")
    return maker.Curve() if hasattr(maker, "Curve") else maker.Surface()


def _as_bspline_curve(curve, approximate: Optional[float] = None) -> Geom_BSplineCurve:
    if isinstance(curve, Geom_BSplineCurve):
        return curve
    if isinstance(_basis(curve), Geom_OffsetCurve):
        tol = _tolerance(approximate, "an offset curve")
        return _checked_approximation(GeomConvert_ApproxCurve(curve, tol, GeomAbs_C2, 1000, 14), tol, "offset curve")
    if not isinstance(curve, (Geom_BezierCurve, Geom_TrimmedCurve)) and not curve.IsPeriodic() and (
            abs(curve.FirstParameter()) > 1e99 or abs(curve.LastParameter()) > 1e99):
        raise CagdError(f"geom: {type(curve).__name__} is unbounded; trim it first (Geom_TrimmedCurve)")
    return GeomConvert.CurveToBSplineCurve_s(curve)


def _as_bspline2d(curve) -> Geom2d_BSplineCurve:
    if isinstance(curve, Geom2d_BSplineCurve):
        return curve
    if isinstance(curve, Geom2d_OffsetCurve) or (isinstance(curve, Geom2d_TrimmedCurve)
                                                 and isinstance(curve.BasisCurve(), Geom2d_OffsetCurve)):
        raise CagdError("geom: a 2-D offset curve has no exact B-spline form")
    if not isinstance(curve, Geom2d_TrimmedCurve) and not curve.IsPeriodic() and (
            abs(curve.FirstParameter()) > 1e99 or abs(curve.LastParameter()) > 1e99):
        raise CagdError(f"geom: {type(curve).__name__} is unbounded; trim it first (Geom2d_TrimmedCurve)")
    return Geom2dConvert.CurveToBSplineCurve_s(curve)


def _as_bspline_surface(surface, approximate: Optional[float] = None) -> Geom_BSplineSurface:
    if isinstance(surface, Geom_BSplineSurface):
        return surface
    if isinstance(_basis(surface), Geom_OffsetSurface):
        tol = _tolerance(approximate, "an offset surface")
        maker = GeomConvert_ApproxSurface(surface, tol, GeomAbs_C1, GeomAbs_C1, 14, 14, 200, 0)
        return _checked_approximation(maker, tol, "offset surface")
    u0, u1, v0, v1 = surface.Bounds()
    if max(abs(u0), abs(u1), abs(v0), abs(v1)) > 1e99:
        raise CagdError(f"geom: {type(surface).__name__} is unbounded; trim it first "
                        "(Geom_RectangularTrimmedSurface)")
    return GeomConvert.SurfaceToBSplineSurface_s(surface)


def _curve_from_bspline(g, dim: int) -> BSplineCurve:
    planar = isinstance(g, Geom2d_BSplineCurve)
    n, k = g.NbPoles(), g.NbKnots()
    poles = np.array([_xyz(p, 2 if planar else 3) for p in _indexed(g.Pole, n)])
    weights = np.array(_indexed(g.Weight, n)) if g.IsRational() else None
    return BSplineCurve.from_occ_form(poles, weights, np.array(_indexed(g.Knot, k)),
                                      np.array(_indexed(g.Multiplicity, k), dtype=int),
                                      g.Degree(), g.IsPeriodic(), None if planar else dim)


def _surface_from_bspline(g: Geom_BSplineSurface) -> BSplineSurface:
    nu, nv = g.NbUPoles(), g.NbVPoles()
    poles = np.array([[_xyz(g.Pole(i, j), 3) for j in range(1, nv + 1)] for i in range(1, nu + 1)])
    weights = None
    if g.IsURational() or g.IsVRational():
        weights = np.array([[g.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)])
    ku, kv = g.NbUKnots(), g.NbVKnots()
    return BSplineSurface.from_occ_form(poles, weights, np.array(_indexed(g.UKnot, ku)),
                                        np.array(_indexed(g.VKnot, kv)),
                                        np.array(_indexed(g.UMultiplicity, ku), dtype=int),
                                        np.array(_indexed(g.VMultiplicity, kv), dtype=int), g.UDegree(), g.VDegree(),
                                        g.IsUPeriodic(), g.IsVPeriodic())
