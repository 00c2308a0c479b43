"""The pole edit mode in FreeCAD's GUI under Xvfb (workbench/tests/gui_edit_macro.py):
real Qt mouse drags on the 3-D view move a curve's and a surface's poles, one undo
step each; the macro's checks must all pass. Here: the redraw rates it measured
(printed; only a generous floor is asserted, the machine's software OpenGL and load
set the rest) and its screenshot: the model's own pixels and the markers' (dark
points, the picked one orange) against the same view out of edit mode."""
import json

import numpy as np
import pytest

from wb_runner import ADDON, need, output_dir, report, run_group

TIMEOUT = 240
STEPS = 6                     # the macro's step count
MIN_REDRAWS_PER_S = 0.5       # a floor only: a drag that stops redrawing fails
MARKERS = 6                   # poles of the screenshot's curve


def _image(path):
    image = pytest.importorskip("matplotlib.image")
    return image.imread(path)[..., :3]


def test_gui_pole_editing(freecad_env):
    exe = need(["freecad", "FreeCAD"], "FreeCAD")
    xvfb = need(["xvfb-run"], "Xvfb")
    out = output_dir("workbench-gui-edit")
    freecad_env.update(CAGD_WB_OUT=str(out), QTWEBENGINE_DISABLE_SANDBOX="1", QT_QPA_PLATFORM="xcb")
    log = out / "freecad-gui.log"
    code, output = run_group([xvfb, "-a", "-s", "-screen 0 1280x1024x24", exe,
                              str(ADDON / "tests" / "gui_edit_macro.py")], freecad_env, TIMEOUT, log)
    assert code is not None, f"FreeCAD GUI timed out after {TIMEOUT} s (macro log {out / 'macro.log'})"
    result_path = out / "result.json"
    assert result_path.is_file(), f"macro wrote no result (exit {code}); log {log}:\n{output[-3000:]}"
    result = json.loads(result_path.read_text())
    result.update(passed=len(result["passed"]), failed=len(result["failed"]), failures=result["failed"])
    report("FreeCAD GUI pole editing", result, log)
    for name, r in result["rates"].items():
        print(f"  {name}: {r['redraws_per_s']:.1f} redraws/s, {r['updates_per_s']:.1f} updates/s, editor "
              f"{r['editor_ms_per_update']:.1f} ms per update, a redraw alone {r['frame_ms']:.1f} ms "
              f"(viewport {r['viewport']}, load {r['load']:.1f})")
    assert result["failed"] == 0, result["failures"]
    assert result["passed"] == STEPS
    assert set(result["rates"]) == {"curve 200 poles + comb", "surface 30x30 + net"}
    for name, r in result["rates"].items():
        assert r["updates"] > 0 and r["redraws_per_s"] >= MIN_REDRAWS_PER_S, (name, r)
    # the screenshot: model pixels (edit mode vs the curve hidden), marker pixels (edit
    # mode vs the same curve out of edit mode: only the markers differ), the picked one orange
    shown, hidden, plain = (_image(out / f"EditPoles{s}.png") for s in ("", "-hidden", "-plain"))
    assert shown.shape == hidden.shape == plain.shape and shown.shape[0] > 100
    model = int((np.abs(shown - hidden).max(axis=-1) > 0.1).sum())
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
