"""``cagd export``: a model (cagd.model) to STEP and IGES, with the round-trip report.

Curves become edges, surfaces faces with natural bounds (the exact NURBS form:
``make_face(nurbs=True)``, as the files get it), trimmed surfaces faces bounded by their
loops (:func:`cagd.occ.make_trimmed_face`, checked for area and classification by
:func:`cagd.occ.verify`'s trim stages), and entries marked
``"solid": true`` are sewn into closed solids (BRepBuilderAPI_Sewing, then
BRepCheck). Every object is put through :func:`cagd.occ.verify`; every solid's
volume by OCCT is compared with the engine's own quadrature
(:func:`cagd.surfaces.properties.enclosed_volume`); the written files are read
back and their faces and free edges counted.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional, Tuple

from OCP.TopAbs import TopAbs_FACE

from .._atomic import check_target, write_files
from .._progress import Progress
from ..errors import CagdError
from ..model.loader import Entry, Model
from ..surfaces.base import Surface
from ..surfaces.properties import enclosed_volume
from .files import iges_bytes, read_iges, read_step, step_bytes
from .shapes import check_valid, make_edge, make_face, solid_from_surfaces, subshapes, volume
from .verify import VerifyReport, verify


@dataclass
class SolidCheck:
    """A solid built from an entry: validity and volume by OCCT and by the engine."""
    name: str
    faces: int
    valid: bool
    volume_occt: float
    volume_engine: float
    volume_error: float          # the engine quadrature's error estimate
    volume_exact: Optional[float] = None   # closed form, where the entry's type has one

    @property
    def relative_difference(self) -> float:
        """|OCCT - engine| / engine."""
        return abs(self.volume_occt - abs(self.volume_engine)) / max(abs(self.volume_engine), 1e-300)

    @property
    def exact_difference(self) -> Optional[float]:
        """|engine - closed form| / closed form."""
        if self.volume_exact is None:
            return None
        return abs(abs(self.volume_engine) - self.volume_exact) / self.volume_exact


def closed_form_volume(entry: Entry) -> Optional[float]:
    """4/3 pi a b c (ellipsoid), 4/3 pi r^3 (sphere), 2 pi^2 R r^2 (torus); else None."""
    src = entry.source
    if entry.type == "ellipsoid":
        return 4.0 / 3.0 * math.pi * src["a"] * src["b"] * src["c"]
    if entry.type == "sphere":
        return 4.0 / 3.0 * math.pi * src["radius"] ** 3
    if entry.type == "torus":
        return 2.0 * math.pi ** 2 * src["R"] * src["r"] ** 2
    return None


@dataclass
class ExportResult:
    """What :func:`export_model` wrote and measured."""
    model_name: str
    step: Optional[Path]
    iges: Optional[Path]
    reports: List[VerifyReport] = field(default_factory=list)
    solids: List[SolidCheck] = field(default_factory=list)
    read_back: List[Tuple[str, int, int, int]] = field(default_factory=list)   # file, items, faces, edges
    expected: Tuple[int, int] = (0, 0)                                            # faces, free curves
    volume_tol: float = 1e-9

    @property
    def passed(self) -> bool:
        files_ok = all((faces, edges) == self.expected for _, _, faces, edges in self.read_back)
        return (all(r.passed for r in self.reports) and files_ok
                and all(s.valid and s.relative_difference <= self.volume_tol
                        and (s.exact_difference or 0.0) <= self.volume_tol for s in self.solids))

    def to_markdown(self) -> str:
        """The report: solids, the round trip of every object, the files read back."""
        out = [f"# cagd export report: {self.model_name}", ""]
        out += [f"- STEP: `{self.step}`" if self.step else "- STEP: not written",
                f"- IGES: `{self.iges}`" if self.iges else "- IGES: not written",
                f"- verdict: {'**all checks passed**' if self.passed else '**FAILED**'}", ""]
        if self.solids:
            out += ["## Solids", "", "| solid | faces | valid (BRepCheck) | volume, OCCT | volume, engine "
                    "quadrature | OCCT vs engine | closed form | engine vs closed form |",
                    "|---|---|---|---|---|---|---|---|"]
            for s in self.solids:
                exact = "" if s.volume_exact is None else f"{s.volume_exact:.10g} | {s.exact_difference:.1e}"
                out.append(f"| {s.name} | {s.faces} | {'yes' if s.valid else '**NO**'} | {s.volume_occt:.10g} | "
                           f"{abs(s.volume_engine):.10g} | {s.relative_difference:.1e} | {exact or '- | -'} |")
            out.append("")
        out += ["## Round trip (cagd.occ.verify)", "",
                "Max deviation relative to the object's size (points) or to the largest derivative "
                "of that order (derivatives); unit normals absolute.", ""]
        for k, r in enumerate(self.reports):
            out.append(r.to_markdown(header=k == 0))
        out += ["", "## Files read back", "", "| file | items | faces | free curves | expected |",
                "|---|---|---|---|---|"]
        out += [f"| {f} | {n} | {fa} | {ed} | {self.expected[0]} faces, {self.expected[1]} curves |"
                for f, n, fa, ed in self.read_back]
        return "\n".join(out) + "\n"


def export_model(model: Model, step: Optional[Path] = None, iges: Optional[Path] = None, samples: int = 41,
                 progress: bool = True, tol: Optional[float] = None, file_tol: float = 1e-9,
                 volume_tol: float = 1e-9, report: Optional[Path] = None) -> ExportResult:
    """Write the exported entries of a loaded model (:func:`cagd.model.load_model`) to
    STEP and/or IGES (and the Markdown report to ``report`` if given), verify every
    object and solid, read the files back. All or nothing: every output is checked
    before any work, and the files are written to temporaries (read back from there)
    and renamed over their targets only when all are complete (:mod:`cagd._atomic`).

    Raises:
        CagdError: an entry that cannot become a shape (e.g. surfaces marked solid
            that do not close), an object the check cannot measure, or a file that
            cannot be written (no file is changed then).
    """
    outputs = [(p, w) for p, w in ((step, "step"), (iges, "iges"), (report, "report")) if p is not None]
    resolved = [os.path.realpath(check_target(p, what)) for p, what in outputs]
    if len(set(resolved)) != len(resolved):
        raise CagdError(f"{', '.join(w for _, w in outputs)}: two outputs name the same file")
    entries = model.exported()
    objects = [(label, obj) for e in entries for label, obj in e.labels()]
    work = Progress(len(objects) + len(entries) + 2, enabled=progress)
    result = ExportResult(model.name or "model", step, iges, volume_tol=volume_tol)
    items, faces, curves = [], 0, 0
    for e in entries:
        try:
            if e.solid:
                solid = solid_from_surfaces(e.objects, nurbs=True)
                vol = enclosed_volume(e.objects)
                result.solids.append(SolidCheck(e.name, len(subshapes(solid, TopAbs_FACE)), check_valid(solid),
                                                volume(solid), vol.value, vol.error, closed_form_volume(e)))
                items.append((e.name, solid))
                faces += len(e.objects)
            else:
                for label, obj in e.labels():
                    items.append((label, make_edge(obj) if e.kind == "curve" else make_face(obj, nurbs=True)))
                    faces, curves = faces + (e.kind != "curve"), curves + (e.kind == "curve")
        except CagdError as exc:                           # e.g. coordinates beyond OCCT's range
            raise CagdError(f"model: entry {e.name!r}: {exc}") from None
        work.step(f"shape {e.name}")
    if not items:
        raise CagdError("model: no entry is exported")
    result.expected = (faces, curves)
    for label, obj in objects:
        try:
            result.reports.append(verify(obj, label, samples, tol=tol, file_tol=file_tol))
        except CagdError as exc:                           # e.g. a domain 1e-300 wide
            raise CagdError(f"model: entry {label!r} cannot be checked: {exc}") from None
        work.step(f"verify {label}")
    files = []
    for path, to_bytes, read in ((step, step_bytes, read_step), (iges, iges_bytes, read_iges)):
        if path is not None:
            files.append((path, _written(to_bytes(items, target=str(path)), read, Path(path).name, result),
                          "step" if read is read_step else "iges"))
        work.step(f"write {Path(path).name if path else '-'}")
    if report is not None:
        files.append((report, lambda temp: temp.write_text(result.to_markdown(), encoding="utf-8"), "report"))
    write_files(files)
    return result


def _written(data: bytes, read, name: str, result: ExportResult):
    """Write ``data`` to the temporary file and read it back from there, before the
    rename: the counts in the report are those of the bytes that become the file."""
    def write(temp: Path) -> None:
        temp.write_bytes(data)
        back = read(temp)
        n_faces = sum(1 for b in back if isinstance(b.object, Surface))   # a TrimmedSurface too
        result.read_back.append((name, len(back), n_faces, len(back) - n_faces))
    return write
