"""Install the cagd FreeCAD workbench for the current user (standard library only).

    cagd-freecad install              link the addon into FreeCAD's user Mod folder
    cagd-freecad install --copy       copy it (and the engine) instead
    cagd-freecad uninstall            remove it again (also: install --uninstall)
    cagd-freecad install --mod-dir DIR   use DIR instead of FreeCAD's user Mod folder

``python -m cagd.freecad ...`` does the same; in a checkout, ``python3
workbench/install.py [--copy] [--uninstall] [--mod-dir DIR]`` runs this file too.

The Mod folder is FreeCAD's user data folder + "Mod": $FREECAD_USER_HOME when set,
otherwise what ``freecadcmd`` reports (``FreeCAD.getUserAppDataDir()``), otherwise
~/.local/share/FreeCAD (FreeCAD 0.20 on Linux). ``Mod/CagdWorkbench`` then holds the
addon's files and ``engine/cagd``, the engine package, so FreeCAD's own Python (Debian:
python3.11 with numpy 1.24) finds ``cagd`` and nothing else of the environment it
was installed from (no second numpy). A link install points at this installation
(updates to it show at the next FreeCAD start); ``--copy`` makes a self-contained copy
that survives removing the environment.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import List, Optional

NAME = "CagdWorkbench"
MARKER = ".cagd-install.json"
MARK = "CAGD_USER_DATA_DIR="
FREECAD_QUERY_TIMEOUT = 60.0          # seconds for `freecadcmd -c ...` to report its user folder
# the checkout's workbench/ folder holds these, which are not part of the addon
_NOT_ADDON = {"tests", "install.py", "__pycache__", "engine_path.txt", "engine", MARKER, "__init__.py"}
_HERE = Path(__file__).resolve().parent            # .../cagd/freecad


class InstallError(RuntimeError):
    """The addon or the Mod folder cannot be used (the message says why)."""


def addon_dir() -> Path:
    """The addon folder of this cagd: ``cagd/freecad/addon`` in an installed wheel, the
    checkout's ``workbench/`` folder in a development (editable) install.

    Raises:
        InstallError: neither holds the addon (a broken installation).
    """
    for folder in (_HERE / "addon", _HERE.parents[1] / "workbench"):
        if (folder / "InitGui.py").is_file() and (folder / "cagdwb" / "__init__.py").is_file():
            return folder
    raise InstallError(f"the FreeCAD addon is missing from this installation ({_HERE / 'addon'}); "
                       "reinstall cagd")


def engine_dir() -> Path:
    """The folder of the ``cagd`` package itself (the engine FreeCAD will import)."""
    return _HERE.parent


def freecad_user_dir() -> Path:
    """FreeCAD's user data folder (see the module docstring for the order tried)."""
    if os.environ.get("FREECAD_USER_HOME"):
        return Path(os.environ["FREECAD_USER_HOME"])
    for exe in ("freecadcmd", "FreeCADCmd"):
        if shutil.which(exe):
            code = f"import FreeCAD; print('{MARK}' + FreeCAD.getUserAppDataDir())"
            try:
                out = subprocess.run([exe, "-c", code], capture_output=True, text=True,
                                     timeout=FREECAD_QUERY_TIMEOUT).stdout
            except (OSError, subprocess.SubprocessError):
                break
            for line in out.splitlines():
                if line.startswith(MARK):
                    return Path(line[len(MARK):].strip())
            break
    return Path.home() / ".local" / "share" / "FreeCAD"


def _remove(target: Path) -> None:
    if target.is_symlink() or target.is_file():
        target.unlink()
    elif target.is_dir():
        shutil.rmtree(target)


def _ours(target: Path) -> bool:
    """A Mod/CagdWorkbench made by this installer (or by the older workbench/install.py:
    a link to an addon folder, or a copy holding InitGui.py and cagdwb/)."""
    if target.is_symlink() or (target / MARKER).is_file():
        return True
    return (target / "InitGui.py").is_file() and (target / "cagdwb").is_dir()


