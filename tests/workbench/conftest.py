"""Fixtures for the FreeCAD workbench tests: find FreeCAD, install the addon into a
throw-away FreeCAD user folder, run FreeCAD in its own process group under a
timeout and read the suite's ``CAGD_WB_RESULT {json}`` summary line.

Without FreeCAD the tests skip locally but fail when the environment variable CI is
set (CI installs FreeCAD through ``python3 dev.py test``; a skip would hide breakage).
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from wb_runner import ADDON  # noqa: E402


@pytest.fixture
def freecad_env(tmp_path):
    """Environment for a FreeCAD run with the addon installed by workbench/install.py
    into a temporary FreeCAD user folder (the real user's home is not touched)."""
    env = dict(os.environ)
    env["HOME"] = str(tmp_path / "home")
    env["FREECAD_USER_HOME"] = str(tmp_path / "freecad")
    env["TMPDIR"] = str(tmp_path / "tmp")      # FreeCAD's temporary files (Start's thumbnails) stay in here
    env["CAGD_WB_EXPECT_INSTALLED"] = "1"
    env.pop("CAGD_PATH", None)
    os.makedirs(env["HOME"])
    os.makedirs(env["TMPDIR"])
    done = subprocess.run([sys.executable, str(ADDON / "install.py")], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (Path(env["FREECAD_USER_HOME"]) / "Mod" / "CagdWorkbench" / "Init.py").is_file()
    return env
