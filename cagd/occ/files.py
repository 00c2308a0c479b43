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
import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import time
import unicodedata
import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, Iterator, List, Optional, Tuple, Union, overload

from OCP.Bnd import Bnd_Box
from OCP.BRepBndLib import BRepBndLib
from OCP.IFSelect import IFSelect_RetDone, IFSelect_SignCounter, IFSelect_SignType
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

from .._atomic import check_target, write_file
from .._validate import check_name, read_bytes, validate_iges, validate_step
from ..curves.base import Curve
from ..curves.bspline import BSplineCurve
from ..errors import CagdError
from ..knots.vectors import is_clamped
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from ..surfaces.trimmed import TrimmedSurface
from .compat import IndexedDataMapOfShapeListOfShape, LabelSequence
from .convert import MAX_COORDINATE, from_occ
from .shapes import make_edge, make_face, subshapes
from .wrapped import describe, is_shape, occ_shape

_REAL_FORMAT = "%.16E"     # 17 significant digits: every double reads back unchanged
STEP_SCHEMAS = ("AP203", "AP214CD", "AP214DIS", "AP214IS", "AP242DIS")   # OCCT's write.step.schema values
MIN_EXTENT = 1e-6          # mm: a face whose bounding box diagonal is smaller is refused on write; OCCT's
#                            STEP reader drops faces at its Precision::Confusion (1e-7): measured, a
#                            B-spline face of diagonal 1.6e-8 reads back as nothing, one of 1.6e-7 reads
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
    its index among the item's faces (or free edges), its kind ("face" or "edge"; "item"
    for an item OCCT transferred as nothing), the reason, and the OCCT shape (still
    usable through OCCT)."""
    name: str
    index: int
    kind: str
    reason: str
    shape: TopoDS_Shape


@dataclass(frozen=True)
class FileContents:
    """What :func:`read_step` / :func:`read_iges` read: ``items`` (iterating, indexing
    and ``len`` go to them) and ``skipped``, the faces and edges that did not convert
    (one bad face never costs the rest of the file); ``unread``, the entities OCCT's
    parser rejected or does not know (what refers to them may be missing from ``items``);
    ``complete`` is True when no face or edge was skipped, ``message`` says what was
    skipped or unread."""
    items: Tuple[Imported, ...]
    skipped: Tuple[Skipped, ...] = ()
    unread: Tuple[str, ...] = ()      # entities OCCT's parser rejected or does not know: "entity 33 (TYPE): reason"

    @property
    def complete(self) -> bool:
        """Every face and free edge OCCT transferred was converted (``unread`` entities
        are reported apart: real files carry damaged styling and unit entities)."""
        return not self.skipped

    @property
    def message(self) -> str:
        out = []
        if self.skipped:
            first = self.skipped[0]
            out.append(f"{len(self.skipped)} of {len(self.items) + len(self.skipped)} faces/edges not converted; "
                       f"first: {first.kind} {first.index} of {first.name!r}: {first.reason}")
        if self.unread:
            out.append(f"{len(self.unread)} entities of the file were not read (what refers to them may be "
                       f"missing); first: {self.unread[0]}")
        return "; ".join(out)

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
        elif isinstance(obj, TrimmedSurface):                 # its own wires (cagd.occ.trim)
            shape = make_face(obj)
        elif isinstance(obj, Surface):
            shape = make_face(_exchange_form(obj), nurbs=True)
        elif is_shape(obj):
            shape = occ_shape(obj, f"objects[{i}]")
        else:
            raise CagdError(f"objects[{i}]: expected a cagd Curve or Surface, a CadQuery or build123d shape "
                            f"or a TopoDS_Shape, got {describe(obj)}")
        label = check_name(str(name), f"objects[{i}] name") if name is not None else f"{type(obj).__name__}_{i + 1}"
        _check_extent(shape, label)
        out.append((label, shape))
    if not out:
        raise CagdError("objects: nothing to write")
    return out


def _check_extent(shape: TopoDS_Shape, name: object) -> None:
    """Refuse a face smaller than MIN_EXTENT (collapsed to a point, or tiny): the file
    would hold it, but OCCT's reader gives back nothing for it; and coordinates beyond
    MAX_COORDINATE, which OCCT treats as infinite."""
    whole = Bnd_Box()
    BRepBndLib.Add_s(shape, whole, False)
    if not whole.IsVoid():
        # CornerMin/CornerMax, not Get(): OCCT 8's Get() returns a struct OCP cannot convert
        lo, hi = whole.CornerMin(), whole.CornerMax()
        reach = max(abs(c) for p in (lo, hi) for c in (p.X(), p.Y(), p.Z()))
        if not reach <= MAX_COORDINATE:
            raise CagdError(f"objects: {name!r} reaches coordinates of {reach:.3g} mm; files hold at most "
                            f"{MAX_COORDINATE:g} (OCCT treats larger values as infinite)")
    for k, face in enumerate(subshapes(shape, TopAbs_FACE)):
        box = Bnd_Box()
        BRepBndLib.Add_s(face, box, False)
        size = 0.0 if box.IsVoid() else box.SquareExtent() ** 0.5
        if not size >= MIN_EXTENT:
            raise CagdError(f"objects: {name!r}" + (f" face {k}" if k else "") + f" is {size:.3g} mm across; "
                            f"faces under {MIN_EXTENT:g} mm are refused: OCCT's reader returns nothing for them "
                            f"(no face was read back from such files; scale the model to mm)")


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
    return os.fspath(check_target(path, "path"))


def write_step(objects: Objects, path: Union[str, os.PathLike], schema: str = "AP214IS") -> Path:
    """Write engine objects (edges for curves, faces with natural bounds for surfaces)
    and shapes (OCCT's, CadQuery's, build123d's: :mod:`cagd.occ.wrapped`) to a STEP
    file, in mm. ``objects``: a list of items or of (name, item) pairs, or a dict
    name -> item.

    The file is written atomically (:mod:`cagd._atomic`): completely, or the old file
    stays as it was.

    Raises:
        CagdError: an unsupported item, a name with control characters, a face under
            MIN_EXTENT, a path that cannot be written (missing folder, full disk), or
            the writer failed.
    """
    target = _target(path)
    return write_file(target, step_bytes(objects, schema, target), "path")


def step_bytes(objects: Objects, schema: str = "AP214IS", target: str = "<memory>") -> bytes:
    """The STEP file :func:`write_step` writes, as bytes (``target`` only names it in errors)."""
    if not isinstance(schema, str) or schema not in STEP_SCHEMAS:
        raise CagdError(f"schema: one of {', '.join(STEP_SCHEMAS)}, got {schema!r}")
    named = _named(objects)
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
    target = _target(path)
    return write_file(target, iges_bytes(objects, target), "path")


def iges_bytes(objects: Objects, target: str = "<memory>") -> bytes:
    """The IGES file :func:`write_iges` writes, as bytes (``target`` only names it in errors)."""
    named = _named(objects)
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


def _print(printer, target: str, kind: str) -> bytes:
    buffer = io.BytesIO()
    if not printer.Print(buffer):
        raise CagdError(f"path: OCCT could not print the {kind} file {target!r}")
    return buffer.getvalue()


# what the XCAF readers would also transfer (colours, layers, GD&T, ...): cagd keeps names only
_UNUSED_MODES = ("SetColorMode", "SetLayerMode", "SetGDTMode", "SetMatMode", "SetMetaMode", "SetProductMetaMode",
                 "SetPropsMode", "SetSHUOMode", "SetViewMode")


def _read(reader, path, kind: str, **settings) -> Tuple[List[Tuple[str, TopoDS_Shape]], Tuple[str, ...]]:
    """The free shapes of a file (validated first: :mod:`cagd._validate`) and the
    entities OCCT's STEP parser rejected. A file with rejected entities is transferred
    in a child process first: OCCT's transfer dies (SIGSEGV) on some of them (a
    B-spline surface with a parameter missing), which must not kill this process."""
    if not _is_file(path):
        raise CagdError(f"path: no such file {str(path)!r}")
    data = read_bytes(path, kind)
    (validate_step if kind == "STEP" else validate_iges)(path, data)
    reader.SetNameMode(True)
    for mode in _UNUSED_MODES:              # only names are kept: the rest costs ~7% of the transfer
        if hasattr(reader, mode):
            getattr(reader, mode)(False)
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    XCAFApp_Application.GetApplication_s().InitDocument(doc)
    with _settings(xstep__cascade__unit="MM", **settings), _private_copy(path, data) as copy:
        if reader.ReadFile(copy) != IFSelect_RetDone:
            raise CagdError(f"path: OCCT could not read {kind} file {str(path)!r}")
        unread, errors = _unread(reader.ChangeReader().Model() if kind == "STEP" else reader.Model(), kind)
        out = None
        if errors and not os.environ.get(_PROBE_FLAG):
            out = _transfer_forked(reader, doc, kind, unread, path)
            if out is None:
                _probe(copy, kind, unread, path)
        if out is None:
            if not reader.Transfer(doc):
                raise CagdError(f"path: OCCT could not read {kind} file {str(path)!r}")
            out = _free_shapes(doc)
    return out, unread


def _free_shapes(doc: TDocStd_Document) -> List[Tuple[str, TopoDS_Shape]]:
    """(name, shape) of the document's free shapes, in order."""
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    labels = LabelSequence()
    tool.GetFreeShapes(labels)
    out = []
    for i in range(1, labels.Length() + 1):
        label = labels.Value(i)
        out.append((_label_name(label) or f"item_{i}", tool.GetShape_s(label)))
    return out


