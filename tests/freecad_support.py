"""Driving the real FreeCAD from pytest: ``freecadcmd`` (headless) and the GUI under Xvfb.

Which FreeCAD: the one on PATH (Debian bookworm's 0.20.2 here), or with ``$CAM_FREECAD_ROOT``
set to a root filesystem made by ``tests/freecad_roots.sh`` (``make freecad-roots``: Debian
trixie's FreeCAD 1.0, unstable's 1.1) that root's, through its wrapper commands — headless,
the GUI with the root's own Xvfb, and the FreeCAD that ``cam-workbench freecad install`` asks.

Each run gets its own HOME, so FreeCAD's user settings and Mod folder are those of the
test, never the developer's.  The workbench is installed into that HOME by the real
``cam-workbench freecad install`` (fixture ``fc_home``): FreeCAD (Debian's 0.20.2 with its
security patch, and newer) only lets a document restore proxies from modules of FreeCAD
or of installed addons, so a checkout merely put on ``sys.path`` would not reopen files.  A script reports back by filling the dict ``RESULT``, which
is written as JSON when it ends (also when it raises: ``RESULT["_traceback"]``).  The
console output (FreeCAD's report view in headless mode) is captured for assertions.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from .conftest import ROOT, SAFETY_S

#: A FreeCAD root filesystem (Debian trixie's FreeCAD 1.0, unstable's 1.1) made by
#: ``tests/freecad_roots.sh build`` (``make freecad-roots``): when set, every FreeCAD the tests
#: start — headless, the GUI and its Xvfb, and the one ``cam-workbench freecad install`` asks —
#: is that root's, through its wrappers in ``$CAM_FREECAD_ROOT/bin``.
FREECAD_ROOT = os.environ.get("CAM_FREECAD_ROOT") or None
if FREECAD_ROOT:
    ROOT_BIN: Path | None = Path(FREECAD_ROOT).resolve() / "bin"
    _missing = [n for n in ("freecadcmd", "freecad", "xvfb-run") if not (ROOT_BIN / n).is_file()]
    if _missing:  # never fall back to the host's FreeCAD: the run would test the wrong version
        raise RuntimeError(f"CAM_FREECAD_ROOT={FREECAD_ROOT}: no {', '.join(_missing)} in {ROOT_BIN} "
                           "(build it with `make freecad-roots`)")
    FREECADCMD: str | None = str(ROOT_BIN / "freecadcmd")
    FREECAD_GUI: str | None = str(ROOT_BIN / "freecad")
    XVFB_RUN: str | None = str(ROOT_BIN / "xvfb-run")
else:
    ROOT_BIN = None
    FREECADCMD = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    FREECAD_GUI = shutil.which("freecad") or shutil.which("FreeCAD")
    XVFB_RUN = shutil.which("xvfb-run")

requires_freecadcmd = pytest.mark.skipif(
    FREECADCMD is None, reason="freecadcmd is not installed (Debian package freecad-python3)")
requires_freecad_gui = pytest.mark.skipif(
    FREECAD_GUI is None or XVFB_RUN is None,
    reason="the FreeCAD GUI under Xvfb needs the Debian packages freecad and xvfb")


@dataclass
class FreeCADRun:
    result: dict[str, Any]
    stdout: str
    stderr: str
    returncode: int

    @property
    def console(self) -> str:
        return self.stdout + self.stderr

    def check(self) -> "FreeCADRun":
        assert "_traceback" not in self.result, self.result["_traceback"] + "\n" + self.console[-3000:]
        assert self.result.get("_done"), f"script did not finish:\n{self.console[-3000:]}"
        return self


_PRELUDE = """\
import json, sys, traceback
RESULT = {{}}
def _camwb_write():
    with open({result!r}, "w") as f:
        json.dump(RESULT, f, indent=1, default=str)
