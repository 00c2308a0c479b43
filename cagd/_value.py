"""Engine objects are values (issue 13): their public attributes are bound once, by the
constructor, and their arrays are read-only (:func:`cagd._checks.frozen`), so every
cache (pp forms, homogeneous nets, closest-point projectors keyed by the object)
derives from data that cannot change. A modified object is a new one
(``with_control_points``, ``moved_pole``, ``with_weights``, ``transformed``, ...)."""
from __future__ import annotations

import inspect
from typing import Any, Dict, Type, TypeVar

import numpy as np

from ._checks import frozen

_V = TypeVar("_V", bound="Value")


class _ValueType(type):
    """Seals an instance once the outermost constructor has returned (a subclass's
    ``__init__`` may still bind attributes after ``super().__init__``)."""

    def __call__(cls, *args: Any, **kwargs: Any) -> Any:
        obj = super().__call__(*args, **kwargs)
        object.__setattr__(obj, "_sealed", True)
        return obj

    @property
    def __signature__(cls) -> inspect.Signature:
        """The constructor's signature (``help()``, IDEs and ``inspect`` would otherwise show
        this metaclass's ``(*args, **kwargs)``)."""
        init = inspect.signature(getattr(cls, "__init__"))
        return init.replace(parameters=list(init.parameters.values())[1:])


class Value(metaclass=_ValueType):
    """Base of the engine objects: after construction, binding or deleting a public
    attribute raises AttributeError naming ``_modified_copy``; private attributes
    (caches) stay settable."""

    _sealed = False
    #: how to get a modified object, for the error message
    _modified_copy = "build a new one (its constructor, transformed(), ...)"

    def __setattr__(self, name: str, value: Any) -> None:
        if self._sealed and not name.startswith("_"):
            self._refuse(name)
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        if self._sealed and not name.startswith("_"):
            self._refuse(name)
        object.__delattr__(self, name)

    def _refuse(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__}.{name}: engine objects are values and cannot be "
                             f"changed after construction; for a modified copy {self._modified_copy}")

    # an immutable object is its own copy; unpickled arrays come back writable: freeze them
    def __copy__(self: _V) -> _V:
        return self

    def __deepcopy__(self: _V, memo: Dict[int, Any]) -> _V:
        return self

    def __setstate__(self, state: Dict[str, Any]) -> None:
        for name, value in state.items():
            object.__setattr__(self, name, _frozen_items(value))

    @classmethod
    def _unchecked(cls: Type[_V], *parts: Any) -> _V:
        """An instance from parts that are already valid (``cls._fill(*parts)``, the
        constructor without its checks), sealed like a constructed one."""
        obj = cls.__new__(cls)
        obj._fill(*parts)
        object.__setattr__(obj, "_sealed", True)
        return obj

    def _fill(self, *parts: Any) -> None:
        raise NotImplementedError


def _frozen_items(value: Any) -> Any:
    """``value`` with every array in it (also inside lists, tuples and dicts) frozen."""
    if isinstance(value, np.ndarray):
        return frozen(value)
    if type(value) in (list, tuple):
        return type(value)(_frozen_items(x) for x in value)
    if type(value) is dict:
        return {k: _frozen_items(x) for k, x in value.items()}
    return value
