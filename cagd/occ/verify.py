"""The round-trip proof: an engine object against OCCT, STEP and IGES.

:func:`verify` samples the object on a fixed parameter set (ends and jittered
interior points; derivatives only away from knots, where one-sided limits may
differ) and compares, quantity by quantity (points; first and second
derivatives; unit normals of surfaces):

- ``to_nurbs``: the object against its own NURBS form (Bezier curves and patches:
  points of the direct Bernstein sum; Bezier triangles: points T(s, t (1 - s))
  against the collapsed-edge form S(s, t); skipped for B-splines);
- ``occt``: OCCT's evaluation (D2) of :func:`cagd.occ.to_occ`;
- ``from_occ``: the engine B-spline read back from that OCCT geometry;
- ``step`` / ``iges``: OCCT's evaluation of the geometry read back from a STEP
  (AP214) or IGES file written by :func:`cagd.occ.write_step` / ``write_iges``.

Deviations are relative: points to the object's size, the k-th derivative to the
largest k-th derivative on the sample set (at least size / (domain length)^k),
normals as unit vectors. Default tolerances (measured, see tests/occ): 1e-12 for
``to_nurbs``, ``occt`` and ``from_occ``, scaled by max(1, (p / 3)^2) x (largest /
smallest weight) for degree p, since two correct evaluators of a degree-10 or
strongly rational B-spline differ by more rounding (5e-12 measured at degree 10);
1e-9 for the files.

A :class:`cagd.TrimmedSurface` is compared as above on its surface (the whole (u, v)
domain), and after each stage that makes a face (``occt``: :func:`cagd.occ.to_occ`, the
face of its pcurves; ``step`` / ``iges``: the face read back from the file written from
the trimmed surface itself) a trim stage (``occt trim``, ``step trim``, ``iges trim``)
checks that face:

- ``area``: |A - A_occ| / A_occ, A the engine's :meth:`~cagd.TrimmedSurface.area`
  (Green's theorem over the loops) and A_occ OCCT's BRepGProp.SurfaceProperties on the
  face at relative precision AREA_EPS, the face split where it is less than C2
  (:func:`occt_face_area`);
- ``inside``: the fraction of TRIM_POINTS_PER_SAMPLE x ``samples`` random (u, v) of the
  loops' box (seeded: the same points every run) on which
  :meth:`~cagd.TrimmedSurface.classify` and OCCT's BRepClass_FaceClassifier (in the
  face's own (u, v): the face keeps the engine surface's parameters; in a periodic
  direction also one period to either side, where a reader may have put the pcurves;
  IN at any of them is IN) disagree, over the
  points farther than TRIM_MARGIN of the box from every boundary curve (where both
  answers are sure; a point OCCT calls ON counts as a disagreement).

Their tolerance is TRIM_TOL (occt) or ``file_tol``; the stage's note gives both areas,
the engine's own error estimate and the number of points compared.
"""
from __future__ import annotations

import hashlib
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Union

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepClass import BRepClass_FaceClassifier
from OCP.GeomAbs import GeomAbs_C2
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Vec
from OCP.ShapeUpgrade import ShapeUpgrade_ShapeDivideContinuity
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_FORWARD, TopAbs_IN, TopAbs_OUT
from OCP.TopoDS import TopoDS_Face

from .. import _checks
from .._validate import check_name
from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..operations.continuity import curve_size
from ..surfaces.base import Surface, unit_normals
from ..surfaces.bezier import BezierSurface
from ..surfaces.bspline import BSplineSurface
from ..surfaces.trimmed import INSIDE, OUTSIDE, TrimmedSurface
from .compat import as_face
from .convert import from_occ, to_occ
from .files import read_shapes, write_iges, write_step
from .shapes import area as occ_area
from .shapes import subshapes

STAGES = ("to_nurbs", "occt", "from_occ", "step", "iges")
_JITTER = 0.6180339887498949        # golden-ratio offset: samples miss uniform knots
NAME_CHARS = 64                     # longest file name stem for the STEP/IGES files (names can be longer)
TRIM_TOL = 1e-9             # trim stage of the built face: relative area difference (OCCT's BRepGProp on
#                             rational faces is good to about 1e-10, see tests/occ/test_verify_trimmed.py)
TRIM_MARGIN = 1e-3          # relative (the loops' (u, v) box): points compared lie farther from the boundary
TRIM_POINTS_PER_SAMPLE = 10  # random (u, v) drawn per sample for the classification
MAX_TRIM_POINTS = 4000
MAX_BOUNDARY_SAMPLES = 1 << 16   # per curve: the spacing of the samples that tell "near the boundary"
AREA_EPS = 1e-14            # relative precision asked of BRepGProp (1e-13: off by 1.1e-9 on rational faces of
#                             trj3_s1-id-203.stp, 8e-11 at 1e-14)
CLASSIFIER_TOL = 1e-9       # relative (the loops' box): BRepClass_FaceClassifier's parametric tolerance
_TRIM_SEED = 15             # the random (u, v) are the same on every run


