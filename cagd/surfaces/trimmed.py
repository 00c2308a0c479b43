"""Trimmed surfaces: an engine surface restricted to a region of its (u, v) domain bounded
by closed loops of 2-D curves (issue 15; the STEP ``advanced_face`` / IGES 144 model:
an outer boundary and holes, each a chain of parameter-space curves).

``loops[0]`` is the outer loop (counter-clockwise in (u, v)), the others holes
(clockwise): the region is on the left of every curve. Each loop is a closed chain of
2-D curves (engine B-spline or Bezier curves; stored as their exact NURBS forms).

Classification (:meth:`TrimmedSurface.classify`) is a winding number. Every loop is
flattened by Bezier decomposition and bisection into chords whose distance to the
curve is bounded by the convex hull of the piece's control points (rational pieces
too: positive weights keep the curve in the hull of its Cartesian control points), to
FLATTEN_TOL of the loops' size. A point farther from a chord than that bound has the
same winding number with respect to the chord as to its curve piece (the piece and the
chord bound a lens inside the bound); for the few points within it the piece is
bisected again, down to the ON band (ON_BAND of the size), where the point is "on".
Crossings are counted along +u with the half-open rule, signed (+1 upwards), over the
chords of the point's horizontal strip (the chords are bucketed by v once).

Area (:meth:`TrimmedSurface.area`) by Green's theorem with a potential:
int_D |S_u x S_v| du dv = oint G dv, G(u, v) = int_{u_ref}^u |S_u x S_v|(s, v) ds
(the boundary counter-clockwise; do Carmo 4-5), G by Gauss-Legendre on the surface's
knot spans (subdivided), the boundary integral adaptively (halves against the whole).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._periodic import wrap
from .._quadrature import adaptive
from .._ranks import ranks
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve, prime_bezier_nets
from ..errors import CagdError
from ._trim_box import BOX_TOL, box_loop, is_box
from ._trim_check import LoopCheck
from ._chords import (_cartesian, _crossings, closed_chains, _end, _halves, _hom_pieces, _hull_bound,
                      _segment_distance)
from .base import Surface

if TYPE_CHECKING:
    from ._tessellate import Tessellation
    from .bspline import BSplineSurface

CLOSURE_TOL = 1e-9
"""Default ``tol``, relative to the size of the surface's (u, v) domain (its largest side):
the largest gap allowed between consecutive curves of a loop (and from the last back to
the first), and how far a loop may leave the domain."""
FLATTEN_TOL = 1e-6
"""Relative (to the loops' (u, v) size) bound of the chord-to-curve distance of the
polylines that classification buckets (refined locally below it)."""
ON_BAND = 1e-12
"""Relative (to the loops' (u, v) size): points within ON_BAND (plus the chord bound, at
most ON_BAND) of a boundary curve are "on" the boundary (``classify`` gives ON)."""
JOINT_TOL = 1e-2
"""Relative (to the loops' size): consecutive curves of a loop may cross within this of
their common point without an error (real files' pcurves overshoot their vertices, and
cusps of thin spikes cross themselves: seen 9e-3 from the joint on trj4_k1_geo-ac-214)."""
MAX_BISECTIONS = 48        # depth bound of the bisection of a Bezier piece (flattening, refinement)
MAX_PIECES = 1 << 16       # chords per curve at most (flattening stops refining there)
CHUNK = 1 << 20            # (point, chord) pairs handled at once: bounds the memory of classify
CROSSING_TOL = 1e-13       # relative orientation below which two chords only touch (no crossing)
GAUSS_POINTS = 10          # Gauss-Legendre nodes per interval (area, boundary fits)
AREA_TOL = 1e-12           # default relative accuracy goal of area()
CROSSING_SAMPLES = 8       # samples per pcurve span where knot-line crossings are looked for
MAX_START_INTERVALS = 1024  # boundary intervals per curve the adaptive area rule starts from at most
MAX_AREA_SPLITS = 32       # sub-intervals per knot span of the inner (u) integral at most
MAX_AREA_INTERVALS = 1 << 14   # live boundary intervals of the adaptive area rule at most (each level
#                                could double them: a face of wing_fuselage.step ran for minutes)
BOUNDARY_TOL = 1e-9        # default 3-D accuracy of boundary() approximations, relative to the surface's size
MAX_FIT_PIECES = 1 << 12   # cubic pieces per boundary curve at most
MAX_COMPOSED_DEGREE = 24   # boundary(): the exact composition S(c(t)) (degree d (p + q)) up to this degree, else a fit
COMPOSITION_TOL = 1e-12    # relative (surface size): a composition must reproduce S(c(t)) at the check points to this
COMPOSITION_GAP = 1e-12    # relative (pcurve range): a knot crossing this close to a pcurve break splits nothing
EDGE_RANGE_TOL = 1e-9      # relative (pcurve range): an edge curve's parameter range must be its pcurve's to this
BOUNDARY_SAMPLES = 8       # points per span (pcurve and image) where boundary() measures |image - S(c(t))|
PROJECTION_STEPS = 12      # Newton steps projecting S(c(t)) onto an edge curve (its own parametrisation)
TESSELLATION_POINTS = 24   # default interior grid points per direction of tessellate()
MAX_TESSELLATION_POINTS = 256

INSIDE, ON, OUTSIDE = 1, 0, -1
_GL_X, _GL_W = np.polynomial.legendre.leggauss(GAUSS_POINTS)


@dataclass(frozen=True)
class AreaResult:
    """The area of a trimmed surface: ``value``, ``error`` (an estimate: the change
    from halving the inner intervals plus the adaptive boundary rule's residual),
    ``converged`` (error within the goal) and ``message``."""
    value: float
    error: float
    converged: bool
    message: str

    def __float__(self) -> float:
        return self.value


@dataclass(frozen=True)
class TrimBoundary:
    """The 3-D boundary of a trimmed surface: ``curves[i][j]`` the image of
    ``loops[i][j]`` over its parameter range, running the same way; ``source[i][j]``
    what it is:

    - ``"edge"``: the face's own 3-D edge curve (:attr:`TrimmedSurface.edges`, e.g. read
      from a STEP/IGES file), in its own parametrisation;
    - ``"iso"``: the surface's exact iso-curve (a pcurve affine at constant u or v);
    - ``"composition"``: the exact composition S(c(t)) (:func:`_compose`, the same t);
    - ``"fit"``: a C1 cubic fit of S(c(t)) (the same t) within ``tol``.

    ``exact[i][j]`` is True for iso-curves and compositions. ``deviation[i][j]``: the
    measured distance of the curve from S(c(t)) (at BOUNDARY_SAMPLES points per span;
    for an edge the distance of S(c(t)) from the edge curve, projected onto it: the
    file's edge tolerance, measured). ``error``: the largest deviation of the fits,
    ``edge_error`` that of the edges; ``converged``: every fit met ``tol``."""
    curves: Tuple[Tuple[BSplineCurve, ...], ...]
    exact: Tuple[Tuple[bool, ...], ...]
    error: float
    tol: float
    converged: bool
    message: str
    source: Tuple[Tuple[str, ...], ...] = ()
    deviation: Tuple[Tuple[float, ...], ...] = ()
    edge_error: float = 0.0


def _flatten_many(curves: Sequence[BSplineCurve], tol: float) -> List[Tuple[np.ndarray, np.ndarray]]:
    """[(nets, bound)] of :func:`_flatten` for many curves at once: the Bezier pieces of
    all curves of one degree are bisected together (one numpy pass per level)."""
    out: List[Tuple[np.ndarray, np.ndarray]] = [(np.empty(0), np.empty(0))] * len(curves)
    groups: dict = {}
    prime_bezier_nets(curves)
    for k, c in enumerate(curves):
        groups.setdefault(c.degree, []).append(k)
    for ks in groups.values():
        parts = [_hom_pieces(curves[k]) for k in ks]
        Q = np.concatenate([n for _, n in parts])
        owner = np.concatenate([np.full(len(n), k) for k, (_, n) in zip(ks, parts)])
        lo = np.concatenate([b[:-1] for b, _ in parts]).astype(float)
        hi = np.concatenate([b[1:] for b, _ in parts]).astype(float)
        done: List[Tuple[np.ndarray, ...]] = []
        for level in range(MAX_BISECTIONS + 1):
            bound = _hull_bound(Q)
            ok = (bound <= tol) | (level == MAX_BISECTIONS)
            total = sum(len(d[0]) for d in done) + len(Q) + int(np.count_nonzero(~ok))
            if total > MAX_PIECES * len(ks):
                ok[:] = True
            done.append((Q[ok], owner[ok], lo[ok], hi[ok], bound[ok]))
            if ok.all():
                break
            Q, owner, lo, hi = Q[~ok], owner[~ok], lo[~ok], hi[~ok]
            L, R = _halves(Q)
            mid = 0.5 * (lo + hi)
            Q, owner = np.concatenate([L, R]), np.concatenate([owner, owner])
            lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        Q, owner, lo, hi, bound = (np.concatenate([d[i] for d in done]) for i in range(5))
        order = np.lexsort((lo, owner))
        Q, owner, bound = Q[order], owner[order], bound[order]
        cuts = np.searchsorted(owner, ks + [max(ks) + 1])
        for j, k in enumerate(ks):
            out[k] = (Q[cuts[j]:cuts[j + 1]], bound[cuts[j]:cuts[j + 1]])
    return out


# --- the trimmed surface --------------------------------------------------------------------
class TrimmedSurface(Surface):
    """An engine surface restricted to the region bounded by ``loops`` in its (u, v)
    domain (see the module docstring).

    Args:
        surface: any engine surface (B-spline, NURBS, Bezier, revolution, ...; not a
            Bezier triangle, not another TrimmedSurface: give its ``untrimmed``).
        loops: ``loops[0]`` the outer loop, the others holes; each a sequence of 2-D
            engine curves, the end of each the start of the next and the last's end the
            first's start (within ``tol``).
        tol: parameter-space tolerance (absolute): largest gap allowed in a chain and
            how far loops may leave a bounded direction of the domain; default
            CLOSURE_TOL times the domain's size. Gaps up to it are closed by straight
            chords in classification and area.
        edges: optional, parallel to ``loops``: ``edges[i][j]`` the 3-D curve of the
            face's edge along ``loops[i][j]`` (an engine curve in the surface's space over
            the pcurve's parameter range, running the same way; e.g. a file's edge curve),
            or None where none is known. :meth:`boundary` returns them, and
            :func:`cagd.occ.make_face` uses them as the edges' 3-D curves. How far an edge
            lies from S(c(t)) is measured by :meth:`boundary`, not checked here.

    Orientation: a loop that runs the wrong way (an outer loop clockwise, a hole
    counter-clockwise, by the sign of its enclosed area) is reversed (auto-fix);
    ``reoriented`` lists the indices of the loops that were.

    Raises:
        CagdError: naming the loop and curve: not a 2-D curve, a gap above ``tol``
            (stated with its size), a curve leaving the domain, a loop enclosing no area,
            curves of different loops (or of one loop) crossing, a hole outside the outer
            loop or inside another hole; ``edges[i][j]`` not a curve of the surface's
            dimension or not over its pcurve's parameter range (to EDGE_RANGE_TOL).
    """

    _modified_copy = "build a new TrimmedSurface"
    #: what a deferred trim (:meth:`_deferred`) converts on first use
    _DEFERRED = frozenset({"loops", "tol", "reoriented", "edges"})

    def __init__(self, surface: Surface, loops: Sequence[Sequence[Curve]], tol: Optional[float] = None,
                 edges: Optional[Sequence[Sequence[Optional[Curve]]]] = None):
        if not isinstance(surface, Surface) or isinstance(surface, TrimmedSurface):
            raise CagdError(f"surface: expected an engine Surface (not a TrimmedSurface), got "
                            f"{type(surface).__name__}")
        if not surface.rectangular:
            raise CagdError("surface: a Bezier triangle cannot be trimmed here; trim its to_nurbs()")
        if isinstance(loops, (Curve, str, bytes)) or not hasattr(loops, "__len__") or not len(loops):
            raise CagdError("loops: expected a non-empty sequence of loops (each a sequence of 2-D curves)")
        (u0, u1), (v0, v1) = surface.domain
        size = max(u1 - u0, v1 - v0)
        tol = CLOSURE_TOL * size if tol is None else _checks.positive(tol, "tol")
        chains: List[Tuple[BSplineCurve, ...]] = []
        for i, loop in enumerate(loops):
            if isinstance(loop, Curve):
                loop = [loop]
            if isinstance(loop, (str, bytes)) or not hasattr(loop, "__len__") or not len(loop):
                raise CagdError(f"loops[{i}]: expected a non-empty sequence of 2-D curves")
            chain = []
            for j, c in enumerate(loop):
                if not isinstance(c, Curve):
                    raise CagdError(f"loops[{i}][{j}]: expected an engine curve, got {type(c).__name__}")
                if c.dim != 2:
                    raise CagdError(f"loops[{i}][{j}]: expected a 2-D curve in (u, v), got a {c.dim}-D one")
                n = c.to_nurbs()
                chain.append(n.clamped() if n.periodic else n)
            chains.append(tuple(chain))
        prime_bezier_nets([c for chain in chains for c in chain])     # all Bezier nets in one pass
        _check_closed(chains, tol)
        _check_domain(surface, chains, tol)
        self._fill(surface, tuple(chains), float(tol), (), _checked_edges(surface, chains, edges))
        self._validate()

    def _fill(self, surface: Surface, loops: Tuple[Tuple[BSplineCurve, ...], ...], tol: float,
              reoriented: Tuple[int, ...], edges: "Edges" = None) -> None:
        self.surface = surface
        self.loops = loops
        self.tol = tol
        self.reoriented = reoriented
        #: None, or per loop curve its 3-D edge curve (None where unknown), see the class docstring
        self.edges = edges
        self.dim = surface.dim
        self.periodic_u, self.periodic_v = surface.periodic_u, surface.periodic_v
        self._flattening: Optional[_Flattened] = None

    # --- a trim converted on first use (files read with ``defer_trims``) -------------------
    @classmethod
    def _deferred(cls, surface: Surface, build: Callable[[], Surface]) -> "TrimmedSurface":
        """A TrimmedSurface on ``surface`` whose loops come from ``build()`` on the first
        access to ``loops``, ``tol``, ``reoriented`` or ``edges`` (a CAD face's pcurves,
        converted and validated only when used). ``build`` returns the TrimmedSurface on
        ``surface``, or a plain surface when the face turned out to be its parameter box
        (or its trim unusable: ``build`` warns), which gives the box as the one loop."""
        obj = cls.__new__(cls)
        obj.surface = surface
        obj.dim = surface.dim
        obj.periodic_u, obj.periodic_v = surface.periodic_u, surface.periodic_v
        obj._flattening = None
        obj._build = build
        object.__setattr__(obj, "_sealed", True)
        return obj

    def __getattr__(self, name: str) -> Any:
        # called only for attributes not set: the deferred ones of a deferred trim
        if name in TrimmedSurface._DEFERRED and "_build" in self.__dict__:
            self._materialize()
            return self.__dict__[name]
        if name == "edges":                # objects pickled before edges existed have none
            return None
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _materialize(self) -> None:
        build = self.__dict__.pop("_build")
        got = build()
        if not isinstance(got, TrimmedSurface):
            got = TrimmedSurface(self.surface, [box_loop(self.surface.domain)])
        for name in ("loops", "tol", "reoriented", "edges", "_flattening"):
            object.__setattr__(self, name, got.__dict__[name])

    @property
    def deferred(self) -> bool:
        """True while the trim of a face read with ``defer_trims`` is not yet converted."""
        return "_build" in self.__dict__

    def __getstate__(self) -> Dict[str, Any]:
        if self.deferred:
            self._materialize()
        return dict(self.__dict__)

    # --- validation ---------------------------------------------------------------------
    def _validate(self) -> None:
        """Orientation (auto-fixed), no crossings, holes nested: decided on the loops'
        pieces bisected where needed (:mod:`cagd.surfaces._trim_check`), the full
        flattening only where an orientation is too close to call or holes are tested."""
        scale = _loops_scale(self.loops)
        check = LoopCheck(closed_chains(self.loops), scale, FLATTEN_TOL * scale, MAX_BISECTIONS)
        signs = check.orientations()
        areas = self._flattened().loop_areas() if signs is None else signs
        fixed = []
        for i, a in enumerate(areas):
            if not abs(a) > 0.0:
                raise CagdError(f"loops[{i}]: encloses no area (a loop must bound a region)")
            if (a < 0) == (i == 0):
                fixed.append(i)
        if fixed:
            loops = tuple(_reversed_loop(loop) if i in fixed else loop for i, loop in enumerate(self.loops))
            object.__setattr__(self, "loops", loops)
            if self.edges is not None:
                edges = tuple(_reversed_edges(e) if i in fixed else e for i, e in enumerate(self.edges))
                object.__setattr__(self, "edges", edges)
            object.__setattr__(self, "reoriented", tuple(fixed))
            self._flattening = None
            check = LoopCheck(closed_chains(self.loops), scale, FLATTEN_TOL * scale, MAX_BISECTIONS)
        check.check_crossings(4 * CHUNK, CROSSING_TOL, JOINT_TOL, _curve_name)
        if len(self.loops) < 2:
            return
        periods = self._shifts()
        outer = np.concatenate([c.control_points for c in self.loops[0]])
        band = ON_BAND * scale
        if any(_spans_period(outer[:, k], T, self.tol) for k, T in enumerate(periods)):
            self._flattened().check_nesting()        # holes with copies a period apart
            return
        lo = outer.min(axis=0) - 4 * band

        def window(P: np.ndarray) -> np.ndarray:
            return np.stack([wrap(P[:, k], lo[k], T) if T > 0 else P[:, k] for k, T in enumerate(periods)], axis=1)
        check.check_nesting(band, window, CHUNK)

    def _flattened(self) -> "_Flattened":
        if self._flattening is None:
            self._flattening = _Flattened(self.loops, self.tol, self._shifts())
        return self._flattening

    def _shifts(self) -> Tuple[float, float]:
        """The periods of the periodic directions (0 for bounded ones)."""
        (u0, u1), (v0, v1) = self.surface.domain
        return (u1 - u0 if self.periodic_u else 0.0, v1 - v0 if self.periodic_v else 0.0)

    def region_box(self) -> Optional[Tuple[np.ndarray, np.ndarray]]:
        """(lo, hi) when the region is a parameter box: one loop, every curve on a side of
        the loops' bounding box [lo, hi] (to BOX_TOL of its size) and its area the box's
        (to BOX_TOL), as a deferred trim found to be the face's box is; else None. Such
        a face meshes as its surface on the box."""
        if len(self.loops) != 1:
            return None
        P = np.concatenate([c.control_points for c in self.loops[0]])
        lo, hi = P.min(axis=0), P.max(axis=0)
        if not is_box(self.loops, ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))):
            return None
        box = float(np.prod(hi - lo))
        if not abs(float(self._flattened().loop_areas()[0]) - box) <= BOX_TOL * box:
            return None
        return lo, hi

    # --- the surface interface: delegated ------------------------------------------------------
    @property
    def untrimmed(self) -> Surface:
        """The surface without its trim."""
        return self.surface

    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        return self.surface.domain

    def _evaluate(self, u: np.ndarray, v: np.ndarray, du: int, dv: int) -> np.ndarray:
        return self.surface._evaluate(u, v, du, dv)

    def _grid(self, us: np.ndarray, vs: np.ndarray, du: int, dv: int) -> np.ndarray:
        return self.surface._grid(us, vs, du, dv)

    def to_nurbs(self) -> "BSplineSurface":
        """The untrimmed surface's exact NURBS form (the trim is not part of it)."""
        return self.surface.to_nurbs()

    def _affine(self, A: np.ndarray, b: np.ndarray) -> "TrimmedSurface":
        edges = None if self.edges is None else \
            tuple(tuple(None if e is None else e._affine(A, b) for e in row) for row in self.edges)
        return TrimmedSurface._unchecked(self.surface._affine(A, b), self.loops, self.tol, self.reoriented, edges)

    @property
    def size(self) -> float:
        return self.surface.size

    def __repr__(self) -> str:
        if self.deferred:
            return f"<TrimmedSurface of {type(self.surface).__name__}, trim converted on first use>"
        counts = ", ".join(str(len(loop)) for loop in self.loops)
        return (f"<TrimmedSurface of {type(self.surface).__name__}, {len(self.loops)} loop(s) of "
                f"[{counts}] curves>")

    # --- classification ------------------------------------------------------------------------
    def classify(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """INSIDE (1), ON (0) or OUTSIDE (-1) for each (u, v) (numpy broadcasting), an
        int8 array of the broadcast shape. ON: within the ON band (ON_BAND of the loops'
        size, plus a chord bound at most that) of a boundary curve; every other point
        is classified exactly up to rounding. Periodic directions are taken modulo the
        period (the loops' own window)."""
        u, v = _checks.parameters(u, "u"), _checks.parameters(v, "v")
        try:
            shape = np.broadcast_shapes(u.shape, v.shape)
        except ValueError:
            raise CagdError(f"u, v: shapes {u.shape} and {v.shape} do not broadcast") from None
        uf = np.broadcast_to(u, shape).ravel()
        vf = np.broadcast_to(v, shape).ravel()
        return self._flattened().classify(uf, vf).reshape(shape)

    def contains(self, u: ArrayLike, v: ArrayLike) -> np.ndarray:
        """True where (u, v) is in the closed trimmed region (INSIDE or ON, see
        :meth:`classify`)."""
        return self.classify(u, v) >= 0

    # --- area ----------------------------------------------------------------------------------
    def area_report(self, rel_tol: float = AREA_TOL) -> AreaResult:
        """The area int_D |S_u x S_v| du dv over the trimmed domain D by Green's theorem
        (see the module docstring) with its error estimate. The inner integral runs
        along the direction with fewer knot spans over the loops (u, or v on the
        surface and loops with u and v exchanged: the same area)."""
        return trimmed_integral(self, _checks.positive(rel_tol, "rel_tol"))

    def _inner_direction(self) -> int:
        """0 (u) or 1 (v): the direction with fewer knot spans over the loops."""
        flat = self._flattened()
        spans = [len(_knot_lines(self, k, float(flat.lo[k]), float(flat.hi[k]))) for k in (0, 1)]
        return 0 if spans[0] <= spans[1] else 1

    def _exchanged(self) -> "TrimmedSurface":
        """The same face with u and v exchanged (surface and loops; a reflection of the
        domain, so the loops are re-oriented)."""
        swap = np.array([[0.0, 1.0], [1.0, 0.0]])
        loops = [[c.transformed(swap) for c in loop] for loop in self.loops]
        return TrimmedSurface(self.surface.to_nurbs().swapped(), loops, tol=self.tol)

    def area(self, rel_tol: float = AREA_TOL) -> float:
        """The area of the trimmed surface (:meth:`area_report` ``.value``)."""
        return self.area_report(rel_tol).value

    # --- boundary ------------------------------------------------------------------------------
    def boundary(self, tol: Optional[float] = None) -> TrimBoundary:
        """The 3-D boundary curve of every loop curve c (see :class:`TrimBoundary`): its
        edge curve where :attr:`edges` has one (its distance from S(c(t)) measured), else
        the exact iso-curve where c is affine at constant u or v, else the exact
        composition S(c(t)) (:func:`_compose`) up to MAX_COMPOSED_DEGREE, else a C1 cubic
        fit within ``tol`` (default BOUNDARY_TOL times the surface's size; a 3-D
        distance)."""
        tol = BOUNDARY_TOL * self.size if tol is None else _checks.positive(tol, "tol")
        return _boundary(self, tol)

    def _image_boundary(self, tol: Optional[float] = None) -> TrimBoundary:
        """The images S(c(t)) in c's own parameter t (iso-curves, else quintic C2 Hermite
        fits within ``tol``: with the second derivative, 279 pieces where C1 cubics took
        1307 on the benchmark's star; no edge curves, no high-degree compositions): what
        the distance queries join and project onto (they map a parameter on the image
        back to (u, v))."""
        tol = BOUNDARY_TOL * self.size if tol is None else _checks.positive(tol, "tol")
        return _boundary(self, tol, images_only=True)

    # --- tessellation --------------------------------------------------------------------------
    def tessellate(self, count: int = TESSELLATION_POINTS) -> Tuple[np.ndarray, np.ndarray]:
        """(vertices (n, dim), triangles (m, 3) int) covering the trimmed region: a
        (count + 1)^2 grid of the loops' box, its cells clear of the trim as two triangles
        each, the rest between them and the trim polylines (vertices on the trim curves)
        ear-clipped, then Lawson-flipped (:mod:`cagd.surfaces._tessellate`). Triangles are
        counter-clockwise in (u, v)."""
        uv, tri = self.tessellate_uv(count)
        return self.surface(uv[:, 0], uv[:, 1]), tri

    def tessellate_uv(self, count: int = TESSELLATION_POINTS) -> Tuple[np.ndarray, np.ndarray]:
        """The (u, v) vertices and triangles of :meth:`tessellate`."""
        t = self.tessellation(count)
        return t.uv, t.triangles

    def tessellation(self, count: int = TESSELLATION_POINTS) -> "Tessellation":
        """:meth:`tessellate_uv` with the trim chords and the trim curves' points at their
        middles (where :func:`cagd.mesh` measures a boundary chord's deviation)."""
        from ._tessellate import tessellation
        return tessellation(self, _checks.integer(count, "count", 0, MAX_TESSELLATION_POINTS))


# --- helpers of the constructor ------------------------------------------------------------------
def _check_closed(chains: List[Tuple[BSplineCurve, ...]], tol: float) -> None:
    for i, chain in enumerate(chains):
        for j, c in enumerate(chain):
            nxt = chain[(j + 1) % len(chain)]
            end, start = _end(c, 1), _end(nxt, 0)
            gap = float(np.linalg.norm(end - start))
            if gap > tol:
                k = (j + 1) % len(chain)
                raise CagdError(f"loops[{i}][{j}]: ends at {tuple(end)} but loops[{i}][{k}] starts at "
                                f"{tuple(start)}: a gap of {gap:.3g} in (u, v) > tol = {tol:.3g} "
                                "(a loop must be a closed chain)")


def _check_domain(surface: Surface, chains: List[Tuple[BSplineCurve, ...]], tol: float) -> None:
    (u0, u1), (v0, v1) = surface.domain
    for i, chain in enumerate(chains):
        for j, c in enumerate(chain):
            P = c.control_points
            lo, hi = P.min(axis=0), P.max(axis=0)
            if c.is_rational:                        # the Bezier nets' hull is tighter than the poles'
                _, nets = _hom_pieces(c)
                cart = _cartesian(nets).reshape(-1, 2)
                lo, hi = cart.min(axis=0), cart.max(axis=0)
            for k, (periodic, a, b, name) in enumerate(((surface.periodic_u, u0, u1, "u"),
                                                        (surface.periodic_v, v0, v1, "v"))):
                if periodic:
                    if hi[k] - lo[k] > (b - a) + tol:
                        raise CagdError(f"loops[{i}][{j}]: spans {hi[k] - lo[k]:.6g} in {name}, more than "
                                        f"the period {b - a:.6g}")
                    continue
                if lo[k] < a - tol or hi[k] > b + tol:
                    # the hull may overshoot where the curve does not: check the curve itself
                    t = np.linspace(*c.domain, 257)
                    x = c(t)[:, k]
                    if x.min() < a - tol or x.max() > b + tol:
                        bad = float(x.min() if x.min() < a - tol else x.max())
                        raise CagdError(f"loops[{i}][{j}]: leaves the surface's domain: {name} = {bad:.9g} "
                                        f"outside [{a:.9g}, {b:.9g}] (tol {tol:.3g})")


def _reversed_loop(loop: Tuple[BSplineCurve, ...]) -> Tuple[BSplineCurve, ...]:
    return tuple(c.reversed() for c in loop[::-1])


Edges = Optional[Tuple[Tuple[Optional[BSplineCurve], ...], ...]]


def _reversed_edges(row: Tuple[Optional[BSplineCurve], ...]) -> Tuple[Optional[BSplineCurve], ...]:
    return tuple(None if e is None else e.reversed() for e in row[::-1])


def _loops_scale(loops: Sequence[Sequence[BSplineCurve]]) -> float:
    """The loops' (u, v) size: the largest side of their control points' box."""
    pts = np.concatenate([c.control_points for loop in loops for c in loop])
    return max(float(np.ptp(pts, axis=0).max()), 1e-300)


def _spans_period(x: np.ndarray, period: float, tol: float) -> bool:
    """Coordinates ``x`` of a loop's points span a whole ``period`` (0: not periodic), to
    CLOSURE_TOL and ``tol``: the region is then periodic, its holes seen a period apart."""
    return bool(period > 0 and np.ptp(x) >= period * (1.0 - CLOSURE_TOL) - tol)


def _curve_name(loop: int, j: int) -> str:
    """How messages name curve j of a loop (-1: a gap closer after a curve)."""
    return f"loops[{loop}][{j}]" if j >= 0 else f"the gap after a curve of loops[{loop}]"


def _checked_edges(surface: Surface, chains: List[Tuple[BSplineCurve, ...]],
                   edges: Optional[Sequence[Sequence[Optional[Curve]]]]) -> Edges:
    """``edges`` as clamped NURBS on their pcurves' exact ranges (an end within
    EDGE_RANGE_TOL of the range is put on it), or None (no edge known anywhere)."""
    if edges is None:
        return None
    if isinstance(edges, (Curve, str, bytes)) or not hasattr(edges, "__len__") or len(edges) != len(chains):
        raise CagdError(f"edges: expected one sequence of edge curves (or None) per loop ({len(chains)})")
    out, known = [], False
    for i, (row, chain) in enumerate(zip(edges, chains)):
        if isinstance(row, (Curve, str, bytes)) or not hasattr(row, "__len__") or len(row) != len(chain):
            raise CagdError(f"edges[{i}]: expected one edge curve (or None) per curve of loops[{i}] ({len(chain)})")
        items: List[Optional[BSplineCurve]] = []
        for j, (e, c) in enumerate(zip(row, chain)):
            if e is None:
                items.append(None)
                continue
            if not isinstance(e, Curve):
                raise CagdError(f"edges[{i}][{j}]: expected an engine curve or None, got {type(e).__name__}")
            if e.dim != surface.dim:
                raise CagdError(f"edges[{i}][{j}]: a {e.dim}-D curve for a {surface.dim}-D surface")
            n = e.to_nurbs()
            n = n.clamped() if n.periodic else n
            (a, b), (ea, eb) = c.domain, n.domain
            if max(abs(ea - a), abs(eb - b)) > EDGE_RANGE_TOL * (b - a):
                raise CagdError(f"edges[{i}][{j}]: runs over [{ea:.12g}, {eb:.12g}], its pcurve loops[{i}][{j}] "
                                f"over [{a:.12g}, {b:.12g}] (an edge curve must share its pcurve's range)")
            if (ea, eb) != (a, b):
                n = n.reparametrized(a, b)
            items.append(n)
            known = True
        out.append(tuple(items))
    return tuple(out) if known else None


class _Flattened:
    """The chords of every loop (with the Bezier piece each stands for), bucketed by v."""

    def __init__(self, loops: Tuple[Tuple[BSplineCurve, ...], ...], tol: float, periods: Tuple[float, float]):
        pts = np.concatenate([c.control_points for loop in loops for c in loop])
        self.lo, self.hi = pts.min(axis=0), pts.max(axis=0)
        self.scale = _loops_scale(loops)
        self.loops = loops
        self.band = ON_BAND * self.scale
        self.periods = periods
        ftol = FLATTEN_TOL * self.scale
        self.curves: List[BSplineCurve] = []     # every chain curve, with straight gap closers (area)
        self.nets: List[np.ndarray] = []         # their Bezier pieces, then those of periodic copies
        self.chain_len: List[int] = []          # pieces per loop, closers included
        self.loop_len: List[int] = []           # curves per loop
        chains = closed_chains(loops)
        for (_, chain, _), loop in zip(chains, loops):
            self.chain_len.append(len(chain))
            self.loop_len.append(len(loop))
        flat = _flatten_many([piece for _, chain, _ in chains for piece in chain], ftol)
        self.curves = [piece for _, chain, _ in chains for piece in chain]
        self.nets = [Q for Q, _ in flat]
        counts = np.array([len(Q) for Q in self.nets])
        # per piece: its loop, its name (-1: a gap closer), its curve's position (a closer's
        # is the curve before it), then repeated per chord
        loop_ids = np.concatenate([np.full(len(chain), i) for i, chain, _ in chains])
        name_ids = np.concatenate([names for _, _, names in chains])
        pos_ids = np.concatenate([[names[q] if names[q] >= 0 else names[q - 1] for q in range(len(names))]
                                  for _, _, names in chains])
        cuts = np.cumsum(counts)[:-1]

        def pieces(values: np.ndarray) -> List[np.ndarray]:
            return np.split(values, cuts)

        A = pieces(_cartesian(np.concatenate([Q[:, 0] for Q in self.nets])))
        B = pieces(_cartesian(np.concatenate([Q[:, -1] for Q in self.nets])))
        bound = [b for _, b in flat]
        owner = pieces(np.stack([np.repeat(np.arange(len(counts)), counts),
                                 ranks(counts)], axis=1))
        loop_of = pieces(np.repeat(loop_ids, counts))
        curve_of = pieces(np.repeat(name_ids, counts))
        pos = pieces(np.repeat(pos_ids, counts))
        outer = np.concatenate(A[:self.chain_len[0]] + B[:self.chain_len[0]])
        self.window = outer.min(axis=0) - 4 * self.band
        # holes of a face whose outer loop spans a whole period: their copies one period
        # on either side (the region is periodic; a hole across the seam shows on both sides)
        for k in (0, 1):
            if not _spans_period(outer[:, k], periods[k], tol):
                continue
            count = len(self.nets)
            for ci in range(sum(self.chain_len[:1]), count):
                for shift in (-periods[k], periods[k]):
                    Q = self.nets[ci].copy()
                    Q[..., k] += shift * Q[..., 2]
                    P = _cartesian(Q)
                    idx = len(self.nets)
                    self.nets.append(Q)
                    A.append(P[:, 0])
                    B.append(P[:, -1])
                    bound.append(bound[ci])
                    owner.append(np.stack([np.full(len(Q), idx), np.arange(len(Q))], axis=1))
                    loop_of.append(loop_of[ci])
                    curve_of.append(np.full(len(Q), -2))
                    pos.append(pos[ci])
        self.A, self.B = np.concatenate(A), np.concatenate(B)
        self.bound = np.concatenate(bound)
        self.owner = np.concatenate(owner)
        self.loop_of = np.concatenate(loop_of)
        self.curve_of = np.concatenate(curve_of)
        self.position = np.concatenate(pos)
        self.original = self.curve_of != -2
        first = np.stack([n[0, 0] for n in self.nets])
        last = np.stack([n[-1, -1] for n in self.nets])
        self.curve_start = (first[:, :2] / first[:, 2:])[self.owner[:, 0]]
        self.curve_end = (last[:, :2] / last[:, 2:])[self.owner[:, 0]]
        self.loop_count = len(loops)
        self.lo = np.minimum(self.lo, np.minimum(self.A, self.B).min(axis=0))
        self.hi = np.maximum(self.hi, np.maximum(self.A, self.B).max(axis=0))
        self._bucket()

    def _bucket(self) -> None:
        """Strips of v: the chords whose v-range (grown by their bound and the band)
        meets each strip, as CSR arrays."""
        n = len(self.A)
        self.nstrips = int(np.clip(4 * n, 256, 1 << 16))
        grow = self.bound + 2 * self.band
        vlo = np.minimum(self.A[:, 1], self.B[:, 1]) - grow
        vhi = np.maximum(self.A[:, 1], self.B[:, 1]) + grow
        self.v0 = self.lo[1] - 4 * self.band
        self.dv = max((self.hi[1] + 4 * self.band - self.v0) / self.nstrips, 1e-300)
        s0 = np.clip(np.floor((vlo - self.v0) / self.dv), 0, self.nstrips - 1).astype(np.int64)
        s1 = np.clip(np.floor((vhi - self.v0) / self.dv), 0, self.nstrips - 1).astype(np.int64)
        counts = s1 - s0 + 1
        seg = np.repeat(np.arange(n), counts)
        strip = np.repeat(s0, counts) + ranks(counts)
        order = np.argsort(strip, kind="stable")
        self.strip_segments = seg[order]
        self.strip_start = np.searchsorted(strip[order], np.arange(self.nstrips + 1))

    def loop_areas(self) -> np.ndarray:
        """Signed (shoelace) areas of the loops' polylines."""
        A, B = self.A[self.original], self.B[self.original]
        cross = A[:, 0] * B[:, 1] - B[:, 0] * A[:, 1]
        return 0.5 * np.bincount(self.loop_of[self.original], weights=cross, minlength=self.loop_count)

    # --- classification -----------------------------------------------------------------------
    def _window(self, x: np.ndarray, k: int) -> np.ndarray:
        """Periodic coordinates moved into the loops' window [lo, lo + period)."""
        period = self.periods[k]
        if period <= 0:
            return x
        return wrap(x, self.window[k], period)

    def classify(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        u, v = self._window(u, 0), self._window(v, 1)
        out = np.full(u.shape, OUTSIDE, dtype=np.int8)
        margin = 4 * self.band + float(self.bound.max(initial=0.0))
        cand = np.flatnonzero((u >= self.lo[0] - margin) & (u <= self.hi[0] + margin) &
                              (v >= self.lo[1] - margin) & (v <= self.hi[1] + margin))
        if not cand.size:
            return out
        strip = np.clip(np.floor((v[cand] - self.v0) / self.dv), 0, self.nstrips - 1).astype(np.int64)
        counts = self.strip_start[strip + 1] - self.strip_start[strip]
        ends = np.cumsum(counts)
        first = 0
        while first < len(cand):
            last = int(np.searchsorted(ends, ends[first] - counts[first] + CHUNK, side="right"))
            last = max(last, first + 1)
            self._classify_chunk(u, v, cand[first:last], strip[first:last], counts[first:last], out)
            first = last
        return out

    def _classify_chunk(self, u: np.ndarray, v: np.ndarray, idx: np.ndarray, strip: np.ndarray,
                        counts: np.ndarray, out: np.ndarray) -> None:
        local = np.repeat(np.arange(len(idx)), counts)
        offset = ranks(counts)
        seg = self.strip_segments[np.repeat(self.strip_start[strip], counts) + offset]
        pu, pv = u[idx][local], v[idx][local]
        a, b = self.A[seg], self.B[seg]
        sign = _crossings(pu, pv, a, b)
        grow = self.bound[seg] + self.band
        box = (pu >= np.minimum(a[:, 0], b[:, 0]) - grow) & (pu <= np.maximum(a[:, 0], b[:, 0]) + grow) & \
              (pv >= np.minimum(a[:, 1], b[:, 1]) - grow) & (pv <= np.maximum(a[:, 1], b[:, 1]) + grow)
        near = np.zeros(len(seg), dtype=bool)
        k = np.flatnonzero(box)
        near[k] = _segment_distance(np.stack([pu[k], pv[k]], axis=1), a[k], b[k]) <= grow[k]
        on = np.zeros(len(idx), dtype=bool)
        if near.any():
            k = np.flatnonzero(near)
            fine, on_pair = self._refine(pu[k], pv[k], seg[k])
            sign[k] = fine
            on[np.unique(local[k[on_pair]])] = True
        winding = np.bincount(local, weights=sign, minlength=len(idx))
        res = np.where(winding != 0, INSIDE, OUTSIDE).astype(np.int8)
        res[on] = ON
        out[idx] = res

    def _refine(self, pu: np.ndarray, pv: np.ndarray, seg: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """The exact crossings of the curve pieces behind chords ``seg`` (instead of the
        chords') for points near them, by bisection; and which points are on the curve."""
        sign = np.zeros(len(seg), dtype=np.int64)
        on = np.zeros(len(seg), dtype=bool)
        curves = self.owner[seg, 0]
        for k in np.unique(curves):
            sel = np.flatnonzero(curves == k)
            Q = self.nets[k][self.owner[seg[sel], 1]]
            pair = sel
            for depth in range(MAX_BISECTIONS + 1):
                L, R = _halves(Q)
                Q = np.concatenate([L, R])
                pair = np.concatenate([pair, pair])
                P = _cartesian(Q)
                a, b = P[:, 0], P[:, -1]
                p = np.stack([pu[pair], pv[pair]], axis=1)
                bound = _hull_bound(Q)
                near = _segment_distance(p, a, b) <= bound + self.band
                fine = bound <= self.band
                hit_on = near & (fine | (depth == MAX_BISECTIONS))
                on[pair[hit_on]] = True
                far = ~near
                np.add.at(sign, pair[far], _crossings(pu[pair[far]], pv[pair[far]], a[far], b[far]))
                keep = near & ~hit_on
                if not keep.any():
                    break
                # near but refinable: keep the crossings of near-and-fine pieces out (they are on)
                Q, pair = Q[keep], pair[keep]
        return sign, on

    def pieces_meet(self, seg: np.ndarray, lo: np.ndarray, hi: np.ndarray, share: float) -> np.ndarray:
        """Per (chord, box) pair: whether the curve piece behind chord ``seg`` may meet the
        box [lo, hi] (grown by the band): the piece bisected while the box of its control
        points (its convex hull's, Farin 3.3) meets the box, until that box lies inside it
        (it meets) or is below ``share`` of the box's larger side, within the band, or
        MAX_BISECTIONS halvings deep (it may). Finer than the chord's bound, for boxes
        smaller than it."""
        out = np.zeros(len(seg), dtype=bool)
        small = share * np.max(hi - lo, axis=1)
        curves = self.owner[seg, 0]
        for k in np.unique(curves):
            sel = np.flatnonzero(curves == k)
            Q, pair = self.nets[k][self.owner[seg[sel], 1]], sel
            for depth in range(MAX_BISECTIONS + 1):
                P = _cartesian(Q)
                qlo, qhi = P.min(axis=1), P.max(axis=1)
                hit = np.all((qlo - self.band <= hi[pair]) & (qhi + self.band >= lo[pair]), axis=1)
                Q, pair, qlo, qhi = Q[hit], pair[hit], qlo[hit], qhi[hit]
                if not len(pair):
                    break
                size = (qhi - qlo).max(axis=1)
                done = np.all((qlo >= lo[pair]) & (qhi <= hi[pair]), axis=1) | (size <= small[pair]) | \
                    (size <= self.band) | (depth == MAX_BISECTIONS)
                out[pair[done]] = True
                Q, pair = Q[~done], pair[~done]
                if not len(pair):
                    break
                L, R = _halves(Q)
                Q, pair = np.concatenate([L, R]), np.concatenate([pair, pair])
        return out

    # --- validation helpers ---------------------------------------------------------------------
    def check_crossings(self) -> None:
        """CagdError when chords of different curves properly cross (the chords stand for
        their curves within FLATTEN_TOL; touching is allowed): :class:`LoopCheck`."""
        LoopCheck(closed_chains(self.loops), self.scale, FLATTEN_TOL * self.scale, MAX_BISECTIONS).check_crossings(
            4 * CHUNK, CROSSING_TOL, JOINT_TOL, _curve_name)

    def check_nesting(self) -> None:
        """Every hole inside the outer loop and outside the other holes (tested at the
        start of its first curve, by the winding number of the chords of each loop)."""
        n = self.loop_count
        if n < 2:
            return
        first = np.searchsorted(self.loop_of[self.original], np.arange(1, n))   # originals are in loop order
        P = self.A[np.flatnonzero(self.original)[first]]
        P = np.stack([self._window(P[:, 0], 0), self._window(P[:, 1], 1)], axis=1)
        reach = np.full(n, -np.inf)
        np.maximum.at(reach, self.loop_of, self.bound)
        reach += self.band
        far = float(reach.max())
        vlo = np.minimum(self.A[:, 1], self.B[:, 1]) - far
        vhi = np.maximum(self.A[:, 1], self.B[:, 1]) + far
        uhi = np.maximum(self.A[:, 0], self.B[:, 0]) + far
        rows = max(1, CHUNK // max(len(self.A), 1))
        for s in range(0, n - 1, rows):             # holes s + 1 .. against every loop at once
            p = P[s:s + rows]
            # only chords within the largest reach of a point can touch it or cross its ray
            # (a crossing needs the point's v in the chord's v-range and the chord's u beyond it)
            holes, seg = np.nonzero((vlo[None] <= p[:, 1, None]) & (p[:, 1, None] <= vhi[None]) &
                                    (p[:, 0, None] <= uhi[None]))
            sign = _crossings(p[holes, 0], p[holes, 1], self.A[seg], self.B[seg])
            loops = self.loop_of[seg]
            w = np.bincount(holes * n + loops, weights=sign, minlength=len(p) * n).reshape(len(p), n)
            d = np.full((len(p), n), np.inf)
            np.minimum.at(d, (holes, loops), _segment_distance(p[holes], self.A[seg], self.B[seg]))
            i = np.arange(s + 1, s + 1 + len(p))[:, None]
            k = np.arange(n)[None]
            bad = (k != i) & ~(d <= reach[None]) & (((k == 0) & (w == 0)) | ((k > 0) & (w != 0)))
            if bad.any():                             # touching (d within reach): no verdict from this point
                r, c = np.unravel_index(int(np.argmax(bad)), bad.shape)
                hole = s + 1 + int(r)
                if c == 0:
                    raise CagdError(f"loops[{hole}]: the hole lies outside the outer loop loops[0]")
                raise CagdError(f"loops[{hole}]: the hole lies inside the hole loops[{int(c)}]")


# --- area ---------------------------------------------------------------------------------------
#: what the trimmed quadrature integrates: None, the area element |S_u x S_v|; else a
#: centre c, the volume element (S - c) . (S_u x S_v) / 3 (divergence theorem)
Density = Optional[np.ndarray]


def _element(d: np.ndarray, centre: Density) -> np.ndarray:
    """The density from the partials d (S, S_u, S_v at [0, 0], [1, 0], [0, 1])."""
    su, sv = d[1, 0], d[0, 1]
    if su.shape[-1] == 2:
        return np.abs(su[..., 0] * sv[..., 1] - su[..., 1] * sv[..., 0])
    n = np.cross(su, sv)
    if centre is None:
        return np.linalg.norm(n, axis=-1)
    return np.einsum("...k,...k", d[0, 0] - centre, n) / 3.0


def _jacobian(surface: Surface, u: np.ndarray, v: np.ndarray, centre: Density = None) -> np.ndarray:
    return _element(surface.derivatives(u, v, 1, 1), centre)


def _inside_domain(surface: Surface, u: np.ndarray, v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Bounded directions clipped into the domain (loops may overshoot it by ``tol``)."""
    (u0, u1), (v0, v1) = surface.domain
    if not surface.periodic_u:
        u = np.clip(u, u0, u1)
    if not surface.periodic_v:
        v = np.clip(v, v0, v1)
    return u, v


def _knot_lines(ts: TrimmedSurface, k: int, lo: float, hi: float) -> np.ndarray:
    """:func:`knot_lines` of the face's surface."""
    return knot_lines(ts.surface.to_nurbs(), k, lo, hi)


def knot_lines(s: "BSplineSurface", k: int, lo: float, hi: float) -> np.ndarray:
    """The NURBS surface's distinct knots in direction k (0: u, 1: v) strictly inside
    (lo, hi), repeated by periods in a periodic direction: where S is not smooth."""
    knots = np.unique(s.knots_u if k == 0 else s.knots_v)
    if (s.periodic_u, s.periodic_v)[k]:
        (a, b) = s.domain[k]
        period = b - a
        k0, k1 = int(np.floor((lo - a) / period)) - 1, int(np.ceil((hi - a) / period)) + 1
        knots = np.unique(np.concatenate([knots + j * period for j in range(k0, k1 + 1)]))
    return knots[(knots > lo) & (knots < hi)]


def _u_breaks(ts: TrimmedSurface, flat: _Flattened, splits: int) -> np.ndarray:
    """u_ref = the loops' smallest u, then the surface's u knots (repeated by periods in
    a periodic direction) up to the largest, each span split ``splits`` times."""
    lo, hi = float(flat.lo[0]), float(flat.hi[0])
    edges = np.concatenate([[lo], _knot_lines(ts, 0, lo, hi), [hi]])
    t = np.linspace(0.0, 1.0, splits + 1)[:-1]
    fine = (edges[:-1, None] + (edges[1:] - edges[:-1])[:, None] * t[None]).ravel()
    return np.concatenate([fine, [hi]])


def _knot_crossings(ts: TrimmedSurface, c: BSplineCurve, a: float, b: float) -> np.ndarray:
    """Parameters in (a, b) where the pcurve c crosses a knot line of the surface (the
    integrand of the boundary rule is only C^(p-1) there: splitting the rule's intervals
    at them keeps Gauss-Legendre convergent at its own rate): sign changes on a sample
    of CROSSING_SAMPLES per span, then bisection to the parameter's rounding."""
    br = np.concatenate([[a], c._breaks_within(a, b), [b]])
    t = (br[:-1, None] + (br[1:] - br[:-1])[:, None] * np.linspace(0.0, 1.0, CROSSING_SAMPLES + 1)[None, :-1]).ravel()
    t = np.concatenate([t, [b]])
    P = c(t)
    found = []
    for k in (0, 1):
        lines = _knot_lines(ts, k, float(P[:, k].min()), float(P[:, k].max()))
        if not len(lines):
            continue
        f = P[:, k][:, None] - lines[None, :]
        on = np.nonzero(f[1:-1] == 0.0)[0]                   # a sample on a knot line: a crossing there
        found.append(t[1:-1][on])
        i, j = np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)
        lo, hi, level, flo = t[i], t[i + 1], lines[j], f[i, j]
        for _ in range(MAX_BISECTIONS):
            mid = 0.5 * (lo + hi)
            fm = c(mid)[:, k] - level
            left = np.sign(fm) == np.sign(flo)
            lo, flo, hi = np.where(left, mid, lo), np.where(left, fm, flo), np.where(left, hi, mid)
        found.append(0.5 * (lo + hi))
    return np.unique(np.concatenate(found)) if found else np.empty(0)


def _jacobian_grid(surface: Surface, us: np.ndarray, vs: np.ndarray, centre: Density = None) -> np.ndarray:
    """The density on the grid us x vs (the surface's fast grid path), (len(us), len(vs)),
    0 outside the domain's bounded directions (:func:`_in_domain`)."""
    mu, mv = _in_domain(surface, us, vs)
    us, vs = _inside_domain(surface, us, vs)
    us = surface._wrap(us, 0, surface.periodic_u, "u")
    vs = surface._wrap(vs, 1, surface.periodic_v, "v")
    return _element(surface._grid(us, vs, 1, 1), centre) * (mu[:, None] & mv[None, :])


def _in_domain(surface: Surface, u: np.ndarray, v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Per direction, whether u and v lie in the domain (always in a periodic one). A
    trim loop may leave a bounded direction by its tol (11752.stp face 407 by 8e-4 in u):
    there is no surface there, so area() and the volume integrate 0 over that sliver
    (before, the density at the clipped point: 3.8e-4 of that face's area too much)."""
    (u0, u1), (v0, v1) = surface.domain
    mu = np.ones(np.shape(u), dtype=bool) if surface.periodic_u else (u >= u0) & (u <= u1)
    mv = np.ones(np.shape(v), dtype=bool) if surface.periodic_v else (v >= v0) & (v <= v1)
    return mu, mv


def _potential(ts: TrimmedSurface, u: np.ndarray, v: np.ndarray, edges: np.ndarray,
               centre: Density = None) -> np.ndarray:
    """G(u, v) = int_{edges[0]}^u |S_u x S_v|(s, v) ds by Gauss-Legendre on each interval
    of ``edges``: the whole intervals left of u on the grid of their nodes x the v's
    (cumulated), the last, partial one point by point; in chunks."""
    out = np.zeros(len(u))
    lo, hi = edges[:-1], edges[1:]
    half = 0.5 * (hi - lo)
    X = ((0.5 * (lo + hi))[:, None] + half[:, None] * _GL_X[None]).ravel()
    step = max(1, (CHUNK // 4) // max(len(X), 1))
    for s in range(0, len(u), step):
        uu, vv = u[s:s + step], v[s:s + step]
        g = _jacobian_grid(ts.surface, X, vv, centre).reshape(len(lo), GAUSS_POINTS, len(vv))
        whole = half[:, None] * np.einsum("jkn,k->jn", g, _GL_W)
        cum = np.concatenate([np.zeros((1, len(vv))), np.cumsum(whole, axis=0)])
        j = np.clip(np.searchsorted(edges, uu, side="right") - 1, 0, len(lo) - 1)
        full = cum[j, np.arange(len(vv))]
        a, b = edges[j], np.maximum(uu, edges[0])
        h = 0.5 * (b - a)
        x = (0.5 * (a + b))[:, None] + h[:, None] * _GL_X[None]
        xu, yv = x.ravel(), np.repeat(vv, GAUSS_POINTS)
        mu, mv = _in_domain(ts.surface, xu, yv)
        xu, yv = _inside_domain(ts.surface, xu, yv)
        part = h * ((_jacobian(ts.surface, xu, yv, centre) * (mu & mv)).reshape(x.shape) @ _GL_W)
        out[s:s + step] = full + part
    return out


def _boundary_integral(ts: TrimmedSurface, flat: _Flattened, edges: np.ndarray, bound: Optional[float],
                       rel_tol: float, centre: Density = None, floor: float = 0.0) -> Tuple[float, float, bool]:
    """oint G dv over every chain curve, adaptive Gauss-Legendre (cagd._quadrature: an
    absolute error ``bound``, or None: ``rel_tol`` of the sum of |parts|); (value,
    error estimate, converged)."""
    curves = flat.curves
    lo_list, hi_list, cid = [], [], []
    for k, c in enumerate(curves):
        P = c.control_points
        if np.all(P[:, 1] == P[0, 1]):
            continue                                 # constant v: dv = 0 along it
        a, b = c.domain
        br = np.concatenate([[a], c._breaks_within(a, b), [b]])
        if len(br) > MAX_START_INTERVALS + 1:   # many short spans (fits): start coarser, adapt
            br = br[np.unique(np.linspace(0, len(br) - 1, MAX_START_INTERVALS + 1).astype(int))]
        br = np.unique(np.concatenate([br, _knot_crossings(ts, c, a, b)]))
        lo_list.append(br[:-1])
        hi_list.append(br[1:])
        cid.append(np.full(len(br) - 1, k))
    if not lo_list:
        return 0.0, 0.0, True
    lo, hi, owner = np.concatenate(lo_list), np.concatenate(hi_list), np.concatenate(cid)

    def rule(lo: np.ndarray, hi: np.ndarray, owner: np.ndarray) -> np.ndarray:
        half = 0.5 * (hi - lo)
        t = (0.5 * (hi + lo))[:, None] + half[:, None] * _GL_X[None]
        us, vs, dvs = np.empty(t.shape), np.empty(t.shape), np.empty(t.shape)
        for k in np.unique(owner):
            sel = owner == k
            d = curves[k].derivatives(t[sel], 1)
            us[sel], vs[sel], dvs[sel] = d[0, ..., 0], d[0, ..., 1], d[1, ..., 1]
        G = _potential(ts, us.ravel(), vs.ravel(), edges, centre).reshape(t.shape)
        return half * ((G * dvs) @ _GL_W)

    q = adaptive(rule, lo, hi, owner, bound, rel_tol, MAX_BISECTIONS, MAX_AREA_INTERVALS,
                 "MAX_BISECTIONS, MAX_AREA_INTERVALS", floor)
    return q.value, q.error, q.converged


def _area(ts: TrimmedSurface, rel_tol: float, centre: Density = None, floor: float = 0.0) -> AreaResult:
    """The area by Green's theorem, A = oint G dv with G(u, v) = int |S_u x S_v| du
    (do Carmo 2-5 for the area element; Green's theorem on the trimmed domain), or with
    a ``centre`` the volume contribution int_D (S - c) . (S_u x S_v) / 3: the inner rule
    refined (u spans split 1, 2, 4, ... times) until two refinements agree; the goal,
    rel_tol times the first estimate (at least ``floor``), is shared between the outer
    quadrature (a quarter) and the change between refinements."""
    flat = ts._flattened()
    value, error, ok = _boundary_integral(ts, flat, _u_breaks(ts, flat, 1), None, rel_tol, centre, floor)
    goal = max(rel_tol * abs(value), floor, 1e-300)
    splits = 2
    while True:
        previous = value
        value, error, ok = _boundary_integral(ts, flat, _u_breaks(ts, flat, splits), 0.25 * goal, rel_tol, centre)
        error += abs(value - previous)
        goal = max(rel_tol * abs(value), floor, 1e-300)
        if (ok and error <= goal) or 2 * splits > MAX_AREA_SPLITS:
            converged = ok and error <= goal
            msg = "" if converged else (f"{'area' if centre is None else 'volume'}: error estimate "
                                        f"{error:.3g} above the goal {goal:.3g} ({rel_tol:.3g} relative)")
            return AreaResult(float(value), float(error), bool(converged), msg)
        splits *= 2


def trimmed_integral(ts: TrimmedSurface, rel_tol: float = AREA_TOL, centre: Density = None,
                     floor: float = 0.0) -> AreaResult:
    """The area (``centre`` None) or the volume contribution about ``centre`` of a
    trimmed face, along the direction with fewer knot spans (see :meth:`area_report`;
    exchanging u and v flips S_u x S_v, so the volume changes sign back). With a centre
    the absolute goal is at least ``floor``, by default rel_tol * size^3 (the face's
    size): a face whose plane passes through c contributes 0, which must be found
    without halving down to rounding."""
    if centre is not None and floor <= 0.0:
        floor = rel_tol * ts.untrimmed.size ** 3
    if ts._inner_direction() == 0:
        return _area(ts, rel_tol, centre, floor)
    r = _area(ts._exchanged(), rel_tol, centre, floor)
    return r if centre is None else AreaResult(-r.value, r.error, r.converged, r.message)


# --- boundary -----------------------------------------------------------------------------------
def _affine_iso(c: BSplineCurve) -> Optional[Tuple[int, float, float, float]]:
    """(k, value, x(a), x(b)) when c is affine in t at a constant coordinate (k the
    varying one: 0 for u, 1 for v), else None."""
    if c.is_rational:
        return None
    P = c.control_points
    for k in (0, 1):
        other = 1 - k
        if np.all(P[:, other] == P[0, other]):
            from ..knots.vectors import greville
            g = greville(c.knots, c.degree)
            a, b = c.domain
            x0, x1 = P[0, k], P[-1, k]
            affine = x0 + (g - a) / (b - a) * (x1 - x0)
            if np.allclose(P[:, k], affine, rtol=0, atol=1e-14 * max(abs(x1 - x0), 1e-300)) and x1 != x0:
                return k, float(P[0, other]), float(x0), float(x1)
    return None


def _hermite_nets(lo: np.ndarray, hi: np.ndarray, f: Callable[[np.ndarray], np.ndarray],
                  df: Callable[[np.ndarray], np.ndarray],
                  ddf: Optional[Callable[[np.ndarray], np.ndarray]]) -> np.ndarray:
    """Bezier nets (k, p + 1, dim) of the Hermite interpolants on [lo, hi]: cubic from
    f, f' (p = 3), quintic from f, f', f'' (p = 5) at both ends (Farin, Curves and
    Surfaces for CAGD, 7.1 and 7.5: the end derivatives of a Bezier curve)."""
    ends = [(f(lo), f(hi)), (df(lo), df(hi))] + ([(ddf(lo), ddf(hi))] if ddf is not None else [])
    return _nets_from_ends(hi - lo, ends)


def _nets_from_ends(width: np.ndarray, ends: List[Tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """The nets of :func:`_hermite_nets` from the end values [(f(lo), f(hi)), (f'(lo),
    f'(hi)), optionally (f''(lo), f''(hi))] of pieces of widths ``width``."""
    h = width[:, None]
    (fa, fb), (da, db) = ends[0], ends[1]
    if len(ends) == 2:
        return np.stack([fa, fa + h / 3 * da, fb - h / 3 * db, fb], axis=1)
    aa, ab = ends[2]
    return np.stack([fa, fa + h / 5 * da, fa + 2 * h / 5 * da + h * h / 20 * aa,
                     fb - 2 * h / 5 * db + h * h / 20 * ab, fb - h / 5 * db, fb], axis=1)


class _EndValues:
    """f, f' (and f'') at parameters, each parameter evaluated once (bisection reuses a
    piece's ends; the functions are evaluated point by point, so a value does not depend
    on the other parameters of a call)."""

    def __init__(self, funcs: List[Callable[[np.ndarray], np.ndarray]]):
        self.funcs = funcs
        self.row: Dict[int, int] = {}
        self.values: List[Optional[np.ndarray]] = [None] * len(funcs)

    def missing(self, t: np.ndarray) -> np.ndarray:
        """The distinct parameters of ``t`` not evaluated yet (first appearance order)."""
        fresh = list(dict.fromkeys(k for k in t.view(np.int64).tolist() if k not in self.row))
        return np.array(fresh, dtype=np.int64).view(np.float64)

    def add(self, t: np.ndarray, values: List[np.ndarray]) -> None:
        base = len(self.row)
        for i, k in enumerate(t.view(np.int64).tolist()):
            self.row[k] = base + i
        self.values = [v if old is None else np.concatenate([old, v]) for old, v in zip(self.values, values)]

    def at(self, t: np.ndarray) -> List[np.ndarray]:
        idx = np.array([self.row[k] for k in t.view(np.int64).tolist()], dtype=np.intp)
        return [v[idx] for v in self.values if v is not None]


def hermite_fit(f: Callable[[np.ndarray], np.ndarray], df: Callable[[np.ndarray], np.ndarray],
                breaks: np.ndarray, tol: float,
                ddf: Optional[Callable[[np.ndarray], np.ndarray]] = None) -> Tuple[BSplineCurve, float, bool]:
    """A piecewise Hermite B-spline (interior knots of full multiplicity): cubic and C1
    through f, f' at its breakpoints, or quintic and C2 with f'' (``ddf``), pieces
    bisected until f is within ``tol`` of it at 5 interior points of each (at most
    MAX_FIT_PIECES pieces): (curve, measured error, converged). Each breakpoint's
    f, f' (f'') is evaluated once, together with the new pieces' check points."""
    lo, hi = breaks[:-1].astype(float), breaks[1:].astype(float)
    checks = np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    p = 3 if ddf is None else 5
    from math import comb
    bern = np.array([[comb(p, k) * s ** k * (1 - s) ** (p - k) for k in range(p + 1)] for s in checks])
    done: List[Tuple[np.ndarray, np.ndarray]] = []
    error, ok = 0.0, True
    known = _EndValues([f, df] + ([ddf] if ddf is not None else []))
    count = 0
    while len(lo):
        t = lo[:, None] + (hi - lo)[:, None] * checks[None, :]
        new = known.missing(np.concatenate([lo, hi]))
        both = f(np.concatenate([new, t.ravel()]))
        if len(new):
            known.add(new, [both[:len(new)]] + [g(new) for g in known.funcs[1:]])
        a, b = known.at(lo), known.at(hi)
        nets = _nets_from_ends(hi - lo, list(zip(a, b)))
        approx = np.einsum("sk,nkd->nsd", bern, nets)
        exact = both[len(new):].reshape(approx.shape)
        err = np.linalg.norm(exact - approx, axis=-1).max(axis=1)
        good = err <= tol
        if count + 2 * int(np.count_nonzero(~good)) + int(np.count_nonzero(good)) > MAX_FIT_PIECES:
            good[:] = True
            ok = False
        error = max(error, float(err[good].max(initial=0.0)))
        done.append((lo[good], nets[good]))
        count += int(np.count_nonzero(good))
        mid = 0.5 * (lo + hi)
        lo, hi = np.concatenate([lo[~good], mid[~good]]), np.concatenate([mid[~good], hi[~good]])
    starts = np.concatenate([d[0] for d in done])
    order = np.argsort(starts)
    nets = np.concatenate([d[1] for d in done])[order]
    lo = starts[order]
    end = float(breaks[-1])
    P = np.concatenate([nets[:, :-1].reshape(-1, nets.shape[2]), nets[-1:, -1]])
    knots = np.concatenate([np.full(p + 1, lo[0]), np.repeat(lo[1:], p), np.full(p + 1, end)])
    return BSplineCurve(P, p, knots), error, ok


# --- exact composition S(c(t)) ------------------------------------------------------------------
def _bernstein_product(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Bernstein coefficients (..., m + n + 1) of the product of polynomials in Bernstein
    form of degrees m and n (..., m + 1), (..., n + 1) (broadcast over leading axes):
    h_k = sum_(i + j = k) C(m, i) C(n, j) / C(m + n, k) f_i g_j (Farouki & Rajan 1988)."""
    from math import comb
    m, n = f.shape[-1] - 1, g.shape[-1] - 1
    fs = f * np.array([comb(m, i) for i in range(m + 1)], dtype=np.float64)
    gs = g * np.array([comb(n, j) for j in range(n + 1)], dtype=np.float64)
    shape = np.broadcast_shapes(f.shape[:-1], g.shape[:-1]) + (m + n + 1,)
    h = np.zeros(shape)
    for i in range(m + 1):
        h[..., i:i + n + 1] += fs[..., i:i + 1] * gs
    return h / np.array([comb(m + n, k) for k in range(m + n + 1)], dtype=np.float64)


def _basis_products(s: np.ndarray, r: np.ndarray, p: int) -> np.ndarray:
    """(k, p + 1, d p + 1): C(p, i) s^i r^(p - i) for i = 0..p, s and r (k, d + 1) in
    Bernstein form (the homogenized Bernstein basis W^p B_i^p(s / W), s + r = W)."""
    from math import comb
    powers_s, powers_r = [np.ones_like(s[:, :1])], [np.ones_like(r[:, :1])]
    for _ in range(p):
        powers_s.append(_bernstein_product(powers_s[-1], s))
        powers_r.append(_bernstein_product(powers_r[-1], r))
    return np.stack([comb(p, i) * _bernstein_product(powers_s[i], powers_r[p - i]) for i in range(p + 1)], axis=1)


def _span_of(x: np.ndarray, breaks: np.ndarray, period: float) -> Tuple[np.ndarray, np.ndarray]:
    """(span index, shift) of parameters x among ``breaks`` (a periodic direction: x moved
    by whole periods ``shift`` into [breaks[0], breaks[-1]); a bounded one: the end spans
    extended beyond the domain)."""
    shift = np.zeros_like(x)
    if period > 0:
        shift = period * np.floor((x - breaks[0]) / period)
    j = np.clip(np.searchsorted(breaks, x - shift, side="right") - 1, 0, len(breaks) - 2)
    return j, shift


def _compose(surface: "BSplineSurface", c: BSplineCurve, cuts: np.ndarray) -> BSplineCurve:
    """The exact composition t -> S(c(t)) of a 2-D (rational) B-spline c with a
    (rational) B-spline surface of degrees (p, q): a B-spline of degree d (p + q), d the
    pcurve's degree, on c's pieces split where c crosses a knot line (``cuts``: the
    crossing parameters found in u and v), C0 at the joints (DeRose, Goldman, Hagen and
    Mann, "Functional composition algorithms via blossoming", ACM ToG 12, 1993; here in
    Bernstein form: with c = (X, Y) / W and u = (X - a W) / (b - a) W on a span [a, b],
    W^p B_i^p(u) = C(p, i) (X - a W)^i (b W - X)^(p - i) / (b - a)^p, products of
    Bernstein polynomials (Farouki & Rajan), then sum_ij of the patch's homogeneous
    points: the homogeneous image, weight W^(p + q) w(c))."""
    p, q = surface.degree_u, surface.degree_v
    a, b = c.domain
    cuts = np.unique(cuts)
    own = np.concatenate([[a], c._breaks_within(a, b), [b]])
    near = np.min(np.abs(cuts[:, None] - own[None, :]), axis=1) if len(cuts) else np.empty(0)
    cuts = cuts[near > COMPOSITION_GAP * (b - a)]
    piece = c.refine(np.repeat(cuts, c.degree)) if len(cuts) else c
    breaks, nets = _hom_pieces(piece)                       # (m, d + 1, 3): (x w, y w, w)
    bu, bv, patches = surface.bezier_net()                   # (mu, mv, p + 1, q + 1, D)
    rational = surface.is_rational or c.is_rational
    H = patches if surface.is_rational else np.concatenate([patches, np.ones(patches.shape[:-1] + (1,))], axis=-1)
    mid = _cartesian(nets.sum(axis=1, keepdims=True))[:, 0]   # the net's centroid: inside the piece's span
    (u0, u1), (v0, v1) = surface.domain
    iu, su = _span_of(mid[:, 0], bu, u1 - u0 if surface.periodic_u else 0.0)
    iv, sv = _span_of(mid[:, 1], bv, v1 - v0 if surface.periodic_v else 0.0)
    X, Y, Wc = nets[..., 0], nets[..., 1], nets[..., 2]
    ua, ub = (bu[iu] + su)[:, None], (bu[iu + 1] + su)[:, None]
    va, vb = (bv[iv] + sv)[:, None], (bv[iv + 1] + sv)[:, None]
    Bu = _basis_products((X - ua * Wc) / (ub - ua), (ub * Wc - X) / (ub - ua), p)    # (m, p + 1, d p + 1)
    Bv = _basis_products((Y - va * Wc) / (vb - va), (vb * Wc - Y) / (vb - va), q)
    prod = _bernstein_product(Bu[:, :, None, :], Bv[:, None, :, :])                  # (m, p + 1, q + 1, D + 1)
    Q = np.einsum("mijk,mijh->mkh", prod, H[iu, iv])                                 # homogeneous image nets
    deg = Q.shape[1] - 1
    hom = np.concatenate([Q[:, :-1].reshape(-1, Q.shape[2]), Q[-1:, -1]])
    knots = np.concatenate([np.full(deg + 1, breaks[0]), np.repeat(breaks[1:-1], deg), np.full(deg + 1, breaks[-1])])
    w = hom[:, -1]
    if rational:
        return BSplineCurve(hom[:, :-1] / w[:, None], deg, knots, w)
    return BSplineCurve(hom[:, :-1] / w[:, None], deg, knots)


def _composed(ts: TrimmedSurface, c: BSplineCurve, t: np.ndarray,
              want: np.ndarray) -> Optional[Tuple[BSplineCurve, float]]:
    """(:func:`_compose` of c on the surface's NURBS form, its measured distance from
    S(c(t)) at ``t``), or None where the degree d (p + q) exceeds MAX_COMPOSED_DEGREE or
    the composition misses S(c(t)) by more than COMPOSITION_TOL of the size (a surface
    whose NURBS form is parametrised otherwise, a pcurve leaving a bounded domain, where
    S is clipped)."""
    s = ts.surface.to_nurbs()
    if c.degree * (s.degree_u + s.degree_v) > MAX_COMPOSED_DEGREE:
        return None
    a, b = c.domain
    try:
        image = _compose(s, c, _knot_crossings(ts, c, a, b))
    except CagdError:
        return None
    err = float(np.linalg.norm(image(t) - want, axis=1).max())
    if not err <= COMPOSITION_TOL * max(ts.size, 1e-300):
        return None
    return image, err


def _samples(curves: Sequence[BSplineCurve]) -> np.ndarray:
    """BOUNDARY_SAMPLES parameters per span of all ``curves`` (their breaks merged) on
    their common range, the ends included."""
    a, b = curves[0].domain
    br = np.unique(np.concatenate([[a, b]] + [c._breaks_within(a, b) for c in curves]))
    s = np.linspace(0.0, 1.0, BOUNDARY_SAMPLES + 1)[:-1]
    return np.concatenate([(br[:-1, None] + (br[1:] - br[:-1])[:, None] * s[None]).ravel(), [b]])


def edge_deviation(edge: BSplineCurve, t: np.ndarray, want: np.ndarray) -> float:
    """The largest distance of the points ``want`` = S(c(t)) from the edge curve: per
    point the smaller of |E(t) - S(c(t))| (the same parameter) and |E(t*) - S(c(t))|,
    t* by PROJECTION_STEPS Newton steps on <E(t) - P, E'(t)> = 0 from t, kept in the
    range (an edge curve in its own parametrisation, e.g. a conic's rational form)."""
    same = np.linalg.norm(edge(t) - want, axis=1)
    a, b = edge.domain
    x = t.copy()
    for _ in range(PROJECTION_STEPS):
        d = edge.derivatives(x, 2)
        r = d[0] - want
        g = np.einsum("ij,ij->i", r, d[1])
        h = np.einsum("ij,ij->i", d[1], d[1]) + np.einsum("ij,ij->i", r, d[2])
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(h > 0, g / np.where(h > 0, h, 1.0), 0.0)
        x = np.clip(x - step, a, b)
    projected = np.linalg.norm(edge(x) - want, axis=1)
    return float(np.minimum(same, projected).max(initial=0.0))


def _boundary(ts: TrimmedSurface, tol: float, images_only: bool = False) -> TrimBoundary:
    s = ts.surface
    curves, exact, sources, deviations = [], [], [], []
    error, edge_error, ok = 0.0, 0.0, True
    for i, loop in enumerate(ts.loops):
        row, flags, kinds, devs = [], [], [], []
        for j, c in enumerate(loop):
            a, b = c.domain

            def f(t: np.ndarray, c: BSplineCurve = c) -> np.ndarray:
                uv = c(t)
                uu, vv = _inside_domain(s, uv[:, 0], uv[:, 1])
                return s(uu, vv)

            edge = None if images_only or ts.edges is None else ts.edges[i][j]
            if edge is not None:
                t = _samples([c, edge])
                dev = edge_deviation(edge, t, f(t))
                row.append(edge)
                flags.append(False)
                kinds.append("edge")
                devs.append(dev)
                edge_error = max(edge_error, dev)
                continue
            iso = _affine_iso(c)
            if iso is not None:
                k, value, x0, x1 = iso
                direction = "u" if k == 0 else "v"
                curve = s.isocurve(direction, value)
                lo_, hi_ = min(x0, x1), max(x0, x1)
                lo_d, hi_d = curve.domain
                if not (curve.periodic or lo_ < lo_d or hi_ > hi_d):
                    piece = curve.segment(max(lo_, lo_d), min(hi_, hi_d))
                    if x1 < x0:
                        piece = piece.reversed()
                    row.append(piece.reparametrized(a, b))
                    flags.append(True)
                    kinds.append("iso")
                    devs.append(0.0)
                    continue
            if not images_only:
                t = _samples([c])
                t = 0.5 * (t[:-1] + t[1:])                   # inside the spans (not the joints)
                hit = _composed(ts, c, t, f(t))
                if hit is not None:
                    row.append(hit[0])
                    flags.append(True)
                    kinds.append("composition")
                    devs.append(hit[1])
                    continue

            def df(t: np.ndarray, c: BSplineCurve = c) -> np.ndarray:
                d = c.derivatives(t, 1)
                uu, vv = _inside_domain(s, d[0, :, 0], d[0, :, 1])
                sd = s.derivatives(uu, vv, 1, 1)
                return sd[1, 0] * d[1, :, :1] + sd[0, 1] * d[1, :, 1:]

            def ddf(t: np.ndarray, c: BSplineCurve = c) -> np.ndarray:
                d = c.derivatives(t, 2)
                uu, vv = _inside_domain(s, d[0, :, 0], d[0, :, 1])
                sd = s.derivatives(uu, vv, 2, 2)
                du, dv, d2u, d2v = d[1, :, :1], d[1, :, 1:], d[2, :, :1], d[2, :, 1:]
                return (sd[2, 0] * du * du + 2.0 * sd[1, 1] * du * dv + sd[0, 2] * dv * dv
                        + sd[1, 0] * d2u + sd[0, 1] * d2v)

            breaks = np.concatenate([[a], c._breaks_within(a, b), [b]])
            fit, err, good = hermite_fit(f, df, breaks, tol, ddf if images_only else None)
            row.append(fit)
            flags.append(False)
            kinds.append("fit")
            devs.append(err)
            error, ok = max(error, err), ok and good
        curves.append(tuple(row))
        exact.append(tuple(flags))
        sources.append(tuple(kinds))
        deviations.append(tuple(devs))
    msg = "" if ok else f"boundary: some fits stopped at {MAX_FIT_PIECES} pieces above tol = {tol:.3g}"
    return TrimBoundary(tuple(curves), tuple(exact), error, tol, ok, msg, tuple(sources), tuple(deviations),
                        edge_error)
