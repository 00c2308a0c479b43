"""Checks made before a file is handed to OCCT, and of the names written into files.

OCCT's readers trust their input: its IGES reader dies (SIGSEGV) on a truncated file,
a parameter section that does not match the directory, or a missing directory
section, and its STEP parser on deeply nested parentheses (issue 14). These checks
are structural only (no geometry): a file that passes may still be rejected by OCCT,
but with an error, not a crash. Pure Python and numpy: no OCCT needed.

Sources: IGES 5.3 (US PRO, 1996) chapter 2 (fixed 80-column records; Start, Global,
Directory Entry, Parameter Data and Terminate sections in that order, each numbered
from 1; two directory records per entity; the terminate record counts the records
of each section); ISO 10303-21 (clear text encoding: ``ISO-10303-21;``, a HEADER
and a DATA section each closed by ``ENDSEC;``, ``END-ISO-10303-21;``).
"""
from __future__ import annotations

import os
import re
import unicodedata
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .errors import CagdError

MAX_NAME_LENGTH = 255      # characters of an object name written to a file or read from a model
MAX_NESTING = 200          # parentheses nesting depth of a STEP file (real files need < 20)
IGES_RECORD = 80           # columns of an IGES record
IGES_SECTIONS = "SGDPT"    # the sections of an ASCII IGES file, in order
_STEP_SKIP = re.compile(rb"'[^']*'|/\*.*?\*/", re.S)       # strings ('' inside is two strings) and comments
_IGES_INT = re.compile(r"^\s*[+-]?\d*\s*$", re.ASCII)   # the format's digits are ASCII
_IGES_NUMBER = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([EeDd][+-]?\d+)?\s*$")
_IGES_HOLLERITH = re.compile(r"\s*(\d+)H")
# entity types whose parameters are numbers and pointers only (IGES 5.3 chapter 4: curves and
# surfaces 100-199, B-rep topology 502-514); a string there shifts every later field (OCCT: SIGSEGV)
_IGES_NUMERIC = tuple(range(100, 200)) + (502, 504, 508, 510, 514)


def check_name(value: Any, what: str = "name") -> str:
    """A name as it goes into a file (a STEP product name, an IGES label, a model entry):
    a non-empty str of at most MAX_NAME_LENGTH characters, without control characters
    (a newline breaks IGES records), lone surrogates (not encodable) or leading and
    trailing spaces.

    Raises:
        CagdError: naming ``what`` and the problem.
    """
    if not isinstance(value, str):
        raise CagdError(f"{what}: must be a string, got {type(value).__name__}")
    if not value.strip() or value != value.strip():
        raise CagdError(f"{what}: must be a non-empty name without leading/trailing spaces, got {value[:40]!r}")
    if len(value) > MAX_NAME_LENGTH:
        raise CagdError(f"{what}: {len(value)} characters, at most {MAX_NAME_LENGTH} allowed")
    for i, ch in enumerate(value):
        cat = unicodedata.category(ch)
        if cat == "Cs":
            raise CagdError(f"{what}: lone surrogate {ch!r} at position {i} (not a Unicode character)")
        if cat == "Cc" or ch in "\u2028\u2029":
            raise CagdError(f"{what}: control character {ch!r} at position {i} (names are one line of text)")
    return value


def read_bytes(path: Any, kind: str) -> bytes:
    """The bytes of a file to validate; CagdError naming it if it cannot be read."""
    return _read_bytes(path, kind)


def _read_bytes(path: Any, kind: str) -> bytes:
    try:
        with open(os.fspath(path), "rb") as fh:
            return fh.read()
    except (OSError, ValueError) as exc:
        raise CagdError(f"path: cannot read {kind} file {str(path)!r}: {getattr(exc, 'strerror', None) or exc}") \
            from None


