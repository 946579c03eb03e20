"""The optimiser panel's logic on a parallel indexer inside a real FreeCAD (``freecadcmd``).

The example indexer (``PARALLEL_INDEXER_SPEC_DICT``: 8 stations, C = 120, R_p = 50, r_r = 10 mm) is
created with ``feature.create`` and recomputed; what the task panel calls
(:mod:`cam_workbench.freecad.optimiser`) runs on it as the panel runs it: the objectives its body
serves (size, normal_force) with their labels, the derivative-free algorithms, no restarts, the
three design variables C, R_p and r_r checked and fixed (its optimiser varies all three:
``optimise.variables = "auto"``) with the note that says so, their bounds in words, no R_b/e bounds;
``settings_of`` → ``run_spec`` with a budget of :data:`BUDGET` evaluations → ``OptimiseJob`` (the
worker thread).  The result's figures are the library's numbers — the body's own design of the start
and of the result spec (designed again here, outside FreeCAD): outer radius, peak roller load, C,
R_p, r_r — and its checks table is every check of those designs, all passing after.
``apply_result`` writes C, R_p and r_r into ``IndexerCentreDistance``, ``IndexerPitchRadius`` and
``FollowerRollerRadius`` as one undo step; the feature recomputes to the result's design: its spec is
the result's, its outer radius (the design's, and the solid's largest radius) the result's value, its
volume the design's, every check passing (Check design); one Undo restores the start.  The plain-Python
parts (the panel's choices, refusals before the run) are tested here too.
"""
from __future__ import annotations

import copy
import json
import math

import pytest

from cam_workbench.generators import design_cam, load_spec
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import PARALLEL_INDEXER_SPEC_DICT

from .freecad_support import fc_home  # noqa: F401  (the fixture: a HOME with the workbench installed)
from .freecad_support import requires_freecad_gui, requires_freecadcmd, run_freecad_gui, run_freecadcmd

SPEC = copy.deepcopy(PARALLEL_INDEXER_SPEC_DICT)
#: the solver's designs at most (the spec's smallest allowed budget is 10)
BUDGET = 20
PATHS = ["indexer.centre_distance", "indexer.pitch_radius", "follower.roller_radius"]
#: the feature's property of each design variable (cam_workbench/freecad/properties.py: camel case)
PROPERTIES = {"indexer.centre_distance": "IndexerCentreDistance", "indexer.pitch_radius": "IndexerPitchRadius",
              "follower.roller_radius": "FollowerRollerRadius"}
#: optimise_parallel's default bounds as factors of the start (C, R_p, r_r)
FACTORS = ((0.5, 2.0), (0.5, 2.0), (0.5, 1.5))
#: design numbers computed by FreeCAD's Python and by this one (numpy builds may differ in the last bits)
REL = 1e-9

