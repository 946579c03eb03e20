"""The new laws through everything downstream: the PH pitch construction, every follower kind, the
checks, areas, the thesis' cutting time, report.json and the command line.

The strongest check: ``law = "polynomial"`` between dwells *is* the 3-4-5 law (and with continuity 3
the 4-5-6-7 law), reached by another road (a solved Bézier segment, read as a B-spline lift), so every
number made from it must equal the number made from ``poly345`` / ``poly4567``."""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.checks.areas import area_summary
from cam_workbench.generators.checks.design import run_checks
from cam_workbench.generators.machining.cutting_time import thesis_cutting_time
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import CamSpec

from .conftest import requires_ocp
from .test_cli import run

H = 12.0


def base(follower, motion, **extra):
    return {"cam": {"base_radius": 50.0, "thickness": 8.0, "bore_diameter": 10.0},
            "follower": follower, "motion": motion, **extra}


def classic(law_rise, law_return, **kw):
    return [{"kind": "dwell", "angle": 40}, {"kind": "rise", "angle": 130, "lift": H, "law": law_rise, **kw},
            {"kind": "dwell", "angle": 50}, {"kind": "return", "angle": 140, "lift": H, "law": law_return, **kw}]


ROLLER = {"kind": "roller", "roller_radius": 6.0, "offset": 5.0, "mass": 0.4, "preload": 15.0, "spring_rate": 0.5}
FOLLOWERS = {
    "roller_offset": ROLLER,
    "knife": {"kind": "knife", "offset": -4.0},
    "flat": {"kind": "flat", "face_width": 60.0},
    "oscillating_roller": {"kind": "roller", "roller_radius": 5.0, "motion": "oscillating", "pivot_distance": 90.0,
                           "arm_length": 70.0},
    "oscillating_flat": {"kind": "flat", "motion": "oscillating", "pivot_distance": 90.0, "face_offset": 4.0},
}


def _lift(fol):
    return 14.0 if fol.get("motion") == "oscillating" else H   # arm degrees for an oscillating follower


@pytest.mark.parametrize("name", list(FOLLOWERS))
@pytest.mark.parametrize("closed, solved", [("poly345", {}), ("poly4567", {"start_continuity": 3, "end_continuity": 3})])
def test_polynomial_equals_its_closed_form_downstream(name, closed, solved):
    """Pitch curve (PH, same junctions), deviation, checks, areas and the thesis' cutting time of a
    ``polynomial`` cam equal those of the closed-form cam it reproduces."""
    fol = FOLLOWERS[name]
    h = _lift(fol)

    def spec(law, kw):
        m = classic(law, law, **kw)
        m[1]["lift"] = m[3]["lift"] = h
        return CamSpec.from_dict(base(fol, m, pitch={"segments": 72}))

    a, b = spec(closed, {}), spec("polynomial", solved)
    da, db = design_cam(a), design_cam(b)
    assert np.allclose(db.pitch.spline.ctrl, da.pitch.spline.ctrl, rtol=0, atol=1e-9)
    assert db.max_deviation[0] == pytest.approx(da.max_deviation[0], rel=1e-6, abs=1e-12)
    ca, cb = run_checks(a), run_checks(b)
    assert [r.name for r in cb.results] == [r.name for r in ca.results[:3]] + ["continuity"] + [
        r.name for r in ca.results[3:]]
    assert cb["continuity"].status == "pass"
    for r in ca.results:
        s = cb[r.name]
        assert s.status == r.status, r.name
        if r.value is not None:
            assert s.value == pytest.approx(r.value, rel=1e-7, abs=1e-9), r.name
    for key, v in area_summary(a).items():
        if v is not None:
            assert area_summary(b)[key] == pytest.approx(v, rel=1e-12), key
    if fol.get("motion") != "oscillating" and fol["kind"] != "flat":
        ta, tb = thesis_cutting_time(a), thesis_cutting_time(b)
        assert (tb.turns, tb.length) == (ta.turns, pytest.approx(ta.length, rel=1e-9))


MIXED = [
    {"kind": "dwell", "angle": 30},
    {"kind": "rise", "angle": 60, "lift": 4.0, "law": "polynomial", "points": [[30.0, 1.6]]},
    {"kind": "rise", "angle": 120, "lift": 12.0, "law": "constant_velocity", "end_blend": 25.0},
    {"kind": "dwell", "angle": 30},
    {"kind": "return", "angle": 120, "lift": 16.0, "law": "table",
     "table": [[float(t), float(16.0 * (1 - (t / 120 - math.sin(2 * math.pi * t / 120) / (2 * math.pi))))]
               for t in np.arange(0.0, 120.01, 2.0)]},
]


