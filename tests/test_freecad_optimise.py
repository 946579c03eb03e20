"""The optimiser inside a real FreeCAD (``freecadcmd``, Debian's nlopt 2.7): the functions the
task panel calls (:mod:`cam_workbench.freecad.optimiser`), on a PH cam with standard laws (R_b
and e) and on the thesis' Example 5 initial design (B-spline rise and return), with small
evaluation budgets.  Apply writes ``OptimiseResult.spec`` into the properties as one undo step
(the spec read back equals it, the solid's volume equals the CadQuery build of it); one Undo
restores the original properties and volume; a cancelled run ends "cancelled" and leaves the
feature unchanged; a result that fails the dense re-check, or a cam edited since the run
started, is refused.  The plain-Python parts (variable tokens, settings) are tested here too."""
from __future__ import annotations

import pytest

from cam_workbench.generators import load_spec, to_toml
from cam_workbench.generators.spec.examples import example_dict, example_spec
from cam_workbench.generators.errors import SpecError

from .conftest import ROOT, SAFETY_S, requires_ocp
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

EX5 = ROOT / "tests" / "fixtures" / "thesis_ex5_initial.toml"

RUNS = """
import time, threading
import FreeCAD
from cam_workbench.generators.spec import to_toml
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import optimiser as O, properties as P

def state(cam):
    doc = cam.Document
    return {"toml": to_toml(P.spec_of(cam)), "volume": cam.Shape.Volume, "undo": doc.UndoCount, "status": cam.Status}

def optimise_and_apply(name, spec_src, tokens, budget):
    doc = FreeCAD.newDocument(name)
    doc.UndoMode = 1
    cam = create(doc, spec_src, name=name)
    doc.recompute()
    before = state(cam)
    spec = P.spec_of(cam)
    out = {"choices": [[c.token, c.count, c.enabled] for c in O.variable_choices(spec)],
           "selected": sorted(O.selected_tokens(spec))}
    s = O.settings_of(spec)
    if tokens is not None:
        s = O.Settings(**{**s.__dict__, "variables": O.variables_text(spec, tokens)})
    s = O.Settings(**{**s.__dict__, "max_evaluations": budget})
    out["settings"] = s.__dict__
    job = O.OptimiseJob(O.run_spec(spec, s)).start()
    job.wait()
    res = job.result
    out["job_error"] = job.error
    out["result"] = {"status": res.status, "feasible": res.feasible, "evaluations": res.evaluations,
                     "value": res.value, "initial": res.initial_value, "variables": list(res.variables),
                     "toml": to_toml(res.spec), "initial_toml": to_toml(res.initial_spec),
                     "history": len(job.history)}
    out["figures"] = [f.cells() for f in O.figures(res)]
    out["checks"] = [c.cells() for c in O.check_comparison(res)]
    out["before"] = before
    O.apply_result(cam, res)
    out["after"] = state(cam)
    out["after"]["undo_names"] = doc.UndoNames[:1]
    out["after"]["valid"] = cam.Shape.isValid()
    out["after"]["props"] = {"OptimiseMaxEvaluations": cam.OptimiseMaxEvaluations,
                             "OptimiseVariables": cam.OptimiseVariables,
                             "OptimiseBaseRadiusMin": cam.OptimiseBaseRadiusMin.Value}
    doc.undo()
    out["undone"] = state(cam)
    return out

from cam_workbench.generators.spec.examples import example_dict
RESULT["ph"] = optimise_and_apply("PH", example_dict("paper"), ["base_radius", "offset"], 40)
RESULT["ex5"] = optimise_and_apply("Ex5", EX5, None, 30)

# cancellation from another thread while the run goes on
doc = FreeCAD.newDocument("Cancel")
doc.UndoMode = 1
cam = create(doc, EX5, name="Cancel")
doc.recompute()
before = state(cam)
spec = O.run_spec(P.spec_of(cam), O.settings_of(P.spec_of(cam)))
job = O.OptimiseJob(spec).start()
while not job.done and (job.latest is None or job.latest.evaluations < 5):    # the run's progress
    time.sleep(0.002)
job.cancel()
# read after the cancel: whatever ran meanwhile (this thread may wait for the CPU) is counted, and
# the run stops at the evaluation in progress
at_cancel = job.latest.evaluations
job.wait()
RESULT["cancel"] = {"status": job.result.status, "evaluations": job.result.evaluations, "at_cancel": at_cancel,
                    "seconds": job.finished - job.cancel_requested_at, "before": before, "after": state(cam),
                    "budget": job.latest.budget}

# cancelled before its first evaluation ends: the starting design, which fails separation
job = O.OptimiseJob(spec)
job.cancel_event.set()
job.start().wait()
res = job.result
RESULT["early"] = {"status": res.status, "evaluations": res.evaluations, "feasible": res.feasible,
                   "failed": list(res.checks.failed)}
try:
    O.apply_result(cam, res)
    RESULT["refused"] = None
except O.ApplyError as exc:
    RESULT["refused"] = str(exc)
RESULT["after_refused"] = state(cam)
O.apply_result(cam, res, allow_failing=True)
RESULT["forced"] = {**state(cam), "names": doc.UndoNames[:1]}
doc.undo()

# a cam edited after the run started is not overwritten
cam.CamThickness = "0.3 in"
doc.recompute()
edited = state(cam)
try:
    O.apply_result(cam, res, allow_failing=True)
    RESULT["stale"] = None
except O.ApplyError as exc:
    RESULT["stale"] = str(exc)
RESULT["after_stale"] = state(cam)
RESULT["edited"] = edited

# the panel's starting values come from the Optimise properties
cam.OptimiseBaseRadiusMin = "3 in"
cam.OptimiseAlgorithm = "cobyla"
cam.OptimiseMaxEvaluations = 123
cam.OptimiseVariables = "base_radius, motion[0].control_points"
s = O.settings_of(P.spec_of(cam))
RESULT["from_props"] = {**s.__dict__, "selected": sorted(O.selected_tokens(P.spec_of(cam))),
                        "default": O.bound_is_default(P.spec_of(cam))}
try:
    O.run_spec(P.spec_of(cam), O.Settings(**{**s.__dict__, "base_radius_min": 0.3}))
except Exception as exc:
    RESULT["bad_bound"] = [exc.field, exc.rule, P.describe_field(exc.field)]
"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory, fc_home):
    body = f"EX5 = {str(EX5)!r}\n" + RUNS
    return run_freecadcmd(body, tmp_path_factory.mktemp("fc_optimise"), fc_home).check().result


#: A length of an inch spec is stored in a FreeCAD quantity in mm and read back: x·25.4, then
#: ÷ 25.4, each correctly rounded, so the spec gets x(1 + δ₁)(1 + δ₂) with |δ| ≤ u = 2⁻⁵³ — at
#: most 2u + u² relative from x (1–2 ulp; whether a value comes back exactly depends on its last
#: bits: Example 5's optimised offset 0.0033096024813739078 in returned 1 ulp low with
#: FreeCAD 1.1's numpy/scipy optimum).  4u also covers the comparison's own rounding.
ROUND_TRIP_REL = 2.0**-51


def _same_spec(a_toml: str, b_toml: str) -> bool:
    """Two specs equal field by field, numbers to :data:`ROUND_TRIP_REL` (a mm spec's lengths
    are stored unconverted: those must be equal exactly, as the test asserts elsewhere)."""
    import math

    def same(x, y) -> bool:
        if isinstance(x, dict) and isinstance(y, dict):
            return x.keys() == y.keys() and all(same(x[k], y[k]) for k in x)
        if isinstance(x, list) and isinstance(y, list):
            return len(x) == len(y) and all(same(u, v) for u, v in zip(x, y))
        if isinstance(x, float) and isinstance(y, float):
            return math.isclose(x, y, rel_tol=ROUND_TRIP_REL, abs_tol=0.0)
        return type(x) is type(y) and x == y

    return same(load_spec(a_toml).to_dict(), load_spec(b_toml).to_dict())


def _volume_mm3(toml_text: str) -> float:
    from cam_workbench import PlateCam

    spec = load_spec(toml_text)
    return PlateCam(spec).volume * (25.4**3 if spec.units == "in" else 1.0)


@requires_freecadcmd
@requires_ocp
@pytest.mark.parametrize("case", ["ph", "ex5"])
def test_apply_writes_the_result_as_one_undo_step(runs, case):
    """Apply: the feature's spec is the result's spec (TOML equal: design and the [optimise]
    settings used; an inch spec's lengths to the mm round trip's rounding, ROUND_TRIP_REL), one
    undo step "Optimise cam", a valid solid whose volume equals the CadQuery build of the result
    (1e-9); one Undo restores the original spec and volume."""
    r = runs[case]
    assert r["job_error"] is None
    res, before, after, undone = r["result"], r["before"], r["after"], r["undone"]
    assert res["initial_toml"].split("[optimise]")[0] == before["toml"].split("[optimise]")[0]
    if load_spec(res["toml"]).units == "mm":
        assert after["toml"] == res["toml"]                     # mm lengths are stored as given
    else:
        assert _same_spec(after["toml"], res["toml"]), (after["toml"], res["toml"])
    assert after["status"] == "ok" and after["valid"]
    assert after["undo"] - before["undo"] == 1 and after["undo_names"] == ["Optimise cam"]
    vol = _volume_mm3(res["toml"])
    assert abs(after["volume"] - vol) / vol < 1e-9
    assert undone["toml"] == before["toml"] and undone["volume"] == before["volume"]
    assert after["props"]["OptimiseMaxEvaluations"] == r["settings"]["max_evaluations"]


@requires_freecadcmd
def test_ph_cam_offers_base_radius_and_offset_only(runs):
    """A PH cam with standard laws: R_b and e are its only variables (no control points; the blank
    orientation only for the machining time).  The default cam fails the 30° pressure-angle limit
    (46.2°); with R_b and e free the result passes every check, R_b grows, e goes to ≈ 0."""
    r = runs["ph"]
    assert r["choices"] == [["base_radius", 1, True], ["offset", 1, True], ["orientation", 1, False]]
    assert r["selected"] == ["base_radius"]          # "auto": the cam's size; the offset only when named
    assert r["settings"]["variables"] == "base_radius, offset"
    res = r["result"]
    assert res["variables"] == ["cam.base_radius", "follower.offset"] and res["evaluations"] <= 40
    assert res["feasible"] is True
    figures = {row[0]: row for row in r["figures"]}
    assert figures["design checks"][1:] == ["FAIL: pressure angle", "all pass"]
    spec = load_spec(res["toml"])
    assert spec.cam.base_radius > example_spec("paper").cam.base_radius and abs(spec.follower.offset) < 0.1
    assert r["settings"]["base_radius_min"] == pytest.approx(example_spec("paper").cam.base_radius / 2, rel=1e-15)
    checks = {row[0]: row for row in r["checks"]}
    assert checks["pressure angle"][4] == "fail" and checks["pressure angle"][7] == "pass"


@requires_freecadcmd
def test_example5_in_freecad(runs):
    """Example 5 from its initial design (fails separation −696 lbf): every control point free,
    30 SLSQP evaluations per solve already bring the thesis area from 78.15 to ≈ 21.3 in² with R_b on the
    default lower bound (½ × 4.5 in) and every check passing — the README's finding that the
    checks do not bound the cam from below."""
    r = runs["ex5"]
    res = r["result"]
    # the budget is per solve: a solve whose result fails the dense check is repeated with twice the
    # windows (optimise.refine_rounds = 2), so at most 3 × 30 evaluations
    # "auto": R_b and the 24 control coordinates, the offset held (the follower's position: only when named)
    assert len(res["variables"]) == 25 and "follower.offset" not in res["variables"]
    assert res["evaluations"] <= 90 and res["history"] == res["evaluations"]
    assert res["feasible"] and res["initial"] == pytest.approx(78.1477, abs=1e-4) and res["value"] < 25.0
    spec = load_spec(res["toml"])
    assert spec.cam.base_radius == pytest.approx(2.25, rel=1e-12)
    assert spec.optimise.base_radius_min == 2.25 and spec.optimise.max_evaluations == 30
    assert r["after"]["props"]["OptimiseBaseRadiusMin"] == pytest.approx(2.25 * 25.4, rel=1e-15)
    assert r["after"]["props"]["OptimiseVariables"] == "auto"        # settings_of keeps the spec's text
    checks = {row[0]: row for row in r["checks"]}
    assert checks["separation"][4] == "fail" and all(row[7] == "pass" for row in checks.values())


@requires_freecadcmd
def test_cancel_stops_at_the_next_evaluation_and_changes_nothing(runs):
    c = runs["cancel"]
    assert c["status"] == "cancelled"
    # the event is looked at after every evaluation: at most the one in progress is finished
    assert c["at_cancel"] <= c["evaluations"] <= c["at_cancel"] + 2, c
    assert c["after"] == c["before"]
    e = runs["early"]
    # cancelled before it starts: no evaluation, or the one already under way; the start's verdict kept
    assert e["status"] == "cancelled" and e["evaluations"] <= 1 and e["feasible"] is False
    assert e["failed"] == ["separation"]


@requires_freecadcmd
def test_failing_or_stale_results_are_refused(runs):
    """A result failing the dense re-check is applied only when confirmed (allow_failing); a cam
    edited after the run started is never overwritten."""
    assert runs["refused"].startswith("the optimised design fails the dense re-check (separation)")
    assert runs["after_refused"] == runs["cancel"]["before"]
    assert runs["forced"]["status"] == "ok" and runs["forced"]["names"] == ["Optimise cam"]
    assert runs["stale"] == ("not applied: the cam's properties changed since the run started; "
                             "run the optimiser again")
    assert runs["after_stale"] == runs["edited"]


@requires_freecadcmd
def test_settings_come_from_the_optimise_properties(runs):
    p = runs["from_props"]
    assert p["base_radius_min"] == pytest.approx(3.0, rel=1e-15) and p["default"] is False
    assert p["algorithm"] == "cobyla" and p["max_evaluations"] == 123
    assert p["selected"] == ["base_radius", "motion[0].control_x", "motion[0].control_y"]
    assert p["base_radius_max"] == pytest.approx(9.0) and p["offset_max"] == pytest.approx(1.5)
    assert runs["bad_bound"] == ["optimise.base_radius_min", "must be > follower.roller_radius (0.425), got 0.3",
                                 "OptimiseBaseRadiusMin (optimise.base_radius_min)"]


# ---- plain Python: tokens and settings ------------------------------------------------------------
def test_variable_tokens_round_trip():
    from cam_workbench.freecad import optimiser as O

    ex5 = load_spec(EX5)
    all_tokens = {c.token for c in O.variable_choices(ex5) if c.enabled}
    assert O.variables_text(ex5, all_tokens) == "base_radius, offset, control_points"
    text = O.variables_text(ex5, {"offset", "motion[2].control_y"})
    assert text == "offset, motion[2].control_y"
    assert O.selected_tokens(ex5.replace(**{"optimise.variables": text})) == {"offset", "motion[2].control_y"}
    # the orientation only for the machining time; disabled choices are dropped
    assert O.variables_text(ex5, {"base_radius", "orientation"}) == "base_radius"
    mt = ex5.replace(**{"optimise.objective": "machining_time"})
    assert O.variables_text(mt, {"base_radius", "orientation"}) == "base_radius, orientation"
    assert "orientation" in O.selected_tokens(mt)          # "auto" includes it for machining_time


def test_default_bounds_are_the_library_defaults():
    """default_bounds reads DesignSpace's own bounds rather than repeating the rule: ½ and 2 × R_b,
    the lower at least 1.05 × (roller + bore radius); |e| ≤ ½ × the lower bound or |e₀|, the
    lower bound raised to ½(|e|max + R_b) when that would not keep R_b > |e|; never a default
    bound that excludes the user's start.  Bounds the spec gives are shown as given."""
    from cam_workbench.freecad import optimiser as O

    spec = example_spec("paper")                               # R_b √500, e = 10, roller 5, bore 10
    r0 = spec.cam.base_radius
    assert O.default_bounds(spec) == pytest.approx((r0 / 2, 2 * r0, 10.0), rel=1e-15)   # |e₀| > R_b/4
    small_e = spec.replace(**{"follower.offset": 2.0})
    assert O.default_bounds(small_e) == pytest.approx((r0 / 2, 2 * r0, r0 / 4), rel=1e-15)
    large_e = spec.replace(**{"follower.offset": 15.0})       # |e₀| ≥ R_b/2: the lower bound rises
    assert O.default_bounds(large_e) == pytest.approx(((15.0 + r0) / 2, 2 * r0, 15.0), rel=1e-15)
    tight = spec.replace(**{"cam.base_radius": 20.0, "cam.bore_diameter": 13.0})   # roller 5 + bore 6.5
    assert O.default_bounds(tight)[0] == pytest.approx(1.05 * 11.5, rel=1e-8)
    tighter = spec.replace(**{"cam.base_radius": 12.0, "cam.bore_diameter": 13.0})
    assert O.default_bounds(tighter)[0] == 12.0                # 1.05 × 11.5 > the start: not moved
    given = spec.replace(**{"optimise.base_radius_min": 15.0, "optimise.offset_max": 12.0})
    assert O.default_bounds(given) == pytest.approx((15.0, 2 * r0, 12.0), rel=1e-15)
    excluding = spec.replace(**{"optimise.base_radius_min": 15.0, "optimise.offset_max": 2.0})
    assert O.default_bounds(excluding) == pytest.approx((15.0, 2 * r0, 2.0), rel=1e-15)
    named = excluding.replace(**{"optimise.variables": "base_radius, offset"})   # the offset a variable:
    job = O.OptimiseJob(O.run_spec(named, O.settings_of(named))).start()           # … the run refuses it
    assert job.wait(SAFETY_S) and job.result is None
    assert job.error.startswith("OptimiseOffsetMax (optimise.offset_max): must be ≥ |follower.offset| "
                                "of the starting design (10 mm)"), job.error
    with pytest.raises(SpecError) as info:
        O.run_spec(spec, O.Settings(**{**O.settings_of(spec).__dict__, "offset_max": 20.0}))
    assert info.value.field == "optimise.offset_max"
    assert to_toml(O.run_spec(spec, O.settings_of(spec))).count("[optimise]") == 1