@dataclass
class StageResult:
    """Max relative deviation of each quantity at one stage."""
    stage: str
    deviations: Dict[str, float]
    tolerance: float
    note: str = ""

    @property
    def max_deviation(self) -> float:
        return max(self.deviations.values()) if self.deviations else 0.0

    @property
    def passed(self) -> bool:
        return bool(self.max_deviation <= self.tolerance)


@dataclass
class VerifyReport:
    """The result of :func:`verify`: per stage, the relative deviations."""
    name: str
    description: str
    size: float
    samples: int
    stages: List[StageResult] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(s.passed for s in self.stages)

    @property
    def max_deviation(self) -> Dict[str, float]:
        return {s.stage: s.max_deviation for s in self.stages}

    def stage(self, name: str) -> StageResult:
        for s in self.stages:
            if s.stage == name:
                return s
        raise KeyError(name)

    def to_markdown(self, header: bool = True) -> str:
        """One table row per stage (with a header unless ``header=False``)."""
        rows = []
        if header:
            rows += ["| object | stage | points | 1st derivatives | 2nd derivatives | normals | tolerance | ok |",
                     "|---|---|---|---|---|---|---|---|"]
        for s in self.stages:
            d = s.deviations
            cells = [f"{d[k]:.1e}" if k in d else "" for k in ("points", "d1", "d2", "normals")]
            ok = "yes" if s.passed else "**NO**"
            note = f" ({s.note})" if s.note else ""
            rows.append(f"| {self.name} | {s.stage}{note} | " + " | ".join(cells)
                        + f" | {s.tolerance:.0e} | {ok} |")
        return "\n".join(rows)

    def __str__(self) -> str:
        lines = [f"{self.name}: {self.description}, size {self.size:.4g}, {self.samples} samples"]
        for s in self.stages:
            devs = ", ".join(f"{k} {v:.1e}" for k, v in s.deviations.items())
            lines.append(f"  {s.stage:9s} max {s.max_deviation:.2e} (tol {s.tolerance:.0e}) "
                         f"{'ok' if s.passed else 'FAILED'}  [{devs}]{'  ' + s.note if s.note else ''}")
        return "\n".join(lines)


# --- sampling --------------------------------------------------------------------------------
def _params(a: float, b: float, n: int) -> np.ndarray:
    """n interior parameters offset by the golden ratio (off uniform knots)."""
    return a + (b - a) * (np.arange(n) + _JITTER) / n


def _pad3(x: np.ndarray) -> np.ndarray:
    out = np.zeros(x.shape[:-1] + (3,))
    out[..., :x.shape[-1]] = x
    return out


