"""Reading a model document: JSON data only (never executed), every field checked, every
problem a :class:`ModelError` naming the JSON path of the offending value."""
from __future__ import annotations

import copy
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np

from ..curves.base import Curve
from ..curves.bezier import BezierCurve
from ..errors import CagdError
from . import _read as R
from ._read import ModelError
from .types import SOLID_TYPES, TYPES, Fields

FORMAT = "cagd-model"
VERSION = 1
SUPPORTED_VERSIONS = (1,)
UNITS = ("mm",)
DOCUMENT_KEYS = ("format", "version", "units", "name", "description", "objects")
ENTRY_KEYS = ("name", "type", "description", "solid", "export")
INLINE_KEYS = ("type", "description")
_ENGINE_NAME = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*): (.*)$", re.S)


@dataclass
class Entry:
    """One named entry of a model: ``objects`` are the engine objects it builds (one,
    or eight for ``ellipsoid``), ``path`` its JSON path, ``source`` its JSON data."""
    name: str
    type: str
    objects: list
    solid: bool = False
    export: bool = True
    path: str = ""
    description: Optional[str] = None
    source: Dict[str, Any] = field(default_factory=dict, repr=False)

    @property
    def kind(self) -> str:
        """"curve" or "surface"."""
        return TYPES[self.type].kind

    def labels(self) -> List[Tuple[str, Any]]:
        """(label, object) pairs: the entry's name for a single object, else name.0, name.1, ..."""
        if len(self.objects) == 1:
            return [(self.name, self.objects[0])]
        return [(f"{self.name}.{k}", obj) for k, obj in enumerate(self.objects)]


@dataclass
class Model:
    """A loaded model: ``entries`` in document order (exported or not)."""
    version: int
    entries: List[Entry]
    units: str = "mm"
    name: Optional[str] = None
    description: Optional[str] = None

    def __getitem__(self, name: str) -> Entry:
        for e in self.entries:
            if e.name == name:
                return e
        raise KeyError(name)

    def exported(self) -> List[Entry]:
        """The entries with ``export`` true, in document order."""
        return [e for e in self.entries if e.export]


def parse_json(text: str) -> Any:
    """JSON text as Python data: NaN/Infinity literals become markers that
    :func:`cagd.model._read.check_tree` rejects with their path, duplicate keys are
    remembered; a syntax error is a ModelError at ``$`` with line and column."""
    try:
        return json.loads(text, parse_constant=R.NonFinite, parse_int=R.parse_int, object_pairs_hook=R.object_pairs)
    except json.JSONDecodeError as exc:
        raise ModelError("$", f"not valid JSON: {exc.msg} at line {exc.lineno}, column {exc.colno}") from None
    except RecursionError:
        raise ModelError("$", f"nested too deeply (a model needs fewer than {R.MAX_DEPTH} levels)") from None


