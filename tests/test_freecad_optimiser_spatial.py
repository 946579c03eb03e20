"""The optimiser panel's logic on a barrel indexer inside a real FreeCAD (``freecadcmd``).

The barrel example (``BARREL_INDEXER_SPEC_DICT``: 6 stations, C = 52, R_p = 60, r_r = 12 mm) is created
with ``feature.create`` and recomputed; what the task panel calls (:mod:`cam_workbench.freecad.optimiser`)
runs on it as the panel runs it, as :mod:`tests.test_freecad_optimiser_indexer` runs it on the parallel
indexer: the objectives its optimiser serves (size, normal_force), the derivative-free algorithms, no
restarts, the three design variables C, R_p (the turret's size) and r_r checked and fixed with the note
that says so and that the turret's other lengths scale with its size, their bounds in words
(``spatial_bounds``), no R_b/e bounds; ``settings_of`` → ``run_spec`` with a budget of :data:`BUDGET`
evaluations → ``OptimiseJob``.  The result's figures are the body's own design of the start and of the
result spec (designed again here, outside FreeCAD): the barrel's outer radius, C, R_p, r_r, the lengths
scaled with the turret, the peak roller load; its checks table is every check of those designs.
``apply_result`` writes the optimum into the feature's properties (C, R_p, r_r and the scaled lengths) as
one undo step; the feature recomputes "ok" to the result's design; one Undo restores the start.  The
plain-Python parts (the globoidal indexer's choices, refusals before the run) are tested here too.
"""
from __future__ import annotations

import copy
import json

import pytest

from cam_workbench.freecad.part_spatial_indexer import GAUSS_ALLOWANCE
from cam_workbench.generators import design_cam, load_spec
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.optimise import spatial_indexer
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import BARREL_INDEXER_SPEC_DICT, GLOBOIDAL_INDEXER_SPEC_DICT

from .freecad_support import fc_home  # noqa: F401  (the fixture: a HOME with the workbench installed)
from .freecad_support import requires_freecad_gui, requires_freecadcmd, run_freecad_gui, run_freecadcmd
from .test_freecad_optimiser_indexer import FACTORS, GUI, REL

SPEC = copy.deepcopy(BARREL_INDEXER_SPEC_DICT)
#: the solver's designs at most (the spec's smallest allowed budget is 10; each trial is a full design)
BUDGET = 10
PATHS = ["indexer.centre_distance", "indexer.pitch_radius", "follower.roller_radius"]
#: the barrel's lengths that scale with its turret's size (spatial_indexer.FOLLOWERS)
SCALED = ["indexer.roller_start", "indexer.roller_end", "indexer.root_radius", "indexer.outer_radius",
          "cam.thickness"]
#: the feature's property of each (cam_workbench/freecad/properties.py: camel case)
PROPERTIES = {"indexer.centre_distance": "IndexerCentreDistance", "indexer.pitch_radius": "IndexerPitchRadius",
              "follower.roller_radius": "FollowerRollerRadius", "indexer.roller_start": "IndexerRollerStart",
              "indexer.roller_end": "IndexerRollerEnd", "indexer.root_radius": "IndexerRootRadius",
              "indexer.outer_radius": "IndexerOuterRadius", "cam.thickness": "CamThickness"}