_EXTERNAL = (b"DOCUMENT_FILE", b"EXTERNAL_SOURCE")     # STEP entities of references to other files


@contextmanager
def _private_copy(path, data: bytes) -> Iterator[str]:
    """OCCT reads the bytes that were validated: a private copy in the system's temporary
    folder (the file at ``path`` may be replaced between the check and OCCT's read).
    A STEP file referring to other files is read in place (its references resolve from
    its folder), as in the probe's child process, where the file already is the copy;
    so is a file whose copy cannot be written."""
    if os.environ.get(_PROBE_FLAG) or any(word in data for word in _EXTERNAL):
        yield os.fspath(path)
        return
    try:
        fd, name = tempfile.mkstemp(prefix="cagd-read-", suffix=Path(path).suffix[:16])
    except OSError:
        yield os.fspath(path)
        return
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
    except OSError:                       # no room for the copy: read the original
        os.unlink(name)
        yield os.fspath(path)
        return
    try:
        yield name
    finally:
        os.unlink(name)


def _is_file(path) -> bool:
    if not isinstance(path, (str, os.PathLike)) or not isinstance(os.fspath(path), str) or "\x00" in os.fspath(path):
        return False
    try:
        return Path(path).is_file()
    except (OSError, ValueError):
        return False


_PROBE_FLAG = "CAGD_OCC_READ_PROBE"     # set in the child process of _probe
PROBE_TIMEOUT = 600.0                   # seconds a child transfer may take (a hang guard only)


