"""FreeCAD glue for the cagd engine: parametric curve and surface objects.

The engine stays in ``cagd`` (pure numpy); this package only converts between the
engine and FreeCAD's Part API and wires objects, view providers and commands.
:func:`ensure_engine` makes ``cagd`` importable inside FreeCAD's own Python: the
installer (``cagd-freecad install``, or ``workbench/install.py`` in a checkout) puts
the engine package into ``<Mod>/CagdWorkbench/engine/cagd``; a ``CAGD_PATH``
environment variable takes precedence, and the checkout holding ``workbench/`` is
the last resort.
"""
from __future__ import annotations

import os
import sys

PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))
ICON_DIR = os.path.join(os.path.dirname(PACKAGE_DIR), "icons")
# the Mod folder entry as FreeCAD sees it (not resolved: an install links cagdwb/ into it)
ADDON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENGINE_DIR = os.path.join(ADDON_DIR, "engine")      # engine/cagd, made by cagd-freecad install
PATH_FILE = os.path.join(ADDON_DIR, "engine_path.txt")


def engine_candidates() -> list:
    """Folders that may hold the ``cagd`` package, in the order they are tried."""
    found = []
    if os.environ.get("CAGD_PATH"):
        found.append(os.environ["CAGD_PATH"])
    found.append(ENGINE_DIR)
    if os.path.isfile(PATH_FILE):                 # copies made by older installers
        with open(PATH_FILE, encoding="utf-8") as f:
            found.append(f.read().strip())
    found.append(os.path.dirname(ADDON_DIR))      # the checkout, for <repo>/workbench itself
    return found


def ensure_engine() -> str:
    """Put the folder holding ``cagd`` on sys.path (once) and return it.

    Raises:
        ImportError: no candidate folder holds ``cagd/__init__.py`` and ``cagd`` is
            not importable otherwise; the message lists the folders tried.
    """
    for folder in engine_candidates():
        if os.path.isfile(os.path.join(folder, "cagd", "__init__.py")):
            folder = os.path.realpath(folder)
            if folder not in sys.path:
                sys.path.insert(0, folder)
            return folder
    try:
        import cagd  # noqa: F401  (installed some other way, e.g. pip)
        return os.path.dirname(os.path.dirname(cagd.__file__))
    except ImportError:
        raise ImportError("cagd workbench: the engine package 'cagd' was not found in "
                          f"{engine_candidates()}; set CAGD_PATH to the repository root "
                          "or run cagd-freecad install again") from None


def icon(name: str) -> str:
    """Absolute path of ``icons/<name>.svg``."""
    return os.path.join(ICON_DIR, name + ".svg")