class _Samples:
    """Engine values, parameters and scales of the compared quantities."""

    def __init__(self, obj, n: int):
        self.obj = obj
        if isinstance(obj, Curve):
            self.curve = True
            a, b = obj.domain
            self.t = np.concatenate([[a, b], _params(a, b, n)])
            self.size = curve_size(obj)
            self.length = b - a
        else:
            self.curve = False
            (a, b), (c, d) = obj.domain
            m = max(int(np.sqrt(n)), 3)
            u, v = np.meshgrid(_params(a, b, m), _params(c, d, m), indexing="ij")
            ends = np.array([[a, c], [a, d], [b, c], [b, d], [(a + b) / 2, c], [a, (c + d) / 2]])
            if not obj.rectangular:
                ends = ends[:3]                                  # triangle corners only
            self.uv = np.concatenate([ends, np.column_stack([u.ravel(), v.ravel()])])
            self.size = float(obj.size)
            self.length = max(b - a, d - c)
        self.ends = 2 if self.curve else (3 if not obj.rectangular else 6)
        self.count = len(self.t) if self.curve else len(self.uv)

    def engine(self, geometry) -> Dict[str, np.ndarray]:
        """points (count, 3); d1, d2 (k, count - ends, 3) at the interior samples."""
        if self.curve:
            d = _pad3(geometry.derivatives(self.t, 2))
            return {"points": d[0], "d1": d[1][None, self.ends:], "d2": d[2][None, self.ends:]}
        d = _pad3(geometry.derivatives(self.uv[:, 0], self.uv[:, 1], 2, 2))
        i = slice(self.ends, None)
        return {"points": d[0, 0], "d1": np.stack([d[1, 0][i], d[0, 1][i]]),
                "d2": np.stack([d[2, 0][i], d[1, 1][i], d[0, 2][i]])}

    def occt(self, geom) -> Dict[str, np.ndarray]:
        """The same quantities from an OCCT Geom_Curve/Geom_Surface (D2 per sample)."""
        if self.curve:
            out = np.empty((3, len(self.t), 3))
            p, v1, v2 = gp_Pnt(), gp_Vec(), gp_Vec()
            for j, x in enumerate(self.t.tolist()):
                geom.D2(x, p, v1, v2)
                out[:, j] = (p.X(), p.Y(), p.Z()), (v1.X(), v1.Y(), v1.Z()), (v2.X(), v2.Y(), v2.Z())
            return {"points": out[0], "d1": out[1][None, self.ends:], "d2": out[2][None, self.ends:]}
        out = np.empty((6, len(self.uv), 3))
        p, vecs = gp_Pnt(), [gp_Vec() for _ in range(5)]
        for j, (u, v) in enumerate(self.uv.tolist()):
            geom.D2(u, v, p, *vecs)
            out[0, j] = p.X(), p.Y(), p.Z()
            for k, w in enumerate(vecs, 1):
                out[k, j] = w.X(), w.Y(), w.Z()
        i = slice(self.ends, None)       # OCCT's D2: P, D1U, D1V, D2U, D2V, D2UV
        return {"points": out[0], "d1": np.stack([out[1][i], out[2][i]]),
                "d2": np.stack([out[3][i], out[5][i], out[4][i]])}

    def check(self, ref: Dict[str, np.ndarray]) -> None:
        """The reference values and the derivative scales size / length^k must be finite
        and positive, else the relative deviations mean nothing (a domain 1e-300 or 1e300
        long: the derivatives and their scales overflow or vanish)."""
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            scales = [np.float64(self.size) / np.float64(self.length) ** k for k in (1, 2)]
        bad = [key for key, v in ref.items() if not np.all(np.isfinite(v))]
        if bad or not all(np.isfinite(x) and x > 0 for x in scales + [np.float64(self.size)]):
            what = (f"its {', '.join(bad)} overflow" if bad
                    else "the derivative scales size / length^k overflow or vanish")
            raise CagdError(f"obj: cannot be compared (size {self.size:.3g}, parameter range {self.length:.3g}: "
                            f"{what}); reparametrise it onto a domain of moderate length")

    def compare(self, ref: Dict[str, np.ndarray], other: Dict[str, np.ndarray]) -> Dict[str, float]:
        dev = {"points": float(np.abs(other["points"] - ref["points"]).max() / self.size)}
        for k, key in ((1, "d1"), (2, "d2")):
            scale = max(float(np.linalg.norm(ref[key], axis=-1).max()), self.size / self.length ** k)
            with np.errstate(over="ignore", invalid="ignore"):
                dev[key] = float(np.abs(other[key] - ref[key]).max() / scale)
        if not self.curve:
            dev["normals"] = _normal_deviation(ref["d1"], other["d1"], self.size / self.length)
        return dev


def _normal_deviation(d1a: np.ndarray, d1b: np.ndarray, scale: float) -> float:
    """Max difference of the unit normals where both are defined
    (:func:`cagd.surfaces.base.unit_normals`, partials of typical size ``scale``: at a
    collapsed point or on a surface collapsed to a line the cross product is rounding
    noise)."""
    na, ok_a = unit_normals(d1a[0], d1a[1], scale, scale)
    nb, ok_b = unit_normals(d1b[0], d1b[1], scale, scale)
    ok = ok_a & ok_b
    if not ok.any():
        return 0.0
    return float(np.abs(na[ok] - nb[ok]).max())


