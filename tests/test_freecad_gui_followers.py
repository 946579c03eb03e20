"""Oscillating and flat-faced followers in the real FreeCAD GUI (Debian's ``freecad``) under Xvfb.

An oscillating roller cam is made from its spec file (*New cam from spec…*); its
follower child is drawn — the roller on its arm, the pivot — and redrawn at another cam angle;
the motion editor shows the lifts in degrees; Check design shows its rows and the follower's
label; a flat-faced cam added beside it shows the cusp and face-width rows.  No Python error or
warning of ours may reach the report view; screenshots go to ``test-artifacts/``.
"""
from __future__ import annotations

import math

import pytest

from cam_workbench.generators.checks.design import format_value
from cam_workbench.generators.spec import to_toml
from cam_workbench.generators.spec.examples import example_spec

from .freecad_support import fc_home, requires_freecad_gui, run_freecad_gui  # noqa: F401

pytestmark = requires_freecad_gui

GUI = r"""
import sys, os
ART = {art!r}
TOML = {toml!r}
FLAT = {flat!r}
R = RESULT
state = {{}}
import warnings
R["our_warnings"] = []
_shown = warnings.showwarning
def _record(message, category, filename, lineno, file=None, line=None):
    if any(f"/{{p}}/" in filename for p in ("cam_workbench", "generators", "exporters")):
        R["our_warnings"].append(f"{{category.__name__}}: {{message}} ({{filename}}:{{lineno}})")
    return _shown(message, category, filename, lineno, file, line)
warnings.showwarning = _record
warnings.simplefilter("always")

def cam():
    return FreeCAD.ActiveDocument.getObject("Cam")

def follower():
    from cam_workbench.freecad.feature import reference_of
    return reference_of(cam(), "follower")

def drawn():
    f = follower()
    out = {{"circles": [], "lines": [], "vertices": []}}
    for c in f.Shape.childShapes():
        if c.ShapeType == "Vertex":
            out["vertices"].append([c.Point.x, c.Point.y])
        elif c.Curve.TypeId == "Part::GeomCircle":
            out["circles"].append([c.Curve.Center.x, c.Curve.Center.y, c.Curve.Radius])
        else:
            a, b = c.Vertexes[0].Point, c.Vertexes[-1].Point
            out["lines"].append([[a.x, a.y], [b.x, b.y]])
    return out

def activate():
    mw.resize(1400, 900)
    cv = task_dock()
    mw.resizeDocks([cv], [560], QtCore.Qt.Horizontal)
    FreeCADGui.activateWorkbench("CamWorkbench")

def open_spec():
    # "New cam from spec…": its file dialog gets the spec file, as a user picks it
    def fill(w):
        R["file_dialog"] = type(w).__name__
        # the file name typed into the dialog (selectFile is asynchronous in Qt's own dialog)
        w.findChild(QtGui.QLineEdit, "fileNameEdit").setText(TOML)
        w.accept()
        if w.isVisible():   # never leave a modal dialog behind: the test would hang
            R["file_dialog_refused"] = True
            w.reject()
    when_modal(fill, QtGui.QFileDialog)
    FreeCADGui.runCommand("CamWorkbench_NewCamFromSpec")

def opened():
    doc = FreeCAD.ActiveDocument
    if doc is None or doc.getObject("Cam") is None:
        raise NotYet("document")
    doc.UndoMode = 1
    c, f = cam(), follower()
    R["opened"] = {{"objects": [o.Name for o in doc.Objects], "status": c.Status, "volume": c.Shape.Volume,
                   "visible": f.ViewObject.Visibility, "line_colour": list(f.ViewObject.LineColor)[:3],
                   "label": f.Label, "angle": f.FollowerAngle.Value, "drawn": drawn(),
                   "max_deviation": str(c.MaxDeviation), "tolerance_type": c.getTypeIdOfProperty("PitchTolerance"),
                   "tree": [o.Label for o in c.ViewObject.claimChildren()]}}
    follower().FollowerAngle = 75.0
    doc.recompute()
    R["at75"] = {{"drawn": drawn(), "status": c.Status}}
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewTop()
    view.fitAll()
    for t in mw.findChildren(QtGui.QTreeWidget):
        t.expandAll()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(follower())

def follower_shot():
    shot("freecad_gui_follower_oscillating.png")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.ActiveDocument.ActiveView.saveImage(os.path.join(ART, "freecad_gui_follower_view.png"), 1000, 750,
                                                   "White")
    FreeCADGui.runCommand("CamWorkbench_EditMotion")

def editor():
    p = motion_panel()
    R["editor_headers"] = [p.table.horizontalHeaderItem(i).text() for i in range(p.table.columnCount())]
    col = [f for f, _ in p.cols].index("lift")
    R["editor_lifts"] = [p.table.item(r, col).text() if p.table.item(r, col) else "" for r in range(p.table.rowCount())]
    shot("freecad_gui_follower_motion_editor.png")
    button("Cancel").click()

def check_design():
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(cam())
    FreeCADGui.runCommand("CamWorkbench_CheckDesign")

def dialog_rows(key):
    d = [w for w in QtGui.QApplication.topLevelWidgets() if w.isVisible() and w.windowTitle().startswith("Check design")]
    if not d:
        raise NotYet("check dialog")
    t = d[0].findChild(QtGui.QTableWidget, "checks")
    b = d[0].findChild(QtGui.QTableWidget, "buildability")
    who = d[0].findChild(QtGui.QLabel, "follower")
    R[key] = {{"title": d[0].windowTitle(), "follower": who.text() if who is not None else None,
              "rows": [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())],
              "build": [[b.item(r, c).text() for c in range(b.columnCount())] for r in range(b.rowCount())]}}
    d[0].move(40, 40)
    state["dialog"] = d[0]

def check_dialog():
    dialog_rows("check")

def check_shot():
    shot("freecad_gui_check_design_oscillating.png")
    state.pop("dialog").close()

def add_flat():
    from cam_workbench.freecad.feature import create
    doc = FreeCAD.ActiveDocument
    flat = create(doc, FLAT, name="Flat")
    doc.recompute()
    R["flat"] = {{"status": flat.Status, "objects": [o.Name for o in doc.Objects]}}
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(flat)
    FreeCADGui.runCommand("CamWorkbench_CheckDesign")

def flat_dialog():
    dialog_rows("flat_check")

def flat_shot():
    shot("freecad_gui_check_design_flat.png")
    state.pop("dialog").close()
    R["report"] = report_text()

steps = [(activate, 500), (open_spec, 1500), (opened, 1500), (follower_shot, 1500), (editor, 1000),
         (check_design, 2000), (check_dialog, 1000), (check_shot, 200), (add_flat, 2000), (flat_dialog, 1000),
         (flat_shot, 200)]
"""


