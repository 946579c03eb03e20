"""The quick-return laws (issue 24): "quick_return_out" (rest → reversal) and "quick_return_in"
(reversal → rest), MechDesigner's "Throw: Quick-Return" as two closed-form segments.

Independent checks: the quintic F(x) = (20x³ − 25x⁴ + 8x⁵)/3 and its mirror G(x) = 1 − F(1 − x)
written here as numpy polynomials, their extremes derived by hand, the published factors, and the
continuity across the top of a program built through the spec."""
from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.polynomial import Polynomial

from cam_workbench.generators.motion.characteristics import law_characteristics
from cam_workbench.generators.motion.laws import CLOSED_FORM_LAWS, LAW_FUNCTIONS, evaluate_law, is_law
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.motion.vdi2143 import classify_program
from cam_workbench.generators.spec.model import CamSpec
from cam_workbench.generators.spec.motion import LAWS
from cam_workbench.pipeline import run_pipeline

X = np.linspace(0.0, 1.0, 20001)
#: F(x) = (20x³ − 25x⁴ + 8x⁵)/3
F = Polynomial([0, 0, 0, 20, -25, 8]) / 3
#: G(x) = 1 − F(1 − x)
G = 1 - F(Polynomial([1, -1]))


@pytest.mark.parametrize("name, poly", [("quick_return_out", F), ("quick_return_in", G)])
def test_closed_form_and_derivatives(name, poly):
    ours = evaluate_law(name, X)
    for n, value in enumerate(ours):
        ref = poly.deriv(n)(X) if n else poly(X)
        assert np.max(np.abs(value - ref)) <= 1e-13 * max(1.0, float(np.max(np.abs(ref)))), (name, n)


def test_mirror_identity():
    """G(x) = 1 − F(1 − x): G′ = F′(1 − x), G″ = −F″(1 − x), G‴ = F‴(1 − x)."""
    f = evaluate_law("quick_return_out", 1.0 - X)
    g = evaluate_law("quick_return_in", X)
    for a, b, tol in ((g[0], 1 - f[0], 1e-15), (g[1], f[1], 1e-14), (g[2], -f[2], 1e-13), (g[3], f[3], 1e-12)):
        assert np.max(np.abs(a - b)) <= tol


def test_end_conditions():
    """F: f = f′ = f″ = 0 at the rest end, f = 1, f′ = 0, f″ = −20/3, f‴ = 0 at the turning point
    (worked by hand from the polynomial; the law's values exact to rounding)."""
    d = [F, F.deriv(1), F.deriv(2), F.deriv(3)]
    assert [p(0.0) for p in d] == pytest.approx([0, 0, 0, 40], abs=1e-14)
    assert [p(1.0) for p in d] == pytest.approx([1, 0, -20 / 3, 0], abs=1e-13)
    f0, f1 = (np.array(v) for v in zip(*(q.tolist() for q in evaluate_law("quick_return_out", np.array([0.0, 1.0])))))
    assert f0.tolist() == [0.0, 0.0, 0.0, 40.0] and f1[0] == 1.0 and f1[1] == 0.0 and f1[3] == 0.0
    assert f1[2] == pytest.approx(-20 / 3, rel=1e-15)
    g = evaluate_law("quick_return_in", np.array([0.0, 1.0]))
    assert [float(v[0]) for v in g] == pytest.approx([0.0, 0.0, 20 / 3, 0.0], abs=1e-15)
    assert [float(v[1]) for v in g] == pytest.approx([1.0, 0.0, 0.0, 40.0], abs=1e-13)
    assert np.all(np.diff(evaluate_law("quick_return_out", X)[0]) >= 0)   # f′ = 20x²(1 − x)(3 − 2x)/3 ≥ 0


