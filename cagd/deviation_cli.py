"""``cagd deviation MODEL points.csv -o report.md``: the signed distances of a point
cloud (a scan, measured points) from a model's surfaces (or curves), their
statistics and a colour-map PNG. MODEL is a JSON model (cagd.model) or a STEP/IGES
file (read through cagd.occ). Exit codes: 0 done, 2 bad input."""
from __future__ import annotations

import argparse
import codecs
import io
import re
import sys
import warnings
from array import array
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterator, List, Optional, Sequence, TextIO, Tuple, Union

import numpy as np

from .curves.base import Curve
from .errors import CagdError
from .surfaces.base import Surface

if TYPE_CHECKING:
    from .queries.deviation import Deviation

#: Bytes per read when checking the CSV's encoding (the file is never held whole).
_READ_BYTES = 1 << 20
#: Decoded text kept from the start of the file to find a header and the separator.
_HEAD_CHARS = 1 << 16


def read_points(path: Path) -> np.ndarray:
    """(N, 2 or 3) points from a CSV file: comma, semicolon or whitespace separated; a
    first line that is not numbers is a header.

    Read in chunks (issue 14: a 10^7-row file was read whole, as bytes and as text,
    before parsing): the UTF-8 check streams _READ_BYTES at a time, numpy's C parser
    reads the file itself, and a file it refuses is read line by line into a compact
    array of doubles. Memory O(N) floats, not the file's size in Python objects.

    Raises:
        CagdError: no points, ragged rows, non-numbers (naming the line), NaN/inf, not UTF-8.
    """
    head = _check_utf8(Path(path))
    pts = _fast_points(path, head)
    if pts is None:
        pts = _checked_points(path)
    if not np.all(np.isfinite(pts)):
        raise CagdError("points: contains NaN or inf")
    return pts


def _check_utf8(path: Path) -> str:
    """The first _HEAD_CHARS characters of the file after checking that all of it is
    UTF-8 (an incremental decoder over chunks of _READ_BYTES)."""
    decoder = codecs.getincrementaldecoder("utf-8-sig")()
    head: List[str] = []
    kept = lines = 0
    try:
        with open(path, "rb") as f:
            while True:
                chunk = f.read(_READ_BYTES)
                try:
                    text = decoder.decode(chunk, final=not chunk)
                except UnicodeDecodeError as exc:
                    at = lines + chunk.count(b"\n", 0, max(exc.start, 0)) + 1
                    bad = chunk[exc.start] if 0 <= exc.start < len(chunk) else 0
                    raise CagdError(f"points: {path} is not UTF-8 text (byte {bad:#04x} on line {at})") from None
                if kept < _HEAD_CHARS:
                    head.append(text[:_HEAD_CHARS - kept])
                    kept += len(head[-1])
                lines += chunk.count(b"\n")
                if not chunk:
                    break
    except OSError as exc:
        raise CagdError(f"points: cannot read {str(path)!r}: {exc.strerror or exc}") from None
    return "".join(head)


def _fast_points(path: Path, content: str) -> Optional[np.ndarray]:
    """numpy's C parser (np.loadtxt, reading the file in chunks) for a well-formed file:
    O(n) memory, no Python loop per line; None when it refuses the file, which
    :func:`_checked_points` then reads line by line to name the offending line.
    ``content`` is the start of the file (the header and the first data line)."""
    head = re.match(r"[^\r\n]*", content).group().strip()        # type: ignore[union-attr]
    header = bool(head) and not head.startswith("#") and not _numbers(head)
    data = ""
    for k, m in enumerate(re.finditer(r"[^\r\n]+", content)):     # lazily: stops at the first data line
        text = m.group().strip()
        if (k or not header) and text and not text.startswith("#"):
            data = text
            break
    sep = ";" if ";" in data else "," if "," in data else None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")                  # loadtxt warns on an empty file
            pts = np.loadtxt(path, delimiter=sep, comments="#", skiprows=int(header), ndmin=2, dtype=np.float64,
                             encoding="utf-8-sig")
    except (ValueError, UserWarning):
        return None
    return pts if pts.shape[0] > 0 and pts.shape[1] in (2, 3) else None


def _numbers(text: str) -> bool:
    try:
        [float(f) for f in re.split("[,; \t]+", text) if f]
    except ValueError:
        return False
    return True


