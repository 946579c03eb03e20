"""The workbench in the real FreeCAD GUI (Debian's ``freecad``) under Xvfb.

One FreeCAD session, driven from Qt's event loop like a user: the workbench is found and
activated (and did not load numpy/scipy/generators at start-up), a cam is created with the
toolbar command, the motion editor opens from the command, is edited and applied with its
OK button (one undo step), refuses a bad program (and stays open) and is cancelled; Check
design and the kinematics plots open their dialogs; STEP is exported through the file
dialog (the suggested name accepted); deleting the cam takes its reference curves along
without a warning.  The report view must hold no Python error.  Screenshots are saved to
``test-artifacts/`` for a person to look at.
"""
from __future__ import annotations

from .freecad_support import fc_home, requires_freecad_gui, run_freecad_gui  # noqa: F401

pytestmark = requires_freecad_gui

GUI = r"""
import sys, os
ART = {art!r}
STEP_PATH = {step!r}
PA_LIMIT = {pa_limit!r}
R = RESULT
R["start_modules"] = {{m: m in sys.modules for m in ("cam_workbench.generators", "scipy", "cam_workbench",
                                                   "cam_workbench.freecad.commands")}}
R["workbenches"] = sorted(FreeCADGui.listWorkbenches())
state = {{}}
# every Python warning our packages cause from here on (deprecations of PySide6, numpy 2, …)
import warnings
R["our_warnings"] = []
_shown = warnings.showwarning
def _record(message, category, filename, lineno, file=None, line=None):
    if any(f"/{{p}}/" in filename for p in ("cam_workbench", "generators", "exporters")):
        R["our_warnings"].append(f"{{category.__name__}}: {{message}} ({{filename}}:{{lineno}})")
    return _shown(message, category, filename, lineno, file, line)
warnings.showwarning = _record
warnings.simplefilter("always")

def activate():
    mw.resize(1400, 900)
    cv = task_dock()
    mw.resizeDocks([cv], [560], QtCore.Qt.Horizontal)
    FreeCADGui.activateWorkbench("CamWorkbench")
    R["active"] = FreeCADGui.activeWorkbench().name()
    menus = [a.text().replace("&", "") for a in mw.menuBar().actions()]
    R["menu"] = "Cam" in menus
    tb = [t for t in mw.findChildren(QtGui.QToolBar) if t.windowTitle() == "Cam"]
    R["toolbar"] = [a.text() for a in tb[0].actions()] if tb else []

def new_cam():
    FreeCADGui.runCommand("CamWorkbench_NewCam")
    doc = FreeCAD.ActiveDocument
    doc.UndoMode = 1
    cam = doc.getObject("Cam")
    R["new"] = {{"status": cam.Status, "valid": cam.Shape.isValid(), "volume": cam.Shape.Volume,
                "objects": [o.Name for o in doc.Objects], "undo": doc.UndoNames[:1]}}
    FreeCADGui.Selection.clearSelection()

def open_editor():
    FreeCADGui.runCommand("CamWorkbench_EditMotion")

def editor_state():
    p = motion_panel()
    R["editor_open"] = bool(FreeCADGui.Control.activeDialog()) and p is not None
    R["editor_rows"] = p.table.rowCount()
    R["editor_status"] = p.status.text()

def screenshot_editor():
    shot("freecad_gui_motion_editor.png")

def edit_and_ok():
    p = motion_panel()
    ok = button("OK")
    col = [f for f, _ in p.cols].index("lift")
    p.table.item(1, col).setText("15")
    p.table.item(3, col).setText("15")
    R["edited_status"] = p.status.text()
    state["undo_before"] = FreeCAD.ActiveDocument.UndoCount
    ok.click()

def after_ok():
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Cam")
    R["after_ok"] = {{"dialog": bool(FreeCADGui.Control.activeDialog()), "lifts": list(cam.MotionLift),
                     "status": cam.Status, "volume": cam.Shape.Volume,
                     "undo_steps": doc.UndoCount - state["undo_before"], "undo": doc.UndoNames[:1]}}

def bad_open():
    FreeCADGui.runCommand("CamWorkbench_EditMotion")

def bad_program():
    p = motion_panel()
    ok = button("OK")
    col = [f for f, _ in p.cols].index("angle")
    p.table.item(0, col).setText("25")
    R["bad_status"] = p.status.text()
    ok.click()

def after_bad():
    R["bad_still_open"] = bool(FreeCADGui.Control.activeDialog())
    shot("freecad_gui_motion_editor_refused.png")
    button("Cancel").click()

def after_cancel():
    cam = FreeCAD.ActiveDocument.getObject("Cam")
    R["after_cancel"] = {{"dialog": bool(FreeCADGui.Control.activeDialog()),
                         "angles": list(cam.MotionAngle)}}
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    tree = mw.findChildren(QtGui.QTreeWidget)
    for t in tree:
        t.expandAll()

def select_cam():
    FreeCADGui.Selection.addSelection(FreeCAD.ActiveDocument.getObject("Cam"))

def screenshot_model():
    shot("freecad_gui_cam.png")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.ActiveDocument.ActiveView.saveImage(os.path.join(ART, "freecad_gui_view.png"), 1000, 750, "White")

def check_design():
    # a stricter pressure-angle limit than the default cam's 30° (which it passes), so the
    # dialog shows a failing row too
    FreeCAD.ActiveDocument.getObject("Cam").ChecksMaxPressureAngle = PA_LIMIT
    FreeCADGui.runCommand("CamWorkbench_CheckDesign")

def check_dialog():
    d = [w for w in QtGui.QApplication.topLevelWidgets() if w.isVisible() and w.windowTitle().startswith("Check design")]
    if not d:
        raise NotYet("check dialog")
    R["check_dialog"] = len(d)
    if d:
        tables = d[0].findChildren(QtGui.QTableWidget)
        t = d[0].findChild(QtGui.QTableWidget, "checks")
        R["check_rows"] = sum(x.rowCount() for x in tables)
        R["check_fail"] = [t.item(r, 0).text() for r in range(t.rowCount()) if t.item(r, 4).text() == "fail"]
        R["check_names"] = [t.item(r, 0).text() for r in range(t.rowCount())]
        d[0].move(40, 40)
        state["check"] = d[0]

def check_shot():
    shot("freecad_gui_check_design.png")
    state.pop("check").close()

def plots():
    FreeCADGui.runCommand("CamWorkbench_ShowPlots")

def plot_dialog():
    d = [w for w in QtGui.QApplication.topLevelWidgets() if w.isVisible() and w.windowTitle().startswith("Kinematics")]
    if not d:
        raise NotYet("plots")
    R["plot_dialog"] = len(d)
    if d:
        d[0].move(250, 0)
        state["plots"] = d[0]

def plot_shot():
    shot("freecad_gui_plots.png")
    state.pop("plots").close()

def export_step():
    def fill(w):
        R["file_dialog"] = type(w).__name__
        w.accept()  # "Save" with the suggested name: <Label>.step in the working folder
    when_modal(fill, QtGui.QFileDialog)
    FreeCADGui.runCommand("CamWorkbench_ExportStep")

def after_export():
    R["step_written"] = os.path.exists(STEP_PATH) and os.path.getsize(STEP_PATH) > 1000

def delete_cam():
    # any modal dialog (a warning) while Std_Delete runs is recorded and closed
    def watch(w):
        R["delete_modal"] = w.text() if hasattr(w, "text") else type(w).__name__
        w.close()
    R["delete_modal"] = None
    when_modal(watch)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(FreeCAD.ActiveDocument.getObject("Cam"))
    FreeCADGui.runCommand("Std_Delete")

def after_delete():
    R["after_delete"] = [o.Name for o in FreeCAD.ActiveDocument.Objects]
    R["report"] = report_text()

steps = [(activate, 500), (new_cam, 1000), (open_editor, 500), (editor_state, 1000), (screenshot_editor, 200),
         (edit_and_ok, 1500), (after_ok, 200), (bad_open, 1500), (bad_program, 1500), (after_bad, 1000),
         (after_cancel, 1500), (select_cam, 1000), (screenshot_model, 200), (check_design, 2000),
         (check_dialog, 1000), (check_shot, 200), (plots, 3000), (plot_dialog, 1500), (plot_shot, 200),
         (export_step, 3000), (after_export, 200), (delete_cam, 1500), (after_delete, 200)]
"""


