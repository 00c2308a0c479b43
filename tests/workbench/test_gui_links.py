"""The task panel's link rows in FreeCAD's GUI under Xvfb (workbench/tests/gui_links_macro.py):
the selection made through FreeCADGui.Selection, the Add selection / Remove / Up / Down
and Set from selection buttons pressed by Qt mouse events; a Gordon surface's new guide
checked against the engine's cagd.gordon, Cancel restoring links and shape. The macro's
checks must all pass."""
from wb_runner import run_gui_macro

TIMEOUT = 240
STEPS = 5                     # the macro's step count


def test_gui_link_rows(freecad_env):
    result, _ = run_gui_macro(freecad_env, "gui_links_macro.py", "workbench-gui-links", TIMEOUT)
    assert result["failed"] == 0, result["failures"]
    assert result["passed"] == STEPS
