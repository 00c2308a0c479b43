"""Qt modules of the running FreeCAD: PySide2 (FreeCAD 0.20/0.21) or PySide6 (Qt 6 builds)."""
try:
    from PySide2 import QtCore, QtGui, QtWidgets  # noqa: F401
except ImportError:                        # pragma: no cover - Qt 6 builds of FreeCAD 1.x
    from PySide6 import QtCore, QtGui, QtWidgets  # noqa: F401