BODY = """
import math
import FreeCAD
from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import to_toml
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import check_design, optimiser as O, properties as P

def state(cam):
    doc = cam.Document
    shape = cam.Shape
    radius = max(math.hypot(p.x, p.y) for e in shape.Edges for p in e.discretize(Number=2000))
    return {"toml": to_toml(P.spec_of(cam)), "volume": shape.Volume, "valid": shape.isValid(),
            "solids": len(shape.Solids), "solid_radius": radius, "undo": doc.UndoCount, "status": cam.Status,
            "properties": {k: float(getattr(cam, k).Value) for k in PROPERTIES.values()}}

doc = FreeCAD.newDocument("Indexer")
doc.UndoMode = 1
cam = create(doc, json.loads(SPEC), name="Indexer")
doc.recompute()
before = state(cam)
spec = P.spec_of(cam)
RESULT["panel"] = {
    "objectives": list(O.objective_choices(spec)),
    "labels": [O.OBJECTIVE_LABELS[n] for n in O.objective_choices(spec)],
    "algorithms": list(O.algorithm_choices(spec)),
    "algorithm_labels": [O.algorithm_label(spec, n) for n in O.algorithm_choices(spec)],
    "multistart": O.multistart_offered(spec),
    "choices": [[c.token, c.label, c.count, c.enabled, c.fixed] for c in O.variable_choices(spec)],
    "selected": sorted(O.selected_tokens(spec)),
    "note": O.fixed_variables_note(spec),
    "bounds_note": O.own_bounds_note(spec),
    "bounds": list(O.default_bounds(spec)),
}
s = O.settings_of(spec)
RESULT["settings"] = dict(s.__dict__)
s = O.Settings(**{**s.__dict__, "variables": O.variables_text(spec, O.selected_tokens(spec)),
                  "max_evaluations": BUDGET})
run = O.run_spec(spec, s)
RESULT["run_toml"] = to_toml(run)
job = O.OptimiseJob(run).start()
job.wait()
RESULT["job_error"] = job.error
res = job.result
RESULT["result"] = {"status": res.status, "status_text": res.status_text, "feasible": res.feasible,
                    "evaluations": res.evaluations, "objective": res.objective, "value": res.value,
                    "initial": res.initial_value, "variables": list(res.variables),
                    "design": [float(x) for x in res.design], "initial_design": [float(x) for x in res.initial_design],
                    "toml": to_toml(res.spec), "initial_toml": to_toml(res.initial_spec),
                    "history": len(job.history), "phases": sorted({h[3] for h in job.history}),
                    "details": {k: res.details[k] for k in ("bounds", "measures")}}
RESULT["report"] = {k: v for k, v in res.report().items() if k.startswith("objective")}
RESULT["figures"] = [[f.name, f.before, f.after, f.unit, f.cells()] for f in O.figures(res)]
RESULT["checks"] = [c.cells() for c in O.check_comparison(res)]
RESULT["before"] = before
O.apply_result(cam, res)
after = state(cam)
after["undo_names"] = doc.UndoNames[:1]
design = design_cam(P.spec_of(cam))
after["outer_radius"] = design.summary()["body"]["outer_radius"]
after["design_volume"] = design.volume
report = check_design.design_report(cam)
after["check_design"] = {"ok": report.ok, "failed": report.failed_checks,
                         "checks": [[c.name, c.status] for c in report.checks]}
RESULT["after"] = after
doc.undo()
RESULT["undone"] = state(cam)
"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory, fc_home):  # noqa: F811
    head = (f"import json\nSPEC = {json.dumps(json.dumps(SPEC))}\nBUDGET = {BUDGET}\n"
            f"PROPERTIES = {PROPERTIES!r}\n")
    r = run_freecadcmd(head + BODY, tmp_path_factory.mktemp("fc_optimise_indexer"), fc_home).check()
    assert "Traceback" not in r.console, r.console[-3000:]
    return r.result


@pytest.fixture(scope="module")
def designs(runs):
    """The body's own design of the start and of the result spec, outside FreeCAD (the library's)."""
    res = runs["result"]
    return (design_cam(load_spec(res["initial_toml"])).summary(), design_cam(load_spec(res["toml"])).summary())


def _variables(spec: CamSpec) -> list[float]:
    return [spec.indexer.centre_distance, spec.indexer.pitch_radius, spec.follower.roller_radius]


@requires_freecadcmd
def test_the_panel_offers_the_indexers_objectives_algorithms_and_fixed_variables(runs):
    p = runs["panel"]
    assert p["objectives"] == ["size", "normal_force"]
    assert p["labels"][0].startswith("Size") and p["labels"][1].startswith("Peak roller load")
    assert p["algorithms"] == ["auto", "cobyla", "bobyqa"]
    assert p["algorithm_labels"][0].startswith("auto: COBYLA") and p["multistart"] is False
    # C, R_p, r_r: checked, fixed (the optimiser varies all three), "auto" for optimise.variables
    assert [c[0] for c in p["choices"]] == PATHS
    assert all(c[2] == 1 and c[3] is True and c[4] is True for c in p["choices"])
    assert p["selected"] == sorted(PATHS)
    # no R_b / e bounds; the note says the optimiser's own bounds (0.5–2 × C, R_p, 0.5–1.5 × r_r)
    assert p["bounds"] == [None, None, None]
    assert "varies all three together" in p["note"], p["note"]
    assert "C ∈ [60, 240] mm, R_p ∈ [25, 100] mm, r_r ∈ [5, 15] mm" in p["bounds_note"], p["bounds_note"]
    s = runs["settings"]
    # the spec's objective "area" is the indexer's "size"; nothing the indexer refuses is written
    assert s["objective"] == "size" and s["variables"] == "auto" and s["algorithm"] == "auto"
    assert s["multistart"] == 0 and s["base_radius_min"] is None and s["offset_max"] is None
    run = load_spec(runs["run_toml"]).optimise
    assert (run.objective, run.variables, run.max_evaluations) == ("size", "auto", BUDGET)
    assert run.base_radius_min is None and run.base_radius_max is None and run.offset_max is None


@requires_freecadcmd
def test_the_run_ends_on_a_checked_smaller_design(runs, designs):
    assert runs["job_error"] is None
    res = runs["result"]
    assert res["feasible"] is True and res["status"] != "infeasible", res["status_text"]
    assert res["objective"] == "size" and res["variables"] == PATHS
    assert 1 <= res["evaluations"] <= BUDGET
    assert res["history"] >= res["evaluations"] and res["phases"] == ["cobyla"]
    assert res["value"] <= res["initial"]
    start, final = designs
    assert start["checks"]["passed"] and final["checks"]["passed"], final["checks"]["failed"]
    # the result's numbers are the designs' own
    assert res["initial"] == pytest.approx(start["body"]["outer_radius"], rel=REL)
    assert res["value"] == pytest.approx(final["body"]["outer_radius"], rel=REL)
    assert res["initial_design"] == _variables(CamSpec.from_dict(SPEC))
    assert res["design"] == _variables(load_spec(res["toml"]))
    for path, x0, x, (lo_f, hi_f) in zip(PATHS, res["initial_design"], res["design"], FACTORS):
        lo, hi = res["details"]["bounds"][path]
        assert (lo, hi) == pytest.approx((lo_f * x0, hi_f * x0), rel=1e-12)
        assert lo <= x <= hi
    # report.json's words for the objective: objectives.py's tables (the shared OptimiseResult.report)
    assert runs["report"] == {"objective": "size", "objective_description":
                              "the cams' outer radius: the largest profile radius over the plates",
                              "objective_label": "outer radius of the cams", "objective_key": "body.outer_radius",
                              "objective_unit": "mm"}


@requires_freecadcmd
def test_figures_are_the_librarys_numbers(runs, designs):
    """objective (outer radius), C, R_p, r_r and the peak roller load before → after: the body's own
    design of the start and of the result; the worst constraint and the verdict of its checks."""
    start, final = designs
    res = runs["result"]
    figs = {f[0]: f for f in runs["figures"]}
    print("\n".join(" | ".join(f[4]) for f in runs["figures"]))
    assert list(figs) == ["objective: size (outer radius of the cams)",
                          "centre distance C (indexer.centre_distance)",
                          "turret pitch radius R_p (indexer.pitch_radius)",
                          "roller radius r_r (follower.roller_radius)", "normal_force (peak roller load)",
                          "worst constraint", "design checks"]
    obj = figs["objective: size (outer radius of the cams)"]
    assert obj[1:4] == [res["initial"], res["value"], "mm"]
    assert obj[1] == pytest.approx(start["body"]["outer_radius"], rel=REL)
    assert obj[2] == pytest.approx(final["body"]["outer_radius"], rel=REL)
    rows = [f for f in runs["figures"] if "(indexer." in f[0] or "(follower." in f[0]]
    assert [[f[1], f[2], f[3]] for f in rows] == [[a, b, "mm"] for a, b in zip(res["initial_design"], res["design"])]
    force = figs["normal_force (peak roller load)"]
    assert force[3] == "N"
    assert force[1] == pytest.approx(start["indexer"]["drive"]["normal_force_peak_N"], rel=REL)
    assert force[2] == pytest.approx(final["indexer"]["drive"]["normal_force_peak_N"], rel=REL)
    assert res["details"]["measures"]["normal_force"] == {"initial": force[1], "final": force[2]}
    assert figs["design checks"][1:3] == ["all pass", "all pass"]
    assert not figs["worst constraint"][2].endswith("FAILS")


@requires_freecadcmd
def test_checks_table_is_every_check_of_both_designs(runs, designs):
    start, final = designs
    rows = {r[0]: r for r in runs["checks"]}
    names = [n.replace("_", " ") for n in final["checks"]["results"]]
    assert list(rows) == names
    for name, r in start["checks"]["results"].items():
        assert rows[name.replace("_", " ")][4] == r["status"]
    for name, r in final["checks"]["results"].items():
        assert rows[name.replace("_", " ")][7] == r["status"]
        assert r["status"] in ("pass", "skipped")


@requires_freecadcmd
def test_apply_writes_c_rp_rr_and_recomputes_to_the_results_design(runs, designs):
    res, before, after, undone = runs["result"], runs["before"], runs["after"], runs["undone"]
    _, final = designs
    # the properties hold the optimised C, R_p, r_r (a mm spec's lengths are stored as given)
    assert after["properties"] == {PROPERTIES[p]: x for p, x in zip(PATHS, res["design"])}
    assert before["properties"] == {PROPERTIES[p]: x for p, x in zip(PATHS, res["initial_design"])}
    assert after["toml"] == res["toml"]
    assert after["status"] == "ok" and after["valid"] and after["solids"] == 1
    assert after["undo"] - before["undo"] == 1 and after["undo_names"] == ["Optimise cam"]
    # the recomputed feature's design: the result's outer radius, every check passing
    assert after["outer_radius"] == pytest.approx(res["value"], rel=REL)
    assert after["check_design"]["ok"] and after["check_design"]["failed"] == []
    assert all(status in ("pass", "skipped") for _, status in after["check_design"]["checks"])
    # the solid: the design's volume, its largest radius the outer radius (on a dwell arc: exact)
    print(f"solid vs design: volume {after['volume'] / final['volume'] - 1:.2e} relative, largest radius "
          f"{after['solid_radius'] - res['value']:+.2e} mm; outer radius {res['initial']:.6g} → "
          f"{res['value']:.6g} mm")
    assert after["volume"] == pytest.approx(final["volume"], rel=1e-6)
    assert after["solid_radius"] == pytest.approx(res["value"], abs=1e-6)
    assert before["solid_radius"] == pytest.approx(res["initial"], abs=1e-6)
    # one Undo restores the start
    assert undone["toml"] == before["toml"] and undone["volume"] == before["volume"]
    assert undone["properties"] == before["properties"]


# ---- plain Python: the panel's choices and refusals ---------------------------------------------------
def test_panel_choices_without_freecad():
    from cam_workbench.freecad import optimiser as O

    spec = CamSpec.from_dict(SPEC)
    assert O.indexer_optimised(spec)
    tokens = O.selected_tokens(spec)
    assert O.variables_text(spec, tokens) == "auto"
    # a fixed variable left out: the run is refused by the indexer's own rule, named
    part = O.variables_text(spec, tokens - {"follower.roller_radius"})
    with pytest.raises(SpecError) as exc:
        O.run_spec(spec, O.Settings(**{**O.settings_of(spec).__dict__, "variables": part}))
    assert exc.value.field == "optimise.variables"
    # normal_force without the output's load is refused before the run, naming indexer.output_inertia
    no_load = spec.replace(**{"indexer.output_inertia": None, "indexer.friction_torque": 0.0})
    with pytest.raises(SpecError) as exc:
        O.run_spec(no_load, O.Settings(**{**O.settings_of(no_load).__dict__, "objective": "normal_force"}))
    assert exc.value.field == "indexer.output_inertia"
    # the plane cam's panel is unchanged: its bounds written, its algorithms all offered
    from cam_workbench.generators.spec.examples import example_spec

    paper = example_spec("paper")
    assert not O.indexer_optimised(paper) and O.fixed_variables_note(paper) == O.own_bounds_note(paper) == ""
    assert O.algorithm_choices(paper) == tuple(O.ALGORITHM_LABELS) and O.multistart_offered(paper)
    assert "optimise.base_radius_min" in O.settings_of(paper).changes()
    assert all(not c.fixed for c in O.variable_choices(paper))


def test_the_objectives_have_words_units_and_report_keys():
    """objectives.py names the indexer's objectives as it names the plane cam's: report.json's
    ``objective_key`` of each holds its value in the design's summary."""
    from cam_workbench.generators.optimise.objectives import UNITS, describe, label, report_key

    spec = CamSpec.from_dict(SPEC)
    s = design_cam(spec).summary()
    for name, unit, value in (("size", "length", s["body"]["outer_radius"]),
                              ("normal_force", "N", s["indexer"]["drive"]["normal_force_peak_N"])):
        assert UNITS[name] == unit and describe(name, spec) and label(name, spec)
        node = s
        for part in report_key(name, spec).split("."):
            node = node[part]
        assert node == value and math.isfinite(value)


