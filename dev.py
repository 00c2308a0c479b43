#!/usr/bin/env python3
"""Bootstrap and run the cagd toolkit on a fresh machine with only python3.

Usage (commands run in the repo root, so relative paths are taken from there):
    python3 dev.py demo [args...]         run `cagd demo` (e.g. -o OUTDIR)
    python3 dev.py test [pytest args...]  run the whole test suite (both OCCT lines)
    python3 dev.py test-b3d [pytest args...]  only the OCCT 8.0 / build123d 0.13 stage

Both first make the virtual environment .venv in the repo root and install the
project into it with `pip install -e '.[cad,test,plot,lint,dask]'` (CadQuery 2.8, OCCT 7.9;
dask for the test that runs the queries on a local Dask cluster),
installing first, as root, the Debian packages that venv and OCP need
(python3.X-venv, libgl1, libx11-6).  All that is skipped when .venv/.cagd-installed
holds the sha256 of setup.py, setup.cfg and pyproject.toml, so a second run starts
at once.

`test` first runs ruff and mypy (configured in pyproject.toml), then builds the
wheel (.build/wheel/, its path in CAGD_WHEEL for the packaging test), runs pytest
in .venv, then the OCCT 8.0 stage: the wheel installed with its extras [b3d,test]
(build123d 0.13, OCCT 8.0, no CadQuery) into .venv-b3d, not editable, and the
bridge, file and build123d tests run against it from a folder outside the
checkout. With pytest arguments only the first stage runs. `test` also installs,
as root, FreeCAD and Xvfb (Debian packages freecad, xvfb, xauth) when missing, for
the FreeCAD workbench tests (tests/workbench); without root those tests
are skipped (and fail when the environment variable CI is set).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from ctypes.util import find_library
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / "bin"
PYTHON = BIN / "python"
STAMP = VENV / ".cagd-installed"
EXTRAS = "cad,test,plot,lint,dask"
VENV_B3D = ROOT / ".venv-b3d"
EXTRAS_B3D = "b3d,test"
WHEEL_DIR = ROOT / ".build" / "wheel"
# the tests of the second OCCT line (8.0, build123d 0.13): bridge, files, build123d helpers
B3D_TESTS = ["tests/occ", "tests/curves/test_occ_form.py", "tests/b3d", "tests/test_packaging.py",
             "tests/test_readme.py"]
DEPENDENCY_FILES = ("setup.py", "setup.cfg", "pyproject.toml")
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


def venv_ready(venv: Path = VENV) -> bool:
    """True if the venv has a python and pip (a failed `venv` run leaves no pip)."""
    return (venv / "bin" / "python").exists() and any(venv.glob("lib*/python*/site-packages/pip"))


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
    for name in DEPENDENCY_FILES:
        digest.update(name.encode() + b"\0" + (ROOT / name).read_bytes() + b"\0")
    return digest.hexdigest()


def make_venv(venv: Path) -> None:
    if not venv_ready(venv):
        log(f"creating virtual environment {venv}")
        check([sys.executable, "-m", "venv", "--clear", venv], f"creating {venv.name}")


def ensure_env() -> None:
    want = deps_hash()
    if venv_ready() and STAMP.exists() and STAMP.read_text().strip() == want:
        log("dependencies up to date (stamp matches)")
        return
    packages = missing_debian_packages()
    if packages:
        install_debian_packages(packages)
    make_venv(VENV)
    log(f"installing cagd with extras [{EXTRAS}] into .venv (takes a minute or two)")
    check([PYTHON, "-m", "pip", "install", "-e", f".[{EXTRAS}]"], "pip install")
    STAMP.write_text(want + "\n")
    log("install done")


def build_wheel() -> Path:
    """The project's wheel, built afresh into .build/wheel/ (what `pip install cagd` gets)."""
    shutil.rmtree(WHEEL_DIR, ignore_errors=True)
    log("building the wheel")
    check([PYTHON, "-m", "pip", "wheel", "--no-deps", "-q", "-w", WHEEL_DIR, "."],
          "building the wheel")
    wheels = sorted(WHEEL_DIR.glob("cagd-*.whl"))
    if len(wheels) != 1:
        log(f"expected one wheel in {WHEEL_DIR}, found {[w.name for w in wheels]}")
        sys.exit(1)
    return wheels[0]


