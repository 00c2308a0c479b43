"""The workbench's headless suite (workbench/tests/headless_suite.py), run by
FreeCAD's own interpreter freecadcmd with the addon installed for a throw-away user;
its pass/fail counts are printed and any failure fails this test."""
from wb_runner import ADDON, output_dir, need, report, run_group, summary

EXPECTED_CASES = 76        # the suite's case count: a suite that stopped early fails too
TIMEOUT = 300


def test_headless_suite(freecad_env):
    exe = need(["freecadcmd", "FreeCADCmd"], "FreeCAD")
    out = output_dir("workbench-headless")
    freecad_env["CAGD_WB_OUT"] = str(out)
    freecad_env["CAGD_WB_EXIT"] = "1"
    log = out / "freecadcmd.log"
    code, output = run_group([exe, str(ADDON / "tests" / "headless_suite.py")], freecad_env, TIMEOUT, log)
    assert code is not None, f"freecadcmd timed out after {TIMEOUT} s; log {log}"
    result = summary(output)
    assert result is not None, f"no summary line from the suite (exit {code}); log {log}:\n{output[-3000:]}"
    report("FreeCAD headless suite", result, log)
    assert result["failed"] == 0, result["failures"]
    assert result["passed"] >= EXPECTED_CASES
    for kind, value in result["max_deviation"].items():
        assert value <= 1e-9, f"{kind} deviation {value}"
