"""Optional dependencies of the command line: checked before any work, so that a missing
one is a clear CagdError naming the option and the install command, not a traceback
after minutes of computing."""
from __future__ import annotations

import importlib

from .errors import CagdError

#: the extra of ``pip install 'cagd[...]'`` that brings each optional module
EXTRAS = {"matplotlib": "plot"}


def require(module: str, option: str) -> None:
    """Import ``module`` or raise CagdError naming ``option`` and the install command.

    Raises:
        CagdError: the module is not installed."""
    try:
        importlib.import_module(module)
    except ImportError:
        raise CagdError(f"{option}: needs {module}, which is not installed "
                        f"(pip install 'cagd[{EXTRAS.get(module, module)}]')") from None
