"""The OCCT shape inside another library's object, found by duck typing (neither
CadQuery nor build123d is imported here).

Accepted: a bare ``TopoDS_Shape``; any CadQuery or build123d shape (``Face``,
``Edge``, ``Wire``, ``Shell``, ``Solid``, ``Compound``; build123d's ``Part``,
``Sketch``, ``Curve``), whose ``.wrapped`` is the ``TopoDS_Shape``; a CadQuery
``Workplane`` (the shapes of its stack, ``vals()``) or ``Sketch`` (its faces); a
build123d ``BuildPart``, ``BuildSketch`` or ``BuildLine`` context (its ``.part``,
``.sketch``, ``.line``). The library is told by the object's module,
``type(obj).__module__.split('.')[0]``. A refusal is a :class:`cagd.CagdError` naming
the argument, the library and the type, e.g. ``faces[2]: expected a face, got a
build123d Sketch holding 0 faces``.
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator, List, Optional

from OCP.BRep import BRep_Builder
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_ShapeEnum
from OCP.TopoDS import TopoDS_Compound, TopoDS_Shape

from ..errors import CagdError

LIBRARIES = {"cadquery": "CadQuery", "build123d": "build123d", "OCP": "OCCT"}
_BUILDERS = {"BuildPart": "part", "BuildSketch": "sketch", "BuildLine": "line"}   # build123d contexts
_WRAPPERS = ("cadquery", "build123d")          # the modules whose objects are unwrapped
_EXPECTED = "a CadQuery or build123d shape or a TopoDS_Shape"


@contextmanager
def occt_errors(name: str, what: str) -> Iterator[None]:
    """Turn an OCCT exception raised inside the block (OCP raises Standard_Failure,
    Standard_NoSuchObject, StdFail_NotDone, ... as plain Exception subclasses from its
    own modules) into a CagdError naming the argument ``name``: "<name>: OCCT failed
    to <what> (<exception> <message>)". Other exceptions pass through."""
    try:
        yield
    except CagdError:
        raise
    except Exception as exc:
        if not type(exc).__module__.startswith("OCP"):
            raise
        raise CagdError(f"{name}: OCCT failed to {what} ({type(exc).__name__} {exc})") from None


def _root(obj) -> str:
    """The top-level module of the object's type: "cadquery", "build123d", "numpy", ..."""
    return type(obj).__module__.split(".")[0]


def library(obj: object) -> str:
    """The library an object comes from, by its module: "CadQuery", "build123d",
    "OCCT" (OCP), else the top-level module's name ("" for builtins)."""
    root = _root(obj)
    return LIBRARIES.get(root, "" if root == "builtins" else root)


def describe(obj: object) -> str:
    """The library and type of an object for messages: "a build123d Sketch", "a
    CadQuery Workplane", "numpy ndarray", "str"."""
    lib, name = library(obj), type(obj).__name__
    if lib in LIBRARIES.values():
        return f"a {lib} {name}"
    return f"{lib} {name}" if lib else name


_NONE = object()      # no ``wrapped`` attribute at all


def _inner(obj):
    """``obj.wrapped``; None for an empty build123d shape (its ``wrapped`` asserts that
    ``_wrapped`` is not None); ``_NONE`` when there is no such attribute."""
    try:
        return obj.wrapped
    except AttributeError:
        return _NONE
    except AssertionError:
        return None


def _members(obj) -> Optional[list]:
    """What a container of the two libraries holds: a Workplane's stack, a CadQuery
    Sketch's faces, a build123d builder's result; None for anything else."""
    root = _root(obj)
    if root == "cadquery" and callable(getattr(obj, "vals", None)) and hasattr(obj, "ctx"):
        return list(obj.vals())
    if root == "cadquery" and hasattr(obj, "_faces") and not hasattr(obj, "wrapped"):
        return [obj._faces] if obj._faces is not None else []
    if root == "build123d":
        attr = next((_BUILDERS[c.__name__] for c in type(obj).__mro__ if c.__name__ in _BUILDERS), None)
        if attr is not None:
            inner = getattr(obj, attr)
            return [inner] if inner is not None else []
    return None


