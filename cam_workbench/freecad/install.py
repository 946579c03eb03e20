"""Register the workbench with a user's FreeCAD: a folder ``CamWorkbench`` in its ``Mod`` folder.

Runs in the CLI's Python (not inside FreeCAD).  The folder holds FreeCAD's two entry
files (``Init.py``, ``InitGui.py``, copied from ``cam_workbench/freecad/mod``), a marker
file, and symbolic links to the package ``cam_workbench`` of this installation — or, from a
checkout, to its folders ``cam_workbench``, ``generators`` and ``exporters`` (the source tree's
layout of ``cam_workbench.generators`` and ``cam_workbench.exporters``).  FreeCAD puts every
``Mod/<name>`` folder on ``sys.path``, so the links make exactly this package importable from
FreeCAD's own Python (never the virtual environment's numpy, scipy or OCP).  Where links
cannot be made (Windows without the privilege) the packages are copied instead; then
``install`` must be run again after an upgrade.

Which ``Mod`` folder: FreeCAD's user data folder (``FreeCAD.getUserAppDataDir()``)
followed by ``Mod``.  It depends on the version and the platform — FreeCAD 0.20 and 1.0
on Linux use ``$XDG_DATA_HOME/FreeCAD`` (``~/.local/share/FreeCAD``; ``~/.FreeCAD`` with
``--keep-deprecated-paths``), FreeCAD 1.1 a versioned ``~/.local/share/FreeCAD/v1-1``
when the user migrated — so it is asked from each FreeCAD found (``freecadcmd`` on PATH
or ``--freecad``).  Without a FreeCAD to ask, the known locations are used.
"""
from __future__ import annotations

import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from cam_workbench import __version__
from cam_workbench.generators.errors import CamError

MOD_NAME = "CamWorkbench"
MARKER = ".cam-workbench-install.json"
#: the folders of a source tree (a checkout): the package and its two subpackages beside it
SOURCE_FOLDERS = ("cam_workbench", "generators", "exporters")
FREECAD_COMMANDS = ("freecadcmd", "FreeCADCmd", "freecad-daily-cmd", "FreeCADCmd-daily")
_QUERY = ("import FreeCAD, sys; "
          "print('CAMWB_DATA=' + FreeCAD.getUserAppDataDir()); "
          "print('CAMWB_VERSION=' + '.'.join(FreeCAD.Version()[:3])); "
          "print('CAMWB_PYTHON=' + '.'.join(map(str, sys.version_info[:3])))")


class InstallError(CamError):
    """Installation cannot proceed (message says why and what to do)."""


@dataclass(frozen=True)
class FreeCADInfo:
    """What a FreeCAD executable told about itself."""

    executable: str
    user_data: Path
    version: str
    python: str

    @property
    def mod_dir(self) -> Path:
        return self.user_data / "Mod"


def package_folders(root: Path) -> tuple[str, ...]:
    """The folders under ``root`` that make ``cam_workbench`` importable: the package alone
    when it holds its subpackages (an installed wheel), else the three folders of a checkout."""
    if (root / "cam_workbench" / "generators" / "__init__.py").is_file():
        return ("cam_workbench",)
    return SOURCE_FOLDERS


def source_root() -> Path:
    """The folder holding ``cam_workbench`` (site-packages for an installed wheel; the checkout,
    with ``generators`` and ``exporters`` beside it, for an editable install)."""
    root = Path(__file__).resolve().parents[2]
    missing = [p for p in package_folders(root) if not (root / p / "__init__.py").is_file()]
    if missing:
        raise InstallError(f"cannot find the packages {', '.join(missing)} next to {root}")
    return root


def mod_template() -> Path:
    return Path(__file__).resolve().parent / "mod"


# ---- finding FreeCAD's Mod folder -----------------------------------------------------------
def find_freecad_commands() -> list[str]:
    """Every headless FreeCAD command on PATH (resolved, duplicates removed)."""
    out, seen = [], set()
    for name in FREECAD_COMMANDS:
        exe = shutil.which(name)
        if exe and os.path.realpath(exe) not in seen:
            seen.add(os.path.realpath(exe))
            out.append(exe)
    return out


def query_freecad(executable: str, timeout: float = 120.0) -> FreeCADInfo:
    """Ask a FreeCAD (``freecadcmd``) for its user data folder, version and Python.

    Raises:
        InstallError: it could not be run or did not answer.
    """
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "camwb_query.py"
        script.write_text(_QUERY + "\n", encoding="utf-8")
        try:
            res = subprocess.run([executable, str(script)], capture_output=True, text=True,
                                 timeout=timeout, stdin=subprocess.DEVNULL)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise InstallError(f"could not run {executable}: {exc}") from None
    found = dict(re.findall(r"^CAMWB_(\w+)=(.*)$", res.stdout, re.M))
    if "DATA" not in found:
        tail = (res.stderr or res.stdout).strip().splitlines()[-3:]
        raise InstallError(f"{executable} did not report its user data folder "
                           f"(exit {res.returncode}: {' | '.join(tail)})")
    return FreeCADInfo(executable, Path(found["DATA"].strip()), found.get("VERSION", "?"),
                       found.get("PYTHON", "?"))


