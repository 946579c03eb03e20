"""The optimiser task panel in the real FreeCAD GUI (Debian's ``freecad``) under Xvfb.

The thesis' Example 5 initial design (inches, B-spline rise and return, fails separation) is
created; the Optimise command (menu and toolbar) opens the panel on it: the objectives, the
design variables this cam has (R_b, e, the angles and free lifts of both B-spline segments; the
blank orientation disabled for the area), the base-radius lower bound flagged as the library's
guess.  A long global run (ISRES) is started and its progress bar and live figures watched while
a GUI-thread timer keeps ticking, then cancelled: it ends "cancelled" after the evaluation in
progress and the cam is unchanged.  A short SLSQP run is let finish: before/after figures and
every design check before and after; Apply writes the optimised spec as one undo step; Undo
restores the original cam; Close during a run cancels it and writes nothing.  No Python error may reach the report view; screenshots go to
``test-artifacts/`` for a person to look at.
"""
from __future__ import annotations

from .conftest import ROOT
from .freecad_support import fc_home, requires_freecad_gui, run_freecad_gui  # noqa: F401

pytestmark = requires_freecad_gui

GUI = r"""
import sys, os, time
ART = {art!r}
EX5 = {ex5!r}
R = RESULT
state = {{}}

def panel():
    from cam_workbench.freecad.optimiser_panel import active_panel
    p = active_panel()
    if p is None or not p.form[0].isVisible():
        raise NotYet("optimiser panel")
    return p

def spec_text():
    from cam_workbench.freecad import properties as P
    from cam_workbench.generators.spec import to_toml
    return to_toml(P.spec_of(FreeCAD.ActiveDocument.getObject("Ex5")))

def activate():
    mw.resize(1400, 900)
    cv = task_dock()
    mw.resizeDocks([cv], [700], QtCore.Qt.Horizontal)
    FreeCADGui.activateWorkbench("CamWorkbench")
    menus = [m for m in mw.findChildren(QtGui.QMenu) if m.title().replace("&", "") == "Cam"]
    R["menu"] = [a.text() for a in menus[0].actions() if a.text()] if menus else []
    tb = [t for t in mw.findChildren(QtGui.QToolBar) if t.windowTitle() == "Cam"]
    R["toolbar"] = [a.text() for a in tb[0].actions()] if tb else []

def new_cam():
    from cam_workbench.freecad.feature import create
    doc = FreeCAD.newDocument("Ex5")
    doc.UndoMode = 1
    cam = create(doc, EX5, name="Ex5")
    doc.recompute()
    state["spec0"] = spec_text()
    state["volume0"] = cam.Shape.Volume
    state["undo0"] = doc.UndoCount
    R["new"] = {{"status": cam.Status, "volume": cam.Shape.Volume}}
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    FreeCADGui.Selection.addSelection(cam)

def open_panel():
    FreeCADGui.runCommand("CamWorkbench_Optimise")

def panel_state():
    p = panel()
    R["panel"] = {{
        "dialog": bool(FreeCADGui.Control.activeDialog()),
        "titles": [w.windowTitle() for w in p.form],
        "objectives": [p.objective.itemData(i) for i in range(p.objective.count())],
        "objective": p.objective.currentData(),
        "algorithms": [p.algorithm.itemData(i) for i in range(p.algorithm.count())],
        "variables": {{t: [cb.text(), cb.isEnabled(), cb.isChecked()] for t, cb in p.var_boxes.items()}},
        "count": p.var_count.text(),
        "rb_min": p.rb_min.value(), "rb_max": p.rb_max.value(), "e_max": p.e_max.value() if p.e_max is not None else None,
        "rb_title": p.rb_min_box.title(), "rb_note": p.rb_note.text(),
        "max_evals": p.max_evals.value(), "status": p.status.text(),
        "run_enabled": p.run_button.isEnabled(), "apply_enabled": p.apply_button.isEnabled(),
        "plot": p.canvas is not None,
        # fits the task area: no panel needs more width than the dock holding it has, and the
        # window is not pushed past the screen
        "min_widths": [w.minimumSizeHint().width() for w in p.form],
        "task_width": task_dock().width(), "task_visible": task_dock().isVisible(),
        "window_width": mw.frameGeometry().width(),
        "right_edges": [w.mapToGlobal(QtCore.QPoint(w.width(), 0)).x() for w in p.form],
        "checked_drawn": {{t: cb.checkState() == QtCore.Qt.Checked for t, cb in p.var_boxes.items()}},
    }}
    shot("freecad_gui_optimise_panel.png")

def start_long():
    p = panel()
    p.objective.setCurrentIndex(p.objective.findData("machining_time"))
    R["machining_time"] = {{"orientation": [p.var_boxes["orientation"].isEnabled(), p.var_boxes["orientation"].isChecked()],
                           "count": p.var_count.text(), "status": p.status.text(),
                           "gradient_items": [p.algorithm.model().item(i).isEnabled() for i in range(p.algorithm.count())]}}
    R["long_started"] = p.start()
    state["progress"] = []

def watch():
    p = panel()
    v = p.progress.value()
    state["progress"].append([v, p.progress.maximum(), p.live.text()])
    # the run's own progress: 250 evaluations and the second phase (the time itself) begun, however
    # long the machine takes (where the stand-in ends depends on the FreeCAD's numpy and nlopt)
    if v < 250 or not p.live.text().startswith("bobyqa"):
        raise NotYet("progress")
    R["watched"] = state["progress"]
    R["running_before_cancel"] = p.running
    R["cancel_enabled"] = p.cancel_button.isEnabled()
    R["run_enabled_while_running"] = p.run_button.isEnabled()
    R["settings_enabled_while_running"] = [w.isEnabled() for w in p.settings_widgets]
    shot("freecad_gui_optimise_running.png")

def cancel():
    p = panel()
    p.cancel_button.click()
    # read after the click: what the run did meanwhile is counted, however busy the machine
    R["evals_at_cancel"] = p.job.latest.evaluations
    R["live_after_cancel_click"] = p.live.text()

def cancelled():
    p = panel()
    if p.running or p.result is None:
        raise NotYet("cancelled run")
    res = p.result
    ticks = p.ticks
    gaps = [b - a for a, b in zip(ticks, ticks[1:])]
    R["cancelled"] = {{"status": res.status, "status_text": res.status_text, "evaluations": res.evaluations,
                      "live": p.live.text(),
                      "cancel_to_end_s": p.job.finished - p.job.cancel_requested_at,
                      "history": len(p.job.history), "ticks": len(ticks),
                      "max_tick_gap_s": max(gaps) if gaps else None, "gaps": sorted(gaps)[-8:],
                      "plot_s": sorted(p.plot_seconds)[-5:], "plots": len(p.plot_seconds),
                      "verdict": p.verdict.text(), "apply_enabled": p.apply_button.isEnabled()}}
    doc = FreeCAD.ActiveDocument
    R["unchanged_after_cancel"] = {{"spec": spec_text() == state["spec0"], "undo": doc.UndoCount - state["undo0"],
                                   "volume": doc.getObject("Ex5").Shape.Volume}}
    shot("freecad_gui_optimise_cancelled.png")

def start_short():
    p = panel()
    p.objective.setCurrentIndex(p.objective.findData("area"))
    R["back_to_area"] = {{"orientation": [p.var_boxes["orientation"].isEnabled(), p.var_boxes["orientation"].isChecked()],
                         "count": p.var_count.text()}}
    p.max_evals.setValue(60)
    R["short_started"] = p.start()

def finished():
    p = panel()
    if p.running or p.result is None:
        raise NotYet("short run")
    res = p.result
    t = p.figure_table
    R["figures"] = [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())]
    t = p.check_table
    R["checks"] = [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())]
    R["short"] = {{"status": res.status, "feasible": res.feasible, "evaluations": res.evaluations,
                  "value": res.value, "initial": res.initial_value, "verdict": p.verdict.text(),
                  "apply_text": p.apply_button.text(), "apply_enabled": p.apply_button.isEnabled(),
                  "variables": list(res.variables), "live": p.live.text()}}
    from cam_workbench.generators.spec import to_toml
    state["result_spec"] = to_toml(res.spec)
    shot("freecad_gui_optimise_result.png")

def plot_shot():
    p = panel()
    p.scroll_to(p.form[3])
    shot("freecad_gui_optimise_convergence.png")

def apply():
    p = panel()
    state["undo_before"] = FreeCAD.ActiveDocument.UndoCount
    p.apply_button.click()

def applied():
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Ex5")
    R["applied"] = {{"dialog": bool(FreeCADGui.Control.activeDialog()), "status": cam.Status,
                    "undo": doc.UndoCount - state["undo_before"], "names": doc.UndoNames[:1],
                    "spec_equal": spec_text() == state["result_spec"], "volume": cam.Shape.Volume,
                    "valid": cam.Shape.isValid(), "base_radius": cam.CamBaseRadius.getValueAs("in").Value,
                    "objective_prop": cam.OptimiseObjective, "variables_prop": cam.OptimiseVariables,
                    "rb_min_prop": cam.OptimiseBaseRadiusMin.getValueAs("in").Value,
                    "max_evals_prop": cam.OptimiseMaxEvaluations}}
    FreeCADGui.ActiveDocument.ActiveView.fitAll()

def applied_shot():
    shot("freecad_gui_optimise_applied.png")
    FreeCAD.ActiveDocument.undo()

def undone():
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Ex5")
    R["undone"] = {{"spec": spec_text() == state["spec0"], "volume": cam.Shape.Volume, "volume0": state["volume0"],
                   "status": cam.Status}}
    state["undo1"] = doc.UndoCount
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.runCommand("CamWorkbench_Optimise")    # the only cam of the document: no selection needed

def close_while_running():
    p = panel()
    R["reopened"] = {{"max_evals": p.max_evals.value(), "algorithm": p.algorithm.currentData()}}
    p.objective.setCurrentIndex(p.objective.findData("machining_time"))
    p.start()
    state["job"] = p.job
    for box in mw.findChildren(QtGui.QDialogButtonBox):
        for b in box.buttons():
            if b.isVisible() and b.text().replace("&", "") == "Close":
                state["close"] = b
    state["close"].click()

def closed():
    job = state["job"]
    if not job.done:
        raise NotYet("the closed panel's run")
    from cam_workbench.freecad.optimiser_panel import active_panel
    doc = FreeCAD.ActiveDocument
    R["closed"] = {{"dialog": bool(FreeCADGui.Control.activeDialog()), "panel": active_panel() is None,
                   "status": job.result.status if job.result else job.error, "spec": spec_text() == state["spec0"],
                   "undo": doc.UndoCount - state["undo1"]}}
    FreeCADGui.runCommand("CamWorkbench_Optimise")

def replaced_while_running():
    p = panel()
    p.start()
    state["job"] = p.job
    FreeCADGui.runCommand("CamWorkbench_EditMotion")   # another task panel takes the task view

def replaced():
    job = state["job"]
    if not job.done:
        raise NotYet("the replaced panel's run")
    vobj = FreeCADGui.ActiveDocument.getInEdit()
    editor = vobj.Proxy.panel if vobj is not None else None
    R["replaced"] = {{"status": job.result.status if job.result else job.error, "editor": editor is not None,
                     "spec": spec_text() == state["spec0"]}}
    editor.reject()

def reopen():
    FreeCADGui.runCommand("CamWorkbench_Optimise")

def failing_result():
    p = panel()
    p.start()
    p.cancel()                                          # at once: the start design, which fails separation

def answer_no():
    p = panel()
    if p.running or p.result is None:
        raise NotYet("the cancelled run")
    R["failing"] = {{"feasible": p.result.feasible, "evaluations": p.result.evaluations,
                    "apply_text": p.apply_button.text(), "verdict": p.verdict.text()}}
    state["undo2"] = FreeCAD.ActiveDocument.UndoCount
    _answer("No")
    p.apply_button.click()
    R["after_no"] = {{"status": p.status.text(), "spec": spec_text() == state["spec0"],
                     "undo": FreeCAD.ActiveDocument.UndoCount - state["undo2"],
                     "dialog": bool(FreeCADGui.Control.activeDialog())}}

def answer_yes():
    p = panel()
    _answer("Yes")
    p.apply_button.click()

def after_yes():
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Ex5")
    R["after_yes"] = {{"dialog": bool(FreeCADGui.Control.activeDialog()), "undo": doc.UndoCount - state["undo2"],
                      "names": doc.UndoNames[:1], "status": cam.Status, "question": state.get("question")}}
    doc.undo()
    R["report_view"] = report_text()

def _answer(which):
    def press(w):
        state["question"] = [w.windowTitle(), w.text()]
        for b in w.buttons():
            if b.text().replace("&", "") == which:
                b.click()
    when_modal(press, QtGui.QMessageBox)

steps = [(activate, 500), (new_cam, 1000), (open_panel, 500), (panel_state, 300), (start_long, 200),
         (watch, 200), (cancel, 100), (cancelled, 300), (start_short, 200), (finished, 500), (plot_shot, 300),
         (apply, 800), (applied, 800), (applied_shot, 800), (undone, 800), (close_while_running, 300), (closed, 800),
         (replaced_while_running, 800), (replaced, 500), (reopen, 500), (failing_result, 300), (answer_no, 500),
         (answer_yes, 1000), (after_yes, 300)]
"""