BODY = """
import math
import time
import FreeCAD
from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import to_toml
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import check_design, optimiser as O, properties as P

def value(v):
    return float(getattr(v, "Value", v))

def state(cam):
    doc = cam.Document
    shape = cam.Shape
    radius = max(math.hypot(p.x, p.y) for e in shape.Edges for p in e.discretize(Number=400))
    return {"toml": to_toml(P.spec_of(cam)), "volume": shape.Volume, "valid": shape.isValid(),
            "solids": len(shape.Solids), "solid_radius": radius, "undo": doc.UndoCount, "status": cam.Status,
            "properties": {k: value(getattr(cam, k)) for k in PROPERTIES.values()}}

t0 = time.perf_counter()
doc = FreeCAD.newDocument("Barrel")
doc.UndoMode = 1
cam = create(doc, json.loads(SPEC), name="Barrel")
doc.recompute()
before = state(cam)
spec = P.spec_of(cam)
RESULT["panel"] = {
    "indexer": O.indexer_optimised(spec),
    "objectives": list(O.objective_choices(spec)),
    "labels": [O.OBJECTIVE_LABELS[n] for n in O.objective_choices(spec)],
    "algorithms": list(O.algorithm_choices(spec)),
    "algorithm_labels": [O.algorithm_label(spec, n) for n in O.algorithm_choices(spec)],
    "multistart": O.multistart_offered(spec),
    "choices": [[c.token, c.label, c.count, c.enabled, c.fixed, c.reason] for c in O.variable_choices(spec)],
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
t1 = time.perf_counter()
job = O.OptimiseJob(run).start()
job.wait()
RESULT["run_seconds"] = time.perf_counter() - t1
RESULT["job_error"] = job.error
res = job.result
RESULT["result"] = {"status": res.status, "status_text": res.status_text, "feasible": res.feasible,
                    "evaluations": res.evaluations, "objective": res.objective, "value": res.value,
                    "initial": res.initial_value, "variables": list(res.variables),
                    "design": [float(x) for x in res.design], "initial_design": [float(x) for x in res.initial_design],
                    "toml": to_toml(res.spec), "initial_toml": to_toml(res.initial_spec),
                    "history": len(job.history),
                    "details": {k: res.details[k] for k in ("bounds", "measures", "turret_scaled")}}
RESULT["report"] = {k: v for k, v in res.report().items() if k.startswith("objective")}
RESULT["figures"] = [[f.name, f.before, f.after, f.unit, f.cells()] for f in O.figures(res)]
RESULT["checks"] = [c.cells() for c in O.check_comparison(res)]
RESULT["before"] = before
O.apply_result(cam, res)
after = state(cam)
after["undo_names"] = doc.UndoNames[:1]
design = design_cam(P.spec_of(cam))
after["outer_radius"] = design.summary()["indexer"]["geometry"]["outer_radius"]
report = check_design.design_report(cam)
after["check_design"] = {"ok": report.ok, "failed": report.failed_checks,
                         "checks": [[c.name, c.status] for c in report.checks]}
RESULT["after"] = after
doc.undo()
doc.recompute()
RESULT["undone"] = state(cam)
RESULT["seconds"] = time.perf_counter() - t0
"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory, fc_home):  # noqa: F811
    head = (f"import json\nSPEC = {json.dumps(json.dumps(SPEC))}\nBUDGET = {BUDGET}\n"
            f"PROPERTIES = {PROPERTIES!r}\n")
    r = run_freecadcmd(head + BODY, tmp_path_factory.mktemp("fc_optimise_barrel"), fc_home).check()
    assert "Traceback" not in r.console, r.console[-3000:]
    print(f"\nFreeCAD: the barrel optimised ({BUDGET} evaluations) in {r.result['run_seconds']:.1f} s, "
          f"the whole script {r.result['seconds']:.1f} s")
    return r.result


@pytest.fixture(scope="module")
def designs(runs):
    """The body's own design of the start and of the result spec, outside FreeCAD (the library's)."""
    res = runs["result"]
    return (design_cam(load_spec(res["initial_toml"])).summary(), design_cam(load_spec(res["toml"])).summary())


def _outer_radius(summary: dict) -> float:
    return summary["indexer"]["geometry"]["outer_radius"]


@requires_freecadcmd
def test_the_panel_offers_the_barrels_objectives_algorithms_and_fixed_variables(runs):
    p = runs["panel"]
    assert p["indexer"] is True
    assert p["objectives"] == ["size", "normal_force"]
    assert p["labels"][0].startswith("Size") and p["labels"][1].startswith("Peak roller load")
    assert all("parallel" not in label for label in p["labels"])
    assert p["algorithms"] == ["auto", "cobyla", "bobyqa"]
    assert p["algorithm_labels"][0].startswith("auto: COBYLA") and p["multistart"] is False
    # C, R_p (the turret's size), r_r: checked, fixed, "auto" for optimise.variables
    assert [c[0] for c in p["choices"]] == PATHS
    assert all(c[2] == 1 and c[3] is True and c[4] is True for c in p["choices"])
    assert p["choices"][1][1] == "Turret pitch radius R_p (turret size) [mm] (indexer.pitch_radius)"
    assert all(c[5].startswith("a barrel indexer's optimiser varies C, R_p and r_r together") for c in p["choices"])
    assert p["selected"] == sorted(PATHS)
    assert p["bounds"] == [None, None, None]
    assert p["note"].startswith("A barrel indexer's optimiser varies all three together"), p["note"]
    assert f"the turret's other lengths ({', '.join(SCALED)}) scale with its size" in p["note"], p["note"]
    # the bounds: spatial_bounds (0.5–2 × C and R_p, 0.5–1.5 × r_r), the scaled lengths, the spatial checks
    assert "C ∈ [26, 104] mm, R_p ∈ [30, 120] mm, r_r ∈ [6, 18] mm" in p["bounds_note"], p["bounds_note"]
    assert f"The turret's other lengths ({', '.join(SCALED)}) scale with its size." in p["bounds_note"]
    assert ("(pressure angle, undercut, rib thickness, locking, contact stress, bore)" in p["bounds_note"]), \
        p["bounds_note"]
    s = runs["settings"]
    assert s["objective"] == "size" and s["variables"] == "auto" and s["algorithm"] == "auto"
    assert s["multistart"] == 0 and s["base_radius_min"] is None and s["offset_max"] is None
    run = load_spec(runs["run_toml"]).optimise
    assert (run.objective, run.variables, run.max_evaluations) == ("size", "auto", BUDGET)


@requires_freecadcmd
def test_the_run_ends_on_a_checked_smaller_barrel(runs, designs):
    assert runs["job_error"] is None
    res = runs["result"]
    assert res["feasible"] is True and res["status"] != "infeasible", res["status_text"]
    assert res["objective"] == "size" and res["variables"] == PATHS
    assert 1 <= res["evaluations"] <= BUDGET and res["history"] >= res["evaluations"]
    assert res["value"] < res["initial"]
    start, final = designs
    assert start["checks"]["passed"] and final["checks"]["passed"], final["checks"]["failed"]
    assert res["initial"] == pytest.approx(_outer_radius(start), rel=REL)
    assert res["value"] == pytest.approx(_outer_radius(final), rel=REL)
    assert res["initial_design"] == [SPEC["indexer"]["centre_distance"], SPEC["indexer"]["pitch_radius"],
                                     SPEC["follower"]["roller_radius"]]
    final_spec = load_spec(res["toml"])
    assert res["design"] == [final_spec.indexer.centre_distance, final_spec.indexer.pitch_radius,
                             final_spec.follower.roller_radius]
    for path, x0, x, (lo_f, hi_f) in zip(PATHS, res["initial_design"], res["design"], FACTORS):
        lo, hi = res["details"]["bounds"][path]
        assert (lo, hi) == pytest.approx((lo_f * x0, hi_f * x0), rel=1e-12)
        assert lo <= x <= hi
    assert res["details"]["turret_scaled"]["with_it"] == SCALED
    # the barrel's own words for "size" (spatial_indexer.SIZE_WORDS), not the parallel indexer's
    label, _, key = spatial_indexer.SIZE_WORDS["barrel_indexer"]
    assert runs["report"]["objective_label"] == label and runs["report"]["objective_key"] == key


@requires_freecadcmd
def test_figures_are_the_barrels_numbers(runs, designs):
    start, final = designs
    res = runs["result"]
    figs = {f[0]: f for f in runs["figures"]}
    print("\n".join(" | ".join(f[4]) for f in runs["figures"]))
    label = spatial_indexer.SIZE_WORDS["barrel_indexer"][0]
    assert list(figs) == [f"objective: size ({label})",
                          "centre distance C (indexer.centre_distance)",
                          "turret pitch radius R_p (turret size) (indexer.pitch_radius)",
                          "roller radius r_r (follower.roller_radius)",
                          *[f"scales with the turret ({path})" for path in SCALED],
                          "normal_force (peak roller load)", "worst constraint", "design checks"]
    obj = figs[f"objective: size ({label})"]
    assert obj[1:4] == [res["initial"], res["value"], "mm"]
    rows = [f for f in runs["figures"] if f[0].endswith(tuple(f"({p})" for p in PATHS))]
    assert [[f[1], f[2], f[3]] for f in rows] == [[a, b, "mm"] for a, b in zip(res["initial_design"], res["design"])]
    # the scaled lengths: the start's and the result's, in the ratio of the turret's size
    k = res["design"][1] / res["initial_design"][1]
    for path in SCALED:
        f = figs[f"scales with the turret ({path})"]
        section, field = path.split(".")
        assert f[1] == SPEC[section][field] and f[2] == pytest.approx(k * f[1], rel=1e-12) and f[3] == "mm"
    force = figs["normal_force (peak roller load)"]
    assert force[3] == "N"
    assert force[1] == pytest.approx(start["indexer"]["drive"]["normal_force_peak_N"], rel=REL)
    assert force[2] == pytest.approx(final["indexer"]["drive"]["normal_force_peak_N"], rel=REL)
    assert res["details"]["measures"]["normal_force"] == {"initial": force[1], "final": force[2]}
    assert figs["design checks"][1:3] == ["all pass", "all pass"]
    assert not figs["worst constraint"][2].endswith("FAILS")


@requires_freecadcmd
def test_checks_table_is_every_check_of_both_barrels(runs, designs):
    start, final = designs
    rows = {r[0]: r for r in runs["checks"]}
    assert list(rows) == [n.replace("_", " ") for n in final["checks"]["results"]]
    for name, r in start["checks"]["results"].items():
        assert rows[name.replace("_", " ")][4] == r["status"]
    for name, r in final["checks"]["results"].items():
        assert rows[name.replace("_", " ")][7] == r["status"] and r["status"] in ("pass", "skipped")


@requires_freecadcmd
def test_apply_writes_the_optimum_and_recomputes_in_one_undo_step(runs, designs):
    res, before, after, undone = runs["result"], runs["before"], runs["after"], runs["undone"]
    final_spec = load_spec(res["toml"])
    expected = {PROPERTIES[p]: x for p, x in zip(PATHS, res["design"])}
    expected.update({PROPERTIES[p]: float(getattr(getattr(final_spec, p.split(".")[0]), p.split(".")[1]))
                     for p in SCALED})
    assert after["properties"] == pytest.approx(expected, rel=1e-12)
    assert before["properties"] == {PROPERTIES[p]: float(SPEC[p.split(".")[0]][p.split(".")[1]]) for p in PROPERTIES}
    assert after["toml"] == res["toml"]
    assert after["status"] == "ok" and after["valid"] and after["solids"] == 1
    assert after["undo"] - before["undo"] == 1 and after["undo_names"] == ["Optimise cam"]
    assert after["outer_radius"] == pytest.approx(res["value"], rel=REL)
    assert after["check_design"]["ok"] and after["check_design"]["failed"] == []
    assert all(status in ("pass", "skipped") for _, status in after["check_design"]["checks"])
    # the solid: the design's volume (FreeCAD's Gauss rule on the B-spline flanks: the feature's
    # allowance, part_spatial_indexer.GAUSS_ALLOWANCE); its largest radius about the cam axis the rib's top
    _, final = designs
    print(f"solid vs design: volume {after['volume'] / final['volume'] - 1:.2e} relative, largest radius "
          f"{after['solid_radius'] - res['value']:+.2e} mm; outer radius {res['initial']:.6g} → "
          f"{res['value']:.6g} mm")
    assert after["volume"] == pytest.approx(final["volume"], rel=GAUSS_ALLOWANCE)
    assert after["solid_radius"] == pytest.approx(res["value"], abs=1e-3)
    assert before["solid_radius"] == pytest.approx(res["initial"], abs=1e-3)
    # one Undo restores the start
    assert undone["toml"] == before["toml"] and undone["properties"] == before["properties"]
    assert undone["status"] == "ok" and undone["volume"] == pytest.approx(before["volume"], rel=1e-9)


# ---- plain Python: the globoidal indexer's choices, refusals before the run ------------------------------
def test_globoid_panel_choices_without_freecad():
    from cam_workbench.freecad import optimiser as O

    spec = CamSpec.from_dict(GLOBOIDAL_INDEXER_SPEC_DICT)
    assert O.indexer_optimised(spec) and O.objective_choices(spec) == ("size", "normal_force")
    paths = list(spatial_indexer.spatial_paths(spec).values())
    assert paths == ["indexer.centre_distance", "indexer.roller_end", "follower.roller_radius"]
    choices = O.variable_choices(spec)
    assert [c.token for c in choices] == paths and all(c.fixed for c in choices)
    assert choices[1].label == "Rollers' outer end t1 (turret size) [mm] (indexer.roller_end)"
    assert O.selected_tokens(spec) == set(paths) and O.variables_text(spec, set(paths)) == "auto"
    note = O.own_bounds_note(spec)
    bounds = spatial_indexer.spatial_bounds(spec)
    assert f"t1 ∈ [{bounds['indexer.roller_end'][0]:.6g}, {bounds['indexer.roller_end'][1]:.6g}] mm" in note, note
    assert "indexer.tip_radius" in note and "rib thickness" in note and "bore" in note
    assert "globoidal indexer's optimiser" in O.fixed_variables_note(spec)
    settings = O.settings_of(spec)
    assert O.run_spec(spec, settings).optimise.variables == "auto"
    # a fixed variable left out: refused by the spatial optimiser's own rule, named
    part = O.variables_text(spec, set(paths) - {"follower.roller_radius"})
    with pytest.raises(SpecError) as exc:
        O.run_spec(spec, O.Settings(**{**settings.__dict__, "variables": part}))
    assert exc.value.field == "optimise.variables"
    # normal_force without the output's load: refused before the run, naming indexer.output_inertia
    no_load = spec.replace(**{"indexer.output_inertia": None, "indexer.friction_torque": 0.0})
    with pytest.raises(SpecError) as exc:
        O.run_spec(no_load, O.Settings(**{**O.settings_of(no_load).__dict__, "objective": "normal_force"}))
    assert exc.value.field == "indexer.output_inertia"


# ---- the task panel itself in the FreeCAD GUI (the parallel indexer's steps, on the barrel) ------------------
@requires_freecad_gui
def test_the_task_panel_on_a_barrel_in_the_freecad_gui(tmp_path, fc_home, artifacts):  # noqa: F811
    script = GUI.replace("freecad_gui_optimise_indexer_", "freecad_gui_optimise_barrel_")
    run = run_freecad_gui(script.format(art=str(artifacts), spec=json.dumps(SPEC), budget=BUDGET), tmp_path, fc_home)
    r = run.check().result
    (artifacts / "freecad_gui_optimise_barrel_result.json").write_text(json.dumps(r, indent=1))
    assert r["new"]["status"] == "ok"
    p = r["panel"]
    assert p["objectives"] == ["size", "normal_force"] and p["objective"] == "size"
    assert p["algorithms"] == ["auto", "cobyla", "bobyqa"] and p["algorithm"] == "auto"
    # C, R_p, r_r: checked and fixed (disabled), the note saying why; no R_b/e spin boxes, no restarts
    assert list(p["variables"]) == PATHS
    assert all(enabled is False and checked is True for _, enabled, checked in p["variables"].values())
    assert p["variables"]["indexer.pitch_radius"][0] == \
        "Turret pitch radius R_p (turret size) [mm] (indexer.pitch_radius)"
    assert p["count"] == "3 design variables (all fixed: varied together)"
    assert p["note_visible"] and "barrel indexer's optimiser varies all three together" in p["note"]
    assert p["spins"] and "R_p ∈ [30, 120] mm" in p["bounds_note"] and "rib thickness" in p["bounds_note"]
    assert p["multistart"] == [False, 0] and p["seed"] is False
    assert p["status"] == "Ready: size over 3 variables." and p["run_enabled"]
    assert r["normal_force"] == {"status": "Ready: normal_force over 3 variables.", "run_enabled": True}
    assert r["started"] is True
    res = r["result"]
    assert res["feasible"] and res["value"] < res["initial"] and res["apply_enabled"]
    figures = {row[0]: row for row in r["figures"]}
    label = spatial_indexer.SIZE_WORDS["barrel_indexer"][0]
    assert figures[f"objective: size ({label})"][1:] == [f"{res['initial']:.6g} mm", f"{res['value']:.6g} mm"]
    assert figures["centre distance C (indexer.centre_distance)"][1:] == ["52 mm", f"{res['design'][0]:.6g} mm"]
    assert figures["scales with the turret (cam.thickness)"][1] == "80 mm"
    assert figures["design checks"][1:] == ["all pass", "all pass"]
    assert r["checks"] and all(row[3].endswith(("— pass", "— skipped")) for row in r["checks"])
    a = r["applied"]
    assert a["status"] == "ok" and a["undo"] == 1 and a["names"] == ["Optimise cam"]
    assert a["properties"] == res["design"]
    assert a["objective_prop"] == "size" and a["variables_prop"] == "auto"
    report = r["report_view"]
    assert "Traceback" not in report and "Traceback" not in run.console
    assert [line for line in report.splitlines() if "Error" in line or "error" in line] == []
    assert f"Indexer: optimised design applied (size {res['initial']:.6g} → {res['value']:.6g})" in report, report
    assert f"size ({label}) {res['initial']:.6g} → {res['value']:.6g} mm" in report, report
