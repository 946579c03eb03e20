"""``cam-workbench freecad install|uninstall`` and the Addon Manager's package.xml, with the
real ``freecadcmd`` answering where its Mod folder is and loading what was installed."""
from __future__ import annotations

import filecmp
import json
import os
import subprocess
import sys
from pathlib import Path
from xml.etree import ElementTree

import pytest

from cam_workbench.freecad import install as inst

from .conftest import ROOT, SAFETY_S
from .freecad_support import fc_env, install_workbench, requires_freecadcmd, run_freecadcmd, user_mod_dir


def cli(*args: str, home: Path, extra_env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    env = fc_env(home)
    env.update(extra_env or {})
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=SAFETY_S, stdin=subprocess.DEVNULL)


def test_install_into_mod_dir_links_this_checkout(tmp_path):
    mod = tmp_path / "Mod"
    res = cli("freecad", "install", "--mod-dir", str(mod), home=tmp_path)
    assert res.returncode == 0, res.stderr
    target = mod / "CamWorkbench"
    assert f"installed: {target} (linked to {ROOT})" in res.stdout
    for pkg in inst.package_folders(ROOT):
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
    sources = sorted(p.relative_to(ROOT) for p in (ROOT / "generators").rglob("*.py")
                     if "__pycache__" not in p.parts)
    assert sources == sorted(p.relative_to(target) for p in (target / "generators").rglob("*.py"))
    assert all((target / rel).read_bytes() == (ROOT / rel).read_bytes() for rel in sources)
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
import cam_workbench.generators as generators, cam_workbench.freecad.feature as feature
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
    mod = user_mod_dir(home, tmp_path / "ask")  # 0.20/1.0: ~/.local/share/FreeCAD/Mod; 1.1: …/v1-1/Mod
    assert mod.is_relative_to(home / ".local/share/FreeCAD")
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
    mod = user_mod_dir(home, tmp_path / "ask", extra_env={"XDG_DATA_HOME": str(xdg)})
    assert mod.is_relative_to(xdg / "FreeCAD"), mod
    assert (mod / "CamWorkbench" / inst.MARKER).is_file()
    assert not (home / ".local/share/FreeCAD").exists()


METADATA = """
import FreeCAD, os
m = FreeCAD.Metadata(os.path.join(ROOT, "package.xml"))
wb = m.Content["workbench"][0]
RESULT.update(name=m.Name, version=m.Version, supports=m.supportsCurrentFreeCAD(),
              classname=wb.Classname, subdirectory=wb.Subdirectory, icon=m.Icon, wb_icon=wb.Icon,
              wb_supports=wb.supportsCurrentFreeCAD(), depends=[dict(d) for d in m.Depend],
              licenses=[dict(x) for x in m.License], maintainers=[dict(x) for x in m.Maintainer],
              freecadmin=str(wb.FreeCADMin), content=sorted(m.Content))
try:  # the Addon Manager of FreeCAD 1.x reads package.xml with its own pure-Python reader
    from addonmanager_metadata import MetadataReader
except ImportError:
    RESULT["addon_manager"] = None
else:
    am = MetadataReader.from_file(os.path.join(ROOT, "package.xml"))
    amwb = am.content["workbench"][0]
    RESULT["addon_manager"] = dict(
        name=am.name, icon=am.icon, classname=amwb.classname, subdirectory=amwb.subdirectory,
        wb_icon=amwb.icon, depends=[[d.package, str(d.dependency_type), d.optional] for d in am.depend],
        maintainers=[[c.name, c.email] for c in am.maintainer], licenses=[lic.name for lic in am.license])
"""


