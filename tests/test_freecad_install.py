"""``cam-workbench freecad install|uninstall`` and the Addon Manager's package.xml, with the
real ``freecadcmd`` answering where its Mod folder is and loading what was installed."""
from __future__ import annotations

import filecmp
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cam_workbench.freecad import install as inst

from .conftest import ROOT
from .freecad_support import fc_env, install_workbench, requires_freecadcmd, run_freecadcmd


def cli(*args: str, home: Path, extra_env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    env = fc_env(home)
    env.update(extra_env or {})
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=600, stdin=subprocess.DEVNULL)


def test_install_into_mod_dir_links_this_checkout(tmp_path):
    mod = tmp_path / "Mod"
    res = cli("freecad", "install", "--mod-dir", str(mod), home=tmp_path)
    assert res.returncode == 0, res.stderr
    target = mod / "CamWorkbench"
    assert f"installed: {target} (linked to {ROOT})" in res.stdout
    for pkg in inst.PACKAGES:
        assert (target / pkg).is_symlink() and (target / pkg).resolve() == ROOT / pkg
    for name in ("Init.py", "InitGui.py"):
        assert filecmp.cmp(target / name, ROOT / "cam_workbench/freecad/mod" / name, shallow=False)
    marker = json.loads((target / inst.MARKER).read_text())
    assert marker["source"] == str(ROOT) and marker["mode"] == "linked"
    assert oct(target.stat().st_mode & 0o777) == oct(0o777 & ~_umask())
    # again: replaces its own copy
    assert cli("freecad", "install", "--mod-dir", str(mod), home=tmp_path).returncode == 0
    assert sorted(p.name for p in mod.iterdir()) == ["CamWorkbench"]
    res = cli("freecad", "uninstall", "--mod-dir", str(mod), home=tmp_path)
    assert res.returncode == 0 and f"removed: {target}" in res.stdout
    assert not target.exists()
    assert (ROOT / "generators" / "__init__.py").is_file()  # links removed, never their targets


def test_install_copy_mode(tmp_path):
    mod = tmp_path / "Mod"
    res = cli("freecad", "install", "--mod-dir", str(mod), "--copy", home=tmp_path)
    assert res.returncode == 0, res.stderr
    target = mod / "CamWorkbench"
    assert not (target / "generators").is_symlink()
    assert (target / "generators" / "spec.py").read_text() == (ROOT / "generators" / "spec.py").read_text()
    assert not list(target.rglob("__pycache__"))
    assert cli("freecad", "uninstall", "--mod-dir", str(mod), home=tmp_path).returncode == 0


def test_foreign_folder_is_never_replaced_or_removed(tmp_path):
    mod = tmp_path / "Mod"
    foreign = mod / "CamWorkbench"
    foreign.mkdir(parents=True)
    (foreign / "mine.txt").write_text("not yours")
    res = cli("freecad", "install", "--mod-dir", str(mod), home=tmp_path)
    assert res.returncode == 2
    assert res.stderr.strip() == (f"error: {foreign} exists and was not installed by cam-workbench; "
                                  "remove it yourself or choose another --mod-dir")
    res = cli("freecad", "uninstall", "--mod-dir", str(mod), home=tmp_path)
    assert res.returncode == 2 and "left alone" in res.stderr
    assert (foreign / "mine.txt").read_text() == "not yours"
    assert sorted(p.name for p in mod.iterdir()) == ["CamWorkbench"]  # no staging left behind


def test_conventional_mod_dirs(tmp_path, monkeypatch):
    """Without a FreeCAD to ask: the XDG data folder, every versioned folder of FreeCAD ≥ 1.1
    that exists, and the legacy ~/.FreeCAD if present."""
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("XDG_DATA_HOME", raising=False)
    base = tmp_path / ".local/share/FreeCAD"
    assert inst.default_mod_dirs() == [base / "Mod"]
    (base / "v1-1").mkdir(parents=True)
    (base / "Macro").mkdir()
    (tmp_path / ".FreeCAD").mkdir()
    assert inst.default_mod_dirs() == [base / "Mod", base / "v1-1/Mod", tmp_path / ".FreeCAD/Mod"]
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    assert inst.default_mod_dirs()[0] == tmp_path / "xdg/FreeCAD/Mod"


LOAD = """
import FreeCAD
import generators, cam_workbench.freecad.feature as feature
RESULT["generators"] = generators.__file__
RESULT["import_types"] = FreeCAD.getImportType("toml")
doc = FreeCAD.newDocument("x")
cam = feature.create(doc)
doc.recompute()
RESULT["status"] = cam.Status
RESULT["volume"] = cam.Shape.Volume
"""

GONE = """
try:
    import cam_workbench
    RESULT["importable"] = cam_workbench.__file__
except ImportError:
    RESULT["importable"] = False
"""


