"""plot_surfaces draws shaded surfaces: the PNG shows coloured (neither white nor grey)
pixels of several brightnesses where a surface is, and none where there is only a net."""
import numpy as np
import pytest

from cagd import BezierTriangle, BSplineSurface, CagdError
from cagd.plotting import _net_lines, plot_surfaces
from cagd.triangles import index_triples

pytest.importorskip("matplotlib")
import matplotlib.image as mpimg  # noqa: E402


def _dome() -> BSplineSurface:
    """A small bicubic B-spline dome, 5 x 4 control points, z = 1 - x^2 - y^2 at the net."""
    x, y = np.meshgrid(np.linspace(-1, 1, 5), np.linspace(-1, 1, 4), indexing="ij")
    return BSplineSurface(np.stack([x, y, 1.0 - x ** 2 - y ** 2], axis=-1), 3, 3)


def _coloured(png) -> np.ndarray:
    """Brightness of the pixels whose RGB channels differ by more than 0.15 (white, the
    grey panes, black text and the grey nets all have equal channels)."""
    img = mpimg.imread(png)[..., :3]
    mask = img.max(axis=-1) - img.min(axis=-1) > 0.15
    return img[mask].max(axis=-1)


def test_shaded_bspline_surface(tmp_path):
    s = _dome()
    png = plot_surfaces(tmp_path / "sub" / "dome.png", "dome", [s], [s.control_points], samples=20)
    assert png.exists() and png.stat().st_size > 1000
    value = _coloured(png)
    img = mpimg.imread(png)
    assert value.size > 0.03 * img.shape[0] * img.shape[1]      # the surface covers part of the picture
    assert np.ptp(np.percentile(value, [5, 95])) > 0.1           # shaded: many brightnesses, not one flat colour


def test_only_a_net_gives_no_coloured_pixels(tmp_path):
    """The detector above is not fooled by the axes, panes or a (grey) control net."""
    png = plot_surfaces(tmp_path / "net.png", "net only", [], [_dome().control_points])
    assert _coloured(png).size < 50


def test_bezier_triangle_is_drawn_inside_its_domain(tmp_path):
    pts = np.array([[i, j, (i * j * k) / 4.0] for i, j, k in index_triples(3)], dtype=float)
    tri = BezierTriangle(pts)
    png = plot_surfaces(tmp_path / "tri.png", "triangle", [tri], [tri.control_points], samples=25)
    assert _coloured(png).size > 2000


def test_triangular_net_lines_follow_constant_indices():
    """Oracle: with P_ijk = (i, j, k) every polyline keeps one of i, j, k fixed and
    steps the other two by one."""
    net = np.array(index_triples(3), dtype=float)
    lines = _net_lines(net)
    assert len(lines) == 12 and sum(len(line) for line in lines) == 3 * 10
    for line in lines:
        fixed = np.ptp(line, axis=0) == 0
        assert fixed.sum() >= 1
        if len(line) > 1:
            assert np.all(np.abs(np.diff(line, axis=0)).sum(axis=1) == 2)


def test_bad_input(tmp_path):
    with pytest.raises(CagdError, match="surfaces"):
        plot_surfaces(tmp_path / "x.png", "x", [np.zeros((3, 3, 3))])
    with pytest.raises(CagdError, match="control_nets"):
        plot_surfaces(tmp_path / "x.png", "x", [_dome()], [np.zeros((4, 3))])
    with pytest.raises(CagdError, match="nothing to draw"):
        plot_surfaces(tmp_path / "x.png", "x", [])
