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
"""
from __future__ import annotations

import hashlib
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Union

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.gp import gp_Pnt, gp_Vec
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE

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
from .convert import from_occ, to_occ
from .files import read_shapes, write_iges, write_step
from .shapes import subshapes

STAGES = ("to_nurbs", "occt", "from_occ", "step", "iges")
_JITTER = 0.6180339887498949        # golden-ratio offset: samples miss uniform knots
NAME_CHARS = 64                     # longest file name stem for the STEP/IGES files (names can be longer)


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
    """The one curve (edge) or surface (face) read back from a file."""
    shapes = [s for _, s in read_shapes(path)]
    kind = TopAbs_EDGE if curve else TopAbs_FACE
    found = [x for s in shapes for x in subshapes(s, kind)]
    if not found:
        raise CagdError(f"{path.name}: no {'edge' if curve else 'face'} was read back")
    if curve:
        edges = [e for e in found if not BRep_Tool.Degenerated_s(e)]
        if len(edges) != 1:
            return None, f"{len(edges)} edges read back"
        return BRep_Tool.Curve_s(edges[0], 0.0, 0.0), ""
    if len(found) != 1:
        return None, f"{len(found)} faces read back"
    return BRep_Tool.Surface_s(found[0]), ""


def verify(obj: Union[Curve, Surface], name: str = "object", samples: int = 41, stages: Sequence[str] = STAGES,
           tol: Optional[float] = None, file_tol: float = 1e-9, workdir: Optional[Path] = None) -> VerifyReport:
    """Compare an engine curve or surface with OCCT, with its STEP and its IGES round
    trip (see the module doc). ``samples``: interior samples (surfaces: about that
    many on a grid); ``workdir``: keep the STEP/IGES files there (default: a
    temporary folder). Returns a :class:`VerifyReport`; ``report.passed`` tells
    whether every stage is within its tolerance.

    Raises:
        CagdError: not an engine curve or surface, an unknown stage name, bad
            ``samples``; a file stage raises when OCCT reads back no edge or face
            (e.g. a surface collapsed to a point has no face).
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
    s = _Samples(nurbs, _checks.integer(samples, "samples", 4, 100_000))
    tol = default_tolerance(nurbs) if tol is None else _checks.scalar(tol, "tol")
    ref = s.engine(nurbs)
    s.check(ref)
    report = VerifyReport(name, repr(obj).strip("<>"), s.size, s.count)
    if "to_nurbs" in stages and not isinstance(obj, (BSplineCurve, BSplineSurface)):
        report.stages.append(_own_form(obj, nurbs, s, ref, tol))
    if "occt" in stages:
        report.stages.append(StageResult("occt", s.compare(ref, s.occt(to_occ(nurbs))), tol))
    if "from_occ" in stages:
        back = from_occ(to_occ(nurbs), dim=3)
        report.stages.append(StageResult("from_occ", s.compare(ref, s.engine(back)), tol))
    files = [k for k in ("step", "iges") if k in stages]
    if files:
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(workdir) if workdir is not None else Path(tmp)
            for kind in files:
                report.stages.append(_file_stage(kind, nurbs, name, folder, s, ref, file_tol))
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


def _file_stage(kind: str, nurbs, name: str, folder: Path, s: _Samples, ref, tol: float) -> StageResult:
    path = folder / f"{_safe(name)}.{'step' if kind == 'step' else 'igs'}"
    (write_step if kind == "step" else write_iges)([(name, nurbs)], path)
    geom, note = _file_geometry(path, s.curve)
    if geom is None:
        return StageResult(kind, {"points": float("inf")}, tol, note)
    return StageResult(kind, s.compare(ref, s.occt(geom)), tol)


def _safe(name: str) -> str:
    """A file name stem for ``name``: ASCII letters, digits, - and _ (others become _),
    at most NAME_CHARS characters (a longer name is cut and ends in a hash of the whole)."""
    safe = "".join(ch if (ch.isascii() and ch.isalnum()) or ch in "-_" else "_" for ch in name) or "object"
    if len(safe) > NAME_CHARS:
        digest = hashlib.sha1(name.encode("utf-8", "surrogatepass")).hexdigest()[:12]
        safe = safe[:NAME_CHARS - 13] + "_" + digest
    return safe
