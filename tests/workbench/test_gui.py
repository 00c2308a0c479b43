"""The workbench in FreeCAD's GUI under Xvfb (workbench/tests/gui_macro.py): the macro
activates the workbench, runs every command on a prepared selection and saves, per
step, a rendering with the step's new object and one with it hidden (same camera).
Here the macro's own checks must all pass and every rendering must show the model:
enough pixels differ between the two images of a step."""
import os

import numpy as np
import pytest

from wb_runner import run_gui_macro

TIMEOUT = 240
STEPS = 21                    # the macro's step count
SCREENSHOTS = {               # step -> minimum number of the model's own pixels
    "Cagd_BezierCurve": 200, "Cagd_BSplineCurve": 200, "Cagd_InterpolationCurve": 200,
    "Cagd_CubicSpline": 200, "Cagd_HermiteCurve": 200, "Cagd_Join": 200,
    "Cagd_BezierSurface": 5000, "Cagd_BSplineSurface": 5000, "Cagd_BezierTriangle": 5000,
    "Cagd_CoonsPatch": 5000, "Cagd_Revolution": 5000, "Cagd_ContinuityCheck": 200,
    "Cagd_ToggleComb": 200, "Cagd_ToggleControlNet": 200, "Cagd_IntersectionCurve": 200,
    "Cagd_DeviationMap": 1000, "Cagd_FitCurve": 200, "Cagd_FitSurface": 5000,
    "Cagd_GordonSurface": 5000, "Cagd_Sweep": 5000, "Cagd_BlendSurface": 5000,
    "Cagd_ToggleCombSurface": 200, "Cagd_SurfaceAnalysis": 5000, "Cagd_SurfaceAnalysisZebra": 2000,
}
COLOURED = {"Cagd_DeviationMap": 1000}    # step -> minimum number of coloured (non-grey) model pixels


def model_pixels(shown, hidden):
    """Pixels that differ (by more than 0.1 in some channel) between the two images."""
    image = pytest.importorskip("matplotlib.image")
    a, b = image.imread(shown)[..., :3], image.imread(hidden)[..., :3]
    assert a.shape == b.shape and a.shape[0] > 100 and a.shape[1] > 100, f"{shown}: image size {a.shape}"
    return int((np.abs(a - b).max(axis=-1) > 0.1).sum())


def coloured_pixels(shown, hidden):
    """Model pixels (see model_pixels) that are clearly coloured: chroma (max - min
    channel) above 0.35, where the render without the object is grey (chroma < 0.1)."""
    image = pytest.importorskip("matplotlib.image")
    a, b = image.imread(shown)[..., :3], image.imread(hidden)[..., :3]
    chroma_a, chroma_b = np.ptp(a, axis=-1), np.ptp(b, axis=-1)
    return int(((np.abs(a - b).max(axis=-1) > 0.1) & (chroma_a > 0.35) & (chroma_b < 0.1)).sum())


def _image(path):
    image = pytest.importorskip("matplotlib.image")
    return image.imread(path)[..., :3]


def sphere_gaussian_colours(shown, hidden):
    """(red fraction of the model's pixels, model pixels, centre pixel is red): the
    Gaussian map of a sphere is uniform, K = +range, drawn red (1, 0, 0)."""
    a, b = _image(shown), _image(hidden)
    model = np.abs(a - b).max(axis=-1) > 0.1
    red = model & (a[..., 0] > 0.8) & (a[..., 1] < 0.2) & (a[..., 2] < 0.2)
    rows, cols = np.nonzero(model)
    centre = a[int(rows.mean()), int(cols.mean())]
    return red.sum() / max(model.sum(), 1), int(model.sum()), bool(centre[0] > 0.8 and centre[1:].max() < 0.2)


def zebra_rows(shown, hidden, fractions=(0.3, 0.5, 0.7)):
    """The dark columns of image rows across the cylinder (model rows at ``fractions``
    of its height): straight vertical stripes give the same columns on every row.
    Returns (transitions per row, largest number of columns where two rows differ)."""
    a, b = _image(shown), _image(hidden)
    model = np.abs(a - b).max(axis=-1) > 0.1
    rows = np.nonzero(model.any(axis=1))[0]
    picks = [int(rows[0] + f * (rows[-1] - rows[0])) for f in fractions]
    dark = [a[r].max(axis=-1) < 0.3 for r in picks]
    transitions = [int(np.count_nonzero(np.diff(d.astype(int)))) for d in dark]
    differ = max(int(np.count_nonzero(d != dark[0])) for d in dark)
    return transitions, differ


