"""``cagd mesh`` via subprocess on a STEP file the test writes: OCCT's RWStl re-reads
the STL with the triangle count printed, and a bad input exits 2 naming the argument."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from trim_shapes import square_patch

ROOT = Path(__file__).resolve().parents[2]


def _run(*argv):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "cagd.cli", *argv], capture_output=True, text=True, env=env,
                          timeout=300)


def test_mesh_step_to_stl(tmp_path):
    occ = pytest.importorskip("cagd.occ")
    from OCP.RWStl import RWStl
    step = tmp_path / "p.step"
    occ.write_step([square_patch()], step)
    out = tmp_path / "p.stl"
    r = _run("mesh", str(step), "-o", str(out), "--tol", "1e-3")
    assert r.returncode == 0, r.stderr
    n = int(r.stdout.split(" triangles")[0].split()[-1])
    assert RWStl.ReadFile_s(str(out)).NbTriangles() == n > 0


def test_mesh_bad_input(tmp_path):
    bad = tmp_path / "x.txt"
    bad.write_text("nothing")
    r = _run("mesh", str(bad), "-o", str(tmp_path / "x.stl"))
    assert r.returncode == 2 and "model" in r.stderr
