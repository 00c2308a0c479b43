"""The cagd model format: a versioned JSON document naming curves and surfaces by type
and parameters (docs/model-format.md). Data only, never executed; an invalid document
raises :class:`ModelError` (a CagdError) whose ``path`` is the JSON path of the bad
value, e.g. ``$.objects[2].knots[4]``.

    >>> from cagd.model import load_model
    >>> model = load_model("part.json")
    >>> [(e.name, e.type, len(e.objects)) for e in model.exported()]
"""
from __future__ import annotations

from pathlib import Path

from ._read import ModelError
from .loader import FORMAT, SUPPORTED_VERSIONS, UNITS, VERSION, Entry, Model, load_model, parse_json
from .types import SOLID_TYPES, TYPES
from .writer import dump_model, dumps, entry_dict, model_to_dict, objects_to_dict

DEFAULT_MODEL_PATH = Path(__file__).with_name("default.json")


def default_model() -> Model:
    """The built-in model of ``cagd demo`` (``cagd/model/default.json``)."""
    return load_model(DEFAULT_MODEL_PATH)


__all__ = [
    "FORMAT", "VERSION", "SUPPORTED_VERSIONS", "UNITS", "TYPES", "SOLID_TYPES", "ModelError", "Model", "Entry",
    "load_model", "parse_json", "entry_dict", "objects_to_dict", "model_to_dict", "dumps", "dump_model",
    "DEFAULT_MODEL_PATH", "default_model",
]