#: the pressure-angle limit Check design is run with (the default cam with 15 mm lifts has 16.9°)
PA_LIMIT = 15.0


def test_workbench_in_the_freecad_gui(tmp_path, fc_home, artifacts):
    from cam_workbench.generators import default_spec
    from cam_workbench.generators.checks.design import run_checks

    step = tmp_path / "Cam.step"  # the dialog's suggestion (the document is unsaved: cwd)
    run = run_freecad_gui(GUI.format(art=str(artifacts), step=str(step), pa_limit=PA_LIMIT), tmp_path, fc_home)
    (artifacts / "freecad_gui_console.txt").write_text(run.console)  # FreeCAD's own output
    r = run.check().result
    (artifacts / "freecad_gui_report_view.txt").write_text(r.get("report", ""))
    assert r["start_modules"] == {"cam_workbench.generators": False, "scipy": False, "cam_workbench": False,
                                  "cam_workbench.freecad.commands": False}, "start-up is not cheap"
    assert "CamWorkbench" in r["workbenches"]
    assert r["active"] == "CamWorkbench" and r["menu"]
    assert r["toolbar"] == ["New cam", "Edit motion program", "Optimise", "Check design",
                            "Show kinematics plots", "Export STEP…", "Export DXF…", "Export G-code…",
                            "Design report (HTML)…"]
    new = r["new"]
    assert new["status"] == "ok" and new["valid"] and new["volume"] > 0
    assert new["objects"] == ["Cam", "CamPitchCurve", "CamBaseCircle", "CamFollower"]
    assert r["editor_open"] and r["editor_rows"] == 5 and r["editor_status"] == "OK"
    assert r["edited_status"] == "OK"
    ok = r["after_ok"]
    assert ok["dialog"] is False
    assert ok["lifts"] == [0.0, 15.0, 0.0, 15.0, 0.0]
    assert ok["status"] == "ok" and ok["volume"] < new["volume"]
    assert ok["undo_steps"] == 1 and ok["undo"] == ["Edit motion program"]
    assert r["bad_status"] == "row 5, angle: spans sum to 355°, must be 360°"
    assert r["bad_still_open"] is True
    assert r["after_cancel"] == {"dialog": False, "angles": [30.0, 120.0, 60.0, 120.0, 30.0]}
    # the dialog lists the library's checks of the cam as edited (the default cam with 15 mm
    # lifts) and fails exactly those the library fails under the stricter limit
    checked = run_checks(default_spec().replace(**{"motion[1].lift": 15.0, "motion[3].lift": 15.0,
                                                   "checks.max_pressure_angle": PA_LIMIT}))
    assert checked.failed, "the stricter limit must make a check fail (the dialog's fail rows)"
    assert r["check_dialog"] == 1 and r["check_rows"] > 15
    assert r["check_names"] == [c.name.replace("_", " ") for c in checked.results]
    assert r["check_fail"] == [n.replace("_", " ") for n in checked.failed]
    assert r["plot_dialog"] == 1
    assert r["file_dialog"] == "QFileDialog" and r["step_written"]
    assert r.get("delete_modal") is None and r["after_delete"] == []  # children go with the cam
    report = r["report"]
    assert "Cam: motion program not applied: row 5, angle: spans sum to 355°" in report
    assert "Traceback" not in report and "Traceback" not in run.console
    assert r["our_warnings"] == []
    bad = [line for line in report.splitlines()
           if ("Error" in line or "error" in line) and "motion program not applied" not in line]
    assert bad == [], bad
    for name in ("freecad_gui_motion_editor.png", "freecad_gui_cam.png", "freecad_gui_check_design.png",
                 "freecad_gui_plots.png", "freecad_gui_view.png"):
        assert (artifacts / name).stat().st_size > 10_000, name
