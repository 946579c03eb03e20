"""A failing check says how to pass (issue 20, item 3): each failing check's remedy in report.json's
``checks.results[name].remedy`` and the messages — the smallest base radius by the bisection of
``sweep --size`` held against the closed-form pressure angle, the offset of the other sign, an
oscillating arm's pivot distance, a groove's disc diameter against the closed-form rim wall, a
cylindrical cam's radius against tan φ = s′/R_p — and every printed command applied passes
``check`` (exit 0)."""
from __future__ import annotations

import json
import math
import shlex

import numpy as np
import pytest

from cam_workbench.generators.checks.design import run_checks
from cam_workbench.generators.errors import GeometryError
from cam_workbench.generators.spec.examples import example_dict, example_spec
from cam_workbench.generators.studies.remedies import add_remedies, remedy_line, with_remedy
from cam_workbench.generators.studies.sizing import smallest_base_radius

from .conftest import requires_ocp
from .test_cli import run

#: the user's cam of issue 20: a 25 mm modified-sine rise in 100° on R_b = 35, the follower 5 mm off
#: the radial line (e = −5: 33.731° > 30°); the return stays the default's cycloidal 120°
USER = {"cam.base_radius": 35.0, "motion[1].lift": 25.0, "motion[1].angle": 100.0,
        "motion[1].law": "modified_sine", "motion[2].angle": 80.0, "motion[3].lift": 25.0,
        "follower.offset": -5.0}
#: the same rise with a gentle return (170°) on R_b = 30: the offset of the other sign passes
SIGN = {**USER, "cam.base_radius": 30.0, "motion[2].angle": 30.0, "motion[3].angle": 170.0}


def _sets(changes: dict) -> list[str]:
    out = []
    for k, v in changes.items():
        out += ["--set", f"{k}={v}"]
    return out


