"""The entry types of the model format: for each, its fields and the engine call that
builds it. Field names are the engine's argument names (see docs/model-format.md)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple

import numpy as np

from .. import (BezierCurve, BezierSurface, BezierTriangle, BSplineCurve, BSplineSurface, CompositeCurve,
                CoonsPatch, HermiteCurve, PolynomialCurve, cone, cylinder, ellipsoid, interpolate,
                interpolate_surface, join, loft, natural_cubic_spline, revolve, ruled, sphere, torus)
from ..curves.base import Curve
from .._deprecation import deprecated
from ..curves.composite import GAP_TOL
from ..curves.cubic_spline import END_CONDITIONS
from ..surfaces.coons import CORNER_TOL
from ..surfaces.trimmed import TrimmedSurface
from ..fitting.parameters import PARAMETERS
from . import _read as R
from ._read import ModelError

CONTINUITIES = ("G0", "G1", "G2", "C0", "C1", "C2")
FULL_TURN_TOL = 1e-14     # relative; as cagd.revolve, which closes the seam exactly within it
SOLID_TOL = 1e-9          # relative: a revolve profile end lies on the axis within SOLID_TOL * size


class Fields:
    """The fields of one entry (or inline object) being read: each value through a
    reader that reports its JSON path; ``values`` keeps what was read."""

    def __init__(self, obj: Mapping[str, Any], path: str, resolver: Any):
        self.obj, self.path, self.resolver = obj, path, resolver
        self.values: Dict[str, Any] = {}

    def at(self, key: str) -> str:
        return R.key_path(self.path, key)

    def req(self, key: str, reader: Callable, *args: Any) -> Any:
        self.values[key] = reader(self.obj[key], self.at(key), *args)
        return self.values[key]

    def opt(self, key: str, reader: Callable, *args: Any, default: Any = None) -> Any:
        self.values[key] = reader(self.obj[key], self.at(key), *args) if key in self.obj else default
        return self.values[key]

    def curve(self, key: str, bezier: bool = False) -> Curve:
        self.values[key] = self.resolver.curve(self.obj[key], self.at(key), bezier)
        return self.values[key]

    def curves(self, key: str, min_count: int) -> List[Curve]:
        items = R.array(self.obj[key], self.at(key), "curves", min_count)
        self.values[key] = [self.resolver.curve(c, f"{self.at(key)}[{i}]") for i, c in enumerate(items)]
        return self.values[key]

    def surface(self, key: str) -> Any:
        self.values[key] = self.resolver.surface(self.obj[key], self.at(key))
        return self.values[key]

    def loops(self, key: str) -> List[List[Curve]]:
        """An array of loops, each an array of at least one 2-D curve (reference or inline)."""
        where = self.at(key)
        out: List[List[Curve]] = []
        for i, loop in enumerate(R.array(self.obj[key], where, "loops (arrays of 2-D curves)", 1)):
            lp = f"{where}[{i}]"
            row = []
            for j, c in enumerate(R.array(loop, lp, "2-D curves in (u, v)", 1)):
                curve = self.resolver.curve(c, f"{lp}[{j}]")
                if curve.dim != 2:
                    raise ModelError(f"{lp}[{j}]", f"a trimming curve lies in the surface's (u, v) domain: it "
                                                   f"must be 2-D (control points [u, v]), got a {curve.dim}-D curve")
                row.append(curve)
            out.append(row)
        self.values[key] = out
        return out


@dataclass(frozen=True)
class TypeSpec:
    kind: str                                   # "curve" or "surface"
    required: Tuple[str, ...]
    optional: Tuple[str, ...]
    build: Callable[[Fields], Any]
    engine: str                                 # the engine call, for messages and docs
    aliases: Mapping[str, str] = field(default_factory=dict)   # engine argument name -> field
    solid: Optional[Callable[[Fields, list], None]] = None     # None: solid not allowed

    @property
    def fields(self) -> Tuple[str, ...]:
        return self.required + self.optional


def _name_or(values: Callable) -> Callable:
    """A reader for a ``parameters`` field: a parametrisation name or explicit values."""
    def read(value, path):
        if isinstance(value, str):
            return R.choice(value, path, PARAMETERS)
        return values(value, path)
    return read


def _numbers(value, path):
    return R.numbers(value, path, min_count=2, what="parameters")


def _surface_parameters(value, path):
    if isinstance(value, str):
        return R.choice(value, path, PARAMETERS)
    pair = R.array(value, path, "parameter arrays")
    if len(pair) != 2:
        raise ModelError(path, f"expected a parametrisation name or a pair [params_u, params_v], "
                               f"got {len(pair)} arrays")
    return tuple(_numbers(x, f"{path}[{i}]") for i, x in enumerate(pair))


# --- curves -------------------------------------------------------------------------------
def _bezier_curve(f: Fields):
    P = f.req("control_points", R.points, 2)
    return BezierCurve(P, f.opt("weights", R.weights, len(P)))


def _bspline_curve(f: Fields):
    P = f.req("control_points", R.points, 2)
    return BSplineCurve(P, f.req("degree", R.integer), f.opt("knots", R.knots),
                        f.opt("weights", R.weights, len(P)), f.opt("periodic", R.boolean, default=False))


def _polynomial_curve(f: Fields):
    A = f.req("coefficients", R.points, 1)
    domain = f.opt("domain", R.numbers, 2, 2, "numbers [start, end]", default=(0.0, 1.0))
    return PolynomialCurve(A, tuple(domain))


def _hermite_curve(f: Fields):
    p0 = f.req("p0", R.vector, (2, 3))
    like = (len(p0),)
    return HermiteCurve(p0, f.req("p1", R.vector, like), f.req("t0", R.vector, like), f.req("t1", R.vector, like))


def _cubic_spline(f: Fields):
    P = f.req("points", R.points, 2)
    two = (2, (P.shape[1],), 2)           # min_count, dims, count
    end = f.opt("end_condition", R.choice, END_CONDITIONS, default="natural")
    old = f.opt("parametrization", R.choice, PARAMETERS)       # the key before "parameters"
    parameters = f.opt("parameters", _name_or(_numbers), default=old or "chord")
    if old is not None:
        if isinstance(f.values["parameters"], str) and "parameters" in f.obj:
            raise ModelError(f.at("parametrization"), "give the parametrisation once, as \"parameters\" "
                                                      "(\"parametrization\" is its old name)")
        deprecated("cagd model", f"{f.at('parametrization')}: the key \"parametrization\" is deprecated; "
                                 f"use \"parameters\"")
    return natural_cubic_spline(P, end, parameters, f.opt("tangents", R.points, *two),
                                f.opt("virtual_points", R.points, *two))


def _interpolate(f: Fields):
    P = f.req("points", R.points, 2)
    return interpolate(P, f.opt("degree", R.integer, default=3),
                       f.opt("parameters", _name_or(_numbers), default="chord"), f.opt("knots", R.knots))


def _join(f: Fields):
    P = f.curve("curve", bezier=True)
    assert isinstance(P, BezierCurve)           # the resolver checked it (bezier=True)
    rest = f.opt("rest_points", R.points, 0, (P.dim,))
    return join(P, rest, f.opt("continuity", R.choice, CONTINUITIES, default="G1"),
                f.opt("alpha", R.number, default=1.0), f.opt("beta", R.number, default=0.0))


def _rel_tol(f: Fields, default: float) -> float:
    """The ``rel_tol`` field (relative to the size), or its old name ``tol`` (one release,
    with a DeprecationWarning)."""
    rel, old = f.opt("rel_tol", R.positive), f.opt("tol", R.positive)
    if old is None:
        return default if rel is None else rel
    if rel is not None:
        raise ModelError(f.at("tol"), "give the tolerance once, as \"rel_tol\" (\"tol\" is its old name)")
    deprecated("cagd model", f"{f.at('tol')}: the key \"tol\" is deprecated here; use \"rel_tol\" (it is "
                             f"relative, and tol means a distance in model units in cagd)")
    return old


def _composite(f: Fields):
    return CompositeCurve(f.curves("curves", 1), _rel_tol(f, GAP_TOL))


# --- surfaces -----------------------------------------------------------------------------
def _bezier_surface(f: Fields):
    P = f.req("control_points", R.grid)
    return BezierSurface(P, f.opt("weights", R.weight_grid, P.shape[:2]))


def _bspline_surface(f: Fields):
    P = f.req("control_points", R.grid)
    return BSplineSurface(P, f.req("degree_u", R.integer), f.req("degree_v", R.integer),
                          f.opt("knots_u", R.knots), f.opt("knots_v", R.knots),
                          f.opt("weights", R.weight_grid, P.shape[:2]),
                          f.opt("periodic_u", R.boolean, default=False), f.opt("periodic_v", R.boolean, default=False))


def _interpolate_surface(f: Fields):
    Q = f.req("points", R.grid)
    return interpolate_surface(Q, f.opt("degree_u", R.integer, default=3), f.opt("degree_v", R.integer, default=3),
                               f.opt("parameters", _surface_parameters, default="chord"))


def _revolve(f: Fields):
    profile = f.curve("profile")
    return revolve(profile, f.opt("axis_point", R.vector, default=(0.0, 0.0, 0.0)),
                   f.opt("axis_direction", R.vector, default=(0.0, 0.0, 1.0)),
                   f.opt("angle", R.number, default=2.0 * math.pi), f.opt("start_angle", R.number, default=0.0))


def _center(f: Fields):
    return f.opt("center", R.vector, default=(0.0, 0.0, 0.0))


def _sphere(f: Fields):
    return sphere(f.req("radius", R.number), _center(f))


def _torus(f: Fields):
    return torus(f.req("R", R.number), f.req("r", R.number), _center(f))


def _cylinder(f: Fields):
    return cylinder(f.req("radius", R.number), f.req("height", R.number), _center(f))


def _cone(f: Fields):
    return cone(f.req("radius", R.number), f.req("height", R.number), _center(f))


def _ellipsoid(f: Fields):
    return ellipsoid(f.req("a", R.number), f.req("b", R.number), f.req("c", R.number))


def _coons(f: Fields):
    c0, c1, d0, d1 = (f.curve(k) for k in ("c0", "c1", "d0", "d1"))
    return CoonsPatch(c0, c1, d0, d1, _rel_tol(f, CORNER_TOL))


def _ruled(f: Fields):
    return ruled(f.curve("c0"), f.curve("c1"))


def _loft(f: Fields):
    sections = f.curves("sections", 2)
    return loft(sections, f.opt("degree_v", R.integer, default=3),
                f.opt("parameters", _name_or(_numbers), default="chord"))


def _trimmed_surface(f: Fields):
    """cagd.TrimmedSurface(surface, loops, tol): loops[0] the outer loop, the others holes
    (the engine reverses a loop that runs the wrong way and checks closure, domain and
    crossings; its errors come back at loops[i][j])."""
    surface = f.surface("surface")
    loops = f.loops("loops")
    return TrimmedSurface(surface, loops, f.opt("tol", R.positive))


def _bezier_triangle(f: Fields):
    P = f.req("control_points", R.points, 3, (3,))
    return BezierTriangle(P, f.opt("weights", R.weights, len(P)))


# --- solids -------------------------------------------------------------------------------
def _closed(f: Fields, objects: list) -> None:
    """ellipsoid, sphere, torus: closed surfaces by construction."""


def _torus_closed(f: Fields, objects: list) -> None:
    """A torus bounds a volume (2 pi^2 R r^2) only when the tube does not pass through
    the axis: r < R. With r >= R the surface intersects itself (a spindle torus) and
    the solid OCCT builds from it is not the torus' volume."""
    big, small = f.values["R"], f.values["r"]
    if not abs(small) < abs(big):
        raise ModelError(f.at("solid"), f"a torus with r >= R ({small!r} >= {big!r}) intersects itself and "
                                       f"bounds no volume; solid needs r < R")


