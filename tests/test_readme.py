"""Every code snippet in README.md and workbench/README.md runs: the ```python blocks as
scripts, and the `cagd ...` lines of the ```sh blocks through the installed command,
each in a fresh folder outside the checkout (``examples/`` linked in, so the paths the
README uses resolve). The snippets are read from the READMEs, never copied.

A python block that imports a library this environment lacks is skipped (CadQuery in
the OCCT 8.0 stage); a block whose first line is ``# needs: build123d`` likewise.
Shell lines that set up the machine (apt-get, dev.py, pip, the FreeCAD installer) are
not run here: tests/test_packaging.py and CI run those.
"""
from __future__ import annotations

import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from typing import List, Tuple

import pytest

ROOT = Path(__file__).resolve().parents[1]
READMES = [ROOT / "README.md", ROOT / "workbench" / "README.md"]
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.S | re.M)
SNIPPET_TIMEOUT = 600      # s
OPTIONAL = ("cadquery", "build123d", "OCP", "matplotlib", "scipy")


def snippets() -> List[Tuple[str, str, str]]:
    """(id, language, code) of every fenced block, ids readme:line."""
    out = []
    for readme in READMES:
        text = readme.read_text(encoding="utf-8")
        for m in FENCE.finditer(text):
            line = text[:m.start()].count("\n") + 1
            out.append((f"{readme.relative_to(ROOT)}:{line}", m.group(1), m.group(2)))
    return out


def needs(code: str) -> List[str]:
    wanted = set(re.findall(r"^\s*(?:import|from)\s+(\w+)", code, re.M)) & set(OPTIONAL)
    first = code.lstrip().splitlines()[0] if code.strip() else ""
    if first.startswith("# needs:"):
        wanted |= {w.strip() for w in first.split(":", 1)[1].split(",")}
    return sorted(w for w in wanted if importlib.util.find_spec(w) is None)


def workdir(tmp_path: Path) -> Path:
    (tmp_path / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    (tmp_path / "out").mkdir()
    return tmp_path


def env() -> dict:
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


SNIPPETS = snippets()
PYTHON = [s for s in SNIPPETS if s[1] == "python"]
SHELL = [(i, line) for i, lang, code in SNIPPETS if lang == "sh" for line in code.splitlines()
         if line.strip().startswith("cagd ")]


def test_the_readmes_have_snippets():
    assert len(PYTHON) >= 4 and SHELL


@pytest.mark.parametrize("ident,lang,code", PYTHON, ids=[s[0] for s in PYTHON])
def test_python_snippet_runs(ident, lang, code, tmp_path):
    missing = needs(code)
    if missing:
        pytest.skip(f"{ident} needs {', '.join(missing)}")
    script = workdir(tmp_path) / "snippet.py"
    script.write_text(code, encoding="utf-8")
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True,
                          timeout=SNIPPET_TIMEOUT, env=env())
    assert done.returncode == 0, f"{ident}\n{code}\n{done.stdout[-2000:]}\n{done.stderr[-4000:]}"


@pytest.mark.parametrize("ident,line", SHELL, ids=[s[0] for s in SHELL])
def test_cli_line_runs(ident, line, tmp_path):
    pytest.importorskip("OCP")
    exe = shutil.which("cagd", path=os.path.dirname(sys.executable)) or shutil.which("cagd")
    assert exe, "the cagd command is not installed"
    args = shlex.split(line.split("#", 1)[0])[1:]
    done = subprocess.run([exe, *args], cwd=workdir(tmp_path), capture_output=True, text=True,
                          timeout=SNIPPET_TIMEOUT, env=env())
    assert done.returncode == 0, f"{ident}: {line}\n{done.stdout[-2000:]}\n{done.stderr[-4000:]}"