# ---- closed forms, written here -----------------------------------------------------------------
def modified_sine(x: np.ndarray, h: float, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """(s, s′ per rad) of the modified sine rise (Kloomok & Muffley), x = θ/β ∈ [0, 1]."""
    k = 4.0 + math.pi
    s = np.where(x <= 1 / 8, h * (math.pi * x / k - np.sin(4 * math.pi * x) / (4 * k)),
                 np.where(x <= 7 / 8,
                          h * (2 / k + math.pi * x / k - 9 * np.sin(math.pi * (4 * x + 1) / 3) / (4 * k)),
                          h * (4 / k + math.pi * x / k - np.sin(4 * math.pi * x) / (4 * k))))
    ds = np.where((x <= 1 / 8) | (x >= 7 / 8), h * math.pi / k * (1 - np.cos(4 * math.pi * x)),
                  h * math.pi / k * (1 - 3 * np.cos(math.pi * (4 * x + 1) / 3))) / beta
    return s, ds


def cycloidal_return(x: np.ndarray, h: float, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """(s, s′ per rad) of a cycloidal return from h to 0."""
    return (h * (1 - x + np.sin(2 * math.pi * x) / (2 * math.pi)),
            h * (np.cos(2 * math.pi * x) - 1) / beta)


def max_pressure_angle(rb: float, e: float, ret_deg: float) -> float:
    """max |φ| [deg], φ = atan((s′ − e)/(√(R_b² − e²) + s)), over the rise (25 mm, 100°, modified
    sine) and the return (25 mm cycloidal over ``ret_deg``); the dwells have φ = atan(−e/…)."""
    x = np.linspace(0.0, 1.0, 200001)
    s0 = math.sqrt(rb * rb - e * e)
    worst = 0.0
    for s, ds in (modified_sine(x, 25.0, math.radians(100.0)), cycloidal_return(x, 25.0, math.radians(ret_deg))):
        worst = max(worst, float(np.max(np.abs(np.degrees(np.arctan((ds - e) / (s0 + s)))))))
    return worst


# ---- the pressure angle: base radius and offset ------------------------------------------------------
def test_pressure_angle_remedy_is_the_sizing_radius_and_passes_the_closed_form():
    spec = example_spec("default").replace(**USER)
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    r = checks["results"]["pressure_angle"]
    assert r["status"] == "fail" and r["value"] == pytest.approx(33.731, abs=5e-4)
    rem = r["remedy"]
    sz = smallest_base_radius(spec)                    # the bisection of `sweep --size`
    assert rem["field"] == "cam.base_radius" and rem["search"] == "smallest" and rem["tolerance"] == 0.01
    assert sz.value - 0.01 < rem["value"] <= sz.value + 0.01 and rem["value"] == round(rem["value"], 2)
    assert rem["value"] == pytest.approx(41.7753, abs=0.01)
    assert rem["command"] == "--set cam.base_radius=41.78" and rem["passes_all"] and rem["fails"] == []
    # independent: the closed-form φ passes at the printed radius and fails one tolerance below
    assert max_pressure_angle(41.78, -5.0, 120.0) <= 30.0 < max_pressure_angle(41.77, -5.0, 120.0)
    assert max_pressure_angle(35.0, -5.0, 120.0) == pytest.approx(r["value"], abs=1e-6)
    # the nearest offset that passes is still negative here (no sign to reverse): the alternative
    alt = {a["field"]: a for a in rem["alternatives"]}["follower.offset"]
    assert -5.0 < alt["value"] < 0 and "other sign" not in alt["text"]
    assert max_pressure_angle(35.0, alt["value"], 120.0) <= 30.0 < max_pressure_angle(35.0, alt["value"] - 0.01, 120.0)


def test_the_offset_of_the_other_sign_where_it_helps():
    spec = example_spec("default").replace(**SIGN)
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    rem = checks["results"]["pressure_angle"]["remedy"]
    alt = {a["field"]: a for a in rem["alternatives"]}["follower.offset"]
    e = alt["value"]
    assert e > 0 and "the offset's other sign lowers the binding pressure angle" in alt["text"]
    assert alt["command"] == f"--set follower.offset={e:.2f}"
    # the closed form: radial fails, e passes, e − 0.01 (nearer the spec's −5) fails
    assert max_pressure_angle(30.0, 0.0, 170.0) > 30.0
    assert max_pressure_angle(30.0, e, 170.0) <= 30.0 < max_pressure_angle(30.0, e - 0.01, 170.0)
    # no offset remedy where no offset passes (the paper's cam: e = 10 mm, 46.2°)
    paper = example_spec("paper")
    rem = add_remedies(run_checks(paper).to_dict(), paper)["results"]["pressure_angle"]["remedy"]
    assert rem["field"] == "cam.base_radius" and rem["alternatives"] == []


def test_check_prints_the_remedy_and_applying_its_command_passes(tmp_path):
    out = tmp_path / "c"
    res = run("check", *_sets(USER), "-o", str(out))
    assert res.returncode == 3, res.stderr
    rep = json.loads((out / "report.json").read_text())
    rem = rep["checks"]["results"]["pressure_angle"]["remedy"]
    line = remedy_line("pressure_angle", rem)
    assert "remedy " + line in " ".join(res.stdout.split()), res.stdout          # one line under the table
    for one in [rem, *rem["alternatives"]]:
        ok = run("check", *_sets(USER), *shlex.split(one["command"]), "-o", str(tmp_path / "ok"))
        assert ok.returncode == 0, one["command"] + "\n" + ok.stdout + ok.stderr
        assert "all checks pass" in ok.stdout


# ---- the other followers and bodies ---------------------------------------------------------------
def test_oscillating_arm_gets_the_nearest_pivot_distance(tmp_path):
    changes = {"cam.base_radius": 60.0}
    spec = example_spec("oscillating").replace(**changes)
    rem = add_remedies(run_checks(spec).to_dict(), spec)["results"]["pressure_angle"]["remedy"]
    assert rem["field"] == "follower.pivot_distance" and rem["search"] == "nearest" and rem["passes_all"]
    d = rem["value"]
    side = 1 if d > 60.0 else -1
    assert not run_checks(spec.replace(**{"follower.pivot_distance": d - side * 0.01})).passed
    assert "cam.base_radius" in {a["field"] for a in rem["alternatives"]}
    for one in [rem, *rem["alternatives"]]:
        ok = run("check", "--example", "oscillating", *_sets(changes), *shlex.split(one["command"]),
                 "-o", str(tmp_path / "ok"))
        assert ok.returncode == 0, one["command"] + "\n" + ok.stdout + ok.stderr


def test_groove_rim_wall_remedy_is_the_closed_form_disc_diameter(tmp_path):
    """Radial roller: at the top dwell the pitch curve is the circle R_b + h, the outer wall the
    circle R_b + h + w/2, so the rim wall passes from OD = 2(R_b + h + w/2 + min_wall) on."""
    changes = {"cam.outer_diameter": 120.0, "groove.min_wall": 3.003}
    res = run("check", "--example", "groove", *_sets(changes), "-o", str(tmp_path / "g"))
    assert res.returncode == 2 and "Traceback" not in res.stderr
    spec = example_spec("groove").replace(**changes)
    w2 = spec.roller_radius + spec.groove.clearance / 2
    od = 2 * (spec.cam.base_radius + 20.0 + w2 + 3.003)                    # 142.106
    assert "rim_wall: cam.outer_diameter = 142.11 mm passes every check" in res.stderr
    assert "--set cam.outer_diameter=142.11" in res.stderr
    assert 142.11 - 0.01 < od <= 142.11
    ok = run("check", "--example", "groove", *_sets(changes), "--set", "cam.outer_diameter=142.11",
             "-o", str(tmp_path / "ok"))
    assert ok.returncode == 0, ok.stdout + ok.stderr
    with pytest.raises(GeometryError) as refused:                  # the library's own message, with it
        from cam_workbench.generators.cam_design import design_cam

        design_cam(spec)
    assert refused.value.checks == ("rim_wall",)
    assert "cam.outer_diameter = 142.11 mm" in str(with_remedy(spec, refused.value))


def test_cylindrical_cam_gets_its_cylinder_radius(tmp_path):
    """tan φ = s′/R_p (translating roller along the axis): the smallest R_p is max|s′|/tan 30°."""
    changes = {"cam.cylinder_radius": 20.0}
    spec = example_spec("cylindrical").replace(**changes)
    from cam_workbench.generators.bodies.cylindrical import cylinder_checks
    from cam_workbench.generators.motion.program import MotionProgram

    checks = add_remedies(cylinder_checks(spec), spec)
    assert checks["failed"] == ["pressure_angle"]
    rem = checks["results"]["pressure_angle"]["remedy"]
    assert rem["field"] == "cam.cylinder_radius" and rem["passes_all"]
    th = np.linspace(0.0, 2 * math.pi, 720001)
    smax = float(np.max(np.abs(MotionProgram.from_spec(spec).evaluate(th).ds)))
    need = smax / math.tan(math.radians(spec.checks.max_pressure_angle))
    assert rem["value"] - 0.01 < need <= rem["value"] + 1e-9
    res = run("check", "--example", "cylindrical", *_sets(changes), "-o", str(tmp_path / "c"))
    assert res.returncode == 3 and remedy_line("pressure_angle", rem) in " ".join(res.stdout.split())
    ok = run("check", "--example", "cylindrical", *_sets(changes), *shlex.split(rem["command"]),
             "-o", str(tmp_path / "ok"))
    assert ok.returncode == 0, ok.stdout + ok.stderr


def test_conjugate_second_cam_gets_the_roller_distance(tmp_path):
    changes = {"conjugate.roller_distance": 80.0}
    spec = example_spec("conjugate").replace(**changes)
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    assert "pressure_angle_cam2" in checks["failed"]
    rem = checks["results"]["pressure_angle_cam2"]["remedy"]
    assert rem["field"] == "conjugate.roller_distance" and rem["passes_all"]
    assert not run_checks(spec.replace(**{"conjugate.roller_distance": rem["value"] - 0.01})).passed
    ok = run("check", "--example", "conjugate", *_sets(changes), *shlex.split(rem["command"]),
             "-o", str(tmp_path / "ok"))
    assert ok.returncode == 0, ok.stdout + ok.stderr


def test_no_single_field_is_said_in_words():
    """Separation needs the follower's load (Example 5's final design: −1.162 lbf), not a size."""
    from .test_cli_check import EX5
    from cam_workbench.generators.spec import load_spec

    spec = load_spec(EX5)
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    rem = checks["results"]["separation"]["remedy"]
    assert rem["field"] is None and rem["command"] is None
    assert "follower.preload" in rem["text"] and "follower.spring_rate" in rem["text"]
    assert all("remedy" not in r for n, r in checks["results"].items() if r["status"] != "fail")


def test_a_passing_cam_has_no_remedy():
    spec = example_spec("default")
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    assert checks["passed"] and all("remedy" not in r for r in checks["results"].values())


def test_the_face_width_a_flat_face_needs():
    d = example_dict("flat")
    d["follower"]["face_width"] = 10.0
    from cam_workbench.generators.spec import CamSpec

    spec = CamSpec.from_dict(d)
    checks = add_remedies(run_checks(spec).to_dict(), spec)
    r = checks["results"]["face_width"]
    assert r["status"] == "fail"
    rem = r["remedy"]
    assert rem["field"] == "follower.face_width" and rem["value"] == math.ceil(r["value"] * 100 - 1e-9) / 100
    assert run_checks(spec.replace(**{"follower.face_width": rem["value"]})).passed


# ---- every entry point ------------------------------------------------------------------------------
@requires_ocp
def test_build_report_html_and_cam_show_the_remedy(tmp_path):
    """The paper's cam (46.2° > 30°): build's summary line, report.html's checks section and
    Cam.checks() carry report.json's remedy, word for word."""
    import html

    from cam_workbench import Cam

    out = tmp_path / "b"
    res = run("build", "--example", "paper", "-o", str(out))
    assert res.returncode == 0, res.stderr
    rep = json.loads((out / "report.json").read_text())
    rem = rep["checks"]["results"]["pressure_angle"]["remedy"]
    assert rem["command"] == "--set cam.base_radius=42.80"
    line = remedy_line("pressure_angle", rem)
    assert f"    remedy {line}" in res.stdout.splitlines()
    page = (out / "report.html").read_text()
    assert (f'<li data-key="checks.results.pressure_angle.remedy"><code>pressure_angle</code>: '
            f"{html.escape(line[len('pressure_angle: '):])}</li>") in page
    assert Cam.example("paper").checks()["results"]["pressure_angle"]["remedy"] == rem
    ok = run("check", "--example", "paper", *shlex.split(rem["command"]), "-o", str(tmp_path / "ok"))
    assert ok.returncode == 0, ok.stdout + ok.stderr


def test_cam_refusal_says_how_to_make_it():
    from cam_workbench.cam import Cam

    with pytest.raises(GeometryError) as refused:
        Cam(example_spec("groove").replace(**{"cam.outer_diameter": 120.0}))
    assert "rim_wall: cam.outer_diameter = 142.11 mm passes every check" in str(refused.value)