def test_optimiser_panel_in_the_freecad_gui(tmp_path, fc_home, artifacts):
    ex5 = ROOT / "tests" / "fixtures" / "thesis_ex5_initial.toml"
    run = run_freecad_gui(GUI.format(art=str(artifacts), ex5=str(ex5)), tmp_path, fc_home)
    r = run.check().result
    (artifacts / "freecad_gui_optimise_report_view.txt").write_text(r.get("report_view", ""))
    (artifacts / "freecad_gui_optimise_result.json").write_text(__import__("json").dumps(r, indent=1))
    assert "Optimise" in r["menu"] and r["menu"].index("Optimise") == r["menu"].index("Edit motion program") + 1
    assert r["toolbar"][:3] == ["New cam", "Edit motion program", "Optimise"]
    assert r["new"]["status"] == "ok"
    p = r["panel"]
    assert p["dialog"] and p["titles"] == ["Optimise Ex5", "Bounds", "Algorithm", "Run", "Result: before → after"]
    assert p["objectives"] == ["area", "profile_area", "machining_time", "gcode_time", "peak_acceleration",
                               "peak_pressure_angle"] and p["objective"] == "area"
    assert p["algorithms"] == ["auto", "slsqp", "mma", "ccsaq", "cobyla", "bobyqa", "isres"]
    v = p["variables"]
    assert list(v) == ["base_radius", "offset", "motion[0].control_x", "motion[0].control_y",
                       "motion[2].control_x", "motion[2].control_y", "orientation"]
    # enabled, and chosen by "auto" except the follower's offset (the machine's: only when named)
    assert all(v[t][1] and v[t][2] == (t != "offset") for t in list(v)[:-1])
    assert v["orientation"][1:] == [False, False]                     # area: no blank orientation
    assert v["motion[0].control_x"][0] == "row 1 (rise): control angles P1x … P9x  (9)"
    assert v["motion[2].control_y"][0] == "row 3 (return): free lifts P4y … P6y  (3)"
    assert p["count"] == "25 design variables"
    # the library's bounds for Example 5: R_b ∈ [½, 2] × 4.5 in, |e| ≤ ½ × 2.25 in
    assert (p["rb_min"], p["rb_max"], p["e_max"]) == (2.25, 9.0, 1.125)
    assert p["rb_title"] == "Smallest base radius R_b (shaft, hub, bore)"
    assert "not a real limit" in p["rb_note"] and "do not bound the cam from below" in p["rb_note"]
    assert p["status"] == "Ready: area over 25 variables." and p["run_enabled"] and not p["apply_enabled"]
    assert p["max_evals"] == 3000 and p["plot"] is True
    # the panel fits: the window stays within the 1400-pixel Xvfb screen, every box of the panel
    # ends on it, and none needs more width than its task area (FreeCAD 1.1's Tasks dock)
    assert p["window_width"] <= 1400 and max(p["right_edges"]) <= 1400, p
    assert max(p["min_widths"]) <= p["task_width"], p
    # the boxes the count reports are checked (PySide6's CheckState compared as an enum)
    assert p["checked_drawn"] == {t: t not in ("orientation", "offset") for t in v}, p["checked_drawn"]
    # machining time: the blank orientation becomes a variable ("auto"), gradient algorithms are off
    mt = r["machining_time"]
    assert mt["orientation"] == [True, True] and mt["count"] == "26 design variables"
    assert mt["status"] == "Ready: machining_time over 26 variables."
    assert mt["gradient_items"] == [True, False, False, False, True, True, True]
    # the long run: the bar moves while the GUI-thread timer keeps ticking; cancel stops it
    assert r["long_started"] is True
    values = [w[0] for w in r["watched"]]
    assert values == sorted(values) and values[-1] >= 250 and len(set(values)) >= 3, values
    assert r["watched"][-1][1] == 6000                                # 3000 × 2 phases (stand-in, time)
    assert "largest constraint value" in r["watched"][-1][2]
    phases = [w[2].split(":")[0] for w in r["watched"] if not w[2].startswith("starting")]
    assert phases[0] == "slsqp on thesis_length" and phases[-1].startswith("bobyqa"), phases
    assert r["back_to_area"] == {"orientation": [False, False], "count": "25 design variables"}
    assert r["running_before_cancel"] and r["cancel_enabled"] and not r["run_enabled_while_running"]
    assert r["settings_enabled_while_running"] == [False, False, False]
    c = r["cancelled"]
    assert c["status"] == "cancelled", c
    # stopped at the evaluation in progress at the click (its count read just after the click)
    assert r["evals_at_cancel"] <= c["evaluations"] <= r["evals_at_cancel"] + 2, (r["evals_at_cancel"], c)
    # the panel says the result's status in words, as report.json's status_text does
    assert c["status_text"].endswith(" — cancelled: the best design found so far"), c["status_text"]
    assert c["live"].startswith(c["status_text"] + ": machining_time ") and c["apply_enabled"] is True
    assert c["ticks"] >= 10
    assert r["unchanged_after_cancel"]["spec"] is True and r["unchanged_after_cancel"]["undo"] == 0
    assert r["unchanged_after_cancel"]["volume"] == r["new"]["volume"]
    # the short run: SLSQP, 60 evaluations; before/after
    assert r["short_started"] is True
    s = r["short"]
    assert s["feasible"] and s["value"] < s["initial"] and s["evaluations"] <= 60
    assert s["apply_text"] == "Apply to the cam" and s["apply_enabled"]
    figures = {row[0]: row for row in r["figures"]}
    obj = "objective: area (thesis Eq. 4.21 area ½∮(R_b + s)² dθ)"     # named as report.json's areas name it
    assert list(figures) == [obj, "thesis Eq. 4.21 area ½∮(R_b + s)² dθ", "area inside the profile",
                             "base radius R_b", "follower offset e", "worst constraint", "design checks"]
    assert figures[obj][1:] == ["78.1477 in²", f"{s['value']:.6g} in²"]
    assert figures["base radius R_b"][1:] == ["4.5 in", "2.25 in"]            # on the default bound
    assert figures["design checks"][1:] == ["FAIL: separation", "all pass"]
    assert figures["worst constraint"][1].startswith("separation -696.") and figures["worst constraint"][1].endswith("FAILS")
    checks = {row[0]: row for row in r["checks"]}
    assert list(checks) == ["pressure angle", "separation", "oscillation", "contact stress", "curvature", "undercut"]
    assert checks["separation"][2].endswith("— fail") and checks["separation"][3].endswith("— pass")
    assert all(row[3].endswith("— pass") for row in checks.values())
    # apply: one undo step, the feature's spec is the result's (settings included); undo restores
    a = r["applied"]
    assert a["dialog"] is False and a["status"] == "ok" and a["valid"]
    assert a["undo"] == 1 and a["names"] == ["Optimise cam"] and a["spec_equal"] is True
    assert a["volume"] < r["new"]["volume"]
    assert a["objective_prop"] == "area" and a["variables_prop"] == "base_radius, control_points"
    assert a["rb_min_prop"] == 2.25 and a["max_evals_prop"] == 60
    u = r["undone"]
    assert u["spec"] is True and u["volume"] == u["volume0"] and u["status"] == "ok"
    # reopened after Undo: the cam's own Optimise properties again (the applied 60 evaluations were undone);
    # Close during a run cancels it and writes nothing
    assert r["reopened"] == {"max_evals": 3000, "algorithm": "auto"}
    assert r["closed"] == {"dialog": False, "panel": True, "status": "cancelled", "spec": True, "undo": 0}
    # another task panel replacing the optimiser's (no Close): its run is cancelled as well
    assert r["replaced"] == {"status": "cancelled", "editor": True, "spec": True}
    # a failing result (cancelled at once: the start design) is applied only after a Yes
    f = r["failing"]
    assert f["feasible"] is False and f["evaluations"] <= 3 and f["apply_text"] == "Apply anyway…"
    assert f["verdict"].startswith("the result FAILS separation — cancelled: the best design found so far "
                                   "(the dense re-check)."), f["verdict"]
    assert r["after_no"] == {"status": "Not applied.", "spec": True, "undo": 0, "dialog": True}
    y = r["after_yes"]
    assert y["dialog"] is False and y["undo"] == 1 and y["names"] == ["Optimise cam"] and y["status"] == "ok"
    assert y["question"][0] == "Apply a failing design?" and "(separation)" in y["question"][1]
    report = r["report_view"]
    assert "Traceback" not in report and "Traceback" not in run.console
    bad = [line for line in report.splitlines() if "Error" in line or "error" in line]
    assert bad == [], bad
    assert f"Ex5: optimise {c['status_text']}: machining_time" in report, report
    assert "Ex5: optimised design applied (area 78.1477" in report
    for name in ("freecad_gui_optimise_panel.png", "freecad_gui_optimise_running.png",
                 "freecad_gui_optimise_cancelled.png", "freecad_gui_optimise_result.png",
                 "freecad_gui_optimise_convergence.png", "freecad_gui_optimise_applied.png"):
        assert (artifacts / name).stat().st_size > 10_000, name