"""


def _wrap(body: str, result: Path, add_root: bool) -> str:
    prelude = _PRELUDE.format(result=str(result))
    if add_root:
        prelude += f"sys.path.insert(0, {str(ROOT)!r})\n"
    return (prelude + "try:\n" + textwrap.indent(textwrap.dedent(body), "    ") +
            "\n    RESULT['_done'] = True\nexcept BaseException:\n"
            "    RESULT['_traceback'] = traceback.format_exc()\n_camwb_write()\n")


def fc_env(home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("XDG_", "PYTHON", "VIRTUAL_ENV"))}
    env["HOME"] = str(home)
    env["QTWEBENGINE_DISABLE_SANDBOX"] = "1"  # the Start page's web view refuses root otherwise
    if ROOT_BIN is not None:
        # `cam-workbench freecad install` asks the freecadcmd on PATH: the root's; and the Python
        # it records for the exports (this one) runs from inside the root as the host's
        env["PATH"] = str(ROOT_BIN) + os.pathsep + env.get("PATH", "")
        env["CAM_FREECAD_HOST_EXES"] = sys.executable
    return env


def cli_env() -> dict[str, str]:
    """The environment for running this checkout's ``python -m cam_workbench.cli`` from any
    folder: the checkout first on the path (the virtual environment's editable install may
    point at another checkout)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(ROOT)
    return env


def install_workbench(home: Path, *extra: str) -> subprocess.CompletedProcess:
    """``cam-workbench freecad install`` for a user whose HOME is ``home`` (asks freecadcmd)."""
    home.mkdir(parents=True, exist_ok=True)
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", "freecad", "install", *extra],
                          capture_output=True, text=True, env=fc_env(home), cwd=ROOT, timeout=SAFETY_S,
                          stdin=subprocess.DEVNULL)


@pytest.fixture(scope="session")
def fc_home(tmp_path_factory) -> Path:
    """A HOME whose FreeCAD has the workbench installed (shared by the FreeCAD tests)."""
    if FREECADCMD is None:
        pytest.skip("freecadcmd is not installed (Debian package freecad-python3)")
    home = tmp_path_factory.mktemp("freecad_home")
    res = install_workbench(home, "--no-verify")
    assert res.returncode == 0, res.stdout + res.stderr
    # the FreeCAD runs must load this checkout's code, not another installation's
    markers = list(home.rglob(".cam-workbench-install.json"))
    assert len(markers) == 1, (markers, res.stdout)
    assert json.loads(markers[0].read_text())["source"] == str(ROOT), markers[0].read_text()
    return home


def user_mod_dir(home: Path, tmp: Path, extra_env: dict[str, str] | None = None) -> Path:
    """The Mod folder of the FreeCAD under test for the user ``home``, as that FreeCAD itself
    says (``getUserAppDataDir()``: ``~/.local/share/FreeCAD`` for 0.20 and 1.0, the versioned
    ``…/FreeCAD/v1-1`` for 1.1), never a path written into a test."""
    run = run_freecadcmd("import FreeCAD\nRESULT['data'] = FreeCAD.getUserAppDataDir()\n", tmp, home,
                         extra_env=extra_env).check()
    return Path(run.result["data"]) / "Mod"


def run_freecadcmd(body: str, tmp: Path, home: Path, add_root: bool = False,
                   timeout: float = SAFETY_S, extra_env: dict[str, str] | None = None) -> FreeCADRun:
    """Run ``body`` (Python) in a fresh ``freecadcmd`` as the user ``home``; ``add_root`` puts
    this checkout on sys.path too (for a FreeCAD without the workbench installed)."""
    tmp.mkdir(parents=True, exist_ok=True)
    script, result = tmp / "fc_script.py", tmp / "fc_result.json"
    result.unlink(missing_ok=True)
    script.write_text(_wrap(body, result, add_root), encoding="utf-8")
    env = fc_env(home)
    env.update(extra_env or {})
    proc = subprocess.run([FREECADCMD, str(script)], capture_output=True, text=True, timeout=timeout,
                          env=env, cwd=tmp, stdin=subprocess.DEVNULL)
    data = json.loads(result.read_text()) if result.exists() else {}
    return FreeCADRun(data, proc.stdout, proc.stderr, proc.returncode)


