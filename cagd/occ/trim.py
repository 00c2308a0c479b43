"""OCCT faces <-> :class:`cagd.TrimmedSurface` (issue 15).

Reading: a face's wires give loops of pcurves (BRepTools_WireExplorer on the face taken
FORWARD, each edge's pcurve on its range, run backwards for a REVERSED edge; a seam
edge gives its two pcurves, a degenerated edge its pole line). The pcurves are
converted exactly (Geom2dConvert: lines, conics and B-splines become 2-D B-splines or
NURBS on their range) in OCCT's (U, V), then mapped into the engine surface's
parameters:

- B-spline, Bezier, plane and extrusion/revolution faces of B-spline curves keep OCCT's
  parameters (the engine surface is the same B-spline);
- an angle direction of an analytic surface (cylinder, cone, sphere, torus, revolution)
  is, on the engine's NURBS form, the rational quadratic circle's parameter: on each
  knot span [a, b] of sweep d = b - a, tan((theta - m) / 2) = (2 s - 1) tan(d / 4),
  m = (a + b) / 2, t = a + s d (:func:`cagd.surfaces.revolution.arc_angle`; which map a
  direction has is measured on the face, OCCT vs engine points, to 1e-9 of the size).
  Pcurves constant in such a direction, and iso-lines along it, map exactly; any other
  pcurve is fitted (C1 cubic, :func:`cagd.surfaces.trimmed.hermite_fit`) within
  PCURVE_FIT_TOL of the parameter box;
- a REVERSED face gives the surface with u reversed (as :func:`cagd.occ.from_occ` always
  did), the loops mirrored and run backwards, so that the normal is the face's.

Each edge's 3-D curve is kept too (``TrimmedSurface.edges``: :func:`cagd.occ.from_occ`
of the edge, exact, running like its pcurve, over the pcurve's range), so that
``boundary()`` gives the file's own edges.

Periodic directions: consecutive pcurves are moved by whole periods to meet, and each
loop by whole periods into the engine surface's window.

Writing: a face on the engine surface's exact B-spline with one edge per loop curve
(BRepBuilderAPI_MakeEdge of the Geom2d curve on the surface, sharing vertices), 3-D
curves the face's known edge curves (``TrimmedSurface.edges``, e.g. read from a file;
BRepLib.SameParameter measures the edge's tolerance), else by BRepLib.BuildCurves3d_s;
curves collapsing to a point become degenerated edges, and pairs of pcurves one period
apart on the same iso-line a seam edge.
"""
from __future__ import annotations

import contextlib
import contextvars
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np
from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve2d
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeVertex,
                                BRepBuilderAPI_MakeWire)
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepLib import BRepLib
from OCP.BRepTools import BRepTools_WireExplorer
from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface, Geom_Plane, Geom_Surface
from OCP.GeomAbs import GeomAbs_C2
from OCP.Geom2d import Geom2d_BSplineCurve, Geom2d_Line, Geom2d_TrimmedCurve
from OCP.gp import gp_Pnt
from OCP.ShapeFix import ShapeFix_Face
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FORWARD, TopAbs_REVERSED, TopAbs_WIRE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS_Face

from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from ..surfaces._trim_box import BOX_TOL, side_of, turn_window
from ..surfaces.trimmed import CLOSURE_TOL, TrimmedSurface, _end, hermite_fit
from .compat import as_edge, as_face, as_wire

MAP_TOL = 1e-9          # relative (surface size): an assumed parameter map must reproduce OCCT's points to this
PCURVE_FIT_TOL = 1e-12  # relative (parameter box): fitted pcurves (non-iso pcurves on angle directions)
MAX_GAP = 1e-2          # relative (parameter box): a wire whose pcurves do not meet within this is refused
DEGENERATE_TOL = 1e-7   # 3-D (mm): an edge whose image is within this of one point is degenerated
CONSTANT_TOL = 1e-12    # relative (parameter box): a pcurve coordinate varying less is constant (an iso-line)
CURVE3D_TOL = 1e-12     # relative (surface size): BuildCurves3d's approximation of the edges' 3-D curves
MAX_CURVE3D_SEGMENTS = 1000
MAP_SAMPLES = 7         # points per direction of the map test
SAME_PARAMETER_RATIO = 2.0  # make_face: a known edge curve this close (times its measured distance from S(c)) to
#                             S(c(t)) at the same t is SameParameter with its pcurve as it is (see _attach_curve)


