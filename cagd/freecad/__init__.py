"""The FreeCAD workbench that ships with cagd, and its installer.

The addon (FreeCAD's ``Init.py``/``InitGui.py``, the ``cagdwb`` package, icons) is
package data here (``cagd/freecad/addon`` in the wheel; the checkout's ``workbench/``
folder in a development install). ``cagd-freecad install`` (or
``python -m cagd.freecad install``) puts it into FreeCAD's user Mod folder; see
:mod:`cagd.freecad.install`. Nothing here imports FreeCAD, and no part of the
engine imports this subpackage.
"""
from .install import addon_dir, engine_dir, freecad_user_dir, install, uninstall

__all__ = ["addon_dir", "engine_dir", "freecad_user_dir", "install", "uninstall"]