@requires_freecadcmd
def test_package_xml_is_read_by_freecad(tmp_path):
    """FreeCAD's own metadata reader (the one its start-up and the Addon Manager use) accepts
    package.xml: it supports this FreeCAD; the workbench class is the one InitGui.py registers,
    in a subdirectory holding Init.py and InitGui.py; both icons exist where FreeCAD looks for
    them (the package's relative to the repository, the workbench's relative to its
    subdirectory); the Python dependencies are declared (nlopt, matplotlib and ezdxf optional)."""
    from cam_workbench import __version__

    r = run_freecadcmd(f"ROOT = {str(ROOT)!r}\n" + METADATA, tmp_path, tmp_path / "home").check()
    out = r.result
    assert out["name"] == "Cam Workbench" and out["version"] == __version__
    assert out["supports"] and out["wb_supports"] and out["freecadmin"].startswith("0.20")
    assert out["content"] == ["workbench"] and out["classname"] == "CamWorkbench"
    assert [lic["name"] for lic in out["licenses"]] == ["LGPL-2.1-or-later"]
    assert (ROOT / out["licenses"][0]["file"]).read_text().lstrip().startswith("GNU LESSER GENERAL PUBLIC LICENSE")
    assert out["maintainers"] and all(m["name"] and "@" in m["email"] for m in out["maintainers"])
    sub = ROOT / out["subdirectory"]
    assert (sub / "Init.py").is_file() and (sub / "InitGui.py").is_file()
    assert "class CamWorkbench(" in (sub / "InitGui.py").read_text()
    assert (ROOT / out["icon"]).is_file()
    assert (sub / out["wb_icon"]).resolve() == (ROOT / out["icon"]).resolve()
    deps = {d["package"]: d for d in out["depends"]}
    assert sorted(deps) == ["ezdxf", "matplotlib", "nlopt", "numpy", "scipy"]
    # type and optional as the Addon Manager reads them (its own XML reader; FreeCAD 0.20's
    # Metadata does not expose them, newer ones may: then they must agree)
    ns = {"p": "https://wiki.freecad.org/Package_Metadata"}
    xml = ElementTree.parse(ROOT / "package.xml").getroot().findall("p:depend", ns)
    assert {d.text: d.get("type") for d in xml} == dict.fromkeys(deps, "python")
    optional = {d.text for d in xml if d.get("optional") == "true"}
    assert optional == {"ezdxf", "matplotlib", "nlopt"}
    for name, d in deps.items():
        if "optional" in d:
            assert bool(d["optional"]) == (name in optional), d
    am = out["addon_manager"]
    if am is not None:   # FreeCAD 1.0, 1.1: what the Addon Manager reads is the same
        assert (am["name"], am["classname"], am["subdirectory"], am["icon"], am["wb_icon"]) == (
            out["name"], out["classname"], out["subdirectory"], out["icon"], out["wb_icon"])
        assert am["depends"] == [[d.text, "python", d.get("optional") == "true"] for d in xml]
        assert am["maintainers"] == [[m["name"], m["email"]] for m in out["maintainers"]]
        assert am["licenses"] == ["LGPL-2.1-or-later"]
    assert "Traceback" not in r.console and "rror" not in r.console, r.console


CLONE_LOAD = """
import FreeCAD, os
import cam_workbench.generators as generators, cam_workbench.freecad.feature as feature
from cam_workbench.freecad import spec_io
RESULT["generators"] = generators.__file__
RESULT["import_types"] = FreeCAD.getImportType("toml")
doc = FreeCAD.newDocument("x")
cam = feature.create(doc)                       # what "New cam" does
doc.recompute()
RESULT["status"] = cam.Status
RESULT["volume"] = cam.Shape.Volume
spec_io.export_spec(cam, os.path.join(os.getcwd(), "cam.toml"))
cam.CamBaseRadius = 45.0
doc.recompute()
RESULT["volume45"] = cam.Shape.Volume
opened = spec_io.open(os.path.join(os.getcwd(), "cam.toml"))   # "New cam from spec…", File › Open
FreeCAD.ActiveDocument.recompute()
RESULT["opened"] = [opened.Status, opened.Shape.Volume]
"""


def _clone_checkout(dest: Path) -> None:
    """``git clone`` of this checkout into ``dest`` — what a user or the Addon Manager does with
    the repository — with the working tree's uncommitted changes copied over, so that the code
    under test is the checkout's (a clean checkout, as in CI, copies nothing)."""
    import shutil

    def git(*args: str, cwd: Path = ROOT) -> str:
        return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout

    git("clone", "--quiet", "--no-hardlinks", str(ROOT), str(dest))
    for rel in git("ls-files", "-z", "--modified", "--others", "--exclude-standard").split("\0"):
        if rel and (ROOT / rel).is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / rel, dest / rel)
    for rel in git("ls-files", "-z", "--deleted").split("\0"):
        if rel:
            (dest / rel).unlink(missing_ok=True)


@requires_freecadcmd
def test_git_clone_into_mod_folder_loads(tmp_path):
    """A plain ``git clone`` of the repository into FreeCAD's Mod folder (the folder FreeCAD
    names for this user) is a working workbench: FreeCAD follows package.xml to
    cam_workbench/freecad/mod, runs Init.py, which puts the clone's root on sys.path; the
    packages import from the clone, a cam is created and recomputed, its spec is exported and
    opened as a new cam."""
    from cam_workbench.generators import default_spec, design_cam

    home = tmp_path / "home"
    mod = user_mod_dir(home, tmp_path / "ask")
    mod.mkdir(parents=True, exist_ok=True)
    clone = mod / "cam_workbench"
    _clone_checkout(clone)
    assert (clone / "package.xml").is_file() and not (clone / ".cache").exists()
    run = run_freecadcmd(CLONE_LOAD, tmp_path / "load", home).check()
    r = run.result
    assert r["generators"] == str(clone / "generators/__init__.py")
    assert "cam_workbench.freecad.spec_io" in r["import_types"]
    assert r["status"] == "ok"
    volume = design_cam(default_spec()).volume      # Green's theorem on the exact profile
    assert abs(r["volume"] - volume) / volume < 1e-9
    assert r["volume45"] > r["volume"]
    assert r["opened"][0] == "ok" and abs(r["opened"][1] - r["volume"]) / r["volume"] < 1e-12
    assert "Traceback" not in run.console


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.parametrize("args", [["freecad"], ["freecad", "install", "--help"]])
def test_cli_help(args, tmp_path):
    res = cli(*args, home=tmp_path)
    text = res.stdout + res.stderr
    assert "install" in text
