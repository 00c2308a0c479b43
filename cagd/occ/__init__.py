"""The bridge to OpenCascade (through OCP, from the ``cadquery-ocp`` wheel).

Every engine curve and surface goes to OCCT B-spline geometry through its exact
NURBS form (``to_nurbs().occ_form()``) and comes back from any geometry OCCT can
convert to a B-spline; shapes (edges, wires, faces, shells, solids; CadQuery's and
build123d's shapes are taken wherever a shape is, see :mod:`.wrapped`), STEP and IGES
files, and :func:`verify`, the round-trip proof (engine vs OCCT, vs STEP, vs IGES).

Only this subpackage imports OCP; ``import cagd`` never does.
"""
try:
    import OCP  # noqa: F401
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ModuleNotFoundError("cagd.occ needs OCP (OpenCascade for Python): pip install 'cagd[cad]' "
                              "or pip install cadquery-ocp", name="OCP") from exc

from OCP.Message import Message, Message_Gravity

for _printer in Message.DefaultMessenger_s().Printers():    # OCCT's transfer chatter, as CadQuery does
    _printer.SetTraceLevel(Message_Gravity.Message_Fail)

from .convert import from_occ, to_occ  # noqa: E402
from .trim import make_trimmed_face  # noqa: E402
from .shapes import (area, check_valid, free_edge_count, make_edge, make_face, make_solid,  # noqa: E402
                     make_wire, sew, sewing, solid_from_surfaces, subshapes, volume)
from .files import (FileContents, Imported, Skipped, read_cad, read_iges, read_shapes, read_step,  # noqa: E402
                    write_iges, write_step)
from .verify import STAGES, StageResult, VerifyReport, verify  # noqa: E402
from .wrapped import occ_shape  # noqa: E402

__all__ = [
    "to_occ", "from_occ", "make_trimmed_face",
    "make_edge", "make_wire", "make_face", "sew", "sewing", "make_solid", "solid_from_surfaces",
    "check_valid", "free_edge_count", "subshapes", "area", "volume", "write_step", "read_step", "write_iges",
    "read_iges", "read_cad", "read_shapes", "Imported", "Skipped", "FileContents", "verify", "VerifyReport",
    "StageResult", "STAGES", "occ_shape",
]