def is_shape(obj: object) -> bool:
    """Whether ``obj`` is a shape or shape container this module unwraps (not whether
    it holds any shape)."""
    if isinstance(obj, TopoDS_Shape):
        return True
    if _root(obj) not in _WRAPPERS:
        return False
    if _members(obj) is not None:
        return True
    inner = _inner(obj)
    return inner is None or isinstance(inner, TopoDS_Shape)


def _found(obj) -> list:
    """The non-null TopoDS shapes in ``obj`` (containers searched), [] if none."""
    if isinstance(obj, TopoDS_Shape):
        return [] if obj.IsNull() else [obj]
    if _root(obj) not in _WRAPPERS:
        return []
    members = _members(obj)
    if members is not None:
        return [w for m in members for w in _found(m)]
    inner = _inner(obj)
    return [inner] if isinstance(inner, TopoDS_Shape) and not inner.IsNull() else []


def occ_shapes(obj: object, name: str = "shape") -> List[TopoDS_Shape]:
    """The non-null OCCT shapes of ``obj`` (one, or the several of a Workplane stack).

    Raises:
        CagdError: not a shape of a known library, a null or empty shape, a container
            holding no shape.
    """
    found = _found(obj)
    if found:
        return found
    if isinstance(obj, TopoDS_Shape):
        raise CagdError(f"{name}: a null shape")
    if is_shape(obj):
        raise CagdError(f"{name}: expected {_EXPECTED}, got {describe(obj)} holding no shapes")
    raise CagdError(f"{name}: expected {_EXPECTED}, got {describe(obj)}")


def compound(shapes: List[TopoDS_Shape]) -> TopoDS_Shape:
    """One shape of several: the shape itself when there is one, else their compound."""
    if len(shapes) == 1:
        return shapes[0]
    out = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(out)
    for s in shapes:
        builder.Add(out, s)
    return out


def occ_shape(obj: object, name: str = "shape") -> TopoDS_Shape:
    """The OCCT shape of ``obj``; several (a Workplane's stack) as one compound.

    Raises:
        CagdError: as :func:`occ_shapes`.
    """
    return compound(occ_shapes(obj, name))


_KINDS = {TopAbs_FACE: ("a face", "faces"), TopAbs_EDGE: ("an edge", "edges")}


def occ_subshapes(obj: object, kind: TopAbs_ShapeEnum, name: str) -> List[TopoDS_Shape]:
    """The OCCT faces (``kind`` TopAbs_FACE) or edges (TopAbs_EDGE) of ``obj``.

    Raises:
        CagdError: as :func:`occ_shapes`, or ``obj`` holds none.
    """
    from .shapes import subshapes        # shapes.py imports this module
    found = [x for s in occ_shapes(obj, name) for x in subshapes(s, kind)]
    if not found:
        one, many = _KINDS[kind]
        raise CagdError(f"{name}: expected {one}, got {describe(obj)} holding 0 {many}")
    return found


def occ_faces(obj: object, name: str = "faces") -> List[TopoDS_Shape]:
    """The OCCT faces of ``obj`` (a face, or the faces of a shell, solid, compound,
    sketch, part or Workplane stack); see :func:`occ_subshapes`."""
    return occ_subshapes(obj, TopAbs_FACE, name)


def occ_edges(obj: object, name: str = "curves") -> List[TopoDS_Shape]:
    """The OCCT edges of ``obj`` (an edge, or the edges of a wire, curve, face, ...);
    see :func:`occ_subshapes`."""
    return occ_subshapes(obj, TopAbs_EDGE, name)


__all__ = ["library", "describe", "is_shape", "occ_shapes", "occ_shape", "occ_subshapes", "occ_faces", "occ_edges",
           "compound"]