@pytest.mark.parametrize("name", list(FOLLOWERS))
@pytest.mark.parametrize("representation", ["ph", "bspline"])
def test_mixed_program_builds_for_every_follower(name, representation):
    """A polynomial rise with a point, a constant-velocity rise blended into a dwell, a table return:
    every junction C2, the pitch curve within its tolerance of the motion, every check evaluated."""
    fol = FOLLOWERS[name]
    motion = copy.deepcopy(MIXED)
    if fol.get("motion") == "oscillating":       # arm degrees: scale the lifts
        for m in motion:
            if "lift" in m:
                m["lift"] *= 14.0 / 16.0
            if "points" in m:
                m["points"] = [[a, s * 14.0 / 16.0] for a, s in m["points"]]
            if "table" in m:
                m["table"] = [[a, s * 14.0 / 16.0] for a, s in m["table"]]
    tol = 2e-4
    spec = CamSpec.from_dict(base(fol, motion, pitch={"tolerance": tol, "representation": representation}))
    prog = MotionProgram.from_spec(spec)
    assert [j.order for j in prog.junctions()] == [2, 2, 2, 2, 2]
    design = design_cam(spec)
    assert design.max_deviation[0] <= tol
    summary = design.summary()
    assert json.loads(json.dumps(summary))["motion"]["junctions"][2]["order"] == 2
    assert summary["checks"]["results"]["continuity"]["status"] == "pass"
    assert summary["motion"]["segments"][4]["max_error"] <= summary["motion"]["segments"][4]["tolerance"]


def _write(tmp_path, motion, **extra):
    from cam_workbench.generators.spec import to_toml

    path = tmp_path / "cam.toml"
    path.write_text(to_toml(CamSpec.from_dict(base(ROLLER, motion, **extra))), encoding="utf-8")
    return path


def test_cli_check_reports_the_junctions_and_fails_a_broken_promise(tmp_path):
    motion = [{"kind": "dwell", "angle": 60}, {"kind": "rise", "angle": 180, "lift": H, "law": "constant_velocity",
                                               "start_blend": 30.0},
              {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}]
    out = tmp_path / "out"
    res = run("check", str(_write(tmp_path, motion)), "-o", str(out))
    assert res.returncode == 3, res.stdout + res.stderr
    assert "segment junctions" in res.stdout and "continuity" in res.stdout
    report = json.loads((out / "report.json").read_text())
    junctions = report["motion"]["junctions"]
    assert [j["order"] for j in junctions] == [2, 2, 0]
    assert junctions[2]["jumps"]["velocity"] == pytest.approx(-H / math.radians(165.0), rel=1e-9)
    r = report["checks"]["results"]["continuity"]
    assert r["status"] == "fail" and r["at_deg"] == pytest.approx(240.0) and "velocity jumps" in r["note"]


@pytest.mark.parametrize("edit, field", [
    ({"table_tolerance": 1e-9}, "motion[4].table_tolerance"),
    ({"table": None, "table_file": "missing.csv"}, "motion[4].table_file"),
])
def test_cli_bad_table_exits_2_naming_the_field_and_writes_nothing(tmp_path, edit, field):
    motion = copy.deepcopy(MIXED)
    motion[4]["table"] = [[a, s + (0.01 if 0 < a < 120 and int(a) % 4 == 0 else 0.0)] for a, s in motion[4]["table"]]
    path = _write(tmp_path, motion)
    text = path.read_text(encoding="utf-8")
    if "table_file" in edit:
        lines = [ln for ln in text.splitlines() if not ln.startswith("table = ")]
        text = "\n".join(lines).replace('law = "table"', 'law = "table"\ntable_file = "missing.csv"') + "\n"
    else:
        text = text.replace('law = "table"', f'law = "table"\ntable_tolerance = {edit["table_tolerance"]}')
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    for cmd in ("check", "build"):
        res = run(cmd, str(path), "-o", str(out))
        assert res.returncode == 2, res.stdout + res.stderr
        assert res.stderr.strip().splitlines()[-1].split(": ", 1)[-1].startswith(field) or field in res.stderr
        assert len(res.stderr.strip().splitlines()) == 1 and "Traceback" not in res.stderr
        assert not out.exists()


@requires_ocp
def test_cli_build_of_the_mixed_program_writes_every_file(tmp_path):
    out = tmp_path / "out"
    res = run("build", str(_write(tmp_path, MIXED, pitch={"tolerance": 2e-4})), "-o", str(out))
    assert res.returncode == 0, res.stdout + res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"cam.step", "cam.dxf", "cam.nc", "commands.csv", "report.json", "report.html"} <= names
    report = json.loads((out / "report.json").read_text())
    assert report["pitch"]["max_deviation"] <= 2e-4
    assert [j["order"] for j in report["motion"]["junctions"]] == [2, 2, 2, 2, 2]
    assert report["motion"]["segments"][1]["degree"] == 6
    # V from the lift: the blend into the dwell rises V·b/2, so 12 = V·(120° − 25°/2)
    assert report["motion"]["segments"][2]["velocity"] == pytest.approx(12.0 / math.radians(107.5), rel=1e-12)
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Segment junctions" in html and "Solved and fitted segments" in html