def validate_step(path: Any, data: Optional[bytes] = None) -> None:
    """The ISO 10303-21 structure of a STEP file: the ``ISO-10303-21;`` start, a HEADER
    and a DATA section closed by ``ENDSEC;``, the ``END-ISO-10303-21;`` end, strings and
    comments closed, parentheses balanced within every entity and nested at most
    MAX_NESTING deep. ``data``: the file's bytes when already read (``path`` then
    only names the file in messages).

    Raises:
        CagdError: naming the file and the first problem found.
    """
    data = _read_bytes(path, "STEP") if data is None else data
    where = f"path: STEP file {str(path)!r}"
    text = _STEP_SKIP.sub(b"", data)
    stray = re.search(rb"'|/\*", text)
    if stray:
        raise CagdError(f"{where}: an unterminated string or comment at byte {stray.start()} (file truncated?)")
    body = text.lstrip(b"\xef\xbb\xbf \t\r\n")
    if not body.startswith(b"ISO-10303-21;"):
        raise CagdError(f"{where}: does not start with ISO-10303-21; (not a STEP file)")
    if not body.rstrip().endswith(b"END-ISO-10303-21;"):
        raise CagdError(f"{where}: does not end with END-ISO-10303-21; (file truncated?)")
    header, data_at = body.find(b"HEADER;"), body.find(b"DATA;")
    if header < 0 or data_at < header:
        raise CagdError(f"{where}: no HEADER; section before the DATA; section")
    if not 0 <= body.find(b"ENDSEC;", header) < data_at:
        raise CagdError(f"{where}: the HEADER section is not closed by ENDSEC; before DATA;")
    if body.rfind(b"ENDSEC;") < data_at:
        raise CagdError(f"{where}: the DATA section is not closed by ENDSEC; (file truncated?)")
    arr = np.frombuffer(body, dtype=np.uint8)
    marks = np.flatnonzero((arr == ord("(")) | (arr == ord(")")) | (arr == ord(";")))
    chars = arr[marks]
    step = np.where(chars == ord("("), 1, np.where(chars == ord(")"), -1, 0)).astype(np.int32)
    depth = np.cumsum(step)
    if depth.size and int(depth.max()) > MAX_NESTING:
        at = int(marks[int(np.argmax(depth > MAX_NESTING))])
        raise CagdError(f"{where}: parentheses nested more than {MAX_NESTING} deep (at byte {at})")
    if depth.size and int(depth.min()) < 0:
        at = int(marks[int(np.argmax(depth < 0))])
        raise CagdError(f"{where}: a ')' without its '(' at byte {at}")
    open_end = (chars == ord(";")) & (depth != 0)
    if open_end.any():
        at = int(marks[int(np.argmax(open_end))])
        raise CagdError(f"{where}: an entity ends with unclosed parentheses at byte {at}")


def _digits(text: str) -> bool:
    """ASCII digits only (``str.isdigit`` also takes superscripts, which ``int`` refuses)."""
    return text.isascii() and text.isdigit()


def _fields(line: str, count: int) -> List[int]:
    """The first ``count`` 8-column integer fields of a directory record (blank: 0)."""
    out = []
    for k in range(count):
        cell = line[8 * k:8 * k + 8]
        if not _IGES_INT.match(cell):
            raise ValueError(f"field {k + 1} {cell.strip()!r} is not an integer")
        cell = cell.strip()
        out.append(int(cell) if cell not in ("", "+", "-") else 0)
    return out


def _delimiters(glob: str) -> Tuple[str, str]:
    """The parameter and record delimiters declared at the start of the global section
    (IGES 5.3 section 2.2.4: ``1H,`` and ``1H;``, or defaulted)."""
    pd, rest = ",", glob
    if rest.startswith("1H"):
        pd, rest = rest[2:3], rest[3:]
    if not rest.startswith(pd):
        raise ValueError("the parameter delimiter is not followed by itself")
    rest = rest[1:]
    rd = ";"
    if rest.startswith("1H"):
        rd = rest[2:3]
    elif not (rest.startswith(pd) or rest.startswith(rd)):
        raise ValueError("the record delimiter field is malformed")
    if not pd or not rd or pd == rd:
        raise ValueError("the delimiters are missing or equal")
    return pd, rd