def test_characteristics_are_the_closed_forms():
    """C_v at the crossover f″ = 0: 8x² − 15x + 6 = 0, x = (15 − √33)/16; max f″ at f‴ = 0:
    40(1 − x)(1 − 4x) = 0, x = ¼, f″ = 55/12; min f″ = −20/3 at x = 1; f‴ from 40 (x = 0) down
    to −22.5 at x = 5/8 (f⁗ = −200 + 320x = 0)."""
    xc = (15 - math.sqrt(33)) / 16
    c = law_characteristics("quick_return_out")
    assert c.C_v == pytest.approx(F.deriv(1)(xc), rel=1e-14) and c.x_v == pytest.approx(xc, abs=1e-12)
    assert (c.C_a_max, c.C_a_min, c.C_a) == (pytest.approx(55 / 12, rel=1e-14), pytest.approx(-20 / 3, rel=1e-14),
                                            pytest.approx(20 / 3, rel=1e-14))
    assert (c.C_j, c.C_j_max, c.C_j_min) == (pytest.approx(40.0, rel=1e-14), pytest.approx(40.0, rel=1e-14),
                                            pytest.approx(-22.5, rel=1e-12))
    g = law_characteristics("quick_return_in")         # the mirror: f″ changes sign, f′ and f‴ do not
    assert g.C_v == pytest.approx(c.C_v, rel=1e-14) and g.x_v == pytest.approx(1 - xc, abs=1e-12)
    assert (g.C_a_max, g.C_a_min) == (pytest.approx(20 / 3, rel=1e-14), pytest.approx(-55 / 12, rel=1e-14))
    assert (g.C_j_max, g.C_j_min) == (pytest.approx(40.0, rel=1e-14), pytest.approx(-22.5, rel=1e-12))
    assert math.isfinite(c.C_j) and math.isfinite(g.C_j)     # the rest end is C2; the top meets a reversal


def test_published_mechdesigner_factors():
    """MechDesigner help, "Throw: Quick-Return: 1: Finite Jerk @ Start/End Motion-Law"
    (http://mechdesigner.support/mt-motion-cam-law-throw.htm), the rise segment (start: zero velocity
    and acceleration, jerk 40; end: position 1, zero velocity, zero jerk): Cv = 1.733, Ca = 4.583,
    Cd = –6.666, Cj max = 40, Cj min = –22.5, as printed (Cd truncated: −20/3 = −6.6667).

    The page's "Jerk at Crossover = -21.5" is not reproduced: f‴ where f″ = 0 (x = (15 − √33)/16)
    is 40(1 − x)(1 − 4x) = −22.15 (and −20 at x = ½)."""
    c = law_characteristics("quick_return_out")
    assert round(c.C_v, 3) == 1.733 and round(c.C_a_max, 3) == 4.583
    assert -6.667 < c.C_a_min <= -6.666                   # the page's three decimals, truncated
    assert round(c.C_j_max, 3) == 40.0 and round(c.C_j_min, 3) == -22.5
    xc = (15 - math.sqrt(33)) / 16
    crossover_jerk = float(evaluate_law("quick_return_out", np.array([xc]))[3][0])
    assert crossover_jerk == pytest.approx(40 * (1 - xc) * (1 - 4 * xc), rel=1e-12)
    assert round(crossover_jerk, 2) == -22.15             # not the page's −21.5


# ---- through the spec ----------------------------------------------------------------------------
def _spec(motion: list[dict]) -> CamSpec:
    return CamSpec.from_dict({"cam": {"base_radius": 60.0, "thickness": 10.0},
                              "follower": {"kind": "roller", "roller_radius": 8.0}, "motion": motion})


THROW = [{"kind": "rise", "angle": 90.0, "lift": 10.0, "law": "quick_return_out"},
         {"kind": "return", "angle": 90.0, "lift": 10.0, "law": "quick_return_in"},
         {"kind": "dwell", "angle": 180.0}]


def test_the_laws_are_spec_choices_but_no_index_laws():
    for name in ("quick_return_out", "quick_return_in"):
        assert name in LAWS and name in CLOSED_FORM_LAWS
        assert name not in LAW_FUNCTIONS and not is_law(name)   # an indexer's turret rests after its index


def test_continuous_over_the_top():
    """Rise 0–90° with F then return 90–180° with G, equal lift and span: s, s′, s″ (and s‴ = 0)
    continuous at the top to 1e-9; the junction reports C3 against the promised C2; VDI 2143 R-U,
    U-R; s″ at the top −(20/3)·h/β² from both sides."""
    prog = MotionProgram.from_spec(_spec(THROW))
    top = np.array([math.pi / 2, math.pi / 2])
    kin = prog.evaluate(top, np.array([0, 1]))
    h, beta = 10.0, math.pi / 2
    for name in ("s", "ds", "d2s", "d3s"):
        left, right = getattr(kin, name)
        assert abs(left - right) <= 1e-9, name
    assert kin.s[0] == pytest.approx(h, abs=1e-12) and abs(kin.ds[0]) <= 1e-12
    assert kin.d2s[0] == pytest.approx(-20 / 3 * h / beta**2, rel=1e-14)
    j = prog.junctions()[1]
    assert (j.left, j.right, j.order, j.promised) == (0, 1, 3, 2)
    assert [t and t["task"] for t in classify_program(prog)] == ["R-U", "U-R", None]


