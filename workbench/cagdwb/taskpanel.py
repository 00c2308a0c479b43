"""A task panel for every workbench object (double-click, or Edit): one widget per
scalar or vector property of the object's own groups (integers, floats, angles,
tolerances as typed numbers, booleans, enumerations, vectors) and per link property
(the links listed with Add selection / Remove / Up / Down, or Set from selection:
linkedit.py); each change recomputes at once and the panel shows the object's Message.
Cancel undoes the changes (one transaction); point and knot lists are edited in the
property editor."""
from __future__ import annotations

from typing import Callable

import FreeCAD as App
import FreeCADGui as Gui
from .linkedit import KINDS as LINK_KINDS, LinkEditor
from .qt import QtWidgets

SKIP_GROUPS = ("", "Base", "Status")
RANGE = 1e9
DEGREE_MIN = 1          # a degree box stops at 1 (degree 0 is not a curve the objects build)


def _spin(value: float, decimals: int, setter: Callable) -> QtWidgets.QDoubleSpinBox:
    box = QtWidgets.QDoubleSpinBox()
    box.setRange(-RANGE, RANGE)
    box.setDecimals(decimals)
    box.setValue(value)
    box.valueChanged.connect(setter)
    return box


def minimum(name: str) -> int:
    """The least value an integer box accepts: 1 for a degree (Degree, DegreeU, ...),
    0 for a count, else -10^6."""
    if name.startswith("Degree"):
        return DEGREE_MIN
    return 0 if name.startswith(("Count", "Max", "Grid", "Samples")) else -10 ** 6


class TaskPanel:
    """Edit panel of one object (``self.form`` is what FreeCAD shows)."""

    def __init__(self, obj):
        self.obj = obj
        self.form = QtWidgets.QWidget()
        self.form.setWindowTitle(f"{obj.Label} ({obj.Proxy.TYPE.split('::')[-1]})")
        layout = QtWidgets.QFormLayout(self.form)
        self.widgets = {}
        names = sorted(obj.PropertiesList, key=lambda n: (obj.getGroupOfProperty(n), n))
        for name in names:
            if obj.getGroupOfProperty(name) in SKIP_GROUPS:
                continue
            widget = self._widget(name, obj.getTypeIdOfProperty(name))
            if widget is not None:
                widget.setToolTip(obj.getDocumentationOfProperty(name))
                layout.addRow(name, widget)
                self.widgets[name] = widget
        self.message = QtWidgets.QLabel(obj.Message)
        self.message.setWordWrap(True)
        layout.addRow("Status", self.message)
        self.sync_enabled()
        obj.Document.openTransaction(f"Edit {obj.Label}")

    def sync_enabled(self) -> None:
        """A row is disabled while its property is read-only (e.g. the tangent scales of
        a blend curve with automatic scales)."""
        for name, widget in self.widgets.items():
            widget.setEnabled("ReadOnly" not in self.obj.getEditorMode(name))

    def _widget(self, name: str, kind: str):
        obj = self.obj
        value = getattr(obj, name)
        if kind == "App::PropertyInteger":
            box = QtWidgets.QSpinBox()
            box.setRange(minimum(name), 10 ** 6)
            box.setValue(value)
            box.valueChanged.connect(lambda v, n=name: self.apply(n, int(v)))
            return box
        if kind == "App::PropertyPrecision":           # tolerances: a spin box would round 1e-7 to 0
            box = QtWidgets.QLineEdit(repr(float(value)))
            box.editingFinished.connect(lambda n=name, b=box: self.apply_text(n, b))
            return box
        if kind in ("App::PropertyFloat", "App::PropertyAngle"):
            return _spin(float(value), 6, lambda v, n=name: self.apply(n, float(v)))
        if kind == "App::PropertyBool":
            box = QtWidgets.QCheckBox()
            box.setChecked(bool(value))
            box.toggled.connect(lambda v, n=name: self.apply(n, bool(v)))
            return box
        if kind == "App::PropertyEnumeration":
            box = QtWidgets.QComboBox()
            box.addItems(obj.getEnumerationsOfProperty(name))
            box.setCurrentText(value)
            box.currentTextChanged.connect(lambda v, n=name: self.apply(n, str(v)))
            return box
        if kind == "App::PropertyVector":
            row = QtWidgets.QWidget()
            hbox = QtWidgets.QHBoxLayout(row)
            hbox.setContentsMargins(0, 0, 0, 0)
            boxes = []

            def changed(_v, n=name):
                self.apply(n, App.Vector(*(b.value() for b in boxes)))
            for c in (value.x, value.y, value.z):
                boxes.append(_spin(c, 4, changed))
                hbox.addWidget(boxes[-1])
            return row
        if kind in LINK_KINDS:
            return LinkEditor(obj, name, kind, self.apply, self.say)
        if kind in ("App::PropertyVectorList", "App::PropertyFloatList"):
            return QtWidgets.QLabel(f"{len(value)} values (edit in the property editor)")
        return None

    def apply(self, name: str, value) -> None:
        """Set the property, recompute, show the result."""
        setattr(self.obj, name, value)
        self.obj.Document.recompute()
        self.message.setText(self.obj.Message)
        self.sync_enabled()

    def say(self, text: str) -> None:
        """A note in the status line (a selection a link button cannot use)."""
        self.message.setText(text)

    def apply_text(self, name: str, box) -> None:
        """A typed tolerance ('1e-7', '0.001'); text that is not a number is put back."""
        try:
            value = float(box.text())
        except ValueError:
            box.setText(repr(float(getattr(self.obj, name))))
            return
        if value != float(getattr(self.obj, name)):
            self.apply(name, value)

    # --- task dialog protocol ---------------------------------------------------------------
    def accept(self) -> bool:
        self.obj.Document.commitTransaction()
        self._close()
        return True

    def reject(self) -> bool:
        self.obj.Document.abortTransaction()
        self.obj.Document.recompute()
        self._close()
        return True

    def _close(self) -> None:
        Gui.Control.closeDialog()
        if Gui.ActiveDocument is not None:
            Gui.ActiveDocument.resetEdit()

    def getStandardButtons(self) -> int:
        return int(QtWidgets.QDialogButtonBox.Ok | QtWidgets.QDialogButtonBox.Cancel)
