#!/usr/bin/env python3
"""Install the cagd workbench from a checkout (stdlib only; the same installer as
``cagd-freecad``, see cagd/freecad/install.py):

    python3 workbench/install.py              link this checkout's addon and engine into FreeCAD's user Mod folder
    python3 workbench/install.py --copy       copy them instead
    python3 workbench/install.py --uninstall  remove it again
    python3 workbench/install.py --mod-dir DIR   use DIR instead of FreeCAD's user Mod folder
"""
import importlib.util
import sys
from pathlib import Path

ADDON = Path(__file__).resolve().parent
REPO = ADDON.parent


def _installer():
    """cagd/freecad/install.py loaded by path: importing the package ``cagd`` would
    need numpy, which the python3 running this may not have."""
    spec = importlib.util.spec_from_file_location("cagd_freecad_install", REPO / "cagd" / "freecad" / "install.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


if __name__ == "__main__":
    sys.exit(_installer().main(sys.argv[1:], addon=ADDON, engine=REPO / "cagd"))