_NUMBER_OR_BLANK = r"\s*(?:[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?)?\s*"     # _IGES_NUMBER, or blank
_NUMBER_LISTS: Dict[str, "re.Pattern[str]"] = {}


def _number_list(pd: str) -> "re.Pattern[str]":
    """Blank or numeric fields separated by ``pd``: one entity's parameters without strings."""
    if pd not in _NUMBER_LISTS:
        _NUMBER_LISTS[pd] = re.compile(f"{_NUMBER_OR_BLANK}(?:{re.escape(pd)}{_NUMBER_OR_BLANK})*")
    return _NUMBER_LISTS[pd]


def _parameters(text: str, pd: str, rd: str) -> List[str]:
    """The fields of one entity's parameter data up to the record delimiter; every
    field blank, a number or a Hollerith string ``nH...`` (IGES 5.3 section 2.2.2).
    Data without an ``H`` holds no string: then one match of the whole field list
    decides (the field-by-field scan below names the first bad field)."""
    if "H" not in text:
        end = text.find(rd)
        if end >= 0 and _number_list(pd).fullmatch(text, 0, end):
            return text[:end].split(pd)
    out, i, n = [], 0, len(text)
    while i < n:
        m = _IGES_HOLLERITH.match(text, i)
        if m:
            end = m.end() + int(m.group(1))
            if end > n:
                raise ValueError("a string runs past the entity's parameter data")
            out.append(text[i:end])
            i = end
            while i < n and text[i] == " ":
                i += 1
            if i >= n or text[i] not in (pd, rd):
                raise ValueError("a string is not followed by a delimiter")
        else:
            j = i
            while j < n and text[j] != pd and text[j] != rd:
                j += 1
            if j >= n:
                raise ValueError("the parameter data does not end with the record delimiter")
            field = text[i:j]
            if field.strip() and not _IGES_NUMBER.match(field):
                raise ValueError(f"field {len(out) + 1} {field.strip()[:20]!r} is not a number or a string")
            out.append(field)
            i = j
        if text[i] == rd:
            return out
        i += 1
    raise ValueError("the parameter data does not end with the record delimiter")


def _ints(params: List[str], first: int, count: int) -> List[int]:
    out = []
    for k in range(first, first + count):
        if k >= len(params) or not _IGES_INT.match(params[k]) or not params[k].strip():
            got = params[k].strip()[:20] if k < len(params) else "nothing"
            raise ValueError(f"field {k + 1} must be an integer, got {got!r}")
        out.append(int(params[k]))
    return out


def _entity_fields(etype: int, params: List[str]) -> None:
    """Field types and counts of the entities OCCT's loader trusts (IGES 5.3 sections
    4.23 and 4.24): no strings in geometry and topology; a B-spline curve (126) has
    K, M, 4 flags, K+M+2 knots, K+1 weights, 3(K+1) coordinates and 2 parameters; a
    B-spline surface (128) K1, K2, M1, M2, 5 flags, K1+M1+2 and K2+M2+2 knots,
    (K1+1)(K2+1) weights, 3 (K1+1)(K2+1) coordinates and 4 parameters."""
    if etype in _IGES_NUMERIC and any("H" in f for f in params):
        for k, f in enumerate(params):
            if _IGES_HOLLERITH.match(f):
                raise ValueError(f"field {k + 1} is a string; entity type {etype} holds numbers only")
    if etype == 126:
        K, M = _ints(params, 1, 6)[:2]
        if K < 1 or M < 1 or K < M:
            raise ValueError(f"upper index {K} and degree {M} do not make a B-spline curve")
        _finite(params, 7, _need(params, etype, 7 + (K + M + 2) + 4 * (K + 1) + 2))
        _knots(params, 7, K + M + 2, "knots")
        _weights(params, 7 + K + M + 2, K + 1)
    elif etype == 128:
        K1, K2, M1, M2 = _ints(params, 1, 9)[:4]
        if min(K1, K2, M1, M2) < 1 or K1 < M1 or K2 < M2:
            raise ValueError(f"upper indices {K1}, {K2} and degrees {M1}, {M2} do not make a B-spline surface")
        _finite(params, 10, _need(params, etype, 10 + (K1 + M1 + 2) + (K2 + M2 + 2) + 4 * (K1 + 1) * (K2 + 1) + 4))
        _knots(params, 10, K1 + M1 + 2, "first knots")
        _knots(params, 10 + K1 + M1 + 2, K2 + M2 + 2, "second knots")
        _weights(params, 10 + K1 + M1 + 2 + K2 + M2 + 2, (K1 + 1) * (K2 + 1))