def test_unequal_spans_jump_in_acceleration_and_fail_the_check():
    """h/β² differs on the two sides: s″ = −(20/3)·h/β² on each, the jump their difference; the
    continuity check fails naming both laws (their promise C2 at the top)."""
    motion = [dict(THROW[0]), dict(THROW[1], angle=120.0), dict(THROW[2], angle=150.0)]
    prog = MotionProgram.from_spec(_spec(motion))
    j = prog.junctions()[1]
    b1, b2 = math.pi / 2, math.radians(120.0)
    assert j.order == 1 and j.promised == 2
    assert j.jumps[2] == pytest.approx(-20 / 3 * 10.0 * (1 / b2**2 - 1 / b1**2), rel=1e-12)
    checks = run_pipeline(_spec(motion), solid=False, machining=False, drawing=False, dynamics=False).summary["checks"]
    cont = checks["results"]["continuity"]
    assert cont["status"] == "fail" and cont["value"] == 1.0 and cont["limit"] == 2.0
    assert "quick_return_out and quick_return_in promise C2" in cont["note"]


def test_into_a_dwell_fails_the_check():
    motion = [THROW[0], {"kind": "dwell", "angle": 30.0},
              {"kind": "return", "angle": 90.0, "lift": 10.0, "law": "cycloidal"}, {"kind": "dwell", "angle": 150.0}]
    checks = run_pipeline(_spec(motion), solid=False, machining=False, drawing=False, dynamics=False).summary["checks"]
    cont = checks["results"]["continuity"]
    assert cont["status"] == "fail" and "quick_return_out promises C2" in cont["note"]


def test_a_return_into_a_bottom_turning_point():
    """The laws serve returns too: a return into a reversal at the bottom (F) and the rise out of it
    (G) over equal h/β meet with s″ = +(20/3)·h/β² from both sides."""
    motion = [{"kind": "rise", "angle": 90.0, "lift": 10.0, "law": "cycloidal"},
              {"kind": "return", "angle": 60.0, "lift": 5.0, "law": "quick_return_out"},
              {"kind": "rise", "angle": 60.0, "lift": 5.0, "law": "quick_return_in"},
              {"kind": "return", "angle": 150.0, "lift": 10.0, "law": "cycloidal"}]
    prog = MotionProgram.from_spec(_spec(motion))
    j = prog.junctions()[2]
    assert j.order == 3
    assert j.values_left[2] == pytest.approx(20 / 3 * 5.0 / math.radians(60.0) ** 2, rel=1e-13)
    assert [t["task"] for t in classify_program(prog)][1:3] == ["R-U", "U-R"]


def test_a_cam_designs_and_report_json_holds_the_factors():
    """The design pipeline (what report.json holds): every check passes, and
    motion.segments[i].characteristics carry the law's values."""
    summary = run_pipeline(_spec(THROW), solid=False, machining=False, drawing=False, dynamics=False).summary
    assert summary["checks"]["passed"], summary["checks"]["failed"]
    rise, ret = summary["motion"]["segments"][:2]
    assert rise["law"] == "quick_return_out" and ret["law"] == "quick_return_in"
    assert rise["vdi2143"]["task"] == "R-U" and ret["vdi2143"]["task"] == "U-R"
    c = rise["characteristics"]
    assert round(c["C_v"], 3) == 1.733 and round(c["C_a_max"], 3) == 4.583
    assert c["C_a_min"] == pytest.approx(-20 / 3, rel=1e-14) and c["C_j"] == pytest.approx(40.0, rel=1e-14)
    assert c["C_j_min"] == pytest.approx(-22.5, rel=1e-12)
    r = ret["characteristics"]
    assert r["C_a_max"] == pytest.approx(20 / 3, rel=1e-14) and r["C_a_min"] == pytest.approx(-55 / 12, rel=1e-14)
    top = summary["motion"]["junctions"][1]
    assert top["order"] == 3 and top["ok"]
