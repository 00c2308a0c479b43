"""workbench/install.py (link, copy, uninstall into a given Mod folder) and the
addon's engine lookup, without FreeCAD: both are plain Python."""
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
    assert target.is_symlink() and target.resolve() == ADDON
    pkg = load_package(target, "cagdwb_linked")
    assert os.path.realpath(pkg.ensure_engine()) == str(ROOT)
    install("--mod-dir", mod)                          # re-install replaces the link
    assert target.is_symlink()
    install("--mod-dir", mod, "--uninstall")
    assert not target.exists() and not target.is_symlink()


def test_copy_install_records_engine_path(tmp_path):
    mod = tmp_path / "Mod"
    install("--mod-dir", mod, "--copy")
    target = mod / "CagdWorkbench"
    assert not target.is_symlink() and (target / "InitGui.py").is_file()
    assert (target / "engine_path.txt").read_text().strip() == str(ROOT)
    assert not list(target.rglob("__pycache__"))
    pkg = load_package(target, "cagdwb_copied")
    assert pkg.ADDON_DIR == str(target.resolve())
    assert os.path.realpath(pkg.ensure_engine()) == str(ROOT)
    (target / "engine_path.txt").write_text(str(tmp_path / "nowhere"))
    assert pkg.engine_candidates()[0] == str(tmp_path / "nowhere")


def test_freecad_user_home_is_respected(tmp_path):
    env = {**os.environ, "FREECAD_USER_HOME": str(tmp_path / "fc")}
    subprocess.run([sys.executable, str(ADDON / "install.py")], env=env, check=True, capture_output=True)
    assert (tmp_path / "fc" / "Mod" / "CagdWorkbench").is_symlink()


def test_missing_freecad_skips_locally_and_fails_on_ci(monkeypatch):
    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(pytest.skip.Exception):
        need(["no-such-freecad-binary"], "FreeCAD")
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception):
        need(["no-such-freecad-binary"], "FreeCAD")