def _need(params: List[str], etype: int, need: int) -> int:
    if len(params) < need:
        raise ValueError(f"{len(params)} fields, a type {etype} entity of these sizes needs {need}")
    return need


def _finite(params: List[str], first: int, end: int) -> None:
    x = _reals(params, first, end - first)
    if not np.all(np.isfinite(x)):
        i = int(np.argmax(~np.isfinite(x)))
        raise ValueError(f"field {first + i + 1} {params[first + i].strip()[:20]!r} is not a finite number")


def _reals(params: List[str], first: int, count: int) -> np.ndarray:
    """Fields first .. first+count-1 as floats (a blank field is 0; D exponents are E)."""
    text = [params[k].strip().replace("D", "E").replace("d", "e") or "0" for k in range(first, first + count)]
    with np.errstate(over="ignore"):
        return np.array([float(t) for t in text])


def _knots(params: List[str], first: int, count: int, what: str) -> None:
    """Knots finite, non-decreasing, not all equal (OCCT's transfer dies on decreasing ones)."""
    k = _reals(params, first, count)
    if not np.all(np.isfinite(k)):
        raise ValueError(f"the {what} are not all finite")
    drop = np.flatnonzero(np.diff(k) < 0)
    if drop.size:
        i = int(drop[0])
        raise ValueError(f"the {what} decrease (field {first + i + 2}: {float(k[i + 1])!r} after {float(k[i])!r})")
    if not k[-1] > k[0]:
        raise ValueError(f"the {what} span no interval")


def _weights(params: List[str], first: int, count: int) -> None:
    w = _reals(params, first, count)
    if not np.all(np.isfinite(w) & (w > 0.0)):
        i = int(np.argmax(~(np.isfinite(w) & (w > 0.0))))
        raise ValueError(f"weight {i + 1} (field {first + i + 1}) is {float(w[i])!r}; weights are positive")