@pytest.mark.parametrize("example, flat_arm, expected", [
    ("oscillating", None, [["base_radius", 1, True], ["pivot_distance", 1, True], ["arm_length", 1, True]]),
    ("flat", None, [["base_radius", 1, True], ["offset", 1, True]]),
    ("oscillating_flat", None, [["base_radius", 1, True], ["pivot_distance", 1, True], ["arm_length", 1, False],
                                ["face_offset", 1, True]]),
    ("oscillating_flat", 50.0, [["base_radius", 1, True], ["pivot_distance", 1, True], ["arm_length", 1, True],
                                ["face_offset", 1, True]]),
])
def test_panel_offers_the_followers_own_position_variables(example, flat_arm, expected):
    """The panel's variables are the follower kind's (library rule ``follower_variable_rule``): an arm's
    pivot distance and length, never a translating offset; a flat arm's length only when given; the
    chosen ones become ``optimise.variables`` that the library accepts."""
    from cam_workbench.freecad import optimiser as O
    from cam_workbench.generators.optimise import optimise
    from cam_workbench.generators.spec import CamSpec

    if example == "oscillating_flat":
        d = example_dict("default")
        d["follower"] = {"kind": "flat", "motion": "oscillating", "pivot_distance": 70.0, "face_offset": 5.0,
                         "arm_inertia": 2000.0, "preload_torque": 800.0}
        if flat_arm is not None:
            d["follower"]["arm_length"] = flat_arm
        for m in d["motion"]:
            if "lift" in m:
                m["lift"] = 12.0
        spec = CamSpec.from_dict(d)
    else:
        spec = example_spec(example)
    choices = [c for c in O.variable_choices(spec) if c.token != "orientation"]
    assert [[c.token, c.count, c.enabled] for c in choices] == expected
    tokens = {c.token for c in choices if c.enabled}
    text = O.variables_text(spec, tokens)
    assert text == ", ".join(c.token for c in choices if c.enabled)
    res = optimise(spec.replace(**{"optimise.variables": text, "optimise.max_evaluations": 10}))
    assert {v["name"] for v in res.report()["variables"]} == {("cam." if t == "base_radius" else "follower.") + t for t in tokens}


def test_oscillating_follower_has_no_offset_bound():
    """An arm has no offset: the panel's settings carry no |e| bound and write no optimise.offset_max
    (the bounds of an arm's position are its Optimise properties); R_b's bounds are the library's."""
    from cam_workbench.freecad import optimiser as O
    from cam_workbench.generators.optimise.space import DesignSpace

    spec = example_spec("oscillating")
    r_lo, r_hi, e_max = O.default_bounds(spec)
    space = DesignSpace(spec.replace(**{"optimise.variables": "base_radius"}))
    assert (r_lo, r_hi) == (float(space.lower[space.r_index]), float(space.upper[space.r_index]))
    assert e_max is None
    settings = O.settings_of(spec)
    assert settings.offset_max is None and "optimise.offset_max" not in settings.changes()
    assert O.run_spec(spec, settings).optimise.offset_max is None
