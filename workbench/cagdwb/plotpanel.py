"""The curvature plot panel of the Curve quality command: curvature against arc length
of the selected edge (the pixels from curvature_plot.py, drawn with QPainter) above the
fairness read-out (analysis.fairness_readout: length, curvature range, energy,
inflections, largest curvature jump at a knot)."""
from __future__ import annotations

import FreeCADGui as Gui

from . import analysis
from .curvature_plot import curvature_plot
from .qt import QtCore, QtGui, QtWidgets

PLOT_SIZE = (360, 200)           # the plot widget's fixed size in pixels
CURVE_COLOUR = (220, 0, 0)       # the curvature line


class CurvatureWidget(QtWidgets.QWidget):
    """Draws one curvature plot: axes, the curve, the axis ranges as text."""

    def __init__(self, arc_length, curvature, parent=None):
        super().__init__(parent)
        self.setFixedSize(*PLOT_SIZE)
        self.plot = curvature_plot(arc_length, curvature, *PLOT_SIZE)

    def paintEvent(self, event) -> None:           # noqa: N802 (Qt's name)
        p = self.plot
        painter = QtGui.QPainter(self)
        painter.fillRect(self.rect(), QtGui.QColor(255, 255, 255))
        painter.setPen(QtGui.QPen(QtGui.QColor(0, 0, 0), 1))
        top, bottom = p.axis_rows
        left, right = p.margin, p.width - p.margin
        zero = p.row_of(0.0)
        painter.drawLine(QtCore.QPointF(left, top), QtCore.QPointF(left, bottom))
        painter.drawLine(QtCore.QPointF(left, zero), QtCore.QPointF(right, zero))
        painter.drawText(QtCore.QPointF(left + 4, top + 10), f"{p.k_high:.4g} 1/mm")
        painter.drawText(QtCore.QPointF(right - 80, p.height - 6), f"s = {p.length:.4g} mm")
        painter.setPen(QtGui.QPen(QtGui.QColor(*CURVE_COLOUR), 2))
        painter.drawPolyline(QtGui.QPolygonF([QtCore.QPointF(float(x), float(y)) for x, y in p.pixels]))
        painter.end()


class CurvaturePanel:
    """Task panel: the curvature plot and the fairness metrics of one edge."""

    def __init__(self, edge, title: str):
        self.fairness, self.text = analysis.fairness_readout(edge)
        self.form = QtWidgets.QWidget()
        self.form.setWindowTitle(title)
        layout = QtWidgets.QVBoxLayout(self.form)
        self.plot = CurvatureWidget(self.fairness.arc_length, self.fairness.curvature)
        layout.addWidget(self.plot)
        self.label = QtWidgets.QLabel(self.text)
        self.label.setWordWrap(True)
        layout.addWidget(self.label)

    def getStandardButtons(self) -> int:            # noqa: N802 (FreeCAD's name)
        return int(QtWidgets.QDialogButtonBox.Close)

    def reject(self) -> bool:
        Gui.Control.closeDialog()
        return True


def show(edge, title: str) -> CurvaturePanel:
    """Open the panel for ``edge`` (closing any open task dialog first)."""
    if Gui.Control.activeDialog():
        Gui.Control.closeDialog()
    panel = CurvaturePanel(edge, title)
    Gui.Control.showDialog(panel)
    return panel