def validate_iges(path: Any, data: Optional[bytes] = None) -> None:
    """The structure of an ASCII IGES file (IGES 5.3 chapter 2): records of 80 columns;
    the sections S, G, D, P, T in that order, each numbered 1, 2, ...; two directory
    records per entity with the same entity type; the terminate record's counts equal
    to the section lengths; every entity's parameter pointer and line count inside the
    parameter section, its parameter records pointing back at it and starting with its
    entity type; directory pointers to existing entities; every parameter a number or
    a string. ``data`` as for :func:`validate_step`.

    Raises:
        CagdError: naming the file, the record and the first problem found.
    """
    data = _read_bytes(path, "IGES") if data is None else data
    where = f"path: IGES file {str(path)!r}"
    lines = re.split(r"\r\n|\n|\r", data.decode("latin-1"))    # not splitlines(): \x85, \x0c may be text
    while lines and not lines[-1].strip(" \t\x1a"):
        lines.pop()
    if not lines:
        raise CagdError(f"{where}: empty")
    sections: dict = {s: [] for s in IGES_SECTIONS}
    order = ""
    for number, line in enumerate(lines, 1):
        if len(line) > IGES_RECORD or len(line) < 73:
            cut = " (file truncated?)" if number == len(lines) else ""
            raise CagdError(f"{where}: line {number} has {len(line)} columns; IGES records have {IGES_RECORD}{cut}")
        letter = line[72]
        if letter not in IGES_SECTIONS:
            kind = "compressed or binary IGES is not supported" if letter in "CBF" else "not an IGES section"
            raise CagdError(f"{where}: line {number}: section letter {letter!r} in column 73 ({kind})")
        if not order or order[-1] != letter:
            if letter in order or (order and IGES_SECTIONS.index(letter) < IGES_SECTIONS.index(order[-1])):
                raise CagdError(f"{where}: line {number}: section {letter} out of order (sections come as "
                                f"{', '.join(IGES_SECTIONS)})")
            order += letter
        rec = sections[letter]
        seqno = line[73:80].strip()
        if not _digits(seqno) or int(seqno) != len(rec) + 1:
            raise CagdError(f"{where}: line {number}: sequence number {seqno!r}, expected {letter}{len(rec) + 1} "
                            f"(a record is missing or repeated)")
        rec.append(line.ljust(IGES_RECORD))
    for letter in "GDT":
        if not sections[letter] and not (letter == "D" and not sections["P"] and order.endswith("T")):
            raise CagdError(f"{where}: no {letter} section" + (" (file truncated?)" if letter == "T" else ""))
    if len(sections["T"]) != 1:
        raise CagdError(f"{where}: {len(sections['T'])} terminate records, expected 1")
    term = sections["T"][0]
    for k, letter in enumerate("SGDP"):
        cell = term[8 * k:8 * k + 8]
        count = cell[1:].strip()
        if cell[0] != letter or not _digits(count) or int(count) != len(sections[letter]):
            raise CagdError(f"{where}: terminate record says {cell.strip()!r}, the file has "
                            f"{len(sections[letter])} {letter} records (file truncated or edited?)")
    D, P = sections["D"], sections["P"]
    if len(D) % 2:
        raise CagdError(f"{where}: {len(D)} directory records; every entity has two")
    try:
        pd, rd = _delimiters("".join(r[:72] for r in sections["G"]))
    except ValueError as exc:
        raise CagdError(f"{where}: global section: {exc}") from None
    owners = [r[64:72].strip().lstrip("0") for r in P]
    for e in range(0, len(D), 2):
        seq = e + 1
        try:
            first, second = _fields(D[e], 9), _fields(D[e + 1], 5)
        except ValueError as exc:
            raise CagdError(f"{where}: directory entry D{seq}: {exc}") from None
        etype, pointer, count = first[0], first[1], second[3]
        if etype <= 0 or second[0] != etype:
            raise CagdError(f"{where}: directory entry D{seq}: entity types {first[0]} and {second[0]} "
                            "(two records of one entity)")
        for k, value in ((2, first[2]), (3, first[3]), (4, first[4]), (5, first[5]), (6, first[6]), (7, first[7])):
            target = -value if k < 5 else value
            if k < 5 and value >= 0:
                continue
            if target and (target < 0 or target % 2 == 0 or target > len(D)):
                raise CagdError(f"{where}: directory entry D{seq}: field {k + 1} points at D{target}, "
                                f"not an entity of the {len(D) // 2}")
        if pointer < 1 or count < 1 or pointer + count - 1 > len(P):
            raise CagdError(f"{where}: directory entry D{seq}: parameter records P{pointer} to "
                            f"P{pointer + count - 1}, the file has P1 to P{len(P)} (file truncated?)")
        if any(o != str(seq) for o in owners[pointer - 1:pointer + count - 1]):
            raise CagdError(f"{where}: directory entry D{seq}: its parameter records P{pointer} to "
                            f"P{pointer + count - 1} belong to other entities (corrupted parameter section)")
        text = "".join(r[:64] for r in P[pointer - 1:pointer + count - 1])
        try:
            params = _parameters(text, pd, rd)
            if not params or not _IGES_INT.match(params[0]) or not params[0].strip() or int(params[0]) != etype:
                raise ValueError(f"starts with {params[0].strip()[:20] if params else ''!r}, not its entity "
                                 f"type {etype}")
            _entity_fields(etype, params)
        except ValueError as exc:
            raise CagdError(f"{where}: parameter data of D{seq} (P{pointer}): {exc}") from None
