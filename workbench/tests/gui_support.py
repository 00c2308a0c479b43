"""Shared by the GUI test macros (gui_macro.py, gui_edit_macro.py): the cagdwb import
(the installed addon, else the folder named by CAGD_WB_ADDON), the output folder
$CAGD_WB_OUT with its macro.log, the step registry and the runner that runs every
step, writes ``result.json`` and ends FreeCAD with ``os._exit`` (the GUI does not exit
by itself). A macro starts the runner with ``QtCore.QTimer.singleShot(500, run)`` once
the main window is up."""
import json
import os
import sys
import time
import traceback

import FreeCAD as App

try:
    import cagdwb  # noqa: F401  (the installed addon, see workbench/install.py)
except ImportError:
    sys.path.insert(0, os.environ["CAGD_WB_ADDON"])          # or the addon folder named here
from cagdwb.qt import QtCore, QtWidgets  # noqa: E402,F401  (QtCore for the macros)

OUT = os.environ.get("CAGD_WB_OUT", "/tmp/cagd-wb-gui")
os.makedirs(OUT, exist_ok=True)
LOG = open(os.path.join(OUT, "macro.log"), "w", encoding="utf-8")
RESULT = {"passed": [], "failed": {}, "out": OUT}
STEPS = []


def log(msg):
    LOG.write(f"{time.strftime('%H:%M:%S')} {msg}\n")
    LOG.flush()


def check(cond, message):
    if not cond:
        raise AssertionError(message)


def settle(n=5):
    for _ in range(n):
        QtWidgets.QApplication.processEvents()


def show_only(objs, orientation="viewIsometric"):
    """Only ``objs`` shown, nothing selected, the 3-D view turned (``orientation``: the
    name of a view method such as viewTop) and fitted; returns the view."""
    import FreeCADGui as Gui
    Gui.Selection.clearSelection()
    for o in App.ActiveDocument.Objects:
        o.ViewObject.Visibility = o in objs
    view = Gui.ActiveDocument.ActiveView
    getattr(view, orientation)()
    view.fitAll()
    settle()
    return view


def step(fn):
    STEPS.append(fn)
    return fn


def run(after_failure=None):
    """Every step in order (a failure is recorded and ``after_failure()`` called, then
    the next step runs); the summary to result.json; FreeCAD ended."""
    start = time.time()
    try:
        for fn in STEPS:
            try:
                fn()
            except Exception as exc:
                RESULT["failed"][fn.__name__] = f"{type(exc).__name__}: {exc}"
                log(f"FAIL {fn.__name__}\n{traceback.format_exc()}")
                if after_failure is not None:
                    after_failure()
            else:
                RESULT["passed"].append(fn.__name__)
                log(f"ok   {fn.__name__}")
        import numpy
        RESULT.update(seconds=round(time.time() - start, 2), freecad=".".join(App.Version()[:3]),
                      numpy=numpy.__version__)
        with open(os.path.join(OUT, "result.json"), "w", encoding="utf-8") as f:
            json.dump(RESULT, f, indent=1)
    finally:
        LOG.close()
        sys.stdout.flush()
        os._exit(0)