def _unread(model, kind: str) -> Tuple[Tuple[str, ...], int]:
    """("entity <number> (<type>): <reason>" for every entity OCCT's parser rejected or
    does not know, the number rejected). Unknown types are skipped by the transfer, and
    what refers to them goes missing (a misspelt B-spline type lost its item silently).
    Both have a report entity or an undefined-entity type: a model with neither (most
    files) is answered from OCCT's report list and a type count, without visiting
    every entity from Python."""
    out, errors = [], 0
    if not model.Reports(False).More() and not _has_undefined_type(model):
        return (), 0
    for i in range(1, model.NbEntities() + 1):
        if model.IsErrorEntity(i):
            errors += 1
            report = model.ReportEntity(i)
            check = report.Check()
            reason = check.CFail(1) if check.NbFails() else "not parsed"
            content = report.Content()
            what = content.StepType() if kind == "STEP" else f"type {content.TypeNumber()}"
            out.append(f"entity {i} ({what}): {reason}")
        elif model.IsUnknownEntity(i) or model.Value(i).DynamicType().Name().endswith("UndefinedEntity"):
            entity = model.Value(i)
            what = entity.StepType() if kind == "STEP" else f"type {entity.TypeNumber()}"
            out.append(f"entity {i} ({what}): an entity type OCCT does not read")
    return tuple(out), errors