# --- parameter maps ------------------------------------------------------------------------------
class _ArcMap:
    """OCCT angle -> engine parameter along one direction of a rational-circle NURBS
    form with knots ``knots`` (distinct, the spans' ends are angles) and ``period``
    (inf for a bounded direction); see the module docstring."""

    def __init__(self, knots: np.ndarray, period: float):
        self.knots = knots
        self.period = period

    def _split(self, theta: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        a = self.knots[0]
        if np.isfinite(self.period):
            k = np.floor((theta - a) / self.period)
            w = theta - k * self.period
            return w, k * self.period
        return theta, np.zeros_like(theta)

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        w, shift = self._split(np.asarray(theta, dtype=float))
        K = self.knots
        j = np.clip(np.searchsorted(K, w, side="right") - 1, 0, len(K) - 2)
        a, b = K[j], K[j + 1]
        d = b - a
        s = (np.tan((w - 0.5 * (a + b)) / 2.0) / np.tan(d / 4.0) + 1.0) / 2.0
        t = a + s * d
        at_knot = np.isin(w, K)
        t = np.where(at_knot, w, t)
        return t + shift

    def derivative(self, theta: np.ndarray) -> np.ndarray:
        """dt/dtheta = d sec^2(x / 2) / (4 tan(d / 4)), x = theta - m."""
        c, x = self._local(theta)
        return c / np.cos(x / 2.0) ** 2

    def second_derivative(self, theta: np.ndarray) -> np.ndarray:
        """d2t/dtheta2 = d sec^2(x / 2) tan(x / 2) / (4 tan(d / 4))."""
        c, x = self._local(theta)
        return c * np.tan(x / 2.0) / np.cos(x / 2.0) ** 2

    def _local(self, theta: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        w, _ = self._split(np.asarray(theta, dtype=float))
        K = self.knots
        j = np.clip(np.searchsorted(K, w, side="right") - 1, 0, len(K) - 2)
        a, b = K[j], K[j + 1]
        d = b - a
        return d / (4.0 * np.tan(d / 4.0)), w - 0.5 * (a + b)


class _Identity:
    knots = np.empty(0)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return np.asarray(x, dtype=float)

    def derivative(self, x: np.ndarray) -> np.ndarray:
        return np.ones_like(np.asarray(x, dtype=float))

    def second_derivative(self, x: np.ndarray) -> np.ndarray:
        return np.zeros_like(np.asarray(x, dtype=float))


Map = Union[_ArcMap, _Identity]


def _point(p) -> np.ndarray:
    return np.array([p.X(), p.Y(), p.Z()])


def _point2d(p) -> np.ndarray:
    return np.array([p.X(), p.Y()])


def parameter_maps(geom: Geom_Surface, engine: BSplineSurface, slack: float = 0.0) -> Tuple[Map, Map]:
    """The maps (u, v) OCCT -> engine of the face's surface ``geom`` and its engine
    B-spline (not reversed), chosen among identity and the rational circle's per
    direction by comparing points on a MAP_SAMPLES x MAP_SAMPLES grid inside the
    engine's domain (the same numbers in OCCT's parameters where both are angles),
    to MAP_TOL of the size plus ``slack`` (an approximation's tolerance).

    Raises:
        CagdError: no combination reproduces OCCT's points within that.
    """
    from .convert import _basis
    if isinstance(_basis(geom), (Geom_BSplineSurface, Geom_BezierSurface, Geom_Plane)) and slack == 0.0:
        return _Identity(), _Identity()       # GeomConvert keeps their parameters
    (a0, a1), (b0, b1) = engine.domain
    grid = np.meshgrid(np.linspace(a0, a1, MAP_SAMPLES + 2)[1:-1], np.linspace(b0, b1, MAP_SAMPLES + 2)[1:-1],
                       indexing="ij")
    U, V = grid[0].ravel(), grid[1].ravel()
    want = np.array([_point(geom.Value(float(x), float(y))) for x, y in zip(U, V)])
    tol = MAP_TOL * max(engine.size, 1e-300) + slack
    pu = engine.domain[0][1] - engine.domain[0][0] if engine.periodic_u else float("inf")
    pv = engine.domain[1][1] - engine.domain[1][0] if engine.periodic_v else float("inf")
    cu: List[Map] = [_Identity(), _ArcMap(np.unique(engine.knots_u), pu)]
    cv: List[Map] = [_Identity(), _ArcMap(np.unique(engine.knots_v), pv)]
    combos = []
    for mu in cu:
        for mv in cv:
            with np.errstate(all="ignore"):
                x, y = mu(U), mv(V)
            if np.all(np.isfinite(x)) and np.all(np.isfinite(y)):
                combos.append((mu, mv, x, y))
    points: List[Optional[np.ndarray]]
    try:                                   # every candidate in one evaluation
        points = list(np.split(_few_points(engine, np.concatenate([c[2] for c in combos]),
                                           np.concatenate([c[3] for c in combos])), len(combos))) if combos else []
    except CagdError:                      # a candidate leaves the domain: one at a time
        points = []
        for _, _, x, y in combos:
            try:
                points.append(_few_points(engine, x, y))
            except CagdError:
                points.append(None)
    best = (np.inf, None)
    for (mu, mv, _, _), got in zip(combos, points):
        if got is None:
            continue
        err = float(np.linalg.norm(got - want, axis=1).max())
        if err <= tol:
            return mu, mv
        best = min(best, (err, None), key=lambda e: e[0])
    raise CagdError(f"face: no parameter map between OCCT's surface ({type(geom).__name__}) and its B-spline "
                    f"reproduces OCCT's points (best {best[0]:.3g}, tol {tol:.3g})")


def _few_points(engine: BSplineSurface, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """engine(u, v) for a few points, through the local bases (Piegl & Tiller A4.4):
    without the pp table that evaluation builds once per surface for many points
    (building it for a face's map test alone cost as much as the test). Raises
    CagdError, as evaluation does, for parameters outside a bounded direction."""
    uf, vf, _ = engine._flat(u, v)
    h = engine._evaluate_by_basis(uf, vf, 0, 0)[0, 0]
    return h[:, :-1] / h[:, -1:] if engine.is_rational else h


# --- reading ---------------------------------------------------------------------------------------
def _pcurve(edge, face: TopoDS_Face) -> BSplineCurve:
    """The edge's pcurve on the face over the edge's range, as an engine 2-D B-spline,
    running along the edge as oriented in the wire."""
    from .convert import _as_bspline2d, _curve_from_bspline
    adaptor = BRepAdaptor_Curve2d(edge, face)
    first, last = adaptor.FirstParameter(), adaptor.LastParameter()
    curve = adaptor.Curve()
    if curve is None:
        raise CagdError("face: an edge has no pcurve on the face")
    backwards = edge.Orientation() == TopAbs_REVERSED
    if isinstance(curve, Geom2d_Line):
        p, q = curve.Value(first), curve.Value(last)
        ends = [[p.X(), p.Y()], [q.X(), q.Y()]]
        # reversed, a segment keeps its knots (reversed() maps the ends exactly)
        return BSplineCurve(np.array(ends[::-1] if backwards else ends), 1, [first, first, last, last])
    else:
        if abs(curve.FirstParameter() - first) > 0 or abs(curve.LastParameter() - last) > 0:
            curve = Geom2d_TrimmedCurve(curve, first, last)
        out = _curve_from_bspline(_as_bspline2d(curve), 2)
    return out.reversed() if backwards else out


#: while a file is read (:func:`shared_edges`): the edges converted so far, by hash (an
#: edge's hash ignores its orientation), as [(edge, its curve unoriented or None)]
_EDGES: contextvars.ContextVar[Optional[Dict[int, List[Tuple[Any, Optional[BSplineCurve]]]]]] = \
    contextvars.ContextVar("cagd_occ_edges", default=None)


@contextlib.contextmanager
def shared_edges() -> Iterator[None]:
    """Within it, an edge's 3-D curve is converted once for all the faces that share the
    edge (a closed shell: every edge twice); the cache ends with the block."""
    token = _EDGES.set({})
    try:
        yield
    finally:
        _EDGES.reset(token)


def _unoriented_edge_curve(edge) -> Optional[BSplineCurve]:
    """The edge's 3-D curve in OCCT's direction, clamped (None: see :func:`_edge_curve`),
    from the cache of :func:`shared_edges` where one is open."""
    cache = _EDGES.get()
    key = hash(edge)
    for seen, curve in (cache or {}).get(key, ()):
        if seen.IsSame(edge):
            return curve
    curve = None
    if not (BRep_Tool.Degenerated_s(edge) or BRep_Tool.Curve_s(edge, 0.0, 0.0) is None):
        from .convert import from_occ
        try:
            got = from_occ(edge, oriented=False)
        except CagdError:
            got = None
        if isinstance(got, BSplineCurve) and got.dim == 3:
            curve = got.clamped() if got.periodic else got
    if cache is not None:
        cache.setdefault(key, []).append((edge, curve))
    return curve


def _edge_curve(edge, pcurve: BSplineCurve) -> Optional[BSplineCurve]:
    """The edge's 3-D curve as an engine B-spline (exact: :func:`cagd.occ.from_occ` of
    the edge, run backwards for a REVERSED edge like its pcurve), over the pcurve's
    range (affinely, where OCCT's 3-D range differs: an edge not SameRange); None for a
    degenerated edge, one without a 3-D curve, or one OCCT cannot convert."""
    curve = _unoriented_edge_curve(edge)
    if curve is None:
        return None
    if edge.Orientation() == TopAbs_REVERSED:
        curve = curve.reversed()
    a, b = pcurve.domain
    return curve if curve.domain == (a, b) else curve.reparametrized(a, b)


def _wires(face: TopoDS_Face) -> Tuple[List[List[BSplineCurve]], List[List[Optional[BSplineCurve]]]]:
    """(loops of pcurves, their edges' 3-D curves (:func:`_edge_curve`)), wire by wire."""
    out, edges = [], []
    ex = TopExp_Explorer(face, TopAbs_WIRE)
    while ex.More():
        wire = as_wire(ex.Current())
        loop, row = [], []
        wex = BRepTools_WireExplorer(wire, face)
        while wex.More():
            pc = _pcurve(wex.Current(), face)
            loop.append(pc)
            row.append(_edge_curve(wex.Current(), pc))
            wex.Next()
        if loop:
            out.append(loop)
            edges.append(row)
        ex.Next()
    return out, edges


def _crossings_of(c: BSplineCurve, k: int, knots: np.ndarray) -> np.ndarray:
    """Parameters where coordinate k of c crosses a value of ``knots`` (sampled, then
    bisected to rounding, all crossings at once)."""
    a, b = c.domain
    t = np.linspace(a, b, 257)
    x = c(t)[:, k]
    which, idx = [], []
    for K in knots:
        s = np.sign(x - K)
        i = np.flatnonzero(s[:-1] * s[1:] < 0)
        which.append(np.full(len(i), K))
        idx.append(i)
    if not knots.size or not sum(len(i) for i in idx):
        return np.array([])
    K, i = np.concatenate(which), np.concatenate(idx)
    lo, hi = t[i], t[i + 1]
    flo = x[i] - K
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        fm = c(mid)[:, k] - K
        left = (fm < 0) == (flo < 0)
        lo, flo, hi = np.where(left, mid, lo), np.where(left, fm, flo), np.where(left, hi, mid)
    return 0.5 * (lo + hi)


def _mapped(c: BSplineCurve, mu: Map, mv: Map, tol: float, scale: float) -> BSplineCurve:
    """The curve in engine parameters (see the module docstring): exact for identity
    maps, constant coordinates and iso-lines along a mapped direction; else fitted."""
    maps = (mu, mv)
    P = c.control_points
    ident = [isinstance(m, _Identity) for m in maps]
    if all(ident):
        return c
    const = [bool(np.all(np.abs(P[:, k] - P[0, k]) <= CONSTANT_TOL * scale)) for k in (0, 1)]
    if all(ident[k] or const[k] for k in (0, 1)):
        Q = P.copy()
        for k in (0, 1):
            if not ident[k]:
                Q[:, k] = float(maps[k](np.array([P[0, k]]))[0])
        return c.with_control_points(Q)
    for k in (0, 1):                      # an iso-line along mapped direction k: a straight segment
        other = 1 - k
        if const[other] and not ident[k]:
            x = P[:, k]
            if np.all(np.diff(x) >= 0) or np.all(np.diff(x) <= 0):
                ends = np.stack([_end(c, 0), _end(c, 1)])
                y = ends[:, other] if ident[other] else maps[other](ends[:, other])
                e = np.empty((2, 2))
                e[:, k] = maps[k](ends[:, k])
                e[:, other] = y
                a, b = c.domain
                return BSplineCurve(e, 1, [a, a, b, b])
    a, b = c.domain
    extra = [_crossings_of(c, k, maps[k].knots) for k in (0, 1) if not ident[k]]
    breaks = np.unique(np.concatenate([[a], c._breaks_within(a, b), *extra, [b]]))

    def f(t: np.ndarray) -> np.ndarray:
        uv = c(t)
        return np.stack([mu(uv[:, 0]), mv(uv[:, 1])], axis=1)

    last: List[Tuple[bytes, np.ndarray]] = []

    def second(t: np.ndarray) -> np.ndarray:
        """c.derivatives(t, 2), once for df and ddf at the same t (its orders 0 and 1 are
        c.derivatives(t, 1) bit for bit: rational derivatives are built order by order)."""
        key = t.tobytes()
        if not last or last[0][0] != key:
            last[:] = [(key, c.derivatives(t, 2))]
        return last[0][1]

    def df(t: np.ndarray) -> np.ndarray:
        d = second(t)
        return np.stack([mu.derivative(d[0, :, 0]) * d[1, :, 0], mv.derivative(d[0, :, 1]) * d[1, :, 1]], axis=1)

    def ddf(t: np.ndarray) -> np.ndarray:
        d = second(t)
        return np.stack([m.second_derivative(d[0, :, k]) * d[1, :, k] ** 2 + m.derivative(d[0, :, k]) * d[2, :, k]
                         for k, m in enumerate(maps)], axis=1)

    fit, err, ok = hermite_fit(f, df, breaks, tol, ddf)
    if not ok:
        raise CagdError(f"face: a pcurve could not be mapped to the B-spline's parameters within {tol:.3g} "
                        f"(reached {err:.3g})")
    return fit


from ..surfaces._trim_box import chained as _chained, into_window as _into_window  # noqa: E402


def _is_box(loops: List[List[BSplineCurve]], domain: Tuple[Tuple[float, float], Tuple[float, float]],
            periods: Tuple[float, float]) -> bool:
    """One loop of iso-lines on the sides of the parameter box, in a periodic direction
    anywhere a period apart (:func:`cagd.surfaces._trim_box.is_box`)."""
    from ..surfaces._trim_box import is_box
    return is_box(loops, domain, BOX_TOL, periods)


def natural_boundary(face: TopoDS_Face, domain: Tuple[Tuple[float, float], Tuple[float, float]],
                     periods: Tuple[float, float] = (float("inf"), float("inf"))) -> bool:
    """True when the face's boundary is its parameter box ``domain`` (the engine
    surface's, whose parameters equal OCCT's on the box's sides; in a direction of
    finite period, ``periods``, the sides may be anywhere a whole period apart): one
    wire, every pcurve a line, or a B-spline with its poles, along a side of the box (to
    BOX_TOL), the lengths between their ends adding up to the perimeter. Decided on
    OCCT's pcurves without converting them; where it says False the converted loops are
    compared with the box (:func:`trimmed_from_face`)."""
    fwd = as_face(face.Oriented(TopAbs_FORWARD))
    wires = TopExp_Explorer(fwd, TopAbs_WIRE)
    if not wires.More():
        return False
    wires.Next()
    if wires.More():
        return False
    (u0, u1), (v0, v1) = domain
    tol = BOX_TOL * max(u1 - u0, v1 - v0)
    pieces = []
    ex = TopExp_Explorer(fwd, TopAbs_EDGE)
    while ex.More():
        adaptor = BRepAdaptor_Curve2d(as_edge(ex.Current()), fwd)
        curve = adaptor.Curve()
        a, b = adaptor.Value(adaptor.FirstParameter()), adaptor.Value(adaptor.LastParameter())
        ends = np.array([[a.X(), a.Y()], [b.X(), b.Y()]])
        if isinstance(curve, Geom2d_Line):
            P = ends
        elif isinstance(curve, Geom2d_BSplineCurve):      # its poles on the side: all of it is
            P = np.array([(q.X(), q.Y()) for q in map(curve.Pole, range(1, curve.NbPoles() + 1))])
        else:
            return False
        pieces.append((P, ends))
        ex.Next()
    if not pieces:
        return False
    box = turn_window(np.concatenate([P for P, _ in pieces]), domain, periods, tol)
    length = 0.0
    for P, ends in pieces:
        side = side_of(P, box, tol)
        if side is None:
            return False
        length += abs(ends[1, 1 - side] - ends[0, 1 - side])
    return abs(length - 2.0 * ((u1 - u0) + (v1 - v0))) <= 8 * tol


def _periods(s: BSplineSurface) -> Tuple[float, float]:
    """The engine surface's periods per direction (inf where bounded)."""
    (a0, a1), (b0, b1) = s.domain
    return (a1 - a0 if s.periodic_u else float("inf"), b1 - b0 if s.periodic_v else float("inf"))


def deferred_trim(face: TopoDS_Face, surface: BSplineSurface,
                  domain: Tuple[Tuple[float, float], Tuple[float, float]],
                  build: Callable[[], Surface]) -> Union[BSplineSurface, TrimmedSurface]:
    """``surface`` itself where the face's boundary is its box (:func:`natural_boundary`),
    else a :class:`TrimmedSurface` on it whose loops ``build()`` converts on first use
    (within the :func:`shared_edges` cache open now, if any)."""
    if natural_boundary(face, domain, _periods(surface)):
        return surface
    cache = _EDGES.get()

    def run() -> Surface:
        token = _EDGES.set(cache)
        try:
            return build()
        finally:
            _EDGES.reset(token)
    return TrimmedSurface._deferred(surface, run)


def trimmed_from_face(face: TopoDS_Face, geom: Geom_Surface, engine: BSplineSurface, reversed_: bool,
                      slack: float = 0.0) -> Union[BSplineSurface, TrimmedSurface]:
    """The TrimmedSurface of an OCCT face on ``engine`` (the B-spline of ``geom``, the
    face's surface on its UV box; u reversed when ``reversed_``), or ``engine``
    (reversed) itself when the face's boundary is its parameter box. ``slack``: the
    tolerance of an approximated surface (offsets)."""
    fwd = as_face(face.Oriented(TopAbs_FORWARD))
    wires, edges = _wires(fwd)
    surface = engine.reversed("u") if reversed_ else engine
    if not wires:
        return surface
    mu, mv = parameter_maps(geom, engine, slack)
    (a0, a1), (b0, b1) = engine.domain
    size = max(a1 - a0, b1 - b0)
    periods = _periods(engine)
    from .convert import _basis
    basis = _basis(geom)                   # a trimmed surface is not periodic, its basis may be
    occ_periods = (float(basis.UPeriod()) if basis.IsUPeriodic() else float("inf"),
                   float(basis.VPeriod()) if basis.IsVPeriodic() else float("inf"))
    loops = []
    for w in wires:
        w = _into_window(_chained(w, occ_periods), occ_periods, engine.domain)
        loops.append([_mapped(c, mu, mv, PCURVE_FIT_TOL * size, size) for c in w])
    loops = [_into_window(_chained(lp, periods), periods, engine.domain) for lp in loops]
    if _is_box(loops, engine.domain, periods):
        return surface
    if reversed_:
        loops = [[_mirrored(c, a0 + a1) for c in lp[::-1]] for lp in loops]
        edges = [[None if e is None else e.reversed() for e in row[::-1]] for row in edges]
    # the loops' sample points (_samples) decide how far they leave the box and which is
    # the outer one; their control hulls bound both, and the samples are computed only
    # where the bounds do not decide (the result is the same either way)
    hulls = [[_hull(c) for c in lp] for lp in loops]
    points: List[np.ndarray] = []
    gap = _gaps(loops)
    if _overshoot([h for lp in hulls for h in lp], surface) < 0.5 * (CLOSURE_TOL * size):
        over = 0.0                         # 2 over < CLOSURE_TOL size: it cannot change tol
    else:
        points = [np.concatenate([_samples(c) for c in lp]) for lp in loops]
        over = _overshoot(points, surface)
    if max(gap, over) > MAX_GAP * size:
        over = _overshoot([np.concatenate([_samples(c) for c in lp]) for lp in loops], surface)
        raise CagdError(f"face: its wires do not close in (u, v) within {MAX_GAP:g} of the parameter box "
                        f"(gap {gap:.3g}, outside the box by {over:.3g})")
    outer = _outer_by_hulls(loops, hulls) if len(loops) > 1 else 0
    if outer is None:
        points = points or [np.concatenate([_samples(c) for c in lp]) for lp in loops]
        boxes = [np.ptp(P, axis=0).prod() for P in points]
        outer = int(np.argmax(boxes))
    order = [outer] + [i for i in range(len(loops)) if i != outer]
    tol = max(CLOSURE_TOL * size, 2.0 * gap, 2.0 * over)
    return TrimmedSurface(surface, [loops[i] for i in order], tol=tol, edges=[edges[i] for i in order])


#: relative (to the largest coordinate of a curve's control points, times its weights'
#: ratio): how far rounding may put an evaluated point beyond the control points' box
#: (the curve lies in their hull; the engine's evaluation errs by 1.7e-14 at degree 20)
EVAL_MARGIN = 1e-12


def _hull(c: BSplineCurve) -> np.ndarray:
    """(2, 2): a box [lo, hi] holding every evaluated point of c (rounding included)."""
    P = c.control_points
    ratio = 1.0 if c.weights is None else float(c.weights.max() / c.weights.min())
    margin = EVAL_MARGIN * float(np.abs(P).max()) * ratio
    return np.stack([P.min(axis=0) - margin, P.max(axis=0) + margin])


def _outer_by_hulls(loops: List[List[BSplineCurve]], hulls: List[List[np.ndarray]]) -> Optional[int]:
    """The loop whose sampled box (np.ptp of its _samples, their product) is the largest,
    where the bounds decide: at least the box of its curves' ends (samples themselves),
    at most that of the control hulls. None where they do not."""
    low = np.array([np.ptp(np.array([e for c in lp for e in (_end(c, 0), _end(c, 1))]), axis=0).prod()
                    for lp in loops])
    high = np.array([np.ptp(np.concatenate(h), axis=0).prod() for h in hulls])
    i = int(np.argmax(low))
    others = np.delete(high, i)
    return i if bool(np.all(low[i] > others)) else None


def _mirrored(c: BSplineCurve, total: float) -> BSplineCurve:
    """c under u -> total - u, run backwards."""
    P = c.control_points.copy()
    P[:, 0] = total - P[:, 0]
    return c.with_control_points(P).reversed()


def _gaps(loops: List[List[BSplineCurve]]) -> float:
    gap = 0.0
    for lp in loops:
        for i, c in enumerate(lp):
            n = lp[(i + 1) % len(lp)]
            gap = max(gap, float(np.linalg.norm(_end(c, 1) - _end(n, 0))))
    return gap


def _samples(c: BSplineCurve, per_span: int = 16) -> np.ndarray:
    """Points of c (its control points can lie far off a rational curve)."""
    a, b = c.domain
    br = np.concatenate([[a], c._breaks_within(a, b), [b]])
    t = (br[:-1, None] + (br[1:] - br[:-1])[:, None] * np.linspace(0, 1, per_span)[None]).ravel()
    return c(np.append(t, b))


def _overshoot(points: List[np.ndarray], surface: Surface) -> float:
    """How far the loops' sample points (arrays of points) leave the bounded directions."""
    (u0, u1), (v0, v1) = surface.domain
    P = np.concatenate(points)
    out = 0.0
    if not surface.periodic_u:
        out = max(out, u0 - P[:, 0].min(), P[:, 0].max() - u1)
    if not surface.periodic_v:
        out = max(out, v0 - P[:, 1].min(), P[:, 1].max() - v1)
    return max(out, 0.0)


# --- writing ---------------------------------------------------------------------------------------
#: a vertex's tolerance covers the 3-D gap it closes between consecutive pcurves, with this margin
VERTEX_MARGIN = 1.5


def make_trimmed_face(ts: TrimmedSurface, tol: float = 1e-7) -> TopoDS_Face:
    """The OCCT face of a TrimmedSurface (see the module docstring), checked by
    BRepCheck_Analyzer (ShapeFix_Face once if needed).

    Raises:
        CagdError: OCCT could not build the edges, wires or face, or the face is invalid.
    """
    from .convert import to_occ
    nurbs = ts.surface.to_nurbs()
    geom = to_occ(nurbs)
    builder = BRep_Builder()
    wires = []
    known: List[Tuple[np.ndarray, object]] = []        # one vertex per 3-D point (closed edges, poles)
    merge = max(tol, DEGENERATE_TOL)

    def vertex(p: np.ndarray, gap: float):
        for q, v in known:
            if np.linalg.norm(p - q) <= max(merge, gap):
                builder.UpdateVertex(v, max(BRep_Tool.Tolerance_s(v), VERTEX_MARGIN * (gap + np.linalg.norm(p - q))))
                return v
        v = BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, p))).Vertex()
        if gap > 0.0:                               # the loop's closing gap there (up to ts.tol)
            builder.UpdateVertex(v, max(BRep_Tool.Tolerance_s(v), VERTEX_MARGIN * gap))
        known.append((p, v))
        return v

    for i, loop in enumerate(ts.loops):
        starts = [c(c.domain[0]) for c in loop]
        ends = [c(c.domain[1]) for c in loop]
        p3, e3 = [nurbs(float(p[0]), float(p[1])) for p in _clipped(starts, nurbs)], \
            [nurbs(float(p[0]), float(p[1])) for p in _clipped(ends, nurbs)]
        # the gap each vertex closes, plus how far OCCT's extrapolation of the surface
        # may put a pcurve's end that leaves the domain (the engine clips it)
        reach = [_clip_reach(nurbs, starts[j]) + _clip_reach(nurbs, ends[j - 1]) for j in range(len(loop))]
        gaps = [float(np.linalg.norm(p3[j] - e3[j - 1])) + reach[j] for j in range(len(loop))]
        vertices = [vertex(p, g) for p, g in zip(p3, gaps)]
        maker = BRepBuilderAPI_MakeWire()
        for j, c in enumerate(loop):
            pc = to_occ(c, plane=True)
            a, b = c.domain
            v1, v2 = vertices[j], vertices[(j + 1) % len(loop)]
            image = _image(nurbs, c)
            if np.ptp(image, axis=0).max() <= DEGENERATE_TOL:
                edge = _degenerated(builder, pc, geom, v1, a, b, tol)
            else:
                em = BRepBuilderAPI_MakeEdge(pc, geom, v1, v2, a, b)
                if not em.IsDone():
                    raise CagdError(f"loops[{i}][{j}]: OCCT could not make an edge on the surface "
                                    f"(error {em.Error()})")
                edge = em.Edge()
                known_curve = None if ts.edges is None else ts.edges[i][j]
                if known_curve is not None and not _attach_curve(builder, edge, known_curve, c, nurbs, tol):
                    edge = BRepBuilderAPI_MakeEdge(pc, geom, v1, v2, a, b).Edge()   # as without: BuildCurves3d
            maker.Add(edge)
            if not maker.IsDone():
                raise CagdError(f"loops[{i}][{j}]: does not connect to the previous edge (OCCT wire error "
                                f"{maker.Error()})")
        wires.append(maker.Wire())
    fm = BRepBuilderAPI_MakeFace(geom, wires[0], True)
    for w in wires[1:]:
        fm.Add(w)
    if not fm.IsDone():
        raise CagdError(f"surface: OCCT could not make the trimmed face (error {fm.Error()})")
    face = fm.Face()
    BRepLib.BuildCurves3d_s(face, CURVE3D_TOL * max(nurbs.size, 1e-300), GeomAbs_C2, 14, MAX_CURVE3D_SEGMENTS)
    if not BRepCheck_Analyzer(face).IsValid():
        fixer = ShapeFix_Face(face)
        fixer.Perform()
        face = as_face(fixer.Face())
        if not BRepCheck_Analyzer(face).IsValid():
            raise CagdError("surface: OCCT reports the trimmed face as invalid (BRepCheck), also after ShapeFix")
    return face