def default_mod_dirs() -> list[Path]:
    """FreeCAD's per-user Mod folders by convention, for when no FreeCAD can be asked:
    the unversioned data folder of this platform, every versioned one that exists
    (FreeCAD ≥ 1.1: ``v1-1``, …) and the legacy ``~/.FreeCAD`` if it exists."""
    home = Path.home()
    system = platform.system()
    if system == "Windows":
        base = Path(os.environ.get("APPDATA", home / "AppData" / "Roaming")) / "FreeCAD"
    elif system == "Darwin":
        base = home / "Library" / "Application Support" / "FreeCAD"
    else:
        base = Path(os.environ.get("XDG_DATA_HOME") or home / ".local" / "share") / "FreeCAD"
    dirs = [base / "Mod"]
    if base.is_dir():
        versioned = sorted(p for p in base.iterdir() if p.is_dir() and re.fullmatch(r"v\d+-\d+", p.name))
        dirs += [p / "Mod" for p in versioned]
    legacy = home / ".FreeCAD"
    if legacy.is_dir():
        dirs.append(legacy / "Mod")
    return dirs


# ---- install / uninstall ----------------------------------------------------------------------
def is_ours(folder: Path) -> bool:
    return (folder / MARKER).is_file()


def install_into(mod_dir: Path, root: Path | None = None, copy: bool = False) -> tuple[Path, str]:
    """Create (or replace our own) ``mod_dir/CamWorkbench``; return it and "linked"/"copied".

    Raises:
        InstallError: a ``CamWorkbench`` folder exists that this tool did not make.
    """
    root = root or source_root()
    target = mod_dir / MOD_NAME
    if (target.exists() or target.is_symlink()) and not is_ours(target):
        raise InstallError(f"{target} exists and was not installed by cam-workbench; "
                           "remove it yourself or choose another --mod-dir")
    mod_dir.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{MOD_NAME}.", dir=mod_dir))
    os.chmod(staging, 0o777 & ~_umask())  # mkdtemp makes it private; a Mod folder is not
    try:
        for name in ("Init.py", "InitGui.py"):
            shutil.copy2(mod_template() / name, staging / name)
        mode = "copied" if copy else "linked"
        for pkg in package_folders(root):
            if not copy:
                try:
                    os.symlink(root / pkg, staging / pkg, target_is_directory=True)
                    continue
                except (OSError, NotImplementedError):
                    mode = "copied"
            shutil.copytree(root / pkg, staging / pkg,
                            ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        (staging / MARKER).write_text(json.dumps({
            "tool": "cam-workbench", "version": __version__, "source": str(root), "mode": mode,
            "installed_with": sys.executable}, indent=2) + "\n", encoding="utf-8")
        if target.exists():
            _remove_tree(target)
        os.replace(staging, target)
    except BaseException:
        if staging.exists():
            _remove_tree(staging)
        raise
    return target, mode


def uninstall_from(mod_dir: Path) -> Path | None:
    """Remove ``mod_dir/CamWorkbench`` if this tool made it; return it, or None if absent.

    Raises:
        InstallError: the folder exists but was not made by this tool (left alone).
    """
    target = mod_dir / MOD_NAME
    if not (target.exists() or target.is_symlink()):
        return None
    if not is_ours(target):
        raise InstallError(f"{target} was not installed by cam-workbench; left alone")
    _remove_tree(target)
    return target


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _remove_tree(folder: Path) -> None:
    """Delete a folder; links inside are removed as links (their targets are never touched)."""
    for entry in folder.iterdir():
        if entry.is_symlink():
            entry.unlink()
    shutil.rmtree(folder)


VERIFY_SCRIPT = """\
import sys
try:
    import cam_workbench.generators as generators, cam_workbench.freecad.feature as f
    from cam_workbench.generators import default_spec, design_cam
    import numpy, scipy
    d = design_cam(default_spec())
    print('CAMWB_OK=' + generators.__file__ + ' numpy ' + numpy.__version__ + ', scipy ' + scipy.__version__)
except Exception as exc:
    print('CAMWB_FAIL=' + type(exc).__name__ + ': ' + str(exc))
"""


def verify(info: FreeCADInfo, timeout: float = 180.0) -> tuple[bool, str]:
    """Start that FreeCAD headless and design the default cam with the installed workbench."""
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "camwb_verify.py"
        script.write_text(VERIFY_SCRIPT, encoding="utf-8")
        try:
            res = subprocess.run([info.executable, str(script)], capture_output=True, text=True,
                                 timeout=timeout, stdin=subprocess.DEVNULL)
        except (OSError, subprocess.TimeoutExpired) as exc:
            return False, str(exc)
    m = re.search(r"^CAMWB_(OK|FAIL)=(.*)$", res.stdout, re.M)
    if not m:
        return False, (res.stderr or res.stdout).strip()[-300:]
    return m.group(1) == "OK", m.group(2)