def _checked_points(path: Path) -> np.ndarray:
    """The file line by line (streamed, the values in a compact array of doubles),
    naming the first offending line."""
    values = array("d")
    width = 0
    count = 0
    with open(path, encoding="utf-8-sig", newline="") as f:
        for number, line in enumerate(_lines(f), 1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            if "," in text or ";" in text:
                fields = [x.strip() for x in re.split("[,;]", text)]
                if any(not x for x in fields):
                    raise CagdError(f"points: line {number} has an empty field: {text[:60]!r}")
            else:
                fields = text.split()
            try:
                row = [float(x) for x in fields]
            except ValueError:
                if not count and number == 1:
                    continue                                  # a header
                raise CagdError(f"points: line {number} is not numbers: {text[:60]!r}") from None
            if not count:
                width = len(row)
            if len(row) != width or len(row) not in (2, 3):
                raise CagdError(f"points: line {number} has {len(row)} values; every line needs the same "
                                "2 or 3 coordinates")
            values.extend(row)
            count += 1
    if not count:
        raise CagdError(f"points: {path} holds no points")
    return np.frombuffer(values, dtype=np.float64).reshape(count, width).copy()


def _lines(f: TextIO) -> Iterator[str]:
    """Lines split at \\r\\n, \\n or \\r (as a split of the whole text), read lazily
    (the file opened with newline="" keeps every line ending)."""
    for raw in f:
        parts = re.split(r"\r\n|\n|\r", raw)
        if parts and parts[-1] == "":
            parts.pop()
        yield from parts


def model_objects(path: Path, names: Optional[Sequence[str]]) -> Tuple[str, List[Tuple[str, Union[Curve, Surface]]]]:
    """(description, [(name, object)]): the selected entries of a JSON model, or the
    faces (else the free curves) of a STEP/IGES file."""
    suffix = path.suffix.lower()
    items: List[Tuple[str, Union[Curve, Surface]]]
    if suffix in (".step", ".stp", ".igs", ".iges"):
        from .occ import read_cad
        items = [(i.name, i.object) for i in read_cad(path)]
    else:
        from .model import load_model
        model = load_model(path)
        entries = [model[n] for n in names] if names else model.exported()
        items = [(label, obj) for e in entries for label, obj in e.labels()]
        names = None
    if names:
        wanted = set(names)
        items = [(n, o) for n, o in items if n in wanted or n.split("[")[0] in wanted]
    surfaces = [(n, o) for n, o in items if hasattr(o, "rectangular")]
    chosen = surfaces or items
    if not chosen:
        raise CagdError(f"model: {path} holds nothing to measure against")
    return str(path), chosen


def _picture_formats() -> Tuple[str, ...]:
    """The file extensions matplotlib can write (png, pdf, svg, ...)."""
    from matplotlib.backend_bases import FigureCanvasBase
    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


#: rows formatted at once by write_point_table (the text of 10^7 rows would be ~1.5 GB)
TABLE_CHUNK = 1 << 16

#: the per-point CSV is written by default (beside the report) only up to this many points
#: (~15 MB); a larger scan needs ``--csv PATH`` (an explicit request) and ``--no-csv`` skips it
TABLE_DEFAULT_POINTS = 100_000


def write_point_table(path: Path, pts: np.ndarray, result: "Deviation", workers: int = 1) -> None:
    """The per-point CSV: x, y[, z], face (index of the nearest object), distance (signed
    where the report says so), certified lower bound, foot; streamed TABLE_CHUNK rows at
    a time, every value with 17 significant digits (round-trips the doubles). With
    ``workers`` > 1 the blocks are formatted in that many processes (issue 16: the text
    of 10^7 rows took a minute), written in order: the same bytes."""
    from ._parallel import ordered_map
    dim = pts.shape[1]
    axes = "xyz"[:dim]
    head = ",".join([*axes, "face", "distance", "lower_bound", *(f"foot_{a}" for a in axes)])
    owner = np.zeros(len(pts), dtype=np.int64) if result.owner is None else result.owner
    fmt = ",".join(["%.17g"] * dim + ["%d"] + ["%.17g"] * (2 + dim))
    starts = range(0, len(pts), TABLE_CHUNK)
    blocks = (np.column_stack([pts[sl], owner[sl], result.distances[sl], result.lower_bounds[sl], result.feet[sl]])
              for sl in (slice(s, s + TABLE_CHUNK) for s in starts))
    with open(path, "wb") as f:
        f.write(head.encode() + b"\n")
        for text in ordered_map(_table_rows, fmt, blocks, max(1, min(workers, len(starts))),
                                name=lambda k: f"rows {starts[k] + 1} to {min(starts[k] + TABLE_CHUNK, len(pts))}"):
            f.write(text)


def _table_rows(fmt: str, block: np.ndarray) -> bytes:
    """The CSV text of the rows of ``block`` (np.savetxt with ``fmt``, lines ending in \\n)."""
    out = io.BytesIO()
    np.savetxt(out, block, fmt=fmt)
    return out.getvalue()


def _progress_bar(count: int, wanted: Optional[bool]) -> Callable[[int, int], None]:
    """The ``progress`` callback of :func:`cagd.queries.deviation.deviation` drawing a bar
    on stderr (one step per chunk of DEVIATION_CHUNK points); shown when ``wanted``, or
    when None and stderr is a terminal."""
    from ._progress import Progress
    from .queries.deviation import DEVIATION_CHUNK
    bar = Progress(-(-count // DEVIATION_CHUNK), enabled=sys.stderr.isatty() if wanted is None else wanted)

    def step(done: int, total: int) -> None:
        bar.step(f"{done:,} of {total:,} points measured")
    return step


def run_deviation(args: argparse.Namespace) -> int:
    """The command; its outputs (report and colour map) are checked before any work and
    written all or nothing (:mod:`cagd._atomic`)."""
    from ._atomic import Output, check_target, write_files
    from ._parallel import checked_workers
    from .queries.deviation import deviation, deviation_map
    try:
        workers = checked_workers(args.workers, "--workers")
        check_target(args.output, "--output")
        if args.png is not None and args.no_png:
            raise CagdError("--png and --no-png: give one of them")
        if args.csv is not None and args.no_csv:
            raise CagdError("--csv and --no-csv: give one of them")
        table: Optional[Path] = None if args.no_csv else (args.csv or args.output.with_suffix(".points.csv"))
        if table is not None:
            check_target(table, "--csv")
        png: Optional[Path] = None if args.no_png else (args.png or args.output.with_suffix(".png"))
        if png is not None:
            check_target(png, "--png")
            from ._optional import require
            try:
                require("matplotlib", "--png")
            except CagdError as exc:
                raise CagdError(f"{exc}; or pass --no-png") from None
            formats = _picture_formats()
            if png.suffix.lower().lstrip(".") not in formats:
                raise CagdError(f"--png {png}: unknown picture type {png.suffix!r} (one of: {', '.join(formats)})")
        where, items = model_objects(args.model, args.object)
        pts = read_points(args.points)
        objects = [o for _, o in items]
        if pts.shape[1] != objects[0].dim:
            raise CagdError(f"points: {pts.shape[1]}-D points against {objects[0].dim}-D geometry")
        result = deviation(objects, pts, workers=workers, progress=_progress_bar(len(pts), args.progress))
    except KeyError as exc:
        print(f"cagd deviation: --object {exc.args[0]}: no such entry in {args.model}", file=sys.stderr)
        return 2
    if table is not None and args.csv is None and len(pts) > TABLE_DEFAULT_POINTS:
        table = None
        table_line = (f"- per point: not written ({len(pts)} points > {TABLE_DEFAULT_POINTS} written by default; "
                      f"give --csv PATH to write them)")
    elif table is None:
        table_line = "- per point: not written (--no-csv)"
    else:
        table_line = (f"- per point: `{table}` (x, y, z, face, distance, lower bound, foot x, y, z; face k is the "
                      f"k-th object: " + ", ".join(f"{k} = {n}" for k, (n, _) in enumerate(items)) + ")")
    gap = float(np.max(np.abs(result.distances) - result.lower_bounds))
    assert result.owner is not None                     # deviation() of a list says which object is nearest
    nearest = np.bincount(result.owner, minlength=len(items))
    lines = [f"# Deviation of {args.points.name} from {args.model.name}", "",
             f"- model: `{where}`; measured against {len(items)} object(s): "
             + ", ".join(f"{n} ({k} points)" for (n, _), k in zip(items, nearest)),
             f"- points: {len(pts)}; distances are global closest-point distances "
             f"({'signed along the surface normal' if result.signed else 'unsigned'}), certified to within "
             f"{gap:.2g} (largest distance - certified lower bound)",
             f"- colour map: `{png}`" if png is not None else "- colour map: not drawn (--no-png)",
             table_line, "", result.table(), ""]
    outputs: List[Output] = []
    if png is not None:
        outputs.append((png, lambda temp: deviation_map(objects, pts, temp, result, title=args.model.name), "--png"))
    if table is not None:
        outputs.append((table, lambda temp: write_point_table(temp, pts, result, workers), "--csv"))
    outputs.append((args.output, "\n".join(lines), "--output"))
    write_files(outputs)
    print("\n".join(lines))
    return 0