def _attach_curve(builder: BRep_Builder, edge, curve: BSplineCurve, pcurve: BSplineCurve, surface: BSplineSurface,
                  tol: float) -> bool:
    """Give the edge (built on its pcurve) the known 3-D curve over the pcurve's range
    (instead of BuildCurves3d's approximation); False where that would change the pcurve
    by more than ``tol`` (the caller then builds the edge without it). Where the two agree
    at the same parameter about as well as the curve and the point set S(c) do
    (SAME_PARAMETER_RATIO times the distance of S(c(t)) from the curve, measured: a
    file's edge tolerance), the edge is SameParameter with that tolerance and the pcurve
    is kept as it is; else (a conic's rational form, parametrised otherwise)
    BRepLib.SameParameter reparametrises the pcurve against the curve, which must reach
    VERTEX_MARGIN times ``tol``."""
    from ..surfaces.trimmed import _inside_domain, _samples, edge_deviation
    from .convert import to_occ
    a, b = pcurve.domain
    t = _samples([pcurve, curve])
    uv = pcurve(t)
    want = surface(*_inside_domain(surface, uv[:, 0], uv[:, 1]))
    same = float(np.linalg.norm(curve(t) - want, axis=1).max())
    if same <= max(tol, SAME_PARAMETER_RATIO * edge_deviation(curve, t, want)):
        builder.UpdateEdge(edge, to_occ(curve), max(tol, VERTEX_MARGIN * same))
        builder.Range(edge, a, b)
        builder.SameParameter(edge, True)
        return True
    builder.UpdateEdge(edge, to_occ(curve), tol)
    builder.Range(edge, a, b)
    builder.SameParameter(edge, False)
    BRepLib.SameParameter_s(edge, tol)
    return BRep_Tool.SameParameter_s(edge) and BRep_Tool.Tolerance_s(edge) <= VERTEX_MARGIN * tol


