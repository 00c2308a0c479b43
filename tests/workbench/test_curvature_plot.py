"""The curvature plot's geometry (workbench/cagdwb/curvature_plot.py) without FreeCAD:
numpy only. Oracles: closed forms of the curvature of a circle (1/R) and of the
parabola y = x^2 (kappa = 2 / (1 + 4x^2)^(3/2), largest 2 at its vertex, mid-length)."""
import math
import sys

import numpy as np
import pytest

from wb_runner import ADDON

sys.path.insert(0, str(ADDON))
from cagdwb import curvature_plot  # noqa: E402

import cagd  # noqa: E402

W = math.sqrt(0.5)


def quarter_circle(radius):
    return cagd.BSplineCurve(np.array([[radius, 0], [radius, radius], [0, radius]], float), 2, None, [1, W, 1])


def test_a_circle_arc_is_a_flat_line_at_one_over_r():
    radius = 4.0
    fair = cagd.analysis.fairness(quarter_circle(radius))
    plot = curvature_plot.curvature_plot(fair.arc_length, fair.curvature, 400, 200)
    x, y = plot.pixels.T
    assert abs(x[0] - 24) <= 1e-12 and abs(x[-1] - (400 - 24)) <= 1e-9
    assert np.abs(y - plot.row_of(1 / radius)).max() <= 1e-9
    assert abs(plot.curvature_at_row(y.mean()) - 1 / radius) <= 1e-12
    assert abs(plot.length - math.pi * radius / 2) <= 1e-9
    top, bottom = plot.axis_rows
    assert top < y.min() and y.max() < bottom            # the line inside the axes, below the headroom
    assert plot.k_low == 0.0 and abs(plot.k_high - 1.1 / radius) <= 1e-12


def test_the_parabola_peaks_at_mid_length_with_curvature_two():
    parabola = cagd.BezierCurve(np.array([[-1.0, 1.0], [0.0, -1.0], [1.0, 1.0]]))   # y = x^2
    fair = cagd.analysis.fairness(parabola, samples_per_span=65)
    plot = curvature_plot.curvature_plot(fair.arc_length, fair.curvature, 300, 150, margin=10)
    i = int(np.argmin(plot.pixels[:, 1]))                  # the highest point drawn
    assert abs(plot.curvature_at_row(plot.pixels[i, 1]) - 2.0) <= 1e-9
    assert abs(plot.pixels[i, 0] - 150.0) <= 1e-9          # mid-length: the middle of the plot
    ends = plot.curvature_at_row(plot.pixels[[0, -1], 1])
    assert np.abs(ends - 2 / 5 ** 1.5).max() <= 1e-9        # kappa(+-1) = 2 / 5^(3/2)


def test_bad_inputs_name_the_argument():
    with pytest.raises(cagd.CagdError, match="arc_length"):
        curvature_plot.curvature_plot([0.0, 1.0, 0.5], [1.0, 1.0, 1.0], 100, 100)
    with pytest.raises(cagd.CagdError, match="curvature"):
        curvature_plot.curvature_plot([0.0, 1.0], [1.0, np.nan], 100, 100)
    with pytest.raises(cagd.CagdError, match="width/height"):
        curvature_plot.curvature_plot([0.0, 1.0], [1.0, 1.0], 40, 100)