def read_document(path: Union[str, Path]) -> Any:
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ModelError("$", f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except OSError as exc:
        raise ModelError("$", f"cannot read {path}: {exc.strerror or exc}") from None
    except ValueError as exc:                      # a NUL in the path
        raise ModelError("$", f"cannot read {str(path)!r}: {exc}") from None
    return parse_json(text)


def load_model(source: Union[str, Path, dict]) -> "Model":
    """The model in ``source``: a path to a JSON file or an already-parsed dict.

    Raises:
        ModelError (a CagdError): invalid JSON, a wrong format or unsupported version,
            unknown, missing or ill-typed fields, bad shapes, invalid references, or an
            engine error while building an entry; ``error.path`` is the JSON path.
    """
    doc = read_document(source) if isinstance(source, (str, Path)) else source
    R.check_tree(doc)
    if not isinstance(doc, dict):
        raise ModelError("$", f"a model is a JSON object, got {R.kind(doc)}")
    _header(doc)
    _keys(doc, "$", DOCUMENT_KEYS, ("objects",))
    units = R.choice(doc["units"], "$.units", UNITS) if "units" in doc else "mm"
    name = R.string(doc["name"], "$.name") if "name" in doc else None
    description = R.string(doc["description"], "$.description") if "description" in doc else None
    items = R.array(doc["objects"], "$.objects", "entries", 1)
    return Model(doc["version"], _Builder(items).entries, units, name, description)


def _header(doc: dict) -> None:
    if "format" not in doc:
        raise ModelError("$.format", f'required field missing (a model starts with "format": "{FORMAT}")')
    if doc["format"] != FORMAT:
        raise ModelError("$.format", f'must be "{FORMAT}", got {R.show(doc["format"])}')
    if "version" not in doc:
        raise ModelError("$.version", f"required field missing (this build reads version {_versions()})")
    v = doc["version"]
    if isinstance(v, bool) or not isinstance(v, int):
        raise ModelError("$.version", f"must be an integer, got {R.show(v)}")
    if v not in SUPPORTED_VERSIONS:
        newer = " (written by a newer cagd?)" if v > max(SUPPORTED_VERSIONS) else ""
        raise ModelError("$.version", f"version {v} is not supported{newer}; this build of cagd reads "
                                      f"version {_versions()} of the {FORMAT} format")


def _versions() -> str:
    return ", ".join(str(v) for v in SUPPORTED_VERSIONS)


def _keys(obj: dict, path: str, allowed, required) -> None:
    """Unknown keys first (a typo then says "did you mean"), then missing ones."""
    for key in obj:
        if key not in allowed:
            raise ModelError(R.key_path(path, key), f"unknown field{R.suggest(key, allowed)} "
                                                    f"(allowed here: {', '.join(allowed)})")
    for key in required:
        if key not in obj:
            raise ModelError(R.key_path(path, key), "required field missing")


class _Builder:
    """Builds the entries in order; references may name earlier entries only."""

    def __init__(self, items: list):
        self.later: Dict[str, str] = {}
        for i, item in enumerate(items):
            if isinstance(item, dict) and isinstance(item.get("name"), str):
                self.later.setdefault(item["name"], f"$.objects[{i}]")
        self.done: Dict[str, Entry] = {}
        self.entries: List[Entry] = []
        for i, item in enumerate(items):
            entry = self._entry(item, f"$.objects[{i}]")
            self.done[entry.name] = entry
            self.entries.append(entry)

    def _entry(self, item: Any, path: str) -> Entry:
        if not isinstance(item, dict):
            raise ModelError(path, f"an entry is a JSON object, got {R.kind(item)}")
        spec_name = _type(item, path)
        spec = TYPES[spec_name]
        _keys(item, path, ENTRY_KEYS + spec.fields, ("name",) + spec.required)
        name = R.name(item["name"], R.key_path(path, "name"))
        if name in self.done:
            raise ModelError(R.key_path(path, "name"), f"duplicate name {name!r} (also {self.done[name].path})")
        solid = R.boolean(item["solid"], R.key_path(path, "solid")) if "solid" in item else False
        export = R.boolean(item["export"], R.key_path(path, "export")) if "export" in item else True
        desc = R.string(item["description"], R.key_path(path, "description")) if "description" in item else None
        if solid and spec.solid is None:
            what = "a curve" if spec.kind == "curve" else f"a {spec_name} surface"
            raise ModelError(R.key_path(path, "solid"), f"{what} does not bound a volume; solid is for "
                                                       f"{', '.join(SOLID_TYPES)}")
        fields, objects = self._build(item, path, spec_name)
        if solid and spec.solid is not None:      # (not None whenever solid: checked above)
            with np.errstate(over="ignore", invalid="ignore"):
                spec.solid(fields, objects)
        return Entry(name, spec_name, objects, solid, export, path, desc, copy.deepcopy(item))

    def _build(self, obj: dict, path: str, spec_name: str) -> Tuple[Fields, list]:
        spec = TYPES[spec_name]
        fields = Fields(obj, path, self)
        try:
            with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
                made = spec.build(fields)
                objects = list(made) if isinstance(made, (list, tuple)) else [made]
                _check_finite(objects, path)
        except ModelError:
            raise
        except CagdError as exc:
            raise _engine_error(exc, obj, path, spec_name) from None
        return fields, objects

    # --- references -----------------------------------------------------------------
    def curve(self, value: Any, path: str, bezier: bool = False) -> Curve:
        """A curve field: {"ref": "<earlier entry>"} or an inline object {"type": ...}."""
        want = "a Bezier curve (bezier_curve or join)" if bezier else "a curve"
        if not isinstance(value, dict):
            raise ModelError(path, f'must be {want}: {{"ref": "<name>"}} or an inline object '
                                   f'{{"type": ...}}, got {R.show(value)}')
        if "ref" in value:
            _keys(value, path, ("ref",), ())
            ref = R.string(value["ref"], R.key_path(path, "ref"))
            entry = self._lookup(ref, R.key_path(path, "ref"))
            obj, type_name, where = entry.objects[0], entry.type, f"entry {ref!r} ({entry.path})"
        else:
            spec_name = _type(value, path, inline=True)
            spec = TYPES[spec_name]
            _keys(value, path, INLINE_KEYS + spec.fields, spec.required)
            if "description" in value:
                R.string(value["description"], R.key_path(path, "description"))
            if spec.kind == "curve":
                obj = self._build(value, path, spec_name)[1][0]
            type_name, where = spec_name, "the inline object"
        if TYPES[type_name].kind != "curve":
            raise ModelError(path, f"must be {want}; {where} is a {type_name} surface")
        if bezier and not isinstance(obj, BezierCurve):
            raise ModelError(path, f"must be {want}; {where} is a {type_name}")
        return obj

    def surface(self, value: Any, path: str) -> Any:
        """A surface field: {"ref": "<earlier entry>"} or an inline object {"type": ...};
        one surface (not an ellipsoid's eight patches) that can be trimmed (not a
        trimmed_surface: refer to its surface instead)."""
        want = 'a surface: {"ref": "<name>"} or an inline object {"type": ...}'
        if not isinstance(value, dict):
            raise ModelError(path, f"must be {want}, got {R.show(value)}")
        if "ref" in value:
            _keys(value, path, ("ref",), ())
            ref = R.string(value["ref"], R.key_path(path, "ref"))
            entry = self._lookup(ref, R.key_path(path, "ref"))
            objects, type_name, where = entry.objects, entry.type, f"entry {ref!r} ({entry.path})"
        else:
            type_name = _type(value, path, inline=True)
            spec = TYPES[type_name]
            _keys(value, path, INLINE_KEYS + spec.fields, spec.required)
            if "description" in value:
                R.string(value["description"], R.key_path(path, "description"))
            objects = self._build(value, path, type_name)[1] if spec.kind == "surface" else []
            where = "the inline object"
        if TYPES[type_name].kind != "surface":
            raise ModelError(path, f"must be a surface; {where} is a {type_name} curve")
        if type_name == "trimmed_surface":
            raise ModelError(path, f"{where} is already trimmed; trim its surface instead (one "
                                   f"trimmed_surface with all the loops)")
        if len(objects) != 1:
            raise ModelError(path, f"must be one surface; {where} is a {type_name} of {len(objects)} patches "
                                   f"(trim one of them: an entry of its own)")
        return objects[0]

    def _lookup(self, ref: str, path: str) -> Entry:
        if ref in self.done:
            return self.done[ref]
        if ref in self.later:
            where = self.later[ref]
            if path.startswith(where + ".") or path.startswith(where + "["):
                raise ModelError(path, f"entry {ref!r} refers to itself")
            raise ModelError(path, f"entry {ref!r} is defined later ({where}); a reference must name an "
                                   f"earlier entry")
        raise ModelError(path, f"no entry named {ref!r}{R.suggest(ref, self.done)}")


def _check_finite(objects: list, path: str) -> None:
    """Extreme inputs (1e300, 5e-324) can overflow inside the engine; the built object
    must evaluate to finite points on a 5 x 5 sample of its domain."""
    g = np.linspace(0.0, 1.0, 5)
    for obj in objects:
        if isinstance(obj, Curve):
            a, b = obj.domain
            x = obj(a + g * (b - a))
        else:
            (u0, u1), (v0, v1) = obj.domain
            u, v = np.meshgrid(g, g)
            if not obj.rectangular:
                u, v = u * (1.0 - v), v
            x = obj(u0 + u * (u1 - u0), v0 + v * (v1 - v0))
        if not np.all(np.isfinite(x)):
            raise ModelError(path, "the object evaluates to NaN or infinity (numbers too large or too small "
                                   "for float64 arithmetic)")


def _type(obj: dict, path: str, inline: bool = False) -> str:
    if "type" not in obj:
        raise ModelError(R.key_path(path, "type"), "required field missing (the entry's type, e.g. \"bspline_curve\")")
    t = obj["type"]
    if not isinstance(t, str) or t not in TYPES:
        hint = R.suggest(t, TYPES) if isinstance(t, str) else ""
        raise ModelError(R.key_path(path, "type"), f"unknown type {R.show(t)}{hint} (types: {', '.join(TYPES)})")
    if inline:
        for key in ("name", "solid", "export"):
            if key in obj:
                raise ModelError(R.key_path(path, key), f"an inline object has no {key}; "
                                                        f"make it a named entry and use {{\"ref\": ...}}")
    return t


def _engine_error(exc: CagdError, obj: dict, path: str, spec_name: str) -> ModelError:
    """The engine's "argument: problem" message at the field's path when the argument
    is a field of this type (through the type's aliases), else at the entry's path.
    An absent field is pointed at (where it should go: "tangents: 'clamped' needs
    tangents"), except for NaN/inf in a value the engine computed itself from other
    fields (e.g. its own spline tangents after an overflow)."""
    msg = str(exc)
    spec = TYPES[spec_name]
    m = _ENGINE_NAME.match(msg)
    if m:
        arg = spec.aliases.get(m.group(1), m.group(1))
        if arg in spec.fields and (arg in obj or "NaN or inf" not in m.group(3)):
            return ModelError(R.key_path(path, arg) + m.group(2), m.group(3))
    return ModelError(path, f"{spec.engine}: {msg}")
