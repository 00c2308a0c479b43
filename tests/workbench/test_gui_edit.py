"""The pole edit mode in FreeCAD's GUI under Xvfb (workbench/tests/gui_edit_macro.py):
real Qt mouse drags on the 3-D view move a curve's and a surface's poles, one undo
step each; the macro's checks must all pass. Here: the redraw rates it measured
(printed; only a generous floor is asserted, the machine's software OpenGL and load
set the rest), that each move is painted once (a count, not a time), and its
screenshot: the model's own pixels and the markers' (dark points, the picked one
orange) against the same view out of edit mode."""
import numpy as np

from test_gui import _image, model_pixels
from wb_runner import run_gui_macro

TIMEOUT = 240
STEPS = 9                     # the macro's step count
MIN_REDRAWS_PER_S = 0.5       # a floor only: a drag that stops redrawing fails
EXTRA_PAINTS = 2              # paints beyond one per move (the press's marker change, a late delay-queue one)
MARKERS = 6                   # poles of the screenshot's curve


def test_gui_pole_editing(freecad_env):
    result, out = run_gui_macro(freecad_env, "gui_edit_macro.py", "workbench-gui-edit", TIMEOUT)
    for name, r in result["rates"].items():
        print(f"  {name}: {r['redraws_per_s']:.1f} redraws/s, {r['updates_per_s']:.1f} updates/s "
              f"({r['paints']} paints, {r['updates']} updates), editor "
              f"{r['editor_ms_per_update']:.1f} ms per update, a redraw alone {r['frame_ms']:.1f} ms "
              f"(viewport {r['viewport']}, load {r['load']:.1f}); CPU per update: GUI thread "
              f"{r['gui_cpu_ms_per_update']:.1f} ms, other threads {r['other_cpu_ms_per_update']:.1f} ms")
    assert result["failed"] == 0, result["failures"]
    assert result["passed"] == STEPS
    assert set(result["rates"]) == {"curve 200 poles + comb", "surface 30x30 + net"}
    for name, r in result["rates"].items():
        assert r["updates"] > 0 and r["redraws_per_s"] >= MIN_REDRAWS_PER_S, (name, r)
        # each move that changes the geometry is painted once (the editor asks for the
        # paint; Coin's delay queue alone painted every second move), none twice
        assert r["updates"] - 1 <= r["paints"] <= r["updates"] + EXTRA_PAINTS, (name, r)
    # the screenshot: model pixels (edit mode vs the curve hidden), marker pixels (edit
    # mode vs the same curve out of edit mode: only the markers differ), the picked one orange
    model = model_pixels(out / "EditPoles.png", out / "EditPoles-hidden.png")
    shown, plain = _image(out / "EditPoles.png"), _image(out / "EditPoles-plain.png")
    assert shown.shape == plain.shape
    markers = np.abs(shown - plain).max(axis=-1) > 0.1
    dark = markers & (shown.max(axis=-1) < 0.3)
    orange = markers & (shown[..., 0] > 0.8) & (np.abs(shown[..., 1] - 0.55) < 0.15) & (shown[..., 2] < 0.2)
    print(f"  screenshot: {model} model pixels, {int(markers.sum())} marker pixels ({int(dark.sum())} dark, "
          f"{int(orange.sum())} orange)")
    assert model >= 200, model
    assert dark.sum() >= (MARKERS - 1) * 20, int(dark.sum())        # a 7-pixel point is 49 pixels
    assert orange.sum() >= 60, int(orange.sum())                     # the picked pole: an 11-pixel point
    rows, cols = np.nonzero(orange)
    assert np.ptp(rows) <= 14 and np.ptp(cols) <= 14, "orange pixels not one marker"
