"""STEP (AP214) and IGES files: engine objects and OCCT shapes out, engine objects in.

Lengths in millimetres. Names travel through OCCT's XCAF document (STEPCAFControl /
IGESCAFControl): each written item is a labelled shape whose name is the STEP
product name (and the IGES entity label, 8 characters at most there).

Reals are written with 17 significant digits (``%.16E``), enough to give every
double back unchanged: OCCT's own writers print 12 (STEP) and 9 (IGES) digits,
which costs about 1e-12 and 1e-9 relative on a round trip (measured in tests/occ).
The models are transferred by OCCT and printed here with OCCT's own
StepData_StepWriter / IGESData_IGESWriter, only their number format changed.
"""
from __future__ import annotations

import io
import os
import unicodedata
import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, Iterator, List, Optional, Tuple, Union, overload

from OCP.IFSelect import IFSelect_RetDone
from OCP.IGESData import IGESData_IGESWriter
from OCP.IGESSelect import IGESSelect_WorkLibrary
from OCP.IGESCAFControl import IGESCAFControl_Reader, IGESCAFControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPCAFControl import STEPCAFControl_Reader, STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.StepAP214 import StepAP214_Protocol
from OCP.StepData import StepData_Logical, StepData_StepWriter
from OCP.StepGeom import StepGeom_BSplineCurve, StepGeom_BSplineSurface
from OCP.TCollection import TCollection_ExtendedString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label
from OCP.TDocStd import TDocStd_Document
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp
from OCP.TopoDS import TopoDS_Shape
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_DocumentTool

from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots.vectors import is_clamped
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from .compat import IndexedDataMapOfShapeListOfShape, LabelSequence
from .convert import from_occ
from .shapes import make_edge, make_face, subshapes
from .wrapped import describe, is_shape, occ_shape

_REAL_FORMAT = "%.16E"     # 17 significant digits: every double reads back unchanged
Item = Union[Curve, Surface, TopoDS_Shape]
Objects = Union[Item, Iterable[Union[Item, Tuple[str, Item]]], Dict[str, Item]]


@dataclass(frozen=True)
class Imported:
    """One curve or surface read from a file: the name of the item it belongs to
    (with ``[i]`` when the item holds several), the engine object and its OCCT shape."""
    name: str
    object: Union[BSplineCurve, BSplineSurface, Surface]     # a TrimmedSurface for a trimmed face
    shape: TopoDS_Shape


@dataclass(frozen=True)
class Skipped:
    """A face or free edge of a file that could not be converted: the name of its item,
    its index among the item's faces (or free edges), its kind ("face" or "edge"), the
    reason, and the OCCT shape (still usable through OCCT)."""
    name: str
    index: int
    kind: str
    reason: str
    shape: TopoDS_Shape


@dataclass(frozen=True)
class FileContents:
    """What :func:`read_step` / :func:`read_iges` read: ``items`` (iterating, indexing
    and ``len`` go to them) and ``skipped``, the faces and edges that did not convert
    (one bad face never costs the rest of the file); ``complete`` is True when nothing
    was skipped, ``message`` says what was."""
    items: Tuple[Imported, ...]
    skipped: Tuple[Skipped, ...] = ()

    @property
    def complete(self) -> bool:
        return not self.skipped

    @property
    def message(self) -> str:
        if not self.skipped:
            return ""
        first = self.skipped[0]
        return (f"{len(self.skipped)} of {len(self.items) + len(self.skipped)} faces/edges not converted; first: "
                f"{first.kind} {first.index} of {first.name!r}: {first.reason}")

    def __iter__(self) -> Iterator[Imported]:
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, index: int) -> Imported:
        return self.items[index]


@contextmanager
def _settings(**values):
    """Set OCCT's global Interface_Static parameters for one transfer and restore
    them afterwards (CadQuery's own importers and exporters read the same ones)."""
    old = {}
    for key, value in values.items():
        name = key.replace("__", ".")
        if isinstance(value, int):
            old[name] = Interface_Static.IVal_s(name)
            Interface_Static.SetIVal_s(name, value)
        else:
            old[name] = Interface_Static.CVal_s(name)
            Interface_Static.SetCVal_s(name, value)
    try:
        yield
    finally:
        for name, value in old.items():
            if isinstance(value, int):
                Interface_Static.SetIVal_s(name, value)
            else:
                Interface_Static.SetCVal_s(name, value)


def _named(objects) -> List[Tuple[str, Item]]:
    if isinstance(objects, (Curve, Surface)) or is_shape(objects):
        objects = [objects]
    if objects is None or isinstance(objects, (str, bytes)) or not hasattr(objects, "__iter__"):
        raise CagdError(f"objects: expected engine objects or OCCT shapes (a list, or a dict by name), "
                        f"got {type(objects).__name__}")
    items = list(objects.items()) if isinstance(objects, dict) else list(objects)
    out = []
    for i, it in enumerate(items):
        name, obj = it if isinstance(it, tuple) else (None, it)
        if isinstance(obj, Curve):
            shape = make_edge(_exchange_form(obj))
        elif isinstance(obj, Surface):
            shape = make_face(_exchange_form(obj), nurbs=True)
        elif is_shape(obj):
            shape = occ_shape(obj, f"objects[{i}]")
        else:
            raise CagdError(f"objects[{i}]: expected a cagd Curve or Surface, a CadQuery or build123d shape "
                            f"or a TopoDS_Shape, got {describe(obj)}")
        out.append((str(name) if name is not None else f"{type(obj).__name__}_{i + 1}", shape))
    if not out:
        raise CagdError("objects: nothing to write")
    return out