def _entries(addon: Path) -> List[Path]:
    return sorted(p for p in addon.iterdir() if p.name not in _NOT_ADDON and not p.name.endswith(".pyc"))


def install(mod_dir: Optional[Path] = None, copy: bool = False, addon: Optional[Path] = None,
            engine: Optional[Path] = None) -> Path:
    """Install the addon as ``<mod_dir>/CagdWorkbench`` (replacing an earlier install)
    and return that folder. ``addon`` and ``engine`` default to this installation's.

    Raises:
        InstallError: the target exists and is not a cagd install, or a file operation
            failed (the message names the path).
    """
    addon = Path(addon) if addon else addon_dir()
    engine = Path(engine) if engine else engine_dir()
    if not (engine / "__init__.py").is_file():
        raise InstallError(f"engine: {engine} is not the cagd package (no __init__.py)")
    mod_dir = Path(mod_dir) if mod_dir else freecad_user_dir() / "Mod"
    target = mod_dir / NAME
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    try:
        if target.exists() or target.is_symlink():
            if not _ours(target):
                raise InstallError(f"mod_dir: {target} exists and is not a cagd workbench install; "
                                   "move it away first")
            _remove(target)
        (target / "engine").mkdir(parents=True)
        for entry in _entries(addon):
            if copy:
                (shutil.copytree(entry, target / entry.name, ignore=ignore) if entry.is_dir()
                 else shutil.copy2(entry, target / entry.name))
            else:
                (target / entry.name).symlink_to(entry.resolve(), target_is_directory=entry.is_dir())
        if copy:      # the engine without the addon it carries as package data
            shutil.copytree(engine, target / "engine" / "cagd",
                            ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "addon"))
        else:
            (target / "engine" / "cagd").symlink_to(engine.resolve(), target_is_directory=True)
        record = {"mode": "copy" if copy else "link", "addon": str(addon.resolve()), "engine": str(engine.resolve())}
        (target / MARKER).write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    except OSError as exc:
        raise InstallError(f"mod_dir: cannot install into {target}: {exc}") from None
    return target


def uninstall(mod_dir: Optional[Path] = None) -> Optional[Path]:
    """Remove ``<mod_dir>/CagdWorkbench``; return it, or None when nothing was installed.

    Raises:
        InstallError: it exists and is not a cagd install, or cannot be removed.
    """
    mod_dir = Path(mod_dir) if mod_dir else freecad_user_dir() / "Mod"
    target = mod_dir / NAME
    if not (target.exists() or target.is_symlink()):
        return None
    if not _ours(target):
        raise InstallError(f"mod_dir: {target} is not a cagd workbench install; not removed")
    try:
        _remove(target)
    except OSError as exc:
        raise InstallError(f"mod_dir: cannot remove {target}: {exc}") from None
    return target


def main(argv: Optional[list] = None, addon: Optional[Path] = None, engine: Optional[Path] = None) -> int:
    """The command line (see the module docstring); exit code 0, or 1 with the reason."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = argparse.ArgumentParser(prog="cagd-freecad", description=(__doc__ or "").splitlines()[0])
    parser.add_argument("action", nargs="?", choices=("install", "uninstall"), default="install")
    parser.add_argument("--copy", action="store_true", help="copy the addon and the engine instead of linking")
    parser.add_argument("--uninstall", action="store_true", help="remove the installed addon")
    parser.add_argument("--mod-dir", type=Path, help="FreeCAD Mod folder (default: the user's)")
    args = parser.parse_args(argv)
    try:
        if args.uninstall or args.action == "uninstall":
            removed = uninstall(args.mod_dir)
            print(f"removed {removed}" if removed else "nothing to remove")
            return 0
        target = install(args.mod_dir, args.copy, addon, engine)
    except InstallError as exc:
        print(f"cagd-freecad: error: {exc}", file=sys.stderr)
        return 1
    how = "copied" if args.copy else "linked"
    print(f"{how} the CAGD workbench into {target} (engine: {target / 'engine' / 'cagd'})")
    print("restart FreeCAD and pick the 'CAGD' workbench")
    return 0


if __name__ == "__main__":
    sys.exit(main())