def ensure_b3d_env(wheel: Path) -> Path:
    """.venv-b3d with the wheel and its extras [b3d,test] (OCCT 8.0), not editable: the
    dependencies are installed once per dependency stamp, the wheel itself every run."""
    python = VENV_B3D / "bin" / "python"
    stamp = VENV_B3D / ".cagd-installed"
    want = deps_hash()
    if not (venv_ready(VENV_B3D) and stamp.exists() and stamp.read_text().strip() == want):
        shutil.rmtree(VENV_B3D, ignore_errors=True)
        make_venv(VENV_B3D)
        log(f"installing the wheel with extras [{EXTRAS_B3D}] into {VENV_B3D.name} (build123d 0.13, OCCT 8.0)")
        check([python, "-m", "pip", "install", "-q", f"{wheel}[{EXTRAS_B3D}]"], "pip install (b3d)")
        stamp.write_text(want + "\n")
    check([python, "-m", "pip", "install", "-q", "--no-deps", "--force-reinstall", wheel], "pip install wheel (b3d)")
    return python


def cmd_demo(args: list[str]) -> int:
    log("running: cagd demo " + " ".join(args))
    return run([BIN / "cagd", "demo", *args])


def pytest_code(code: int) -> int:
    if code == PYTEST_NO_TESTS:
        log("pytest collected no tests: treating that as a failure")
        return 1
    return code


def lint() -> int:
    """ruff on the tree and mypy on the engine (pyproject.toml), before any test."""
    for cmd in ([BIN / "ruff", "check", "."], [BIN / "mypy"]):
        log("running: " + " ".join(str(c.name) if isinstance(c, Path) else c for c in cmd))
        code = run(cmd)
        if code:
            log(f"{cmd[0].name} found problems (exit code {code})")
            return code
    return 0


def cmd_test(args: list[str]) -> int:
    ensure_test_tools()
    if not args:
        code = lint()
        if code:
            return code
    wheel = build_wheel()
    os.environ["CAGD_WHEEL"] = str(wheel)
    os.environ["CAGD_EXPECT_OCP"] = "7"          # .venv: CadQuery 2.8 on OCCT 7.9
    log("running: pytest " + " ".join(args))
    code = pytest_code(run([PYTHON, "-m", "pytest", *args]))
    if args:
        return code
    return code or cmd_test_b3d([], wheel)


def cmd_test_b3d(args: list[str], wheel: Path | None = None) -> int:
    """The OCCT 8.0 stage: the installed wheel, tests run from outside the checkout."""
    wheel = wheel or build_wheel()
    python = ensure_b3d_env(wheel)
    outside = Path(tempfile.mkdtemp(prefix="cagd-b3d-"))
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(CAGD_WHEEL=str(wheel), CAGD_EXPECT_INSTALLED="1", CAGD_EXPECT_OCP="8")
    tests = [str(ROOT / t) for t in B3D_TESTS if (ROOT / t).exists()]
    # test paths given relative to the repo root still name the checkout's tests
    args = [str(ROOT / a) if not a.startswith("-") and (ROOT / a.split("::")[0]).exists() else a for a in args]
    cmd = [python, "-m", "pytest", "-c", ROOT / "setup.cfg", "--rootdir", ROOT, "-p", "no:cacheprovider",
           *(args or tests)]
    log(f"running (OCCT 8.0, in {outside}): pytest " + " ".join(map(str, args or B3D_TESTS)))
    try:
        return pytest_code(subprocess.call([str(c) for c in cmd], cwd=outside, env=env))
    finally:
        shutil.rmtree(outside, ignore_errors=True)


COMMANDS = {"demo": cmd_demo, "test": cmd_test, "test-b3d": cmd_test_b3d}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in COMMANDS:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    ensure_env()
    return COMMANDS[argv[0]](argv[1:])


if __name__ == "__main__":
    sys.exit(main())