def _has_undefined_type(model) -> bool:
    """Whether the model holds an entity of an undefined type (StepData_UndefinedEntity,
    IGESData_UndefinedEntity), by OCCT's own count of the entities' types."""
    counter = IFSelect_SignCounter(IFSelect_SignType(True), False, False)
    counter.AddModel(model)
    names = counter.List()
    return any(names.Value(i).ToCString().endswith("UndefinedEntity") for i in range(1, names.Length() + 1))


def _probe(path, kind: str, unread: Tuple[str, ...], shown: object = None) -> None:
    """Transfer the file in a child process; CagdError (naming ``shown``, the user's
    path) if OCCT dies there. Skipped
    where the interpreter is embedded (FreeCAD: sys.executable is not a Python); a
    child that cannot start (exit code, no signal) leaves the decision to the transfer."""
    if "python" not in Path(sys.executable).name.lower():
        return
    code = ("import sys; from cagd.occ.files import read_shapes; "
            "read_shapes(sys.argv[1], sys.argv[2].lower())")
    shown = path if shown is None else shown
    env = dict(os.environ, **{_PROBE_FLAG: "1"})
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if isinstance(p, str) and p)
    try:
        run = subprocess.run([sys.executable, "-c", code, os.fspath(path), kind], env=env, timeout=PROBE_TIMEOUT,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        raise CagdError(f"path: OCCT did not finish reading {kind} file {str(shown)!r} in {PROBE_TIMEOUT:g} s; "
                        f"{len(unread)} damaged entities, first {unread[0]}") from None
    except OSError:
        return
    if run.returncode < 0 or run.returncode > 128:
        raise CagdError(f"path: {kind} file {str(shown)!r} has {len(unread)} damaged entities that OCCT's "
                        f"transfer crashes on (signal {abs(run.returncode) % 128}); first: {unread[0]}")


def _can_fork() -> bool:
    """Whether the transfer can be tried in a forked copy of this process: Linux and a
    Python interpreter (not FreeCAD's embedded one, whose GUI threads must not be
    forked). A fork copies only the calling thread; it holds the GIL, and OCP keeps the
    GIL through OCCT calls, so no other thread is inside OCCT then (idle thread pools,
    numpy's BLAS workers, hold no lock the child's transfer needs)."""
    return sys.platform.startswith("linux") and hasattr(os, "fork") and \
        "python" in Path(sys.executable).name.lower()


def _transfer_forked(reader, doc, kind: str, unread: Tuple[str, ...],
                     shown: object) -> Optional[List[Tuple[str, TopoDS_Shape]]]:
    """The transfer of a model with damaged entities, made in a forked copy of this
    process (the model already parsed: no new interpreter, no second parse), whose free
    shapes come back in OCCT's binary BRep format (BinTools: geometry, locations,
    orientations, tolerances and shared sub-shapes as transferred), with their names:
    if OCCT dies there, only the copy dies. None where a fork cannot be used
    (:func:`_can_fork`; then the caller runs :func:`_probe` and transfers itself).
    CagdError if OCCT dies, hangs or fails there."""
    if not _can_fork():
        return None
    from OCP.BinTools import BinTools
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound, TopoDS_Iterator
    try:
        folder = tempfile.mkdtemp(prefix="cagd-transfer-")
    except OSError:
        return None
    shapes, names = os.path.join(folder, "shapes.brep"), os.path.join(folder, "names.json")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)    # 3.12+: "multi-threaded" (see _can_fork)
            pid = os.fork()
        if pid == 0:                                             # the child: transfer, write, nothing else
            code = 1
            try:
                import faulthandler
                faulthandler.disable()                           # a crash is an expected outcome
                null = os.open(os.devnull, os.O_WRONLY)
                os.dup2(null, 1)
                os.dup2(null, 2)
                code = _TRANSFER_FAILED
                if reader.Transfer(doc):
                    code = _NOT_WRITTEN
                    free = _free_shapes(doc)
                    compound, builder = TopoDS_Compound(), BRep_Builder()
                    builder.MakeCompound(compound)
                    for _, shape in free:
                        builder.Add(compound, shape)
                    if BinTools.Write_s(compound, shapes):
                        with open(names, "w", encoding="utf-8") as fh:
                            json.dump([name for name, _ in free], fh)
                        code = 0
            finally:
                os._exit(code)
        status = _wait(pid, kind, unread, shown)
        if os.WIFSIGNALED(status):
            raise CagdError(f"path: {kind} file {str(shown)!r} has {len(unread)} damaged entities that OCCT's "
                            f"transfer crashes on (signal {os.WTERMSIG(status)}); first: {unread[0]}")
        code = os.WEXITSTATUS(status)
        if code == _TRANSFER_FAILED:
            raise CagdError(f"path: OCCT could not read {kind} file {str(shown)!r}")
        if code == _NOT_WRITTEN:                          # the transfer survived there: make it here
            return _transfer_here(reader, doc, kind, shown)
        if code != 0:                                     # the copy failed before its transfer
            return None
        with open(names, encoding="utf-8") as fh:
            labels = json.load(fh)
        compound = TopoDS_Shape()
        if not BinTools.Read_s(compound, shapes):
            return _transfer_here(reader, doc, kind, shown)
        it, out = TopoDS_Iterator(compound), []
        while it.More():
            out.append(it.Value())
            it.Next()
        if len(out) != len(labels):
            return _transfer_here(reader, doc, kind, shown)
        return list(zip(labels, out))
    finally:
        for name in (shapes, names):
            if os.path.exists(name):
                os.unlink(name)
        os.rmdir(folder)