def red_marker(shown, hidden):
    """(pixels of the worst-station marker: red where the render without it is not,
    their mean row and column, the faces' top row and middle column in the render
    without it: the faces x in [-2, 2], y in [0, L] from the top, so the far end of the
    shared edge x = 0 is the middle of the top side)."""
    a, b = _image(shown), _image(hidden)
    red = (a[..., 0] > 0.8) & (a[..., 1] < 0.25) & (a[..., 2] < 0.25) & (np.abs(a - b).max(axis=-1) > 0.1)
    rows, cols = np.nonzero(red)
    frows, fcols = np.nonzero(b.min(axis=-1) < 0.9)
    return (int(red.sum()), (float(rows.mean()) if len(rows) else -1.0), (float(cols.mean()) if len(cols) else -1.0),
            int(frows.min()), (fcols.min() + fcols.max()) / 2.0)


def torus_signs(shown, hidden, outer=28.0, inner=12.0, radius=20.0, minor=8.0):
    """The torus' Gaussian map seen from the top: an annulus of radii inner..outer (mm)
    about its centre. Its pixel extent along the centre row gives centre and scale; at
    the radii radius +- minor / 2 (outer half: K > 0; inner half: K < 0) on both sides
    of the centre row and column, (red - blue) of the pixel. Returns the (4,) outer and
    (4,) inner values."""
    a, b = _image(shown), _image(hidden)
    model = np.abs(a - b).max(axis=-1) > 0.1
    rows, cols = np.nonzero(model)
    r0, r1, c0, c1 = rows.min(), rows.max(), cols.min(), cols.max()
    centre_r, centre_c = (r0 + r1) / 2.0, (c0 + c1) / 2.0
    scale = ((c1 - c0) + (r1 - r0)) / (4.0 * outer)          # pixels per mm
    def sample(rho):
        d = rho * scale
        pts = [(centre_r, centre_c + d), (centre_r, centre_c - d), (centre_r + d, centre_c), (centre_r - d, centre_c)]
        return np.array([a[int(round(r)), int(round(c)), 0] - a[int(round(r)), int(round(c)), 2] for r, c in pts])
    return sample(radius + minor / 2), sample(radius - minor / 2)


