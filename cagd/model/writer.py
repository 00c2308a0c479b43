"""Writing engine objects as model documents (e.g. to save a STEP import as a model).

Floats are written with Python's shortest round-trip repr, so reading the document
back gives bit-identical control points, weights and knots."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional, Tuple, Union

from .._atomic import write_file
from .._validate import check_name
from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bezier import BezierSurface
from ..surfaces.bspline import BSplineSurface
from ..surfaces.trimmed import TrimmedSurface
from ..triangles.bezier_triangle import BezierTriangle
from .loader import FORMAT, VERSION, Model


def entry_dict(name: str, obj: Any, export: bool = True, description: Optional[str] = None) -> dict:
    """A model entry holding ``obj``'s data: bezier_curve, bspline_curve, bezier_surface,
    bspline_surface, bezier_triangle or trimmed_surface (its surface inline, as one of
    the others, its loops as 2-D bspline_curve entries and its ``tol``); any other
    engine curve or surface is written as its exact ``to_nurbs()`` form. Curves must be
    2-D or 3-D, surfaces 3-D.

    Raises:
        CagdError: not an engine curve or surface, or of an unsupported dimension.
    """
    check_name(name, "name")
    if not isinstance(obj, (Curve, Surface)):
        raise CagdError(f"obj: expected a cagd curve or surface, got {type(obj).__name__}")
    dims = (2, 3) if isinstance(obj, Curve) else (3,)
    if obj.dim not in dims:
        raise CagdError(f"obj: the model format holds {' or '.join(map(str, dims))}-D "
                        f"{'curves' if dims[0] == 2 else 'surfaces'}, got a {obj.dim}-D one")
    out: dict = {"name": name}
    if description is not None:
        out["description"] = description
    out.update(_data(obj))
    if not export:
        out["export"] = False
    return out


def _data(obj: Any) -> dict:
    w = getattr(obj, "weights", None)
    weights = {} if w is None else {"weights": w.tolist()}
    if isinstance(obj, BezierCurve):
        return {"type": "bezier_curve", "control_points": obj.control_points.tolist(), **weights}
    if isinstance(obj, BSplineCurve):
        out = {"type": "bspline_curve", "control_points": obj.control_points.tolist(), "degree": obj.degree,
               "knots": obj.knots.tolist(), **weights}
        return {**out, "periodic": True} if obj.periodic else out
    if isinstance(obj, BezierSurface):
        return {"type": "bezier_surface", "control_points": obj.control_points.tolist(), **weights}
    if isinstance(obj, BSplineSurface):
        out = {"type": "bspline_surface", "control_points": obj.control_points.tolist(),
               "degree_u": obj.degree_u, "degree_v": obj.degree_v,
               "knots_u": obj.knots_u.tolist(), "knots_v": obj.knots_v.tolist(), **weights}
        for flag in ("periodic_u", "periodic_v"):
            if getattr(obj, flag):
                out[flag] = True
        return out
    if isinstance(obj, TrimmedSurface):          # before the fallback: to_nurbs() drops the trim
        return {"type": "trimmed_surface", "surface": _data(obj.surface),
                "loops": [[_data(c) for c in loop] for loop in obj.loops], "tol": obj.tol}
    if isinstance(obj, BezierTriangle):
        return {"type": "bezier_triangle", "control_points": obj.control_points.tolist(), **weights}
    return _data(obj.to_nurbs())


def objects_to_dict(items: Union[Mapping[str, Any], Iterable[Tuple[str, Any]]], name: Optional[str] = None,
                    description: Optional[str] = None) -> dict:
    """A whole model document from {name: object} or (name, object) pairs."""
    pairs = list(items.items()) if isinstance(items, Mapping) else list(items)
    doc = _header(name, description)
    doc["objects"] = [entry_dict(n, obj) for n, obj in pairs]
    return doc


def model_to_dict(model: Model) -> dict:
    """The document of a loaded model: its header and each entry's JSON as read."""
    doc = _header(model.name, model.description)
    doc["units"] = model.units
    doc["objects"] = [e.source for e in model.entries]
    return doc


def _header(name: Optional[str], description: Optional[str]) -> dict:
    doc: dict = {"format": FORMAT, "version": VERSION, "units": "mm"}
    if name is not None:
        doc["name"] = name
    if description is not None:
        doc["description"] = description
    return doc


def dumps(doc: dict) -> str:
    """JSON text of a document: objects one key per line, arrays of numbers on one line."""
    return _dump(doc, "") + "\n"


def _dump(value: Any, indent: str) -> str:
    inner = indent + "  "
    if isinstance(value, dict):
        if not value:
            return "{}"
        body = ",\n".join(f"{inner}{json.dumps(k)}: {_dump(v, inner)}" for k, v in value.items())
        return "{\n" + body + "\n" + indent + "}"
    if isinstance(value, (list, tuple)):
        if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value):
            return json.dumps(list(value), allow_nan=False)
        return "[\n" + ",\n".join(inner + _dump(x, inner) for x in value) + "\n" + indent + "]"
    return json.dumps(value, allow_nan=False)


def dump_model(doc: Union[dict, Model], path: Union[str, Path]) -> None:
    """Write a document (or a loaded Model) as a JSON file, atomically (:mod:`cagd._atomic`):
    completely, or the old file stays as it was.

    Raises:
        CagdError: a value JSON cannot hold (NaN, a huge integer, a non-data type), or a
            path that cannot be written (missing folder, full disk), naming the path.
    """
    if isinstance(doc, Model):
        doc = model_to_dict(doc)
    try:
        text = dumps(doc)
    except (TypeError, ValueError, RecursionError) as exc:
        raise CagdError(f"doc: cannot be written as JSON: {exc}") from None
    write_file(path, text, "path")