# --- the stages ------------------------------------------------------------------------------
def _file_geometry(path: Path, curve: bool):
    """(geometry, note, face): the one curve (edge) or surface (face) read back from a
    file, and the face (None for curves)."""
    shapes = [s for _, s in read_shapes(path)]
    kind = TopAbs_EDGE if curve else TopAbs_FACE
    found = [x for s in shapes for x in subshapes(s, kind)]
    if not found:
        raise CagdError(f"{path.name}: no {'edge' if curve else 'face'} was read back")
    if curve:
        edges = [e for e in found if not BRep_Tool.Degenerated_s(e)]
        if len(edges) != 1:
            return None, f"{len(edges)} edges read back", None
        return BRep_Tool.Curve_s(edges[0], 0.0, 0.0), "", None
    if len(found) != 1:
        return None, f"{len(found)} faces read back", None
    return BRep_Tool.Surface_s(found[0]), "", as_face(found[0])


def verify(obj: Union[Curve, Surface], name: str = "object", samples: int = 41, stages: Sequence[str] = STAGES,
           tol: Optional[float] = None, file_tol: float = 1e-9, workdir: Optional[Path] = None) -> VerifyReport:
    """Compare an engine curve or surface with OCCT, with its STEP and its IGES round
    trip (see the module doc). ``samples``: interior samples (surfaces: about that
    many on a grid); ``workdir``: keep the STEP/IGES files there (default: a
    temporary folder). Returns a :class:`VerifyReport`; ``report.passed`` tells
    whether every stage is within its tolerance. A :class:`cagd.TrimmedSurface` gets a
    trim stage (area, classification; see the module doc) after each of ``occt``,
    ``step`` and ``iges``, its files holding the trimmed face.

    Raises:
        CagdError: not an engine curve or surface, an unknown stage name, bad
            ``samples``; a file stage raises when OCCT reads back no edge or face
            (e.g. a surface collapsed to a point has no face); a trimmed surface whose
            face OCCT cannot build (:func:`cagd.occ.make_trimmed_face`) raises its error.
    """
    if not isinstance(obj, (Curve, Surface)):
        raise CagdError(f"obj: expected a cagd Curve or Surface, got {type(obj).__name__}")
    unknown = set(stages) - set(STAGES)
    if unknown:
        raise CagdError(f"stages: unknown {sorted(unknown)}; choose from {STAGES}")
    if obj.dim not in (2, 3):
        raise CagdError(f"obj: OCCT geometry is 2-D or 3-D, got a {obj.dim}-D object")
    if not isinstance(name, str):
        raise CagdError(f"name: expected a string, got {type(name).__name__}")
    check_name(name, "name")                   # it goes into the STEP and IGES files
    nurbs = obj.to_nurbs()
    samples = _checks.integer(samples, "samples", 4, 100_000)
    s = _Samples(nurbs, samples)
    tol = default_tolerance(nurbs) if tol is None else _checks.scalar(tol, "tol")
    s.check({})                                # the derivative scales, before evaluating
    try:
        ref = s.engine(nurbs)
    except CagdError as exc:                   # a derivative beyond the float range
        raise CagdError(f"obj: cannot be compared ({exc})") from None
    s.check(ref)
    report = VerifyReport(name, repr(obj).strip("<>"), s.size, s.count)
    if "to_nurbs" in stages and not isinstance(obj, (BSplineCurve, BSplineSurface)):
        report.stages.append(_own_form(obj, nurbs, s, ref, tol))
    trimmed = obj if isinstance(obj, TrimmedSurface) else None
    checker = _TrimCheck(trimmed, samples) if trimmed is not None else None
    if "occt" in stages:
        report.stages.append(StageResult("occt", s.compare(ref, s.occt(to_occ(nurbs))), tol))
        if checker is not None:
            report.stages.append(checker.stage("occt trim", to_occ(checker.ts), TRIM_TOL))
    if "from_occ" in stages:
        back = from_occ(to_occ(nurbs), dim=3)
        report.stages.append(StageResult("from_occ", s.compare(ref, s.engine(back)), tol))
    files = [k for k in ("step", "iges") if k in stages]
    if files:
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(workdir) if workdir is not None else Path(tmp)
            for kind in files:
                result, face = _file_stage(kind, trimmed or nurbs, name, folder, s, ref, file_tol)
                report.stages.append(result)
                if checker is not None:
                    report.stages.append(checker.stage(f"{kind} trim", face, file_tol) if face is not None else
                                         StageResult(f"{kind} trim", {"area": float("inf")}, file_tol, result.note))
    return report