# ---- the task panel itself in the FreeCAD GUI ------------------------------------------------------------
GUI = r"""
import json
ART = {art!r}
SPEC = json.loads({spec!r})
BUDGET = {budget!r}
R = RESULT
state = {{}}

def panel():
    from cam_workbench.freecad.optimiser_panel import active_panel
    p = active_panel()
    if p is None or not p.form[0].isVisible():
        raise NotYet("optimiser panel")
    return p

def new_indexer():
    from cam_workbench.freecad.feature import create
    mw.resize(1400, 900)
    mw.resizeDocks([task_dock()], [700], QtCore.Qt.Horizontal)
    FreeCADGui.activateWorkbench("CamWorkbench")
    doc = FreeCAD.newDocument("Indexer")
    doc.UndoMode = 1
    cam = create(doc, SPEC, name="Indexer")
    doc.recompute()
    state["undo0"] = doc.UndoCount
    R["new"] = {{"status": cam.Status}}
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    FreeCADGui.Selection.addSelection(cam)
    FreeCADGui.runCommand("CamWorkbench_Optimise")

def panel_state():
    p = panel()
    R["panel"] = {{
        "titles": [w.windowTitle() for w in p.form],
        "objectives": [p.objective.itemData(i) for i in range(p.objective.count())],
        "objective_texts": [p.objective.itemText(i) for i in range(p.objective.count())],
        "objective": p.objective.currentData(),
        "algorithms": [p.algorithm.itemData(i) for i in range(p.algorithm.count())],
        "algorithm": p.algorithm.currentData(),
        "variables": {{t: [cb.text(), cb.isEnabled(), cb.isChecked()] for t, cb in p.var_boxes.items()}},
        "count": p.var_count.text(), "note": p.var_note.text(), "note_visible": p.var_note.isVisible(),
        "spins": [p.rb_min, p.rb_max, p.e_max] == [None, None, None], "bounds_note": p.bounds_note.text(),
        "multistart": [p.multistart.isEnabled(), p.multistart.maximum()], "seed": p.seed.isEnabled(),
        "status": p.status.text(), "run_enabled": p.run_button.isEnabled(),
    }}
    # normal_force: a choice (the example has the output's load)
    p.objective.setCurrentIndex(p.objective.findData("normal_force"))
    R["normal_force"] = {{"status": p.status.text(), "run_enabled": p.run_button.isEnabled()}}
    p.objective.setCurrentIndex(p.objective.findData("size"))
    shot("freecad_gui_optimise_indexer_panel.png")

def start():
    p = panel()
    p.max_evals.setValue(BUDGET)
    R["started"] = p.start()

def finished():
    p = panel()
    if p.running or p.result is None:
        raise NotYet("the run")
    res = p.result
    t = p.figure_table
    R["figures"] = [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())]
    t = p.check_table
    R["checks"] = [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())]
    R["result"] = {{"feasible": res.feasible, "value": res.value, "initial": res.initial_value,
                   "design": [float(x) for x in res.design], "live": p.live.text(), "verdict": p.verdict.text(),
                   "apply_enabled": p.apply_button.isEnabled()}}
    shot("freecad_gui_optimise_indexer_result.png")
    state["undo1"] = FreeCAD.ActiveDocument.UndoCount
    p.apply_button.click()

def applied():
    if FreeCADGui.Control.activeDialog():
        raise NotYet("the panel closing after Apply")
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Indexer")
    R["applied"] = {{"status": cam.Status, "undo": doc.UndoCount - state["undo1"], "names": doc.UndoNames[:1],
                    "properties": [float(cam.IndexerCentreDistance.Value), float(cam.IndexerPitchRadius.Value),
                                   float(cam.FollowerRollerRadius.Value)],
                    "objective_prop": cam.OptimiseObjective, "variables_prop": cam.OptimiseVariables}}
    R["report_view"] = report_text()

steps = [(new_indexer, 1000), (panel_state, 300), (start, 200), (finished, 500), (applied, 500)]
"""