def test_followers_in_the_freecad_gui(tmp_path, fc_home, artifacts):
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.checks.design import run_checks
    from cam_workbench.generators.spec.examples import example_dict

    spec = example_spec("oscillating")
    toml = tmp_path / "oscillating_cam.toml"
    toml.write_text(to_toml(spec))
    run = run_freecad_gui(GUI.format(art=str(artifacts), toml=str(toml), flat=example_dict("flat")), tmp_path,
                          fc_home)
    (artifacts / "freecad_gui_followers_console.txt").write_text(run.console)
    r = run.check().result
    (artifacts / "freecad_gui_followers_report_view.txt").write_text(r.get("report", ""))
    assert r["file_dialog"] == "QFileDialog" and "file_dialog_refused" not in r
    o = r["opened"]
    assert o["objects"] == ["Cam", "CamPitchCurve", "CamBaseCircle", "CamFollower"]
    assert o["status"] == "ok"
    exact = design_cam(spec).volume
    assert abs(o["volume"] - exact) / exact < 1e-9
    assert o["visible"] is True and o["angle"] == 0.0
    assert o["tree"] == ["Cam pitch curve", "Cam base circle", "Cam follower"]
    assert o["tolerance_type"] == "App::PropertyAngle"
    assert o["max_deviation"].endswith("°") or "deg" in o["max_deviation"], o["max_deviation"]
    # the arm and its pivot, the roller: pivot at (d, 0) rotated by −θ (ccw), an arm of L = 45
    d, arm, rr = 60.0, 45.0, 8.0
    for key, theta in (("opened", 0.0), ("at75", 75.0)):
        dr = (o if key == "opened" else r[key])["drawn"]
        pivot = (d * math.cos(-math.radians(theta)), d * math.sin(-math.radians(theta)))
        (a, b), = dr["lines"]
        assert math.dist(a, pivot) < 1e-9 and math.dist(a, b) == pytest.approx(arm, abs=1e-9)
        rollers = [c for c in dr["circles"] if abs(c[2] - rr) < 1e-12]
        assert len(rollers) == 1 and math.dist(rollers[0][:2], b) < 1e-9
        assert any(math.dist(v, pivot) < 1e-9 for v in dr["vertices"])
    assert r["at75"]["status"] == "ok" and r["at75"]["drawn"] != o["drawn"]
    # lifts in degrees, not lengths
    assert "lift [°]" in r["editor_headers"], r["editor_headers"]
    assert [float(x) for x in r["editor_lifts"] if x] == [15.0, 15.0], r["editor_lifts"]
    # Check design: the library's checks of this cam, in order, and the follower's label
    checked = run_checks(spec)
    c = r["check"]
    assert c["follower"] == "Follower: oscillating roller r = 8, pivot d = 60, arm L = 45 mm"
    assert [row[0] for row in c["rows"]] == [x.name.replace("_", " ") for x in checked.results]
    assert [row[4] for row in c["rows"]] == [x.status for x in checked.results]
    build = {(g, item): value for g, item, value, _s in c["build"]}
    assert build[("Motion", "max lift")] == "15 deg"
    assert build[("Pitch curve", "max follower rotation deviation |s_actual − s|")].endswith(" deg at 57.00°")
    # the flat face: its cusp and face-width rows, the contact curve
    flat = run_checks(example_spec("flat"))
    f = r["flat_check"]
    assert r["flat"]["status"] == "ok"
    assert f["follower"] == "Follower: translating flat face, offset e = 0 mm"
    assert [row[0] for row in f["rows"]] == [x.name.replace("_", " ") for x in flat.results]
    assert {"cusp", "face width"} <= {row[0] for row in f["rows"]}
    fw = next(row for row in f["rows"] if row[0] == "face width")
    assert fw[3] == f"≤ {format_value(40.0, 'mm')}" and fw[4] == "pass"
    assert fw[1] == format_value(flat["face_width"].value, "mm")
    assert ("Contact curve", "PH quintic segments M") in {(g, i) for g, i, _v, _s in f["build"]}
    report = r["report"]
    assert "Traceback" not in report and "Traceback" not in run.console
    assert r["our_warnings"] == []
    # (the Check design table printed to the report view is indented: a flat face's profile
    # claim names its "max error" there)
    bad = [line for line in report.splitlines() if ("Error" in line or "error" in line) and not line.startswith("  ")]
    assert bad == [], bad
    for name in ("freecad_gui_follower_oscillating.png", "freecad_gui_follower_view.png",
                 "freecad_gui_check_design_oscillating.png", "freecad_gui_check_design_flat.png",
                 "freecad_gui_follower_motion_editor.png"):
        assert (artifacts / name).stat().st_size > 10_000, name
