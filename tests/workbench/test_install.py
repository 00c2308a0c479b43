"""workbench/install.py, the checkout's front of cagd/freecad/install.py (link, copy,
uninstall into a given Mod folder), and the addon's engine lookup, without FreeCAD:
both are plain Python. The installed wheel's `cagd-freecad` is tested in
tests/test_packaging.py."""
import importlib.util
import os
import subprocess
import sys

import pytest

from wb_runner import ADDON, ROOT, need


def install(*args):
    done = subprocess.run([sys.executable, str(ADDON / "install.py"), *map(str, args)],
                          capture_output=True, text=True, env={**os.environ, "CAGD_PATH": ""})
    assert done.returncode == 0, done.stderr
    return done.stdout


def load_package(addon_dir, name):
    """Import <addon_dir>/cagdwb/__init__.py under a fresh module name."""
    spec = importlib.util.spec_from_file_location(name, addon_dir / "cagdwb" / "__init__.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_link_install_finds_engine_and_uninstalls(tmp_path):
    mod = tmp_path / "Mod"
    install("--mod-dir", mod)
    target = mod / "CagdWorkbench"
    assert target.is_dir() and not target.is_symlink()
    assert (target / "cagdwb").is_symlink() and (target / "cagdwb").resolve() == ADDON / "cagdwb"
    assert (target / "engine" / "cagd").resolve() == ROOT / "cagd"
    assert not (target / "install.py").exists() and not (target / "tests").exists()
    pkg = load_package(target, "cagdwb_linked")
    assert pkg.ADDON_DIR == str(target)
    assert pkg.ensure_engine() == str(target / "engine")
    install("--mod-dir", mod)                          # re-install replaces it
    assert (target / "engine" / "cagd").is_symlink()
    install("--mod-dir", mod, "--uninstall")
    assert not target.exists() and not target.is_symlink()


def test_copy_install_carries_the_engine(tmp_path):
    mod = tmp_path / "Mod"
    install("--mod-dir", mod, "--copy")
    target = mod / "CagdWorkbench"
    assert not target.is_symlink() and (target / "InitGui.py").is_file()
    engine = target / "engine" / "cagd"
    assert not engine.is_symlink() and (engine / "__init__.py").is_file()
    assert (engine / "curves" / "bspline.py").read_bytes() == (ROOT / "cagd" / "curves" / "bspline.py").read_bytes()
    assert not list(target.rglob("__pycache__"))
    pkg = load_package(target, "cagdwb_copied")
    assert pkg.ensure_engine() == str(target / "engine")
    (target / "engine_path.txt").write_text(str(tmp_path / "nowhere"))     # an older copy's record
    assert str(tmp_path / "nowhere") in pkg.engine_candidates()


def test_an_unrelated_folder_is_not_replaced(tmp_path):
    target = tmp_path / "Mod" / "CagdWorkbench"
    target.mkdir(parents=True)
    (target / "notes.txt").write_text("mine")
    done = subprocess.run([sys.executable, str(ADDON / "install.py"), "--mod-dir", str(tmp_path / "Mod")],
                          capture_output=True, text=True)
    assert done.returncode == 1 and "is not a cagd workbench install" in done.stderr
    assert (target / "notes.txt").read_text() == "mine"


def test_installer_runs_without_numpy(tmp_path):
    """workbench/install.py loads the installer by path: a python without numpy (here:
    ``-S``, no site-packages) installs the addon."""
    probe = subprocess.run([sys.executable, "-S", "-c", "import numpy"], capture_output=True)
    assert probe.returncode != 0, "python -S still imports numpy"
    done = subprocess.run([sys.executable, "-S", str(ADDON / "install.py"), "--mod-dir", str(tmp_path / "Mod")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "Mod" / "CagdWorkbench" / "engine" / "cagd").is_symlink()


def test_freecad_user_home_is_respected(tmp_path):
    env = {**os.environ, "FREECAD_USER_HOME": str(tmp_path / "fc")}
    subprocess.run([sys.executable, str(ADDON / "install.py")], env=env, check=True, capture_output=True)
    assert (tmp_path / "fc" / "Mod" / "CagdWorkbench" / "engine" / "cagd").is_symlink()


def test_missing_freecad_skips_locally_and_fails_on_ci(monkeypatch):
    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(pytest.skip.Exception):
        need(["no-such-freecad-binary"], "FreeCAD")
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception):
        need(["no-such-freecad-binary"], "FreeCAD")