@requires_freecadcmd
def test_install_asks_freecad_for_its_mod_folder(tmp_path):
    """The installer asks the real freecadcmd where its Mod folder is, checks that FreeCAD
    loads the workbench, and FreeCAD then imports the packages from there (no sys.path
    help) and runs Init.py; uninstall makes them unimportable again."""
    home = tmp_path / "home"
    res = install_workbench(home)
    assert res.returncode == 0, res.stdout + res.stderr
    mod = home / ".local/share/FreeCAD/Mod"  # FreeCAD 0.20 / 1.0 on Linux (XDG data folder)
    assert f"installed: {mod / 'CamWorkbench'}" in res.stdout
    assert f"uses {mod}" in res.stdout
    assert "checked: FreeCAD" in res.stdout and "designs the default cam" in res.stdout
    run = run_freecadcmd(LOAD, tmp_path / "load", home).check()
    r = run.result
    assert r["generators"] == str(mod / "CamWorkbench/generators/__init__.py")
    assert "cam_workbench.freecad.spec_io" in r["import_types"]
    assert r["status"] == "ok" and r["volume"] > 0
    res = cli("freecad", "uninstall", home=home)
    assert res.returncode == 0 and f"removed: {mod / 'CamWorkbench'}" in res.stdout
    assert run_freecadcmd(GONE, tmp_path / "gone", home).check().result["importable"] is False


@requires_freecadcmd
def test_install_follows_freecads_own_data_folder(tmp_path):
    """With XDG_DATA_HOME set, FreeCAD's data folder moves and the installer follows it."""
    home, xdg = tmp_path / "home", tmp_path / "xdg"
    home.mkdir()
    res = cli("freecad", "install", "--no-verify", home=home, extra_env={"XDG_DATA_HOME": str(xdg)})
    assert res.returncode == 0, res.stdout + res.stderr
    assert (xdg / "FreeCAD/Mod/CamWorkbench" / inst.MARKER).is_file()
    assert not (home / ".local/share/FreeCAD/Mod/CamWorkbench").exists()


METADATA = """
import FreeCAD, os
m = FreeCAD.Metadata(os.path.join(ROOT, "package.xml"))
wb = m.Content["workbench"][0]
RESULT.update(name=m.Name, version=m.Version, supports=m.supportsCurrentFreeCAD(),
              classname=wb.Classname, subdirectory=wb.Subdirectory, icon=m.Icon,
              wb_supports=wb.supportsCurrentFreeCAD(), depends=[d["package"] for d in m.Depend],
              licenses=[dict(x) for x in m.License])
"""


@requires_freecadcmd
def test_package_xml_is_read_by_freecad(tmp_path):
    """FreeCAD's own metadata reader accepts package.xml; it names the workbench class that
    InitGui.py registers, in a subdirectory holding Init.py and InitGui.py, and an icon
    that exists."""
    from cam_workbench import __version__

    r = run_freecadcmd(f"ROOT = {str(ROOT)!r}\n" + METADATA, tmp_path, tmp_path / "home").check().result
    assert r["name"] == "Plate Cam" and r["version"] == __version__
    assert r["supports"] and r["wb_supports"]
    assert r["classname"] == "CamWorkbench"
    assert [lic["name"] for lic in r["licenses"]] == ["LGPL-2.1-or-later"]
    assert (ROOT / r["licenses"][0]["file"]).read_text().lstrip().startswith("GNU LESSER GENERAL PUBLIC LICENSE")
    sub = ROOT / r["subdirectory"]
    assert (sub / "Init.py").is_file() and (sub / "InitGui.py").is_file()
    assert "class CamWorkbench(" in (sub / "InitGui.py").read_text()
    assert (ROOT / r["icon"]).is_file()
    assert r["depends"] == ["numpy", "scipy", "matplotlib"]


@requires_freecadcmd
def test_addon_manager_layout_loads(tmp_path):
    """The Addon Manager clones the repository into Mod/<name>: FreeCAD then follows
    package.xml to cam_workbench/freecad/mod and the packages import from the clone."""
    home = tmp_path / "home"
    mod = home / ".local/share/FreeCAD/Mod"
    mod.mkdir(parents=True)
    os.symlink(ROOT, mod / "cam_workbench")
    run = run_freecadcmd(LOAD, tmp_path / "load", home).check()
    assert run.result["generators"] == str(mod / "cam_workbench/generators/__init__.py")
    assert "cam_workbench.freecad.spec_io" in run.result["import_types"]
    assert run.result["status"] == "ok"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.parametrize("args", [["freecad"], ["freecad", "install", "--help"]])
def test_cli_help(args, tmp_path):
    res = cli(*args, home=tmp_path)
    text = res.stdout + res.stderr
    assert "install" in text