def _revolve_closed(f: Fields, objects: list) -> None:
    """A full turn of a profile that is closed or starts and ends on the axis."""
    where = f.at("solid")
    angle = f.values["angle"]
    if abs(angle - 2.0 * math.pi) > FULL_TURN_TOL * 2.0 * math.pi:
        raise ModelError(where, f"a revolve bounds a volume only for a full turn: leave angle out or write "
                                f"{2.0 * math.pi!r} (2 pi), got {angle!r}")
    profile = f.values["profile"]
    a = np.asarray(f.values["axis_point"], dtype=float)
    d = np.asarray(f.values["axis_direction"], dtype=float)
    d = d / np.linalg.norm(d)
    ends = profile(np.array(profile.domain))
    P = profile.to_nurbs().control_points
    size = max(float(np.linalg.norm(P.max(axis=0) - P.min(axis=0))), 1e-300)
    off = ends - a
    dist = np.linalg.norm(off - np.outer(off @ d, d), axis=1)
    tol = SOLID_TOL * size
    if float(np.linalg.norm(ends[1] - ends[0])) <= tol or bool(np.all(dist <= tol)):
        return
    i = int(np.argmax(dist > tol))
    raise ModelError(where, f"a revolve bounds a volume only if the profile is closed or starts and ends "
                            f"on the axis; its {('start', 'end')[i]} point {ends[i].tolist()} is "
                            f"{dist[i]:.6g} from the axis (tolerance {tol:.3g})")