def run_freecad_gui(body: str, tmp: Path, home: Path, timeout: float = SAFETY_S,
                    screen: str = "1400x900x24") -> FreeCADRun:
    """Run ``body`` inside the real FreeCAD GUI under Xvfb.  ``body`` defines ``steps``, a list
    of functions run one after another from Qt's event loop (``(function, delay_ms)`` pairs; the
    delay only paces the session for the screenshots: a step that needs something to have
    happened says so by raising ``NotYet``).  A step raising ``NotYet`` (its widget has not
    appeared, the run has not reached its mark) is tried again every 250 ms, as long as it
    takes: the only limit is the safety net ``timeout`` (less a minute, so that the result names
    the step that hung), never a window the product must beat.  ``when_modal(action, kind)``
    runs ``action`` on the modal dialog the calling step opens, as soon as it is shown.  The
    application quits after the last step."""
    tmp.mkdir(parents=True, exist_ok=True)
    script, result = tmp / "gui_script.py", tmp / "gui_result.json"
    result.unlink(missing_ok=True)
    driver = f"""
import os, time
from PySide import QtCore, QtGui
import FreeCAD, FreeCADGui

class NotYet(Exception):
    pass  # raised by a step whose widget has not appeared yet: the step is retried

# the safety net: a step still not ready by then is a hang, reported by name
_camwb_deadline = time.monotonic() + {max(timeout - 60.0, timeout / 2)!r}
_camwb_calls = [0]  # calls of steps finished

mw = FreeCADGui.getMainWindow()

def shot(name):  # a screenshot of the whole screen into the body's ART folder
    QtGui.QGuiApplication.primaryScreen().grabWindow(0).save(os.path.join(ART, name))

def report_text():  # the report view's text
    dock = mw.findChild(QtGui.QDockWidget, "Report view")
    edits = dock.findChildren(QtGui.QTextEdit) + dock.findChildren(QtGui.QPlainTextEdit)
    return "\\n".join(e.toPlainText() for e in edits)

def button(text):  # the visible dialog-box button labelled text (mnemonic & ignored)
    for box in mw.findChildren(QtGui.QDialogButtonBox):
        for b in box.buttons():
            if b.isVisible() and b.text().replace("&", "") == text:
                return b
    raise NotYet(text)

def task_dock():  # the dock holding the task panels: "Combo View" (0.20), "Tasks" (1.0, 1.1)
    docks = mw.findChildren(QtGui.QDockWidget)
    for name in ("Combo View", "Tasks"):
        for d in docks:
            if d.objectName() == name:
                return d
    raise RuntimeError("no task-panel dock among " + ", ".join(repr(d.objectName()) for d in docks))

def when_modal(action, kind=QtGui.QDialog):
    # action(dialog) on the modal dialog of type kind that the running step opens, as soon as it
    # is shown: looked for every 100 ms from Qt's event loop (the dialog's own loop too) for as
    # long as the step that called this runs
    armed = _camwb_calls[0]
    def look():
        w = QtGui.QApplication.activeModalWidget()
        if isinstance(w, kind) and w.isVisible():
            action(w)
        elif _camwb_calls[0] == armed:
            QtCore.QTimer.singleShot(100, look)
    QtCore.QTimer.singleShot(100, look)

def motion_panel():  # the open motion-editor task panel
    vobj = FreeCADGui.ActiveDocument.getInEdit()
    p = vobj.Proxy.panel if vobj is not None else None
    if p is None or not p.form.isVisible():
        raise NotYet("motion editor")
    return p

{textwrap.dedent(body)}
def _camwb_run(i=0):
    try:
        if i < len(steps):
            fn, delay = steps[i]
            try:
                try:
                    fn()
                finally:
                    _camwb_calls[0] += 1
            except NotYet:
                if time.monotonic() < _camwb_deadline:  # not ready yet, however long it takes
                    QtCore.QTimer.singleShot(250, lambda: _camwb_run(i))
                    return
                raise
            QtCore.QTimer.singleShot(delay, lambda: _camwb_run(i + 1))
            return
        RESULT['_done'] = True
    except BaseException:
        RESULT['_traceback'] = traceback.format_exc()
    _camwb_write()
    try:
        FreeCADGui.Control.closeDialog()
        for _d in list(FreeCAD.listDocuments()):
            FreeCAD.closeDocument(_d)
    finally:
        QtGui.QApplication.instance().quit()
QtCore.QTimer.singleShot(1000, _camwb_run)
"""
    script.write_text(_PRELUDE.format(result=str(result)) + driver, encoding="utf-8")
    # in a root, its xvfb-run starts its own freecad (the wrapper would nest another namespace)
    gui = "freecad" if ROOT_BIN is not None else FREECAD_GUI
    cmd = [XVFB_RUN, "-a", "-s", f"-screen 0 {screen}", gui, str(script)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=fc_env(home),
                          cwd=tmp, stdin=subprocess.DEVNULL)
    data = json.loads(result.read_text()) if result.exists() else {}
    return FreeCADRun(data, proc.stdout, proc.stderr, proc.returncode)
