"""Every script in examples/ runs, passes its own checks and writes its model files."""
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples").glob("*.py"))


def test_there_are_examples():
    assert EXAMPLES


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs(script, tmp_path):
    pytest.importorskip("matplotlib")
    done = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, timeout=600,
                          cwd=script.parent.parent)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "checks passed" in done.stdout
    outputs = [p for p in tmp_path.iterdir() if p.stat().st_size > 1000]
    assert outputs, "the example wrote no model or picture"