def _transfer_here(reader, doc, kind: str, shown: object) -> List[Tuple[str, TopoDS_Shape]]:
    """The transfer in this process, once the forked copy survived it."""
    if not reader.Transfer(doc):
        raise CagdError(f"path: OCCT could not read {kind} file {str(shown)!r}")
    return _free_shapes(doc)


_TRANSFER_FAILED, _NOT_WRITTEN = 3, 4        # exit codes of the forked transfer (0: written; a signal: died)


def _wait(pid: int, kind: str, unread: Tuple[str, ...], shown: object) -> int:
    """The forked copy's wait status; killed after PROBE_TIMEOUT (CagdError)."""
    deadline = time.monotonic() + PROBE_TIMEOUT
    try:
        fd = os.pidfd_open(pid)
    except (AttributeError, OSError):
        fd = -1
    try:
        while True:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                return status
            left = deadline - time.monotonic()
            if left <= 0:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                raise CagdError(f"path: OCCT did not finish reading {kind} file {str(shown)!r} in "
                                f"{PROBE_TIMEOUT:g} s; {len(unread)} damaged entities, first {unread[0]}")
            if fd >= 0:
                select.select([fd], [], [], left)
            else:
                time.sleep(min(0.01, left))
    finally:
        if fd >= 0:
            os.close(fd)


def _label_name(label: TDF_Label) -> str:
    attr = TDataStd_Name()
    if label.FindAttribute(TDataStd_Name.GetID_s(), attr):
        return attr.Get().ToExtString()
    return ""


def read_shapes(path: Union[str, os.PathLike], kind: str = "auto") -> List[Tuple[str, TopoDS_Shape]]:
    """(name, shape) of every top-level item of a STEP or IGES file (by extension
    unless ``kind`` is "step" or "iges"), lengths converted to mm. The file's structure
    is checked first (:func:`cagd._validate.validate_step` / ``validate_iges``): OCCT's
    readers die on some damaged files, which are a CagdError naming the problem here."""
    if not isinstance(kind, str):
        raise CagdError(f"kind: expected 'auto', 'step' or 'iges', got {kind!r}")
    kind = kind.lower()
    if kind == "auto":
        kind = "iges" if Path(path).suffix.lower() in IGES_SUFFIXES else "step"
    return _shapes(path, kind)[0]


