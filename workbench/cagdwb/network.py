"""Curve-network and blending objects (issue 18): Gordon surface through two linked
families of edges, Sweep along one path and between two rails, Blend curve between
two edge ends, Blend surface between two face edges and Match surface (a face's edge
moved onto another face's edge, G0/G1/G2).

Each object links its inputs (``App::PropertyLinkSub`` / ``LinkSubList``), so FreeCAD
recomputes it when a linked edge or face changes or moves; ``execute`` (features.Feature)
builds the engine result (``cagd.gordon``, ``cagd.sweep``, ``cagd.sweep2``,
``cagd.blend_curve``, ``cagd.blend_surface``, ``cagd.match_surface``) from the links'
exact B-spline forms (``conversion.edge_to_curve``, ``conversion.face_to_surface``) and
shows what the engine measured in read-only properties (``MaxError``, ``MaxAngle``,
``MaxCurvatureGap``, ``Converged``). A bad link or value puts the object in FreeCAD's
error state with an empty shape and a message naming the property: engine argument
names are renamed to the properties (``profiles[1], guides[2]`` -> ``Profiles[1]
(Label.Edge3), Guides[2] (Line.Edge1)``, ``tol`` -> ``Tolerance``, ``s1`` -> ``Face1``,
...). A result the engine reports as not converged (a tolerance not reached) stays
valid with a warning in ``Message``, as the fitting objects do.

Face edges are named by the face's parameter box, as in the engine: "u0" (u = u_min,
running in v), "u1", "v0", "v1" of the face's untrimmed B-spline surface cut to the
face's ParameterRange; trimmed faces are refused. :func:`edge_side` finds the name of a
selected edge of a face (the commands use it).
"""
from __future__ import annotations

import contextlib
import re
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np

import Part

from . import conversion
from .conversion import cagd
from .features import add, add_enum, linked_edge, linked_edges, make
from .fitting import PRECISION, Measured, _readonly, _tolerance, linked_element

EDGES = ("u0", "u1", "v0", "v1")
ENDS = ("start", "end")
FRAMES = ("rmf", "frenet", "fixed")
G12 = ("G1", "G2")
G123 = ("G1", "G2", "G3")
G012 = ("G0", "G1", "G2")
SIDE_SAMPLES = 9                 # points of a box edge compared with a selected edge (edge_side)


# --- messages ---------------------------------------------------------------------------------
_TOKEN = re.compile(r"^([A-Za-z_]+)(\[(\d+)\])?$")
_INDEXED = re.compile(r"\b([a-z_]+)\[(\d+)\]")       # an indexed argument inside a message: 'guides[0]'


@contextlib.contextmanager
def renamed(names: Dict[str, str], labels: Optional[Dict[str, Sequence[str]]] = None) -> Iterator[None]:
    """Re-raise an engine CagdError whose head (the text before the first ':') names
    engine arguments, e.g. 'profiles[1], guides[2]: ...', with the properties instead
    ('Profiles[1] (Sketch.Edge2), Guides[2] (Line.Edge1): ...'; ``labels`` gives the
    linked elements of a list property by index); in the rest of such a message the
    indexed list arguments ('meets guides[0]') are renamed likewise. Other messages are
    kept."""
    labels = labels or {}

    def indexed(base: str, k: int) -> str:
        label = labels.get(base)
        return names[base] + f"[{k}]" + (f" ({label[k]})" if label is not None and k < len(label) else "")
    try:
        yield
    except cagd.CagdError as exc:
        text = str(exc)
        head, sep, rest = text.partition(":")
        if not sep:
            raise
        tokens = [t.strip() for t in head.split(",")]
        out = []
        for token in tokens:
            if token in names:                     # a whole token (tangent_scales[0])
                out.append(names[token])
                continue
            m = _TOKEN.match(token)
            if m is None or m.group(1) not in names:
                raise
            out.append(indexed(m.group(1), int(m.group(3))) if m.group(2) else names[m.group(1)])
        rest = _INDEXED.sub(lambda m: indexed(m.group(1), int(m.group(2))) if m.group(1) in labels else m.group(0),
                            rest)
        raise cagd.CagdError(f"{', '.join(out)}:{rest}") from None


