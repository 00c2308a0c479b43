#!/usr/bin/env python3
"""Bootstrap and run the cagd toolkit on a fresh machine with only python3.

Usage (commands run in the repo root, so relative paths are taken from there):
    python3 dev.py demo [args...]         run `cagd demo` (e.g. -o OUTDIR)
    python3 dev.py test [pytest args...]  run the whole test suite

Both first make the virtual environment .venv in the repo root and install the
project into it with `pip install -e '.[cad,test,plot]'`, installing first, as
root, the Debian packages that venv and OCP need (python3.X-venv, libgl1,
libx11-6).  All that is skipped when .venv/.cagd-installed holds the sha256 of
setup.cfg and pyproject.toml, so a second run starts at once.

`test` also installs, as root, FreeCAD and Xvfb (Debian packages freecad, xvfb,
xauth) when missing, for the FreeCAD workbench tests (tests/workbench); without root
those tests are skipped (and fail when the environment variable CI is set).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from ctypes.util import find_library
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / "bin"
PYTHON = BIN / "python"
STAMP = VENV / ".cagd-installed"
EXTRAS = "cad,test,plot"
PYTEST_NO_TESTS = 5
# Shared libraries that OCP (OpenCascade, VTK build) loads, by Debian package.
SYSTEM_LIBS = {"GL": "libgl1", "X11": "libx11-6"}
# Programs the FreeCAD workbench tests run (any of the names), by Debian package
# (xvfb-run needs xauth, which xvfb only recommends).
TEST_TOOLS = {"freecad": ("freecadcmd", "FreeCADCmd"), "xvfb": ("xvfb-run",), "xauth": ("xauth",)}


def log(msg: str) -> None:
    print(f"[dev] {msg}", file=sys.stderr, flush=True)


def run(cmd: Sequence[str | Path]) -> int:
    """Run a command in the repo root and return its exit code."""
    return subprocess.call([str(c) for c in cmd], cwd=ROOT)


def check(cmd: Sequence[str | Path], what: str) -> None:
    code = run(cmd)
    if code != 0:
        log(f"{what} failed (exit code {code})")
        sys.exit(code)


def venv_module_ok() -> bool:
    """venv needs ensurepip, which Debian ships apart in python3.X-venv."""
    return all(importlib.util.find_spec(m) is not None for m in ("venv", "ensurepip"))


def venv_ready() -> bool:
    """True if .venv has a python and pip (a failed `venv` run leaves no pip)."""
    return PYTHON.exists() and any(VENV.glob("lib*/python*/site-packages/pip"))


def missing_debian_packages() -> list[str]:
    """Debian packages still needed to make .venv and to import OCP."""
    missing = []
    if not venv_ready() and not venv_module_ok():
        missing.append(f"python3.{sys.version_info.minor}-venv")
    if sys.platform.startswith("linux"):
        missing += [pkg for lib, pkg in SYSTEM_LIBS.items() if not find_library(lib)]
    return missing


def install_debian_packages(packages: list[str]) -> None:
    """apt-get install the packages as root; otherwise say what to run, exit 1."""
    command = ["apt-get", "install", "-y", *packages]
    if os.geteuid() != 0 or shutil.which("apt-get") is None:
        log(f"missing system packages: {' '.join(packages)}")
        log(f"install them, then run again:  sudo {' '.join(command)}")
        sys.exit(1)
    log(f"installing Debian packages: {' '.join(packages)}")
    os.environ["DEBIAN_FRONTEND"] = "noninteractive"
    check(["apt-get", "update"], "apt-get update")
    check(command, "apt-get install")


def missing_test_packages() -> list[str]:
    """Debian packages of the programs the FreeCAD workbench tests need."""
    if not sys.platform.startswith("linux"):
        return []
    return [pkg for pkg, names in TEST_TOOLS.items() if not any(shutil.which(n) for n in names)]


def ensure_test_tools() -> None:
    """apt-get install FreeCAD and Xvfb as root when missing; otherwise say how."""
    packages = missing_test_packages()
    if not packages:
        return
    if os.geteuid() != 0 or shutil.which("apt-get") is None:
        log(f"missing test programs (Debian packages {' '.join(packages)}): the FreeCAD workbench "
            "tests will be skipped (with CI set they fail)")
        log(f"to run them:  sudo apt-get install -y {' '.join(packages)}")
        return
    install_debian_packages(packages)


def deps_hash() -> str:
    digest = hashlib.sha256()
    for name in ("setup.cfg", "pyproject.toml"):
        digest.update(name.encode() + b"\0" + (ROOT / name).read_bytes() + b"\0")
    return digest.hexdigest()


def ensure_env() -> None:
    want = deps_hash()
    if venv_ready() and STAMP.exists() and STAMP.read_text().strip() == want:
        log("dependencies up to date (stamp matches)")
        return
    packages = missing_debian_packages()
    if packages:
        install_debian_packages(packages)
    if not venv_ready():
        log(f"creating virtual environment {VENV}")
        check([sys.executable, "-m", "venv", "--clear", VENV], "creating .venv")
    log(f"installing cagd with extras [{EXTRAS}] into .venv (takes a minute or two)")
    check([PYTHON, "-m", "pip", "install", "-e", f".[{EXTRAS}]"], "pip install")
    STAMP.write_text(want + "\n")
    log("install done")


def cmd_demo(args: list[str]) -> int:
    log("running: cagd demo " + " ".join(args))
    return run([BIN / "cagd", "demo", *args])


def cmd_test(args: list[str]) -> int:
    ensure_test_tools()
    log("running: pytest " + " ".join(args))
    code = run([PYTHON, "-m", "pytest", *args])
    if code == PYTEST_NO_TESTS:
        log("pytest collected no tests: treating that as a failure")
        return 1
    return code


COMMANDS = {"demo": cmd_demo, "test": cmd_test}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in COMMANDS:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    ensure_env()
    return COMMANDS[argv[0]](argv[1:])


if __name__ == "__main__":
    sys.exit(main())