def _shapes(path, kind: str) -> Tuple[List[Tuple[str, TopoDS_Shape]], Tuple[str, ...]]:
    if kind == "step":
        return _read(STEPCAFControl_Reader(), path, "STEP")
    if kind == "iges":
        # whole B-splines: by default OCCT's IGES reader splits curves at C0 knots into several edges
        return _read(IGESCAFControl_Reader(), path, "IGES", read__iges__bspline__continuity=0)
    raise CagdError(f"kind: expected 'auto', 'step' or 'iges', got {kind!r}")


def _objects(named: Iterable[Tuple[str, TopoDS_Shape]], approximate: Optional[float],
             unread: Tuple[str, ...] = (), defer_trims: bool = False) -> FileContents:
    """Faces -> surfaces; edges that bound no face -> curves; what does not convert is
    listed in ``skipped`` (and warned about), never dropped silently."""
    from .trim import shared_edges
    with shared_edges():                  # an edge of two faces: its 3-D curve converted once
        out, skipped = _convert(named, approximate, defer_trims)
    result = FileContents(tuple(out), tuple(skipped), unread)
    if skipped or unread:
        warnings.warn(f"read: {result.message}", RuntimeWarning, stacklevel=3)
    return result


def _convert(named: Iterable[Tuple[str, TopoDS_Shape]],
             approximate: Optional[float], defer_trims: bool = False) -> Tuple[List[Imported], List[Skipped]]:
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
                    found.append((from_occ(s, approximate=approximate, defer_trims=defer_trims), s))
                except CagdError as exc:
                    failed.append((kind, index, str(exc), s))
        if not faces and not free and not subshapes(shape, TopAbs_EDGE):
            failed.append(("item", 0, "holds no face and no curve: its geometry did not transfer (see unread, "
                                      "or the file's entities are inconsistent)", shape))
        many = len(found) + len(failed) > 1
        out += [Imported(f"{name}[{j}]" if many else name, obj, s) for j, (obj, s) in enumerate(found)]
        skipped += [Skipped(name, index, kind, reason, s) for kind, index, reason, s in failed]
    return out, skipped


def _seen(edge, found) -> bool:
    return any(s.IsSame(edge) for _, s in found)


def read_step(path: Union[str, os.PathLike], approximate: Optional[float] = None,
              defer_trims: bool = True) -> FileContents:
    """Every surface (face) and free curve (edge of no face) of a STEP file as an
    engine B-spline, with its name (see :class:`Imported`), in a :class:`FileContents`
    (iterable like a list). A face or edge that does not convert (an offset surface
    without ``approximate``, geometry OCCT cannot turn into a B-spline) is listed in
    ``skipped`` with the reason and a RuntimeWarning; every other one comes back.
    ``approximate``: as :func:`cagd.occ.from_occ` (a distance in model units within
    which OCCT may approximate offsets).

    ``defer_trims`` (default): a trimmed face's pcurves are converted and checked on
    the first use of its trim, not while reading (:func:`cagd.occ.from_occ`); reading a
    file then costs little more than OCCT's reader, and a trim found unusable warns
    when used. ``defer_trims=False`` converts every trim now (its warnings now)."""
    named, unread = _shapes(path, "step")
    return _objects(named, approximate, unread, defer_trims)


def read_iges(path: Union[str, os.PathLike], approximate: Optional[float] = None,
              defer_trims: bool = True) -> FileContents:
    """As :func:`read_step`, for IGES files."""
    named, unread = _shapes(path, "iges")
    return _objects(named, approximate, unread, defer_trims)


#: file name endings read as STEP and as IGES (any case)
STEP_SUFFIXES = (".step", ".stp")
IGES_SUFFIXES = (".iges", ".igs")


def read_cad(path: Union[str, os.PathLike], approximate: Optional[float] = None,
             defer_trims: bool = True) -> FileContents:
    """:func:`read_step` or :func:`read_iges`, by the file's ending (.step/.stp,
    .iges/.igs, any case).

    Raises:
        CagdError: another ending; as read_step / read_iges."""
    suffix = Path(path).suffix.lower()
    if suffix in STEP_SUFFIXES:
        return read_step(path, approximate, defer_trims)
    if suffix in IGES_SUFFIXES:
        return read_iges(path, approximate, defer_trims)
    raise CagdError(f"path: {str(path)!r} is not a .step/.stp/.iges/.igs file")
