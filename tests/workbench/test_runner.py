"""The FreeCAD test runner helpers themselves (no FreeCAD needed): the summary line
is found and parsed, a hanging process group is killed at the timeout."""
import sys
import time

from wb_runner import report, run_group, summary


def test_summary_takes_the_last_result_line():
    out = ("noise\nCAGD_WB_RESULT {\"passed\": 1, \"failed\": 2}\nmore\n"
           "\x1b[0mCAGD_WB_RESULT {\"passed\": 3, \"failed\": 0}\n")
    assert summary(out) == {"passed": 3, "failed": 0}
    assert summary("no result here\n") is None


def test_timeout_kills_the_whole_process_group(tmp_path):
    child = tmp_path / "child.pid"
    script = ("import os, subprocess, sys, time; "
              f"p = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)']); "
              f"open({str(child)!r}, 'w').write(str(p.pid)); time.sleep(60)")
    start = time.monotonic()
    code, _ = run_group([sys.executable, "-c", script], None, 2, tmp_path / "log.txt")
    assert code is None and time.monotonic() - start < 30
    pid = int(child.read_text())
    for _ in range(50):                         # the grandchild must be gone too
        try:
            with open(f"/proc/{pid}/stat") as f:
                state = f.read().split()[2]
        except FileNotFoundError:
            break
        if state == "Z":
            break
        time.sleep(0.1)
    else:
        raise AssertionError(f"process {pid} survived the timeout")


def test_report_prints_failures(capsys, tmp_path):
    report("suite", {"passed": 1, "failed": 1, "failures": {"case_a": "boom"}, "max_deviation": {"step": 1e-13}},
           tmp_path / "log")
    out = capsys.readouterr().out
    assert "1 passed, 1 failed" in out and "FAILED case_a: boom" in out and "step 1e-13" in out