def _warning(result) -> Optional[str]:
    return None if result.converged else result.message


# --- linked edges and faces ---------------------------------------------------------------------
def _curves(links, name: str) -> Tuple[List[object], List[str]]:
    """(engine curves, labels) of the edges of a LinkSubList property."""
    if not links:
        raise cagd.CagdError(f"{name}: no edges linked")
    pairs = linked_edges(links, name)
    return [conversion.edge_to_curve(e) for _, e in pairs], [label for label, _ in pairs]


def _curve(link, name: str):
    return conversion.edge_to_curve(linked_edge(link, name))


def linked_face(link, name: str):
    """(Part face, label) of a LinkSub to a face (or an object whose shape is one face)."""
    element, where = linked_element(link, name)
    if element.ShapeType != "Face":
        raise cagd.CagdError(f"{name}: {where} is an edge, not a face")
    return element, where


def face_surface(link, name: str):
    """The engine B-spline surface of a linked face, cut to its parameter box; a trimmed
    face (its boundary not that box) is refused: its box edges are not its edges."""
    face, where = linked_face(link, name)
    surface, reason = conversion.face_to_trimmed(face)
    if isinstance(surface, cagd.TrimmedSurface) or reason is not None:
        raise cagd.CagdError(f"{name}: {where} is a trimmed face (its boundary is not its parameter box"
                             + (f"; {reason}" if reason else "") + "); blends and matches take whole faces")
    return surface


def edge_side(face, edge) -> Optional[str]:
    """Which parameter-box edge of ``face`` ("u0", "u1", "v0", "v1") the Part ``edge`` is
    (SIDE_SAMPLES points of the box edge within 1e-6 of the edge's size from it), or None."""
    u0, u1, v0, v1 = face.ParameterRange
    size = max(edge.BoundBox.DiagonalLength, face.BoundBox.DiagonalLength * 1e-3, 1e-300)
    t = np.linspace(0.0, 1.0, SIDE_SAMPLES)
    best, best_d = None, np.inf
    for side in EDGES:
        if side[0] == "u":
            uv = [((u0 if side == "u0" else u1), v0 + (v1 - v0) * s) for s in t]
        else:
            uv = [(u0 + (u1 - u0) * s, (v0 if side == "v0" else v1)) for s in t]
        d = max(edge.distToShape(Part.Vertex(face.Surface.value(u, v)))[0] for u, v in uv)
        if d < best_d:
            best, best_d = side, d
    return best if best_d <= 1e-6 * size else None


# --- Gordon surface --------------------------------------------------------------------------------
GORDON_NAMES = {"profiles": "Profiles", "guides": "Guides", "tol": "Tolerance"}


class GordonSurface(Measured):
    """The surface through a network of profile and guide edges (cagd.gordon: Gordon's
    Boolean sum of two skins and their tensor-product interpolant, Piegl & Tiller 10.5);
    u along the profiles, v along the guides. Every profile must cross every guide once;
    curves may come in any order and direction."""

    TYPE = "Cagd::GordonSurface"
    DEFAULT_LABEL = "GordonSurface"
    LINKS = ("Profiles", "Guides")
    POINTS = "Profiles, Guides"
    RESULTS = (("MaxError", 0.0), ("MaxMiss", 0.0), ("Converged", False))

    def setup(self, obj) -> None:
        add(obj, "LinkSubList", "Profiles", "Gordon", "Edges of the first family (u runs along them), 2 or more")
        add(obj, "LinkSubList", "Guides", "Gordon", "Edges of the second family, each crossing every profile once")
        add(obj, PRECISION, "Tolerance", "Gordon", "Distance (mm, > 0) within which profiles and guides count as "
            "meeting, and the bound a reparametrising refit must keep", 1e-3)
        add(obj, PRECISION, "MaxError", "Status", "Upper bound of the input edges' distance from the surface (mm)",
            0.0)
        add(obj, PRECISION, "MaxMiss", "Status", "Largest gap between a profile and a guide where they meet (mm)",
            0.0)
        add(obj, "Bool", "Converged", "Status", "MaxError within Tolerance", False)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def compute(self, obj):
        tol = _tolerance(obj)
        profiles, pl = _curves(obj.Profiles, "Profiles")
        guides, gl = _curves(obj.Guides, "Guides")
        with renamed(GORDON_NAMES, {"profiles": pl, "guides": gl}):
            r = cagd.gordon(profiles, guides, tol)
        values = {"MaxError": float(r.max_error), "MaxMiss": float(r.max_miss), "Converged": bool(r.converged)}
        return r.surface, values, _warning(r)


