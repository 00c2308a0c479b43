"""The one place that knows which OCP (OpenCascade for Python) is installed.

OCCT 7.9 (``cadquery-ocp`` 7.9, with CadQuery 2.8) exposes its collection classes
under their C++ typedef names (``TColgp_Array1OfPnt``, ``TColStd_Array1OfReal``,
``TopTools_IndexedDataMapOfShapeListOfShape``, ...). OCCT 8.0 (``cadquery-ocp`` 8.0,
with build123d 0.13) dropped those typedefs: the same NCollection templates live in
``OCP.collections`` as ``Array1_gp_Pnt``, ``Array1_double``, ... and ``OCP.TColgp``
is empty. Everything else the bridge uses is the same in both. The bridge and
``cq_ext`` import collections from here only, under the neutral names below.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import OCP
from OCP.TopoDS import TopoDS as _TopoDS

VERSION: str = getattr(OCP, "__version__", "0")
"""The OCP wheel's version, e.g. ``"7.9.3.1"`` or ``"8.0.1.1"``."""
MAJOR: int = int(VERSION.split(".")[0]) if VERSION.split(".")[0].isdigit() else 0

if TYPE_CHECKING:
    # OCP ships no stubs, so to mypy every OCP class is Any; declaring the neutral names
    # once keeps it from seeing the two layouts below as redefinitions.
    Array1OfPnt: Any
    Array1OfPnt2d: Any
    Array2OfPnt: Any
    Array1OfInteger: Any
    Array1OfReal: Any
    Array2OfReal: Any
    LabelSequence: Any
    IndexedDataMapOfShapeListOfShape: Any
    ListOfShape: Any
else:
    try:                                    # OCCT 7.x: the typedef names
        from OCP.TColgp import TColgp_Array1OfPnt as Array1OfPnt
        from OCP.TColgp import TColgp_Array1OfPnt2d as Array1OfPnt2d
        from OCP.TColgp import TColgp_Array2OfPnt as Array2OfPnt
        from OCP.TColStd import TColStd_Array1OfInteger as Array1OfInteger
        from OCP.TColStd import TColStd_Array1OfReal as Array1OfReal
        from OCP.TColStd import TColStd_Array2OfReal as Array2OfReal
        from OCP.TDF import TDF_LabelSequence as LabelSequence
        from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape as IndexedDataMapOfShapeListOfShape
        from OCP.TopTools import TopTools_ListOfShape as ListOfShape
    except ImportError:                     # OCCT 8: the templates in OCP.collections
        from OCP.collections import Array1_double as Array1OfReal
        from OCP.collections import Array1_gp_Pnt as Array1OfPnt
        from OCP.collections import Array1_gp_Pnt2d as Array1OfPnt2d
        from OCP.collections import Array1_int as Array1OfInteger
        from OCP.collections import Array2_double as Array2OfReal
        from OCP.collections import Array2_gp_Pnt as Array2OfPnt
        from OCP.collections import (
            IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as IndexedDataMapOfShapeListOfShape)
        from OCP.collections import List_TopoDS_Shape as ListOfShape
        from OCP.collections import Sequence_TDF_Label as LabelSequence


def _cast(kind: str) -> Any:
    """OCCT 7: the static ``TopoDS::Face`` is ``TopoDS.Face_s``; OCCT 8 made TopoDS a
    namespace, so it is ``TopoDS.Face``."""
    return getattr(_TopoDS, kind + "_s", None) or getattr(_TopoDS, kind)


as_vertex, as_edge, as_wire, as_face = _cast("Vertex"), _cast("Edge"), _cast("Wire"), _cast("Face")
as_shell, as_solid, as_compound = _cast("Shell"), _cast("Solid"), _cast("Compound")

__all__ = ["as_vertex", "as_edge", "as_wire", "as_face", "as_shell", "as_solid", "as_compound", "VERSION", "MAJOR",
           "Array1OfPnt", "Array1OfPnt2d", "Array2OfPnt", "Array1OfInteger", "Array1OfReal", "Array2OfReal",
           "LabelSequence", "IndexedDataMapOfShapeListOfShape", "ListOfShape"]