@overload
def _exchange_form(obj: Curve) -> BSplineCurve: ...


@overload
def _exchange_form(obj: Surface) -> BSplineSurface: ...


def _exchange_form(obj: Union[Curve, Surface]) -> Union[BSplineCurve, BSplineSurface]:
    """The object's NURBS form with clamped knots (knot insertion: the same curve or
    surface, same parameters). Files get only that: OCCT's STEP and IGES transfer of
    unclamped knot vectors and of periodic directions with few poles loses the shape."""
    nurbs = obj.to_nurbs()
    if isinstance(nurbs, BSplineCurve):
        return nurbs if not nurbs.periodic and is_clamped(nurbs.knots, nurbs.degree) else nurbs.clamped()
    clamped = not (nurbs.periodic_u or nurbs.periodic_v) and is_clamped(nurbs.knots_u, nurbs.degree_u) \
        and is_clamped(nurbs.knots_v, nurbs.degree_v)
    return nurbs if clamped else nurbs.clamped()


def _document(named: List[Tuple[str, TopoDS_Shape]], unicode: bool) -> TDocStd_Document:
    """An XCAF document holding the named shapes. STEP takes UTF-8 names; IGES labels
    are ASCII, so there the names are folded to ASCII (accents dropped)."""
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    for name, shape in named:
        label = tool.AddShape(shape, False)
        text = TCollection_ExtendedString(name, True) if unicode else TCollection_ExtendedString(_ascii(name))
        TDataStd_Name.Set_s(label, text)
    return doc


def _ascii(name: str) -> str:
    return unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode("ascii") or "item"


def _target(path) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise CagdError(f"path: expected a file path, got {type(path).__name__}")
    path = Path(path)
    if path.is_dir():
        raise CagdError(f"path: {str(path)!r} is a folder; give a file name")
    if not path.parent.is_dir():
        raise CagdError(f"path: folder {str(path.parent)!r} does not exist")
    return os.fspath(path)


def write_step(objects: Objects, path: Union[str, os.PathLike], schema: str = "AP214IS") -> Path:
    """Write engine objects (edges for curves, faces with natural bounds for surfaces)
    and shapes (OCCT's, CadQuery's, build123d's: :mod:`cagd.occ.wrapped`) to a STEP
    file, in mm. ``objects``: a list of items or of (name, item) pairs, or a dict
    name -> item.

    Raises:
        CagdError: an unsupported item, a missing folder, or the writer failed.
    """
    named, target = _named(objects), _target(path)
    writer = STEPCAFControl_Writer()
    writer.SetNameMode(True)
    with _settings(write__step__unit="MM", write__step__schema=schema, xstep__cascade__unit="MM"):
        if not writer.Transfer(_document(named, unicode=True), STEPControl_AsIs):
            raise CagdError(f"path: OCCT could not transfer the objects to STEP for {target!r}")
    model = writer.ChangeWriter().Model()
    _open_closed_flags(model)
    printer = StepData_StepWriter(model)
    printer.FloatWriter().SetFormat(_REAL_FORMAT, True)
    printer.SendModel(StepAP214_Protocol())
    return _print(printer, target, "STEP")


def write_iges(objects: Objects, path: Union[str, os.PathLike]) -> Path:
    """Write engine objects and OCCT shapes to an IGES 5.3 file (faces as trimmed
    B-spline surfaces, type 144/128; curves type 126), in mm; see :func:`write_step`."""
    named, target = _named(objects), _target(path)
    with _settings(write__iges__unit="MM", xstep__cascade__unit="MM"):
        writer = IGESCAFControl_Writer()
        writer.SetNameMode(True)
        if not writer.Transfer(_document(named, unicode=False)):
            raise CagdError(f"path: OCCT could not transfer the objects to IGES for {target!r}")
        writer.ComputeModel()
    printer = IGESData_IGESWriter(writer.Model())
    printer.FloatWriter().SetFormat(_REAL_FORMAT, True)
    printer.SendModel(IGESSelect_WorkLibrary.DefineProtocol_s())
    return _print(printer, target, "IGES")


def _open_closed_flags(model) -> None:
    """Clear the informational closed_curve / u_closed / v_closed flags of the
    B-splines: OCCT's STEP reader turns a curve flagged closed into a periodic one,
    which changes a rational curve whose end weights differ (measured: 0.17 off).
    The knots are clamped, so the flag carries nothing the geometry does not."""
    for i in range(1, model.NbEntities() + 1):
        entity = model.Value(i)
        if isinstance(entity, StepGeom_BSplineCurve):
            entity.SetClosedCurve(StepData_Logical.StepData_LFalse)
        elif isinstance(entity, StepGeom_BSplineSurface):
            entity.SetUClosed(StepData_Logical.StepData_LFalse)
            entity.SetVClosed(StepData_Logical.StepData_LFalse)