def default_tolerance(nurbs: Union[BSplineCurve, BSplineSurface]) -> float:
    """1e-12 x max(1, (p / 3)^2) x (largest / smallest weight), p the highest degree."""
    degree = nurbs.degree if isinstance(nurbs, BSplineCurve) else max(nurbs.degree_u, nurbs.degree_v)
    w = nurbs.weights
    ratio = 1.0 if w is None else float(np.max(w) / np.min(w))
    return 1e-12 * max(1.0, (degree / 3.0) ** 2) * ratio


def _own_form(obj, nurbs, s: _Samples, ref, tol: float) -> StageResult:
    """The object by its own evaluator against its NURBS form. Bezier curves and
    patches evaluate through their NURBS form, so for them the points come from the
    direct Bernstein sum (seed 000, 5.2.1) instead."""
    if isinstance(obj, (BezierCurve, BezierSurface)):
        mine = _pad3(obj.bernstein_evaluate(s.t) if isinstance(obj, BezierCurve)
                     else obj.bernstein_evaluate(s.uv[:, 0], s.uv[:, 1]))
        return StageResult("to_nurbs", {"points": float(np.abs(mine - ref["points"]).max() / s.size)}, tol,
                           "Bernstein sum")
    if isinstance(obj, Surface) and not obj.rectangular:
        u, t = s.uv[:, 0], s.uv[:, 1]
        mine = _pad3(obj(u, t * (1.0 - u)))
        return StageResult("to_nurbs", {"points": float(np.abs(mine - ref["points"]).max() / s.size)}, tol,
                           "T(s, t(1-s)) vs S(s, t)")
    return StageResult("to_nurbs", s.compare(ref, s.engine(obj)), tol)


def _file_stage(kind: str, obj, name: str, folder: Path, s: _Samples, ref, tol: float):
    """(the stage's result, the face read back or None). ``obj``: the NURBS form, or a
    TrimmedSurface (written as its trimmed face; its surface keeps the engine's
    parameters, so the points compare as for the untrimmed surface)."""
    path = folder / f"{_safe(name)}.{'step' if kind == 'step' else 'igs'}"
    (write_step if kind == "step" else write_iges)([(name, obj)], path)
    geom, note, face = _file_geometry(path, s.curve)
    if geom is None:
        return StageResult(kind, {"points": float("inf")}, tol, note), None
    return StageResult(kind, s.compare(ref, s.occt(geom)), tol), face


class _TrimCheck:
    """The engine's side of the trim stages, computed once: the area (with its error
    estimate) and the classified random (u, v) farther than TRIM_MARGIN from the loops."""

    def __init__(self, ts: TrimmedSurface, samples: int):
        self.ts = ts
        self.area = ts.area_report()
        curves = [c for loop in ts.loops for c in loop]
        lo = np.min([c.control_points.min(axis=0) for c in curves], axis=0)
        hi = np.max([c.control_points.max(axis=0) for c in curves], axis=0)
        spacing = 0.25 * TRIM_MARGIN * max(float((hi - lo).max()), 1e-300)
        boundary = np.concatenate([_dense(c, spacing) for c in curves])
        lo, hi = boundary.min(axis=0), boundary.max(axis=0)
        self.scale = max(float((hi - lo).max()), 1e-300)
        count = min(TRIM_POINTS_PER_SAMPLE * samples, MAX_TRIM_POINTS)
        uv = lo + (hi - lo) * np.random.default_rng(_TRIM_SEED).random((count, 2))
        # the nearest boundary sample is at most a spacing farther than the curve
        far = _far_from(uv, boundary, TRIM_MARGIN * self.scale + spacing)
        self.uv = uv[far]
        self.state = ts.classify(self.uv[:, 0], self.uv[:, 1])
        (u0, u1), (v0, v1) = ts.domain
        pu = (0.0, u1 - u0, u0 - u1) if ts.periodic_u else (0.0,)
        pv = (0.0, v1 - v0, v0 - v1) if ts.periodic_v else (0.0,)
        self.shifts = [(float(a), float(b)) for a in pu for b in pv]

    def stage(self, stage: str, face, tol: float) -> StageResult:
        """The trim stage of ``face`` (a TopoDS_Face on the engine surface's parameters)."""
        face = as_face(face.Oriented(TopAbs_FORWARD))
        theirs = occt_face_area(face)
        ours = self.area.value
        dev_area = abs(ours - theirs) / max(abs(theirs), 1e-300)
        ctol = CLASSIFIER_TOL * self.scale
        occ = np.full(len(self.uv), OUTSIDE, dtype=np.int8)
        for du, dv in self.shifts:           # a periodic face's pcurves may lie a period away (IGES)
            for k, (u, v) in enumerate(self.uv.tolist()):
                if occ[k] == OUTSIDE:
                    occ[k] = _state(BRepClass_FaceClassifier(face, gp_Pnt2d(u + du, v + dv), ctol).State())
        wrong = int(np.count_nonzero(occ != self.state))
        n, inside = len(self.uv), int(np.count_nonzero(self.state == INSIDE))
        estimate = self.area.error / max(abs(ours), 1e-300)
        note = (f"area {ours:.12g} vs BRepGProp {theirs:.12g}: {dev_area:.1e} relative (engine's estimate "
                f"{estimate:.1e}{'' if self.area.converged else ', NOT converged'}); {wrong} of {n} (u, v) "
                f"classified differently ({inside} inside, all >= {TRIM_MARGIN:g} of the box from the boundary)")
        return StageResult(stage, {"area": dev_area, "inside": wrong / max(n, 1)}, tol, note)