def _clip_reach(s: BSplineSurface, p: np.ndarray) -> float:
    """A bound on |S(p) - S(clipped p)| for a (u, v) outside the domain by a little: the
    first partials at the clipped point times the distance clipped (twice, for the
    curvature over that distance)."""
    q = _clipped([p], s)[0]
    du, dv = abs(float(p[0] - q[0])), abs(float(p[1] - q[1]))
    if du == 0.0 and dv == 0.0:
        return 0.0
    d = s.derivatives(float(q[0]), float(q[1]), 1, 1)
    return 2.0 * (float(np.linalg.norm(d[1, 0])) * du + float(np.linalg.norm(d[0, 1])) * dv)


def _clipped(points: List[np.ndarray], s: BSplineSurface) -> List[np.ndarray]:
    (u0, u1), (v0, v1) = s.domain
    out = []
    for p in points:
        q = p.copy()
        if not s.periodic_u:
            q[0] = min(max(q[0], u0), u1)
        if not s.periodic_v:
            q[1] = min(max(q[1], v0), v1)
        out.append(q)
    return out


def _image(s: BSplineSurface, c: BSplineCurve) -> np.ndarray:
    uv = c(np.linspace(*c.domain, 9))
    q = _clipped(list(uv), s)
    uv = np.array(q)
    return s(uv[:, 0], uv[:, 1])


def _degenerated(builder: BRep_Builder, pc, geom: Geom_Surface, vertex, a: float, b: float, tol: float):
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS_Edge
    edge = TopoDS_Edge()
    builder.MakeEdge(edge)
    builder.UpdateEdge(edge, pc, geom, TopLoc_Location(), tol)
    builder.Degenerated(edge, True)
    builder.Range(edge, a, b)
    v1 = vertex.Oriented(TopAbs_FORWARD)
    v2 = vertex.Oriented(TopAbs_REVERSED)
    builder.Add(edge, v1)
    builder.Add(edge, v2)
    return as_edge(edge)


__all__ = ["trimmed_from_face", "deferred_trim", "natural_boundary", "make_trimmed_face", "parameter_maps",
           "TrimmedSurface"]
