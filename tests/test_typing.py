"""The engine's public API is fully typed: every public function and every public method
of a public class in a public module of ``cagd`` annotates each parameter and its
return (``__init__`` its parameters); mypy (configured in pyproject.toml, run by
``python3 dev.py test``) checks the annotations are right. Modules that need OCP are
checked where it is installed."""
from __future__ import annotations

import importlib
import inspect
import pkgutil
from typing import List

import pytest

import cagd

# modules whose import needs more than numpy (checked where it is there)
OPTIONAL = {"cagd.occ": "OCP", "cagd.plotting": "matplotlib"}


def public_modules() -> List[str]:
    names = ["cagd"]
    for info in pkgutil.walk_packages(cagd.__path__, "cagd."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts) or info.name.startswith("cagd.freecad.addon"):
            continue
        names.append(info.name)
    return names


def missing_annotations(func, qualname: str) -> List[str]:
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return []
    out = []
    for i, (name, p) in enumerate(sig.parameters.items()):
        if i == 0 and name in ("self", "cls"):
            continue
        if p.annotation is inspect.Parameter.empty:
            out.append(f"{qualname}: parameter {name!r}")
    if sig.return_annotation is inspect.Signature.empty and func.__name__ != "__init__":
        out.append(f"{qualname}: return")
    return out


def public_callables(module):
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj):
            yield f"{module.__name__}.{name}", obj
        elif inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if attr.startswith("_") and attr != "__init__":
                    continue
                func = member.__func__ if isinstance(member, (classmethod, staticmethod)) else member
                if isinstance(member, property):
                    func = member.fget
                if inspect.isfunction(func):
                    if attr == "__init__" and "__init__" not in vars(obj):
                        continue
                    yield f"{module.__name__}.{name}.{attr}", func


@pytest.mark.parametrize("module_name", public_modules())
def test_public_functions_are_annotated(module_name):
    need = next((lib for prefix, lib in OPTIONAL.items() if module_name.startswith(prefix)), None)
    if need:
        pytest.importorskip(need)
    module = importlib.import_module(module_name)
    missing = [m for qualname, func in public_callables(module) for m in missing_annotations(func, qualname)]
    assert not missing, "\n".join(missing)


def test_the_check_sees_a_missing_annotation():
    def untyped(a, b: int):
        return a
    assert missing_annotations(untyped, "untyped") == ["untyped: parameter 'a'", "untyped: return"]
