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
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, List, Tuple, Union

from OCP.IFSelect import IFSelect_RetDone
from OCP.IGESData import IGESData_IGESWriter
from OCP.IGESSelect import IGESSelect_WorkLibrary
from OCP.IGESCAFControl import IGESCAFControl_Reader, IGESCAFControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPCAFControl import STEPCAFControl_Reader, STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.StepAP214 import StepAP214_Protocol
from OCP.StepData import StepData_StepWriter
from OCP.TCollection import TCollection_ExtendedString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label, TDF_LabelSequence
from OCP.TDocStd import TDocStd_Document
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp
from OCP.TopoDS import TopoDS_Shape
from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_DocumentTool

from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from .convert import from_occ
from .shapes import make_edge, make_face, subshapes

_REAL_FORMAT = "%.16E"     # 17 significant digits: every double reads back unchanged
Item = Union[Curve, Surface, TopoDS_Shape]


@dataclass
class Imported:
    """One curve or surface read from a file: the name of the item it belongs to
    (with ``[i]`` when the item holds several), the engine object and its OCCT shape."""
    name: str
    object: Union[BSplineCurve, BSplineSurface]
    shape: TopoDS_Shape


def _named(objects) -> List[Tuple[str, Item]]:
    if isinstance(objects, (Curve, Surface, TopoDS_Shape)):
        objects = [objects]
    items = list(objects.items()) if isinstance(objects, dict) else list(objects)
    out = []
    for i, it in enumerate(items):
        name, obj = it if isinstance(it, tuple) else (None, it)
        if isinstance(obj, Curve):
            shape = make_edge(obj)
        elif isinstance(obj, Surface):
            shape = make_face(obj)
        elif isinstance(obj, TopoDS_Shape):
            shape = obj
        else:
            raise CagdError(f"objects[{i}]: expected a cagd Curve or Surface or an OCCT shape, "
                            f"got {type(obj).__name__}")
        out.append((str(name) if name is not None else f"{type(obj).__name__}_{i + 1}", shape))
    if not out:
        raise CagdError("objects: nothing to write")
    return out


def _document(named: List[Tuple[str, TopoDS_Shape]]) -> TDocStd_Document:
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    for name, shape in named:
        label = tool.AddShape(shape, False)
        TDataStd_Name.Set_s(label, TCollection_ExtendedString(name))
    return doc


def _target(path) -> str:
    path = Path(path)
    if not path.parent.is_dir():
        raise CagdError(f"path: folder {str(path.parent)!r} does not exist")
    return os.fspath(path)


def write_step(objects, path, schema: str = "AP214IS") -> Path:
    """Write engine objects (edges for curves, faces with natural bounds for surfaces)
    and OCCT shapes to a STEP file, in mm. ``objects``: a list of items or of
    (name, item) pairs, or a dict name -> item.

    Raises:
        CagdError: an unsupported item, a missing folder, or the writer failed.
    """
    named, target = _named(objects), _target(path)
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    Interface_Static.SetCVal_s("write.step.schema", schema)
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    writer = STEPCAFControl_Writer()
    writer.SetNameMode(True)
    if not writer.Transfer(_document(named), STEPControl_AsIs):
        raise CagdError(f"path: OCCT could not transfer the objects to STEP for {target!r}")
    printer = StepData_StepWriter(writer.ChangeWriter().Model())
    printer.FloatWriter().SetFormat(_REAL_FORMAT, True)
    printer.SendModel(StepAP214_Protocol())
    return _print(printer, target, "STEP")


def write_iges(objects, path) -> Path:
    """Write engine objects and OCCT shapes to an IGES 5.3 file (faces as trimmed
    B-spline surfaces, type 144/128; curves type 126), in mm; see :func:`write_step`."""
    named, target = _named(objects), _target(path)
    Interface_Static.SetCVal_s("write.iges.unit", "MM")
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    writer = IGESCAFControl_Writer()
    writer.SetNameMode(True)
    if not writer.Transfer(_document(named)):
        raise CagdError(f"path: OCCT could not transfer the objects to IGES for {target!r}")
    writer.ComputeModel()
    printer = IGESData_IGESWriter(writer.Model())
    printer.FloatWriter().SetFormat(_REAL_FORMAT, True)
    printer.SendModel(IGESSelect_WorkLibrary.DefineProtocol_s())
    return _print(printer, target, "IGES")


def _print(printer, target: str, kind: str) -> Path:
    buffer = io.BytesIO()
    if not printer.Print(buffer):
        raise CagdError(f"path: OCCT could not print the {kind} file {target!r}")
    Path(target).write_bytes(buffer.getvalue())
    return Path(target)


def _read(reader, path, kind: str) -> List[Tuple[str, TopoDS_Shape]]:
    if not Path(path).is_file():
        raise CagdError(f"path: no such file {str(path)!r}")
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    reader.SetNameMode(True)
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    if reader.ReadFile(os.fspath(path)) != IFSelect_RetDone or not reader.Transfer(doc):
        raise CagdError(f"path: OCCT could not read {kind} file {str(path)!r}")
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    labels = TDF_LabelSequence()
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


def read_shapes(path, kind: str = "auto") -> List[Tuple[str, TopoDS_Shape]]:
    """(name, shape) of every top-level item of a STEP or IGES file (by extension
    unless ``kind`` is "step" or "iges"), lengths converted to mm."""
    kind = kind.lower()
    if kind == "auto":
        kind = "iges" if Path(path).suffix.lower() in (".igs", ".iges") else "step"
    if kind == "step":
        return _read(STEPCAFControl_Reader(), path, "STEP")
    if kind == "iges":
        return _read(IGESCAFControl_Reader(), path, "IGES")
    raise CagdError(f"kind: expected 'auto', 'step' or 'iges', got {kind!r}")


def _objects(named: Iterable[Tuple[str, TopoDS_Shape]]) -> List[Imported]:
    """Faces -> surfaces; edges that bound no face -> curves."""
    out = []
    for name, shape in named:
        found = []
        faces = subshapes(shape, TopAbs_FACE)
        for f in faces:
            found.append((from_occ(f), f))
        owners = TopTools_IndexedDataMapOfShapeListOfShape()
        TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, owners)
        for e in subshapes(shape, TopAbs_EDGE):
            if owners.Contains(e) and owners.FindFromKey(e).Size() == 0 and not _seen(e, found):
                found.append((from_occ(e), e))
        many = len(found) > 1
        out += [Imported(f"{name}[{j}]" if many else name, obj, s) for j, (obj, s) in enumerate(found)]
    return out


def _seen(edge, found) -> bool:
    return any(s.IsSame(edge) for _, s in found)


def read_step(path) -> List[Imported]:
    """Every surface (face) and free curve (edge of no face) of a STEP file as an
    engine B-spline, with its name (see :class:`Imported`)."""
    return _objects(read_shapes(path, "step"))


def read_iges(path) -> List[Imported]:
    """As :func:`read_step`, for IGES files."""
    return _objects(read_shapes(path, "iges"))