def occt_face_area(face: TopoDS_Face) -> float:
    """OCCT's area of a face: BRepGProp.SurfaceProperties (:func:`cagd.occ.area`, relative
    precision AREA_EPS) of the face split where its surface or pcurves are less than C2
    (ShapeUpgrade_ShapeDivideContinuity: exact segments). BRepGProp integrates across
    inner C0/C1 knot lines badly and does not know it: on faces of trj3_s1-id-203.stp
    (rational, C0 in u) it is off by 1.2e-8 and 1.4e-8 with error estimates of 1e-13;
    split, it agrees with the engine to 7.7e-10 and 2.0e-11."""
    split = ShapeUpgrade_ShapeDivideContinuity(face)
    for criterion in (split.SetBoundaryCriterion, split.SetPCurveCriterion, split.SetSurfaceCriterion):
        criterion(GeomAbs_C2)
    split.Perform()
    result = split.Result()
    return occ_area(face if result is None or result.IsNull() else result, AREA_EPS)


def _state(s) -> int:
    return INSIDE if s == TopAbs_IN else (OUTSIDE if s == TopAbs_OUT else 0)


def _dense(c: BSplineCurve, spacing: float) -> np.ndarray:
    """Points of a curve no farther than ``spacing`` apart (doubling the count per span)."""
    a, b = c.domain
    br = np.unique(np.concatenate([[a], c._breaks_within(a, b), [b]]))
    per = 16
    while True:
        t = np.concatenate([np.linspace(x, y, per, endpoint=False) for x, y in zip(br[:-1], br[1:])] + [[b]])
        P = c(t)
        if float(np.linalg.norm(np.diff(P, axis=0), axis=1).max(initial=0.0)) <= spacing or \
                len(t) >= MAX_BOUNDARY_SAMPLES:
            return P
        per *= 2


def _far_from(P: np.ndarray, Q: np.ndarray, h: float) -> np.ndarray:
    """True where a point of P has no point of Q within distance h (so it is farther than
    h from all of them; points up to 2 sqrt(2) h away may be called near too): Q marks
    the cells of a grid of side h, a point is far when the 3 x 3 cells around its own
    are empty. O(len(P) + len(Q)) time, one boolean per cell of the box."""
    lo = np.minimum(P.min(axis=0), Q.min(axis=0))
    cells = np.floor((Q - lo) / h).astype(np.int64) + 1
    shape = tuple(int(n) for n in cells.max(axis=0) + 2)
    mine = np.floor((P - lo) / h).astype(np.int64) + 1
    shape = tuple(max(a, int(b) + 2) for a, b in zip(shape, mine.max(axis=0)))
    occupied = np.zeros(shape, dtype=bool)
    occupied[cells[:, 0], cells[:, 1]] = True
    near = np.zeros(len(P), dtype=bool)
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            near |= occupied[mine[:, 0] + di, mine[:, 1] + dj]
    return ~near


def _safe(name: str) -> str:
    """A file name stem for ``name``: ASCII letters, digits, - and _ (others become _),
    at most NAME_CHARS characters (a longer name is cut and ends in a hash of the whole)."""
    safe = "".join(ch if (ch.isascii() and ch.isalnum()) or ch in "-_" else "_" for ch in name) or "object"
    if len(safe) > NAME_CHARS:
        digest = hashlib.sha1(name.encode("utf-8", "surrogatepass")).hexdigest()[:12]
        safe = safe[:NAME_CHARS - 13] + "_" + digest
    return safe