TYPES: Dict[str, TypeSpec] = {
    "bezier_curve": TypeSpec("curve", ("control_points",), ("weights",), _bezier_curve, "BezierCurve"),
    "bspline_curve": TypeSpec("curve", ("control_points", "degree"), ("knots", "weights", "periodic"),
                              _bspline_curve, "BSplineCurve"),
    "polynomial_curve": TypeSpec("curve", ("coefficients",), ("domain",), _polynomial_curve, "PolynomialCurve"),
    "hermite_curve": TypeSpec("curve", ("p0", "p1", "t0", "t1"), (), _hermite_curve, "HermiteCurve"),
    "cubic_spline": TypeSpec("curve", ("points",),
                             ("end_condition", "parameters", "tangents", "virtual_points", "parametrization"),
                             _cubic_spline, "natural_cubic_spline"),
    "interpolate": TypeSpec("curve", ("points",), ("degree", "parameters", "knots"), _interpolate, "interpolate"),
    "join": TypeSpec("curve", ("curve",), ("continuity", "alpha", "beta", "rest_points"), _join, "join",
                     {"P": "curve"}),
    "composite": TypeSpec("curve", ("curves",), ("rel_tol", "tol"), _composite, "CompositeCurve"),
    "bezier_surface": TypeSpec("surface", ("control_points",), ("weights",), _bezier_surface, "BezierSurface"),
    "bspline_surface": TypeSpec("surface", ("control_points", "degree_u", "degree_v"),
                                ("knots_u", "knots_v", "weights", "periodic_u", "periodic_v"),
                                _bspline_surface, "BSplineSurface"),
    "interpolate_surface": TypeSpec("surface", ("points",), ("degree_u", "degree_v", "parameters"),
                                    _interpolate_surface, "interpolate_surface"),
    "revolve": TypeSpec("surface", ("profile",), ("axis_point", "axis_direction", "angle", "start_angle"),
                        _revolve, "revolve", solid=_revolve_closed),
    "sphere": TypeSpec("surface", ("radius",), ("center",), _sphere, "sphere", solid=_closed),
    "torus": TypeSpec("surface", ("R", "r"), ("center",), _torus, "torus", solid=_torus_closed),
    "cylinder": TypeSpec("surface", ("radius", "height"), ("center",), _cylinder, "cylinder"),
    "cone": TypeSpec("surface", ("radius", "height"), ("center",), _cone, "cone"),
    "ellipsoid": TypeSpec("surface", ("a", "b", "c"), (), _ellipsoid, "ellipsoid", solid=_closed),
    "coons": TypeSpec("surface", ("c0", "c1", "d0", "d1"), ("rel_tol", "tol"), _coons, "CoonsPatch"),
    "ruled": TypeSpec("surface", ("c0", "c1"), (), _ruled, "ruled"),
    "loft": TypeSpec("surface", ("sections",), ("degree_v", "parameters"), _loft, "loft",
                     {"curves": "sections"}),
    "bezier_triangle": TypeSpec("surface", ("control_points",), ("weights",), _bezier_triangle, "BezierTriangle"),
    "trimmed_surface": TypeSpec("surface", ("surface", "loops"), ("tol",), _trimmed_surface, "TrimmedSurface"),
}

SOLID_TYPES = tuple(name for name, spec in TYPES.items() if spec.solid is not None)
