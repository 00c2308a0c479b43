"""Keywords that changed name or meaning: accepted for one release with a warning that
says what to use (DeprecationWarning for a new name, FutureWarning for a new meaning),
attributed to the caller's line outside cagd (and cq_ext, which uses them too)."""
from __future__ import annotations

import sys
import warnings
from types import FrameType
from typing import Any, Optional

from .errors import CagdError


_OURS = ("cagd", "cq_ext")


def _outside_level() -> int:
    """The stacklevel of the first frame outside the cagd package and its front end
    cq_ext (for warnings.warn called from the function that calls this one)."""
    level = 2
    frame: Optional[FrameType] = sys._getframe(2)
    while frame is not None and frame.f_globals.get("__name__", "").split(".")[0] in _OURS:
        level, frame = level + 1, frame.f_back
    return level


RELATIVE = "it is relative (to the size), and tol means a distance in model units in cagd"


def renamed(func: str, old: str, new: str, value: Any, current: Any, default: Any, why: str = "") -> Any:
    """The value for keyword ``new`` of ``func`` when the deprecated ``old`` was given as
    ``value`` (``current`` is what ``new`` received, ``default`` its default): warns
    with a DeprecationWarning (giving ``why``) and returns ``value``.

    Raises:
        CagdError: both keywords were given."""
    if current is not default:
        raise CagdError(f"{old}: {func} got both {old}= (deprecated) and {new}=; pass {new}= only")
    deprecated(func, f"the keyword {old}= is deprecated; use {new}=" + (f" ({why})" if why else ""))
    return value


def deprecated(func: str, text: str) -> None:
    """A DeprecationWarning: ``text`` says what is deprecated in ``func`` and what to use."""
    warnings.warn(f"{func}: {text} (it will be removed in the next release)", DeprecationWarning,
                  stacklevel=_outside_level())


def changed(func: str, text: str) -> None:
    """A FutureWarning that a keyword of ``func`` means something else now (``text``
    says what it means, what it meant and how to get the old behaviour)."""
    warnings.warn(f"{func}: {text} (this notice is shown for one release)", FutureWarning,
                  stacklevel=_outside_level())
