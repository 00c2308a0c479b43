"""Helpers shared by the workbench tests (see conftest.py)."""
import json
import os
import shutil
import signal
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ADDON = ROOT / "workbench"
OUT = ROOT / "out"
RESULT = "CAGD_WB_RESULT "


def need(tool_names, what):
    """The first tool found on PATH; skip (fail on CI) when none is."""
    for name in tool_names:
        path = shutil.which(name)
        if path:
            return path
    message = (f"{what} not installed ({' or '.join(tool_names)} not on PATH); "
               "`python3 dev.py test` installs it as root (apt-get install freecad xvfb)")
    if os.environ.get("CI"):
        pytest.fail(message)
    pytest.skip(message)


def output_dir(name):
    """A fresh out/<name> folder in the repo (ignored by git) for the run's files."""
    path = OUT / name
    shutil.rmtree(path, ignore_errors=True)
    path.mkdir(parents=True)
    return path


def run_group(cmd, env, timeout, log_path):
    """Run cmd in a new process group; kill the whole group on timeout. Returns
    (exit code or None on timeout, combined output)."""
    with open(log_path, "w+", encoding="utf-8", errors="replace") as log:
        proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, cwd=str(ROOT),
                                start_new_session=True)
        try:
            code = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            code = None
        log.seek(0)
        return code, log.read()


def run_gui_macro(env, macro, out_name, timeout):
    """Run workbench/tests/<macro> in FreeCAD's GUI under Xvfb with its output in
    out/<out_name>; returns (the macro's result.json with passed/failed as counts and the
    failures listed, the output folder). Fails when FreeCAD times out or writes no result."""
    exe = need(["freecad", "FreeCAD"], "FreeCAD")
    xvfb = need(["xvfb-run"], "Xvfb")
    out = output_dir(out_name)
    env.update(CAGD_WB_OUT=str(out), QTWEBENGINE_DISABLE_SANDBOX="1", QT_QPA_PLATFORM="xcb")
    log = out / "freecad-gui.log"
    code, output = run_group([xvfb, "-a", "-s", "-screen 0 1280x1024x24", exe, str(ADDON / "tests" / macro)],
                             env, timeout, log)
    assert code is not None, f"FreeCAD GUI timed out after {timeout} s (macro log {out / 'macro.log'})"
    result_path = out / "result.json"
    assert result_path.is_file(), f"macro wrote no result (exit {code}); log {log}:\n{output[-3000:]}"
    result = json.loads(result_path.read_text())
    result.update(passed=len(result["passed"]), failed=len(result["failed"]), failures=result["failed"])
    report(f"FreeCAD GUI {macro}", result, log)
    return result, out


def summary(output):
    """The JSON summary from the suite's last CAGD_WB_RESULT line (None if absent)."""
    lines = [line for line in output.splitlines() if RESULT in line]
    if not lines:
        return None
    return json.loads(lines[-1].split(RESULT, 1)[1])


def report(name, result, log_path):
    print(f"\n{name}: {result['passed']} passed, {result['failed']} failed "
          f"({result.get('seconds')} s in FreeCAD {result.get('freecad')}, numpy {result.get('numpy')})")
    for case, message in result.get("failures", {}).items():
        print(f"  FAILED {case}: {message}")
    if "max_deviation" in result:
        print("  max relative deviations: " + ", ".join(f"{k} {v:.3g}" for k, v in result["max_deviation"].items()))
    print(f"  output: {result.get('out')}  log: {log_path}")
