#!/usr/bin/env python3
"""Install the cagd workbench for the current user (stdlib only).

    python3 workbench/install.py              link <repo>/workbench into FreeCAD's user Mod folder
    python3 workbench/install.py --copy       copy it instead (records the engine path)
    python3 workbench/install.py --uninstall  remove it again
    python3 workbench/install.py --mod-dir DIR   use DIR instead of FreeCAD's user Mod folder

The Mod folder is FreeCAD's user data folder + "Mod": $FREECAD_USER_HOME when set,
otherwise what `freecadcmd` reports (FreeCAD.getUserAppDataDir()), otherwise
~/.local/share/FreeCAD (FreeCAD 0.20 on Linux). The addon finds the engine `cagd` as
the repository it is linked from; a copy gets an engine_path.txt naming the repository.
FreeCAD's own Python (Debian: python3.11 + python3-numpy) needs nothing else.
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

ADDON = Path(__file__).resolve().parent
REPO = ADDON.parent
NAME = "CagdWorkbench"
MARK = "CAGD_USER_DATA_DIR="


def freecad_user_dir() -> Path:
    """FreeCAD's user data folder (see the module docstring for the order tried)."""
    if os.environ.get("FREECAD_USER_HOME"):
        return Path(os.environ["FREECAD_USER_HOME"])
    for exe in ("freecadcmd", "FreeCADCmd"):
        if shutil.which(exe):
            code = f"import FreeCAD; print('{MARK}' + FreeCAD.getUserAppDataDir())"
            try:
                out = subprocess.run([exe, "-c", code], capture_output=True, text=True, timeout=60).stdout
            except (OSError, subprocess.SubprocessError):
                break
            for line in out.splitlines():
                if line.startswith(MARK):
                    return Path(line[len(MARK):].strip())
            break
    return Path.home() / ".local" / "share" / "FreeCAD"


def remove(target: Path) -> None:
    if target.is_symlink() or target.is_file():
        target.unlink()
    elif target.is_dir():
        shutil.rmtree(target)


def main(argv: list | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copy", action="store_true", help="copy the addon instead of linking it")
    parser.add_argument("--uninstall", action="store_true", help="remove the installed addon")
    parser.add_argument("--mod-dir", type=Path, help="FreeCAD Mod folder (default: the user's)")
    args = parser.parse_args(argv)
    mod_dir = args.mod_dir or freecad_user_dir() / "Mod"
    target = mod_dir / NAME
    if args.uninstall:
        remove(target)
        print(f"removed {target}")
        return 0
    if not (REPO / "cagd" / "__init__.py").is_file():
        print(f"error: {REPO} does not hold the engine package cagd/", file=sys.stderr)
        return 1
    mod_dir.mkdir(parents=True, exist_ok=True)
    remove(target)
    if args.copy:
        shutil.copytree(ADDON, target, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        (target / "engine_path.txt").write_text(str(REPO) + "\n", encoding="utf-8")
        print(f"copied {ADDON} to {target} (engine: {REPO})")
    else:
        target.symlink_to(ADDON, target_is_directory=True)
        print(f"linked {target} -> {ADDON}")
    print("restart FreeCAD and pick the 'CAGD' workbench")
    return 0


if __name__ == "__main__":
    sys.exit(main())