@requires_freecad_gui
def test_the_task_panel_on_an_indexer_in_the_freecad_gui(tmp_path, fc_home, artifacts):  # noqa: F811
    run = run_freecad_gui(GUI.format(art=str(artifacts), spec=json.dumps(SPEC), budget=BUDGET), tmp_path, fc_home)
    r = run.check().result
    (artifacts / "freecad_gui_optimise_indexer_result.json").write_text(json.dumps(r, indent=1))
    assert r["new"]["status"] == "ok"
    p = r["panel"]
    assert p["titles"] == ["Optimise Indexer", "Bounds", "Algorithm", "Run", "Result: before → after"]
    assert p["objectives"] == ["size", "normal_force"] and p["objective"] == "size"
    assert p["objective_texts"][0].startswith("Size")
    assert p["algorithms"] == ["auto", "cobyla", "bobyqa"] and p["algorithm"] == "auto"
    # C, R_p, r_r: checked and fixed (disabled), the note saying why; no R_b/e spin boxes, no restarts
    assert list(p["variables"]) == PATHS
    assert all(enabled is False and checked is True for _, enabled, checked in p["variables"].values())
    assert p["variables"]["indexer.centre_distance"][0] == "Centre distance C [mm] (indexer.centre_distance)"
    assert p["count"] == "3 design variables (all fixed: varied together)"
    assert p["note_visible"] and "varies all three together" in p["note"]
    assert p["spins"] and "C ∈ [60, 240] mm" in p["bounds_note"]
    assert p["multistart"] == [False, 0] and p["seed"] is False
    assert p["status"] == "Ready: size over 3 variables." and p["run_enabled"]
    assert r["normal_force"] == {"status": "Ready: normal_force over 3 variables.", "run_enabled": True}
    assert r["started"] is True
    res = r["result"]
    assert res["feasible"] and res["value"] <= res["initial"] and res["apply_enabled"]
    figures = {row[0]: row for row in r["figures"]}
    assert figures["objective: size (outer radius of the cams)"][1:] == [f"{res['initial']:.6g} mm",
                                                                        f"{res['value']:.6g} mm"]
    assert figures["centre distance C (indexer.centre_distance)"][1:] == ["120 mm", f"{res['design'][0]:.6g} mm"]
    assert figures["design checks"][1:] == ["all pass", "all pass"]
    assert r["checks"] and all(row[3].endswith(("— pass", "— skipped")) for row in r["checks"])
    a = r["applied"]
    assert a["status"] == "ok" and a["undo"] == 1 and a["names"] == ["Optimise cam"]
    assert a["properties"] == res["design"]
    assert a["objective_prop"] == "size" and a["variables_prop"] == "auto"
    report = r["report_view"]
    assert "Traceback" not in report and "Traceback" not in run.console
    assert [line for line in report.splitlines() if "Error" in line or "error" in line] == []
    assert "Indexer: optimised design applied (size 71.6211" in report, report