# --- sweeps ------------------------------------------------------------------------------------
SWEEP_NAMES = {"profile": "Profile", "path": "Path", "frame": "Frame", "tol": "Tolerance", "profiles": "Profiles",
               "rail1": "Rail1", "rail2": "Rail2"}
SWEEP_RESULTS = (("MaxError", 0.0), ("Converged", False))


def _sweep_status(obj) -> None:
    add(obj, PRECISION, "Tolerance", "Sweep", "Largest allowed distance (mm, > 0) from the true sweep", 1e-4)
    add(obj, PRECISION, "MaxError", "Status", "The engine's bound of the distance from the true sweep (mm)", 0.0)
    add(obj, "Bool", "Converged", "Status", "MaxError within Tolerance", False)


def _point(edge, at_end: bool) -> np.ndarray:
    return np.array(tuple(edge.valueAt(edge.LastParameter if at_end else edge.FirstParameter)))


class Sweep(Measured):
    """The Profile edge swept along the Path edge (cagd.sweep: rotation-minimising,
    Frenet or fixed frame; exact translational surface for a straight path). The
    profile is taken where it sits; the path runs from its end nearer the profile (a
    path edge pointing the other way is reversed)."""

    TYPE = "Cagd::Sweep"
    DEFAULT_LABEL = "Sweep"
    LINKS = ("Profile", "Path")
    POINTS = "Profile"
    RESULTS = SWEEP_RESULTS

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Profile", "Sweep", "The profile edge (where it sits at the path's start)")
        add(obj, "LinkSub", "Path", "Sweep", "The path edge")
        add_enum(obj, "Frame", "Sweep", "Moving frame: rmf (rotation-minimising), frenet or fixed (translation)",
                 FRAMES, "rmf")
        _sweep_status(obj)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def compute(self, obj):
        tol = _tolerance(obj)
        profile_edge, path_edge = linked_edge(obj.Profile, "Profile"), linked_edge(obj.Path, "Path")
        profile, path = conversion.edge_to_curve(profile_edge), conversion.edge_to_curve(path_edge)
        shape = Part.Compound([profile_edge])
        near = [shape.distToShape(Part.Vertex(path_edge.valueAt(t)))[0]
                for t in (path_edge.FirstParameter, path_edge.LastParameter)]
        if near[1] < near[0]:
            path = path.reversed()
        with renamed(SWEEP_NAMES):
            r = cagd.sweep(profile, path, frame=str(obj.Frame), tol=tol)
        return r.surface, {"MaxError": float(r.max_error), "Converged": bool(r.converged)}, _warning(r)


class Sweep2(Measured):
    """Profile edges placed between two rail edges (cagd.sweep2: each profile mapped by
    the similarity taking its ends onto the rails, several profiles blended along the
    rails). A profile running from Rail2 to Rail1 is reversed, and Rail2 when its start
    is nearer Rail1's end (the rails run alike)."""

    TYPE = "Cagd::Sweep2"
    DEFAULT_LABEL = "Sweep2"
    LINKS = ("Profiles", "Rail1", "Rail2")
    POINTS = "Profiles"
    RESULTS = SWEEP_RESULTS

    def setup(self, obj) -> None:
        add(obj, "LinkSubList", "Profiles", "Sweep", "One or more profile edges, each from Rail1 to Rail2")
        add(obj, "LinkSub", "Rail1", "Sweep", "The first rail edge")
        add(obj, "LinkSub", "Rail2", "Sweep", "The second rail edge")
        _sweep_status(obj)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def compute(self, obj):
        tol = _tolerance(obj)
        rails = [linked_edge(obj.Rail1, "Rail1"), linked_edge(obj.Rail2, "Rail2")]
        if not obj.Profiles:
            raise cagd.CagdError("Profiles: no edges linked")
        pairs = linked_edges(obj.Profiles, "Profiles")
        profiles = []
        for _, e in pairs:
            c = conversion.edge_to_curve(e)
            a, b = Part.Vertex(e.valueAt(e.FirstParameter)), Part.Vertex(e.valueAt(e.LastParameter))
            keep = rails[0].distToShape(a)[0] + rails[1].distToShape(b)[0]
            swap = rails[0].distToShape(b)[0] + rails[1].distToShape(a)[0]
            profiles.append(c.reversed() if swap < keep else c)
        r1, r2 = (conversion.edge_to_curve(e) for e in rails)
        ends = [[_point(e, k == 1) for k in (0, 1)] for e in rails]
        along = np.linalg.norm(ends[0][0] - ends[1][0]) + np.linalg.norm(ends[0][1] - ends[1][1])
        across = np.linalg.norm(ends[0][0] - ends[1][1]) + np.linalg.norm(ends[0][1] - ends[1][0])
        if across < along:                      # Rail2 drawn the other way: run it like Rail1
            r2 = r2.reversed()
        with renamed(SWEEP_NAMES, {"profiles": [label for label, _ in pairs]}):
            r = cagd.sweep2(profiles, r1, r2, tol=tol)
        return r.surface, {"MaxError": float(r.max_error), "Converged": bool(r.converged)}, _warning(r)


# --- blends ----------------------------------------------------------------------------------------
BLEND_CURVE_NAMES = {"c1": "Edge1", "c2": "Edge2", "end1": "End1", "end2": "End2", "continuity": "Continuity",
                     "tangent_scales[0]": "TangentScale1", "tangent_scales[1]": "TangentScale2",
                     "tangent_scales": "TangentScale1, TangentScale2"}
BLEND_SURFACE_NAMES = {"s1": "Face1", "s2": "Face2", "edge1": "Edge1", "edge2": "Edge2",
                       "continuity": "Continuity", "tangent_scales[0]": "TangentScale1",
                       "tangent_scales[1]": "TangentScale2", "tangent_scales": "TangentScale1, TangentScale2"}
MATCH_NAMES = {"s": "Face", "edge": "Edge", "target": "Target", "target_edge": "TargetEdge",
               "continuity": "Continuity"}


def _scales(obj) -> Optional[Tuple[float, float]]:
    """(TangentScale1, TangentScale2), or None for the engine's default: for a blend curve
    when AutomaticScales is on (the scales of least curvature variation), for a blend
    surface at (1, 1) (a rational blend surface may shorten a default scale to keep its
    weights positive)."""
    a, b = float(obj.TangentScale1), float(obj.TangentScale2)
    if hasattr(obj, "AutomaticScales"):
        return None if obj.AutomaticScales else (a, b)
    return None if (a, b) == (1.0, 1.0) else (a, b)


SURFACE_SCALE_DOC = "Tangent length at Edge{k} relative to the default (> 0; 1 = the default)"
CURVE_SCALE_DOC = ("Used when AutomaticScales is off: the bridge's end speed at Edge{k} = this x the chord "
                   "between the two ends (> 0; 1: the first leg is the chord / degree long)")
AUTOMATIC_DOC = ("On (default): the tangent scales of least curvature variation (the engine's automatic "
                 "choice; TangentScale1/2 are not used, UsedScale1/2 show what was chosen). Off: "
                 "TangentScale1/2 as given")


def _scale_properties(obj, group: str, doc: str = SURFACE_SCALE_DOC) -> None:
    add(obj, "Float", "TangentScale1", group, doc.format(k=1), 1.0)
    add(obj, "Float", "TangentScale2", group, doc.format(k=2), 1.0)


CONTINUITY_DOC = ("G1: cubic bridge; G2: quintic, curvature matched too; G3: degree 7, also the curvature's "
                  "arc-length derivative (and the torsion)")


def _level(obj) -> int:
    return int(str(obj.Continuity)[1])


class BlendCurve(Measured):
    """A Bezier bridge from End1 of Edge1 to End2 of Edge2, G1 (cubic), G2 (quintic) or
    G3 (degree 7) to both (cagd.blend_curve, Farin 14.1). Ends are the edges' own: start
    = FirstParameter. Tangent scales automatic (least curvature variation) unless
    AutomaticScales is off."""

    TYPE = "Cagd::BlendCurve"
    DEFAULT_LABEL = "BlendCurve"
    LINKS = ("Edge1", "Edge2")
    POINTS = "Edge1, Edge2"
    RESULTS = (("MaxAngle", 0.0), ("MaxCurvatureGap", 0.0), ("MaxCurvatureDerivativeGap", 0.0),
               ("UsedScale1", 0.0), ("UsedScale2", 0.0), ("Converged", False))

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Edge1", "Blend", "The first edge")
        add_enum(obj, "End1", "Blend", "The end of Edge1 the bridge starts at (start: its FirstParameter)", ENDS,
                 "end")
        add(obj, "LinkSub", "Edge2", "Blend", "The second edge")
        add_enum(obj, "End2", "Blend", "The end of Edge2 the bridge ends at", ENDS, "start")
        add_enum(obj, "Continuity", "Blend", CONTINUITY_DOC, G123, "G2")
        self.add_automatic(obj)
        _scale_properties(obj, "Blend", CURVE_SCALE_DOC)
        self.add_status(obj)
        self.scale_modes(obj)

    @staticmethod
    def scale_modes(obj) -> None:
        """TangentScale1/2 read-only (in the property editor and the task panel) while
        AutomaticScales is on: they are not used then."""
        for k in (1, 2):
            if hasattr(obj, f"TangentScale{k}") and hasattr(obj, "AutomaticScales"):
                obj.setEditorMode(f"TangentScale{k}", 1 if obj.AutomaticScales else 0)

    def onChanged(self, obj, prop: str) -> None:
        super().onChanged(obj, prop)
        if prop == "AutomaticScales":
            self.scale_modes(obj)

    @staticmethod
    def add_automatic(obj, value: bool = True) -> None:
        add(obj, "Bool", "AutomaticScales", "Blend", AUTOMATIC_DOC)
        obj.AutomaticScales = value

    def add_status(self, obj) -> None:
        """The read-only results (those a restored older document lacks are added)."""
        docs = {"MaxAngle": ("Float", "Largest angle between the bridge's and the edges' tangents (rad)"),
                "MaxCurvatureGap": ("Float", "Largest relative curvature-vector difference at the ends"),
                "MaxCurvatureDerivativeGap": ("Float", "Largest relative difference of the third arc-length "
                                              "derivative (d curvature / ds, torsion) at the ends: the G3 measure"),
                "UsedScale1": ("Float", "The tangent scale used at Edge1 (given or automatic)"),
                "UsedScale2": ("Float", "The tangent scale used at Edge2 (given or automatic)"),
                "Converged": ("Bool", "The requested continuity reached at both ends")}
        for name, empty in self.RESULTS:
            if not hasattr(obj, name):
                add(obj, docs[name][0], name, "Status", docs[name][1], empty)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def onDocumentRestored(self, obj) -> None:
        """A document saved before G3 and AutomaticScales: G3 added to Continuity (its
        value kept), AutomaticScales on exactly when the scales were (1, 1) (what (1, 1)
        meant then), the new results added."""
        super().onDocumentRestored(obj)
        if "G3" not in obj.getEnumerationsOfProperty("Continuity"):
            value = str(obj.Continuity)
            obj.Continuity = list(G123)
            obj.Continuity = value
            obj.setDocumentationOfProperty("Continuity", CONTINUITY_DOC)
        if not hasattr(obj, "AutomaticScales"):
            self.add_automatic(obj, (float(obj.TangentScale1), float(obj.TangentScale2)) == (1.0, 1.0))
            for k in (1, 2):
                obj.setDocumentationOfProperty(f"TangentScale{k}", CURVE_SCALE_DOC.format(k=k))
        self.add_status(obj)
        self.scale_modes(obj)

    def claimed(self, obj) -> list:
        """Nothing: the bridged edges stay curves of their own."""
        return []

    def compute(self, obj):
        c1, c2 = _curve(obj.Edge1, "Edge1"), _curve(obj.Edge2, "Edge2")
        with renamed(BLEND_CURVE_NAMES):
            r = cagd.blend_curve(c1, str(obj.End1), c2, str(obj.End2), _level(obj), _scales(obj))
        values = {"MaxAngle": float(max(r.g1_angles)), "MaxCurvatureGap": float(max(r.curvature_gaps)),
                  "MaxCurvatureDerivativeGap": float(max(r.curvature_derivative_gaps)),
                  "UsedScale1": float(r.tangent_scales[0]), "UsedScale2": float(r.tangent_scales[1]),
                  "Converged": bool(r.converged)}
        return r.curve, values, _warning(r)


SURFACE_RESULTS = (("MaxAngle", 0.0), ("MaxCurvatureGap", 0.0), ("MaxGap", 0.0), ("Converged", False))


def _surface_status(obj) -> None:
    add(obj, "Float", "MaxAngle", "Status", "Largest tangent-plane angle across the edge(s) at 50 stations (rad)",
        0.0)
    add(obj, "Float", "MaxCurvatureGap", "Status", "G2: largest relative normal-curvature difference across the "
        "edge(s); 0 otherwise", 0.0)
    add(obj, PRECISION, "MaxGap", "Status", "Largest position gap along the edge(s) (mm)", 0.0)
    add(obj, "Bool", "Converged", "Status", "The requested continuity reached along the edge(s)", False)


def _surface_values(r) -> dict:
    return {"MaxAngle": float(r.max_angle), "MaxCurvatureGap": float(r.max_curvature_gap or 0.0),
            "MaxGap": float(r.max_gap), "Converged": bool(r.converged)}


class BlendSurface(Measured):
    """A surface bridging Edge1 of Face1 and Edge2 of Face2, G1 (cubic across) or G2
    (quintic across) along both whole edges (cagd.blend_surface); u along Edge1."""

    TYPE = "Cagd::BlendSurface"
    DEFAULT_LABEL = "BlendSurface"
    LINKS = ("Face1", "Face2")
    POINTS = "Face1, Face2"
    RESULTS = SURFACE_RESULTS

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Face1", "Blend", "The first face (untrimmed B-spline or analytic)")
        add_enum(obj, "Edge1", "Blend", "Face1's parameter-box edge: u0, u1 (u = min, max) or v0, v1", EDGES, "u1")
        add(obj, "LinkSub", "Face2", "Blend", "The second face")
        add_enum(obj, "Edge2", "Blend", "Face2's parameter-box edge", EDGES, "u0")
        add_enum(obj, "Continuity", "Blend", "G1: cubic across; G2: quintic, normal curvature matched too", G12,
                 "G1")
        _scale_properties(obj, "Blend")
        _surface_status(obj)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def claimed(self, obj) -> list:
        return []

    def compute(self, obj):
        s1, s2 = face_surface(obj.Face1, "Face1"), face_surface(obj.Face2, "Face2")
        with renamed(BLEND_SURFACE_NAMES):
            r = cagd.blend_surface(s1, str(obj.Edge1), s2, str(obj.Edge2), _level(obj), _scales(obj))
        return r.surface, _surface_values(r), _warning(r)


class MatchSurface(Measured):
    """Face with its control rows next to Edge replaced so that it meets Target at
    TargetEdge G0, G1 or G2 (cagd.match_surface, Rhino's MatchSrf without refitting);
    the rest of Face's net, and its opposite edge, stay."""

    TYPE = "Cagd::MatchSurface"
    DEFAULT_LABEL = "MatchSurface"
    LINKS = ("Face", "Target")
    POINTS = "Face"
    RESULTS = SURFACE_RESULTS

    def setup(self, obj) -> None:
        add(obj, "LinkSub", "Face", "Match", "The face to modify (untrimmed B-spline or analytic)")
        add_enum(obj, "Edge", "Match", "Face's parameter-box edge that moves", EDGES, "u1")
        add(obj, "LinkSub", "Target", "Match", "The face to meet (stays as it is)")
        add_enum(obj, "TargetEdge", "Match", "Target's parameter-box edge", EDGES, "u0")
        add_enum(obj, "Continuity", "Match", "G0: position; G1: tangent planes; G2: normal curvature too", G012,
                 "G1")
        _surface_status(obj)
        _readonly(obj, [n for n, _ in self.RESULTS])

    def claimed(self, obj) -> list:
        """Face (the match replaces it); Target stays a face of its own."""
        face = obj.Face[0] if obj.Face else None
        return [face] if face is not None and face is not obj else []

    def compute(self, obj):
        s, t = face_surface(obj.Face, "Face"), face_surface(obj.Target, "Target")
        with renamed(MATCH_NAMES):
            r = cagd.match_surface(s, str(obj.Edge), t, str(obj.TargetEdge), _level(obj))
        return r.surface, _surface_values(r), _warning(r)


KINDS = {"GordonSurface": GordonSurface, "Sweep": Sweep, "Sweep2": Sweep2, "BlendCurve": BlendCurve,
         "BlendSurface": BlendSurface, "MatchSurface": MatchSurface}


# --- creation helpers (used by the commands and the tests) ---------------------------------------
def _sub(link):
    """(obj, 'EdgeN') as the (obj, ['EdgeN']) a LinkSub property holds."""
    if isinstance(link, tuple) and len(link) == 2 and isinstance(link[1], str):
        return link[0], [link[1]]
    return link


def link_values(values: dict) -> dict:
    """Property values with every (obj, 'EdgeN') link (alone or in a list) as (obj, ['EdgeN'])."""
    return {k: ([_sub(x) for x in v] if isinstance(v, list) else _sub(v)) for k, v in values.items()}


def make_gordon(profiles, guides, doc=None, **values):
    """``profiles``, ``guides``: LinkSubList values, e.g. [(obj, 'Edge1'), ...]."""
    return make(GordonSurface, doc=doc, Profiles=profiles, Guides=guides, **values)


def make_sweep(profile, path, doc=None, **values):
    """``profile``, ``path``: (object, 'EdgeN')."""
    return make(Sweep, doc=doc, Profile=profile, Path=path, **values)


def make_sweep2(profiles, rail1, rail2, doc=None, **values):
    return make(Sweep2, doc=doc, Profiles=profiles, Rail1=rail1, Rail2=rail2, **values)


def make_blend_curve(edge1, edge2, doc=None, **values):
    """``edge1``, ``edge2``: (object, 'EdgeN'); End1/End2 default to the nearest pair of
    ends (:func:`nearest_ends`) unless given."""
    if "End1" not in values and "End2" not in values:
        values.update(zip(("End1", "End2"), nearest_ends(linked_edge(_sub(edge1), "Edge1"),
                                                         linked_edge(_sub(edge2), "Edge2"))))
    return make(BlendCurve, doc=doc, Edge1=edge1, Edge2=edge2, **values)


def make_blend_surface(face1, edge1, face2, edge2, doc=None, **values):
    """``face1``, ``face2``: (object, 'FaceN'); ``edge1``, ``edge2``: 'u0', 'u1', 'v0', 'v1'."""
    return make(BlendSurface, doc=doc, Face1=face1, Edge1=edge1, Face2=face2, Edge2=edge2, **values)


def make_match_surface(face, edge, target, target_edge, doc=None, **values):
    return make(MatchSurface, doc=doc, Face=face, Edge=edge, Target=target, TargetEdge=target_edge, **values)


def nearest_ends(e1, e2) -> Tuple[str, str]:
    """(End1, End2): the pair of ends of two Part edges closest to each other."""
    best = min(((a, b) for a in ENDS for b in ENDS),
               key=lambda ab: float(np.linalg.norm(_point(e1, ab[0] == "end") - _point(e2, ab[1] == "end"))))
    return best


def facing_sides(f1, f2) -> Tuple[str, str]:
    """(Edge1, Edge2): the parameter-box edges of two Part faces whose midpoints are
    closest (the edges facing each other across a gap)."""
    def mids(face):
        u0, u1, v0, v1 = face.ParameterRange
        um, vm = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
        uv = {"u0": (u0, vm), "u1": (u1, vm), "v0": (um, v0), "v1": (um, v1)}
        return {k: np.array(tuple(face.Surface.value(*p))) for k, p in uv.items()}
    m1, m2 = mids(f1), mids(f2)
    return min(((a, b) for a in EDGES for b in EDGES), key=lambda ab: float(np.linalg.norm(m1[ab[0]] - m2[ab[1]])))


# --- selections (the commands) --------------------------------------------------------------------
#: property values of a new object of each kind (besides its links), for :func:`check`
DEFAULTS = {"GordonSurface": {"Tolerance": 1e-3}, "Sweep": {"Frame": "rmf", "Tolerance": 1e-4},
            "Sweep2": {"Tolerance": 1e-4},
            "BlendCurve": {"Continuity": "G2", "AutomaticScales": True, "TangentScale1": 1.0, "TangentScale2": 1.0},
            "BlendSurface": {"Continuity": "G1", "TangentScale1": 1.0, "TangentScale2": 1.0},
            "MatchSurface": {"Continuity": "G1"}}


class _Trial:
    """Stands in for a new object in :func:`check` (its properties as attributes)."""

    Label = "new object"

    def __init__(self, values):
        self.__dict__.update(values)


def check(kind: str, **values) -> None:
    """Raise the CagdError a new ``kind`` object with these links (and the defaults)
    would be in, before any object is made (the commands refuse a wrong selection);
    LinkSub values as (obj, 'EdgeN') or (obj, ['EdgeN'])."""
    cls = KINDS[kind]
    cls.compute(cls.__new__(cls), _Trial(dict(DEFAULTS[kind], **link_values(values))))


def split_network(edges, tol: float = 1e-3) -> Tuple[list, list]:
    """Profiles and guides of a network given as one list of (obj, 'EdgeN'): the first
    edge is a profile, the edges touching it (within ``tol``) are the guides, the rest
    profiles (curves of one family do not meet)."""
    shapes = [o.Shape.getElement(s) for o, s in edges]
    first = shapes[0]
    guides = [k for k in range(1, len(edges)) if first.distToShape(shapes[k])[0] <= tol]
    profiles = [k for k in range(len(edges)) if k not in guides]
    return [edges[k] for k in profiles], [edges[k] for k in guides]


def face_and_side(obj, sub: str) -> Tuple[Tuple[object, str], str]:
    """((obj, 'FaceN'), side) for a selected face edge (obj, 'EdgeN'): the face of obj
    holding the edge and which parameter-box edge of it the edge is.

    Raises:
        CagdError: no face of obj holds the edge, or it is not a box edge of that face.
    """
    edge = obj.Shape.getElement(sub)
    for k, face in enumerate(obj.Shape.Faces):
        if any(e.isSame(edge) for e in face.Edges):
            side = edge_side(face, edge)
            if side is None:
                raise cagd.CagdError(f"{obj.Label}.{sub} is not a parameter-box edge (u0, u1, v0, v1) of "
                                     f"{obj.Label}.Face{k + 1} (a trimmed face's edge)")
            return (obj, f"Face{k + 1}"), side
    raise cagd.CagdError(f"{obj.Label}.{sub} is not an edge of a face")