def _print(printer, target: str, kind: str) -> Path:
    buffer = io.BytesIO()
    if not printer.Print(buffer):
        raise CagdError(f"path: OCCT could not print the {kind} file {target!r}")
    Path(target).write_bytes(buffer.getvalue())
    return Path(target)


def _read(reader, path, kind: str, **settings) -> List[Tuple[str, TopoDS_Shape]]:
    if not isinstance(path, (str, os.PathLike)) or not Path(path).is_file():
        raise CagdError(f"path: no such file {str(path)!r}")
    reader.SetNameMode(True)
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    with _settings(xstep__cascade__unit="MM", **settings):
        if reader.ReadFile(os.fspath(path)) != IFSelect_RetDone or not reader.Transfer(doc):
            raise CagdError(f"path: OCCT could not read {kind} file {str(path)!r}")
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    labels = LabelSequence()
    tool.GetFreeShapes(labels)
    out = []
    for i in range(1, labels.Length() + 1):
        label = labels.Value(i)
        out.append((_label_name(label) or f"item_{i}", tool.GetShape_s(label)))
    return out


def _label_name(label: TDF_Label) -> str:
    attr = TDataStd_Name()
    if label.FindAttribute(TDataStd_Name.GetID_s(), attr):
        return attr.Get().ToExtString()
    return ""


def read_shapes(path: Union[str, os.PathLike], kind: str = "auto") -> List[Tuple[str, TopoDS_Shape]]:
    """(name, shape) of every top-level item of a STEP or IGES file (by extension
    unless ``kind`` is "step" or "iges"), lengths converted to mm."""
    if not isinstance(kind, str):
        raise CagdError(f"kind: expected 'auto', 'step' or 'iges', got {kind!r}")
    kind = kind.lower()
    if kind == "auto":
        kind = "iges" if Path(path).suffix.lower() in (".igs", ".iges") else "step"
    if kind == "step":
        return _read(STEPCAFControl_Reader(), path, "STEP")
    if kind == "iges":
        # whole B-splines: by default OCCT's IGES reader splits curves at C0 knots into several edges
        return _read(IGESCAFControl_Reader(), path, "IGES", read__iges__bspline__continuity=0)
    raise CagdError(f"kind: expected 'auto', 'step' or 'iges', got {kind!r}")


def _objects(named: Iterable[Tuple[str, TopoDS_Shape]], approximate: Optional[float]) -> FileContents:
    """Faces -> surfaces; edges that bound no face -> curves; what does not convert is
    listed in ``skipped`` (and warned about), never dropped silently."""
    out: List[Imported] = []
    skipped: List[Skipped] = []
    for name, shape in named:
        found: List[Tuple[Union[BSplineCurve, BSplineSurface, Surface], TopoDS_Shape]] = []
        failed: List[Tuple[str, int, str, TopoDS_Shape]] = []
        faces = subshapes(shape, TopAbs_FACE)
        owners = IndexedDataMapOfShapeListOfShape()
        TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, owners)
        free = [e for e in subshapes(shape, TopAbs_EDGE) if owners.Contains(e) and owners.FindFromKey(e).Size() == 0]
        for kind, shapes in (("face", faces), ("edge", free)):
            for index, s in enumerate(shapes):
                if kind == "edge" and _seen(s, found):
                    continue
                try:
                    found.append((from_occ(s, approximate=approximate), s))
                except CagdError as exc:
                    failed.append((kind, index, str(exc), s))
        many = len(found) + len(failed) > 1
        out += [Imported(f"{name}[{j}]" if many else name, obj, s) for j, (obj, s) in enumerate(found)]
        skipped += [Skipped(name, index, kind, reason, s) for kind, index, reason, s in failed]
    result = FileContents(tuple(out), tuple(skipped))
    if skipped:
        warnings.warn(f"read: {result.message}", RuntimeWarning, stacklevel=3)
    return result


def _seen(edge, found) -> bool:
    return any(s.IsSame(edge) for _, s in found)


def read_step(path: Union[str, os.PathLike], approximate: Optional[float] = None) -> FileContents:
    """Every surface (face) and free curve (edge of no face) of a STEP file as an
    engine B-spline, with its name (see :class:`Imported`), in a :class:`FileContents`
    (iterable like a list). A face or edge that does not convert (an offset surface
    without ``approximate``, geometry OCCT cannot turn into a B-spline) is listed in
    ``skipped`` with the reason and a RuntimeWarning; every other one comes back.
    ``approximate``: as :func:`cagd.occ.from_occ` (a distance in model units within
    which OCCT may approximate offsets)."""
    return _objects(read_shapes(path, "step"), approximate)


def read_iges(path: Union[str, os.PathLike], approximate: Optional[float] = None) -> FileContents:
    """As :func:`read_step`, for IGES files."""
    return _objects(read_shapes(path, "iges"), approximate)