def colour_bar(out):
    """The surface analysis' colour bar in its screenshots (see gui_macro.py's
    surface_analysis_colour_bar): (bar pixels: coloured ones only with the bar on, the
    mean RGB of the bar's top and bottom tenth, the bar's leftmost column, the sphere's
    rightmost, the sphere's yellow fraction and centre colour with Range = 2 K)."""
    bar_on, bar_off, ranged = (_image(out / f"Cagd_SurfaceAnalysis{n}.png") for n in ("Legend", "Legend-hidden",
                                                                                      "Range"))
    bar = (np.abs(bar_on - bar_off).max(axis=-1) > 0.1) & (np.ptp(bar_on, axis=-1) > 0.35)
    rows, cols = np.nonzero(bar)
    tenth = max((rows.max() - rows.min()) // 10, 1) if len(rows) else 1
    top = bar_on[rows[rows <= rows.min() + tenth], cols[rows <= rows.min() + tenth]].mean(axis=0)
    bottom = bar_on[rows[rows >= rows.max() - tenth], cols[rows >= rows.max() - tenth]].mean(axis=0)
    sphere = bar_off.min(axis=-1) < 0.9                       # non-white pixels without the bar
    srows, scols = np.nonzero(sphere)
    yellow = sphere & (ranged[..., 0] > 0.8) & (ranged[..., 1] > 0.8) & (ranged[..., 2] < 0.2)
    centre = ranged[int(srows.mean()), int(scols.mean())]
    return int(bar.sum()), top, bottom, int(cols.min()), int(scols.max()), yellow.sum() / sphere.sum(), centre


def test_gui_commands_and_screenshots(freecad_env):
    result, out = run_gui_macro(freecad_env, "gui_macro.py", "workbench-gui", TIMEOUT)
    assert result["failed"] == 0, result["failures"]
    assert result["passed"] == STEPS
    counts = {}
    for name, minimum in SCREENSHOTS.items():
        shown, hidden = out / f"{name}.png", out / f"{name}-hidden.png"
        assert shown.is_file() and hidden.is_file(), f"screenshot {name} missing"
        counts[name] = model_pixels(shown, hidden)
    print("  model pixels per screenshot: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    print(f"  screenshots in {out}")
    low = {k: v for k, v in counts.items() if v < SCREENSHOTS[k]}
    assert not low, f"screenshots without the model: {low}"
    coloured = {name: coloured_pixels(out / f"{name}.png", out / f"{name}-hidden.png") for name in COLOURED}
    print("  coloured model pixels: " + ", ".join(f"{k} {v}" for k, v in coloured.items()))
    pale = {k: v for k, v in coloured.items() if v < COLOURED[k]}
    assert not pale, f"deviation map without its coloured points: {pale}"
    # the trimmed face drawn as itself: coloured pixels of the holed plate / the whole plate
    # = area ratio 1 - 16 pi / 100 (the UV box would give 1)
    holed, whole = (coloured_pixels(out / f"Cagd_DeviationMap{n}.png", out / f"Cagd_DeviationMap{n}-hidden.png")
                    for n in ("Holed", "Whole"))
    ratio, expected = holed / max(whole, 1), 1 - 16 * np.pi / 100
    print(f"  trimmed deviation map: {holed} / {whole} coloured pixels = {ratio:.4f} (area ratio {expected:.4f})")
    assert whole > 5000 and abs(ratio - expected) <= 0.05 * expected, (holed, whole, ratio)
    # surface analysis: the sphere's Gaussian map one colour (red = +range), the cylinder's
    # zebra straight stripes (the same dark columns on rows across it)
    fraction, pixels, centre = sphere_gaussian_colours(out / "Cagd_SurfaceAnalysis.png",
                                                       out / "Cagd_SurfaceAnalysis-hidden.png")
    print(f"  sphere Gaussian map: {fraction:.4f} of {pixels} model pixels red, centre red {centre}")
    assert pixels > 5000 and fraction >= 0.95 and centre, (fraction, pixels, centre)
    transitions, differ = zebra_rows(out / "Cagd_SurfaceAnalysisZebra.png",
                                     out / "Cagd_SurfaceAnalysisZebra-hidden.png")
    print(f"  cylinder zebra: dark/light transitions per row {transitions}, rows differ in {differ} columns")
    assert min(transitions) >= 4 and len(set(transitions)) == 1 and differ <= 4, (transitions, differ)
    # the colour bar: blue (-range) at the bottom to red (+range) at the top, right of the
    # sphere; Range = 2 K turns the sphere yellow (the scale's 3/4 stop)
    pixels, top, bottom, bar_left, sphere_right, yellow, centre = colour_bar(out)
    print(f"  colour bar: {pixels} pixels, top {np.round(top, 2)}, bottom {np.round(bottom, 2)}, from column "
          f"{bar_left} (sphere to {sphere_right}); Range 0.02: {yellow:.4f} of the sphere yellow, centre {centre}")
    assert pixels >= 300 and bar_left > sphere_right, (pixels, bar_left, sphere_right)
    assert top[0] > 0.8 and top[2] < 0.2 and bottom[2] > 0.8 and bottom[0] < 0.2, (top, bottom)
    assert yellow >= 0.9 and centre[0] > 0.8 and centre[1] > 0.8 and centre[2] < 0.2, (yellow, centre)
    # issue 19: the worst station of the growing kink (the far end of the shared edge) marked red
    pixels, row, col, top, middle = red_marker(out / "Cagd_ContinuityStation.png",
                                               out / "Cagd_ContinuityStation-hidden.png")
    print(f"  worst-station marker: {pixels} red pixels at row {row:.1f}, column {col:.1f}; "
          f"the far end of the shared edge at row {top}, column {middle:.1f}")
    assert pixels >= 20 and abs(row - top) <= 4 and abs(col - middle) <= 4, (pixels, row, col, top, middle)
    # the torus' Gaussian map: K > 0 on the outer half (towards red), K < 0 on the inner (towards blue)
    outer, inner = torus_signs(out / "Cagd_TorusGaussian.png", out / "Cagd_TorusGaussian-hidden.png")
    print(f"  torus Gaussian map, red - blue: outer half {np.round(outer, 2)}, inner half {np.round(inner, 2)}")
    assert outer.min() > 0.3 and inner.max() < -0.3, (outer, inner)
    assert os.path.getsize(out / "macro.log") > 0
