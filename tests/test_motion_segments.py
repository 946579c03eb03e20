"""Polynomial (Norton's SVAJ method), constant-velocity and table segments, the boundary values the
program carries between segments, and the junction continuity report — against closed forms and
hand computations written out here, not against the code's own laws."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_workbench.generators.checks.design import run_checks
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.motion.polynomial import Condition, power_coefficients, solve_conditions
from cam_workbench.generators.spec import CamSpec, load_spec, to_toml

H = 10.0     # lift [mm]


def spec(motion, **extra):
    return CamSpec.from_dict({"cam": {"base_radius": 60.0, "thickness": 5.0},
                              "follower": {"kind": "roller", "roller_radius": 5.0}, "motion": motion, **extra})


def program(motion, **extra):
    return MotionProgram.from_spec(spec(motion, **extra))


def dwell(angle):
    return {"kind": "dwell", "angle": angle}


def interior(a_deg, b_deg, n=201):
    """Cam angles [rad] strictly inside [a, b] degrees."""
    return np.radians(np.linspace(a_deg, b_deg, n)[1:-1])


# ---- polynomials from boundary conditions ------------------------------------------------------
def poly_345(x):
    """s/h, s′, s″, s‴ (per x^n) of 10x³ − 15x⁴ + 6x⁵ (Norton, Eq. 3.xx: the 3-4-5 rise)."""
    return (10 * x**3 - 15 * x**4 + 6 * x**5, 30 * x**2 - 60 * x**3 + 30 * x**4,
            60 * x - 180 * x**2 + 120 * x**3, 60 - 360 * x + 360 * x**2)


def poly_4567(x):
    """35x⁴ − 84x⁵ + 70x⁶ − 20x⁷ and its derivatives: the 4-5-6-7 rise."""
    return (35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7, 140 * x**3 - 420 * x**4 + 420 * x**5 - 140 * x**6,
            420 * x**2 - 1680 * x**3 + 2100 * x**4 - 840 * x**5, 840 * x - 5040 * x**2 + 8400 * x**3 - 4200 * x**4)


def test_solver_gives_345_from_its_six_boundary_conditions():
    """s(0) = 0, s′(0) = 0, s″(0) = 0, s(β) = h, s′(β) = 0, s″(β) = 0: six conditions, degree 5."""
    beta = math.radians(120.0)
    conds = [Condition(0.0, 0, 0.0, ""), Condition(0.0, 1, 0.0, ""), Condition(0.0, 2, 0.0, ""),
             Condition(1.0, 0, H, ""), Condition(1.0, 1, 0.0, ""), Condition(1.0, 2, 0.0, "")]
    a = power_coefficients(solve_conditions(conds, beta))
    assert np.allclose(a, [0, 0, 0, 10 * H, -15 * H, 6 * H], rtol=0, atol=1e-11)


def test_solver_gives_4567_from_its_eight_boundary_conditions():
    beta = math.radians(75.0)
    conds = [Condition(e, n, H if (e == 1.0 and n == 0) else 0.0, "") for e in (0.0, 1.0) for n in range(4)]
    a = power_coefficients(solve_conditions(conds, beta))
    assert np.allclose(a, [0, 0, 0, 0, 35 * H, -84 * H, 70 * H, -20 * H], rtol=0, atol=1e-10)


@pytest.mark.parametrize("extra, closed, degree", [
    ({}, poly_345, 5),                                                        # law = "polynomial" alone
    ({"start_continuity": 3, "end_continuity": 3}, poly_4567, 7),
    ({"start_jerk": 0.0, "end_jerk": 0.0}, poly_4567, 7),                      # the same by values
])
def test_polynomial_rise_between_dwells_is_the_closed_form(extra, closed, degree):
    prog = program([dwell(90), {"kind": "rise", "angle": 120, "lift": H, "law": "polynomial", **extra},
                    dwell(60), {"kind": "return", "angle": 90, "lift": H, "law": "cycloidal"}])
    assert prog.infos[1]["degree"] == degree
    beta = math.radians(120.0)
    th = interior(90, 210)
    x = (th - math.radians(90.0)) / beta
    k = prog.evaluate(th)
    f = closed(x)
    for got, want, n in zip((k.s, k.ds, k.d2s, k.d3s), f, range(4)):
        assert np.max(np.abs(got - H * want / beta**n)) <= 1e-10 * H / beta**n, n


def test_polynomial_return_is_the_mirrored_345():
    prog = program([{"kind": "rise", "angle": 180, "lift": H, "law": "cycloidal"},
                    {"kind": "return", "angle": 180, "lift": H, "law": "polynomial"}])
    th = interior(180, 360)
    x = (th - math.pi) / math.pi
    assert np.max(np.abs(prog.s(th) - H * (1 - poly_345(x)[0]))) < 1e-11
    assert np.allclose(prog.infos[1]["coefficients"], [H, 0, 0, -10 * H, 15 * H, -6 * H], atol=1e-10)


def test_polynomial_through_interior_points_is_the_power_basis_solution():
    """Eight conditions (zero velocity and acceleration at both ends, s at 0 and 120°, two points):
    the degree-7 polynomial solved here independently in the power basis."""
    pts = [[40.0, 2.0], [80.0, 8.5]]
    prog = program([dwell(60), {"kind": "rise", "angle": 120, "lift": H, "law": "polynomial", "points": pts},
                    dwell(60), {"kind": "return", "angle": 120, "lift": H, "law": "poly345"}])
    assert prog.infos[1]["degree"] == 7
    beta = math.radians(120.0)
    rows, rhs = [], []
    k = np.arange(8)

    def deriv_row(x, n):
        c = np.array([math.perm(j, n) if j >= n else 0 for j in k], dtype=float)
        return c * np.where(k >= n, float(x) ** np.maximum(k - n, 0), 0.0)

    for x, n, v in [(0, 0, 0.0), (0, 1, 0.0), (0, 2, 0.0), (1, 0, H), (1, 1, 0.0), (1, 2, 0.0),
                    (40 / 120, 0, 2.0), (80 / 120, 0, 8.5)]:
        rows.append(deriv_row(x, n))
        rhs.append(v)
    a = np.linalg.solve(np.array(rows), np.array(rhs))
    assert np.allclose(prog.infos[1]["coefficients"], a, rtol=0, atol=1e-8 * np.max(np.abs(a)))
    # it meets the points and the ends exactly
    at = np.radians([60 + 40, 60 + 80])
    assert np.allclose(prog.s(at), [2.0, 8.5], atol=1e-11)
    th = np.radians([60.0, 180.0])
    kin = prog.evaluate(th, np.array([1, 1]))
    assert np.allclose([kin.ds, kin.d2s], 0.0, atol=1e-9)
    assert np.allclose(kin.s, [0.0, H], atol=1e-12)


def test_rise_into_rise_with_a_given_velocity_is_carried_to_the_next_polynomial():
    """A rise ending with s′ = 6 mm/rad, the next rise starts with it (it matches by default): the
    junction is C2; the second polynomial solved here by hand from its conditions."""
    prog = program([dwell(60), {"kind": "rise", "angle": 60, "lift": 5.0, "law": "polynomial", "end_velocity": 6.0},
                    {"kind": "rise", "angle": 60, "lift": 7.0, "law": "polynomial"}, dwell(60),
                    {"kind": "return", "angle": 120, "lift": 12.0, "law": "cycloidal"}])
    j = prog.junctions()[2]
    assert (j.left, j.right, j.order) == (1, 2, 2)
    assert j.values_left[1] == pytest.approx(6.0, abs=1e-10) and j.values_right[1] == pytest.approx(6.0, abs=1e-10)
    beta = math.radians(60.0)
    conds = [Condition(0.0, 0, 5.0, ""), Condition(0.0, 1, 6.0, ""), Condition(0.0, 2, 0.0, ""),
             Condition(1.0, 0, 12.0, ""), Condition(1.0, 1, 0.0, ""), Condition(1.0, 2, 0.0, "")]
    assert np.allclose(prog.infos[2]["coefficients"], power_coefficients(solve_conditions(conds, beta)), atol=1e-10)
    # by hand: s = 5 + 6βx + a3 x³ + a4 x⁴ + a5 x⁵ with s(1) = 12, s′(1) = s″(1) = 0
    v = 6.0 * beta
    m = np.array([[1, 1, 1], [3, 4, 5], [6, 12, 20]], dtype=float)
    a345 = np.linalg.solve(m, [7.0 - v, -v, 0.0])
    assert np.allclose(prog.infos[2]["coefficients"], [5.0, v, 0.0, *a345], atol=1e-10)


def test_rise_with_free_end_acceleration_carries_it_into_the_return():
    """Norton's two-segment single-dwell cam: the rise meets s, s′, s″ = 0 at its start and s = h,
    s′ = 0 at its end (end_continuity = 1: acceleration free) — the quartic h(4x³ − 3x⁴) — and the
    return starts with that acceleration, −12h/β²."""
    beta = math.radians(90.0)
    prog = program([dwell(180), {"kind": "rise", "angle": 90, "lift": H, "law": "polynomial", "end_continuity": 1},
                    {"kind": "return", "angle": 90, "lift": H, "law": "polynomial"}])
    assert np.allclose(prog.infos[1]["coefficients"], [0, 0, 0, 4 * H, -3 * H], atol=1e-10)
    j = prog.junctions()[2]
    assert j.values_left[2] == pytest.approx(-12 * H / beta**2, rel=1e-10)
    assert j.values_right[2] == pytest.approx(-12 * H / beta**2, rel=1e-10)
    assert j.order == 2 and j.promised == 1 and j.ok


# ---- junction continuity against hand-computed jumps -------------------------------------------
def test_cycloidal_into_harmonic_jumps_as_computed_by_hand():
    """Cycloidal rise (β₁ = 150°) straight into a harmonic return (β₂ = 210°): s′ is 0 on both sides;
    s″ jumps from 0 to −hπ²/(2β₂²); s‴ from 4π²h/β₁³ to 0.  Velocity continuous only: order 1, which is
    what the harmonic promises."""
    b1, b2 = math.radians(150.0), math.radians(210.0)
    prog = program([{"kind": "rise", "angle": 150, "lift": H, "law": "cycloidal"},
                    {"kind": "return", "angle": 210, "lift": H, "law": "harmonic"}])
    top = prog.junctions()[1]
    assert top.jumps[1] == pytest.approx(0.0, abs=1e-12)
    assert top.jumps[2] == pytest.approx(-H * math.pi**2 / (2 * b2**2), rel=1e-12)
    assert top.jumps[3] == pytest.approx(-4 * math.pi**2 * H / b1**3, rel=1e-12)
    assert (top.order, top.promised, top.ok) == (1, 1, True)
    # a closed-form program meets its promises: no continuity check is shown
    assert "continuity" not in [r.name for r in run_checks(spec(
        [{"kind": "rise", "angle": 150, "lift": H, "law": "cycloidal"},
         {"kind": "return", "angle": 210, "lift": H, "law": "harmonic"}])).results]


def test_constant_velocity_without_blends_breaks_its_promise_at_both_dwells():
    """s′ jumps by ±h/β where the stroke meets the dwells: order 0 < the promised 2 — the check fails
    and names the velocity jump."""
    beta = math.radians(180.0)
    motion = [dwell(60), {"kind": "rise", "angle": 180, "lift": H, "law": "constant_velocity"},
              dwell(30), {"kind": "return", "angle": 90, "lift": H, "law": "cycloidal"}]
    prog = program(motion)
    j = prog.junctions()
    assert j[1].jumps[1] == pytest.approx(H / beta, rel=1e-12) and j[2].jumps[1] == pytest.approx(-H / beta, rel=1e-12)
    assert [x.order for x in j] == [2, 0, 0, 2] and [x.ok for x in j] == [True, False, False, True]
    r = run_checks(spec(motion))["continuity"]
    assert (r.status, r.value, r.limit, r.at_deg) == ("fail", 0.0, 2.0, pytest.approx(60.0))
    assert "velocity jumps by 3.183 mm/rad" in r.note and "constant_velocity promises C2" in r.note


def test_explicit_velocity_that_does_not_meet_a_dwell_fails_the_check():
    motion = [dwell(60), {"kind": "rise", "angle": 120, "lift": H, "law": "polynomial", "start_velocity": 5.0},
              dwell(60), {"kind": "return", "angle": 120, "lift": H, "law": "polynomial"}]
    j = program(motion).junctions()[1]
    assert j.jumps[1] == pytest.approx(5.0, rel=1e-12) and j.order == 0
    assert run_checks(spec(motion))["continuity"].status == "fail"


@pytest.mark.parametrize("law, status", [("poly345", "fail"), ("poly4567", "pass")])
def test_min_continuity_3_asks_for_continuous_jerk(law, status):
    """checks.min_continuity = 3: a 3-4-5 rise jumps in jerk by 60h/β³ at a dwell (by hand), a 4-5-6-7
    rise does not."""
    motion = [dwell(90), {"kind": "rise", "angle": 90, "lift": H, "law": law},
              dwell(90), {"kind": "return", "angle": 90, "lift": H, "law": law}]
    r = run_checks(spec(motion, checks={"min_continuity": 3}))["continuity"]
    assert r.status == status and r.limit == 3.0
    if law == "poly345":
        j = program(motion).junctions()[1]
        assert j.jumps[3] == pytest.approx(60 * H / math.radians(90.0) ** 3, rel=1e-12)
        assert "below checks.min_continuity = 3" in r.note


def test_report_lists_every_junction():
    motion = [dwell(60), {"kind": "rise", "angle": 180, "lift": H, "law": "constant_velocity",
                          "start_blend": 30.0, "end_blend": 30.0},
              dwell(30), {"kind": "return", "angle": 90, "lift": H, "law": "polynomial"}]
    rep = program(motion).report()
    assert [j["at_deg"] for j in rep["junctions"]] == pytest.approx([0.0, 60.0, 240.0, 270.0])
    assert [(j["from"], j["to"]) for j in rep["junctions"]] == [(3, 0), (0, 1), (1, 2), (2, 3)]
    assert all(j["ok"] and j["order"] == 2 for j in rep["junctions"])
    assert rep["segments"][1]["velocity"] == pytest.approx(H / math.radians(150.0))
    assert rep["segments"][3]["degree"] == 5


# ---- constant velocity with blended ends ------------------------------------------------------
@pytest.mark.parametrize("cont", [2, 3])
def test_blends_are_the_defining_polynomials(cont):
    """Between dwells, a blend of b from rest to the cruise velocity V has s′ = V·g(x), x = t/b, with
    g = 3x² − 2x³ (continuity 2) or 10x³ − 15x⁴ + 6x⁵ (continuity 3); either rises V·b/2, so
    V = h/(β − (b₁ + b₂)/2)."""
    b1, b2, beta = 30.0, 45.0, 200.0
    motion = [dwell(40), {"kind": "rise", "angle": beta, "lift": H, "law": "constant_velocity", "start_blend": b1,
                          "end_blend": b2, "start_continuity": cont, "end_continuity": cont},
              {"kind": "return", "angle": 120, "lift": H, "law": "poly4567"}]
    prog = program(motion)
    V = H / math.radians(beta - (b1 + b2) / 2)
    assert prog.infos[1]["velocity"] == pytest.approx(V, rel=1e-12)
    if cont == 2:
        g = (lambda x: 3 * x**2 - 2 * x**3)
        G = (lambda x: x**3 - x**4 / 2)
    else:
        g = (lambda x: 10 * x**3 - 15 * x**4 + 6 * x**5)
        G = (lambda x: 2.5 * x**4 - 3 * x**5 + x**6)
    rb1, rb2 = math.radians(b1), math.radians(b2)
    th = interior(40, 40 + b1)
    x = (th - math.radians(40)) / rb1
    k = prog.evaluate(th)
    assert np.max(np.abs(k.ds - V * g(x))) < 1e-11
    assert np.max(np.abs(k.s - V * rb1 * G(x))) < 1e-11
    th = interior(40 + b1, 40 + beta - b2)
    k = prog.evaluate(th)
    assert np.max(np.abs(k.ds - V)) < 1e-11 and np.max(np.abs(k.d2s)) < 1e-9
    assert np.max(np.abs(k.s - (V * rb1 / 2 + V * (th - math.radians(40 + b1))))) < 1e-11
    th = interior(40 + beta - b2, 40 + beta)
    x = (th - math.radians(40 + beta - b2)) / rb2
    k = prog.evaluate(th)
    assert np.max(np.abs(k.ds - V * (1 - g(x)))) < 1e-11
    assert np.max(np.abs(k.s - (H - V * rb2 * G(1 - x)))) < 1e-11
    j = prog.junctions()
    assert [x.order for x in j[1:3]] == [cont, cont] and all(x.ok for x in j)
    if cont == 2:   # the jerk jumps at the dwell by V·6/b₁² (g″(0) = 6)
        assert j[1].jumps[3] == pytest.approx(6 * V / rb1**2, rel=1e-10)


def test_polynomial_rise_and_return_take_the_cruise_velocity():
    """Norton's constant-velocity cam: dwell, polynomial rise, unblended cruise, polynomial rise, polynomial
    return — the polynomials meet the cruise's s′ = V = 15 mm/120°, s″ = 0, so every junction is C2."""
    motion = [dwell(60), {"kind": "rise", "angle": 60, "lift": 5.0, "law": "polynomial"},
              {"kind": "rise", "angle": 120, "lift": 15.0, "law": "constant_velocity"},
              {"kind": "rise", "angle": 60, "lift": 5.0, "law": "polynomial"},
              {"kind": "return", "angle": 60, "lift": 25.0, "law": "polynomial"}]
    prog = program(motion)
    V = 15.0 / math.radians(120.0)
    j = prog.junctions()
    assert j[2].values_left[1] == pytest.approx(V, rel=1e-12) and j[3].values_right[1] == pytest.approx(V, rel=1e-12)
    assert all(x.order >= 2 for x in j)
    assert "continuity" not in run_checks(spec(motion)).failed


def test_area_of_a_blended_stroke_against_quadrature_of_its_formula():
    """checks.areas integrates the cruise over its own knot spans: against scipy's quad of the
    defining formula ½(R + s)² (smoothstep blends, line)."""
    from scipy.integrate import quad

    from cam_workbench.generators.checks.areas import thesis_area

    b, beta, r0 = 30.0, 180.0, 60.0
    s = spec([dwell(60), {"kind": "rise", "angle": beta, "lift": H, "law": "constant_velocity",
                          "start_blend": b, "end_blend": b}, dwell(30),
              {"kind": "return", "angle": 90, "lift": H, "law": "polynomial"}])
    V = H / math.radians(beta - b)
    rb = math.radians(b)

    def s_of(t):           # t from the stroke's start [rad]
        if t < rb:
            x = t / rb
            return V * rb * (x**3 - x**4 / 2)
        if t > math.radians(beta) - rb:
            x = (math.radians(beta) - t) / rb
            return H - V * rb * (x**3 - x**4 / 2)
        return V * rb / 2 + V * (t - rb)

    def ret(t):             # the polynomial return: 3-4-5 between the dwells
        x = t / (math.pi / 2)
        return H * (1 - (10 * x**3 - 15 * x**4 + 6 * x**5))

    want = (0.5 * r0**2 * math.radians(60) + quad(lambda t: 0.5 * (r0 + s_of(t)) ** 2, 0, math.radians(beta),
                                                  points=[rb, math.radians(beta) - rb], epsabs=1e-12)[0]
            + 0.5 * (r0 + H) ** 2 * math.radians(30) + quad(lambda t: 0.5 * (r0 + ret(t)) ** 2, 0, math.pi / 2,
                                                            epsabs=1e-12)[0])
    assert thesis_area(s) == pytest.approx(want, rel=1e-12)


# ---- tables -----------------------------------------------------------------------------------
def cycloid(x):
    return x - np.sin(2 * np.pi * x) / (2 * np.pi)


def table_motion(rows, **extra):
    return [dwell(60), {"kind": "rise", "angle": 120, "lift": H, "law": "table", "table": rows, **extra},
            dwell(60), {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}]


def test_table_fit_of_a_sampled_cycloid():
    """A cycloidal rise sampled every 2° and fitted to 1e-5 mm: the errors at the points (measured here
    from the program) are within the tolerance and are the ones reported; between the points the fit
    follows the cycloid itself, and its velocity the cycloid's; the ends meet the dwells to C2."""
    a = np.arange(0.0, 120.0 + 1e-9, 2.0)
    rows = [[float(t), float(H * cycloid(t / 120.0))] for t in a]
    prog = program(table_motion(rows, table_tolerance=1e-5))
    info = prog.infos[1]
    th = np.radians(60.0 + a)
    err = np.abs(prog.evaluate(th, np.full(th.shape, 1)).s - np.array(rows)[:, 1])
    assert err.max() <= 1e-5
    assert info["max_error"] == pytest.approx(err.max(), rel=1e-6, abs=1e-15)
    assert info["max_error_at_deg"] == pytest.approx(60.0 + a[np.argmax(err)])
    assert info["points"] == len(rows) and info["order"] == 5
    mid = np.radians(60.0 + np.arange(1.0, 120.0, 2.0))
    x = (mid - math.radians(60)) / math.radians(120)
    k = prog.evaluate(mid)
    assert np.max(np.abs(k.s - H * cycloid(x))) < 3e-5
    assert np.max(np.abs(k.ds - H * (1 - np.cos(2 * np.pi * x)) / math.radians(120))) < 1e-3
    assert [j.order for j in prog.junctions()[1:3]] == [2, 2]


def test_table_uses_the_fewest_spans_that_meet_the_tolerance():
    a = np.arange(0.0, 120.0 + 1e-9, 1.0)
    rows = [[float(t), float(H * cycloid(t / 120.0))] for t in a]
    loose = program(table_motion(rows, table_tolerance=1e-2)).infos[1]
    tight = program(table_motion(rows, table_tolerance=1e-6)).infos[1]
    assert loose["spans"] < tight["spans"] and tight["max_error"] <= 1e-6 and loose["max_error"] <= 1e-2


def test_table_tolerance_not_met_names_the_field():
    rng = np.random.default_rng(3)
    a = np.arange(0.0, 120.0 + 1e-9, 1.0)
    rows = [[float(t), float(H * cycloid(t / 120.0) + 0.05 * rng.standard_normal())] for t in a]
    rows[0][1], rows[-1][1] = 0.0, H
    with pytest.raises(SpecError) as exc:
        spec(table_motion(rows, table_tolerance=1e-3))
    assert exc.value.field == "motion[1].table_tolerance"
    assert "misses its points by up to" in exc.value.rule and "from the segment start" in exc.value.rule


def test_table_file_relative_to_the_spec_and_toml_round_trip(tmp_path, monkeypatch):
    d = tmp_path / "cams"
    d.mkdir()
    a = np.arange(0.0, 120.0 + 1e-9, 3.0)
    lines = ["# a servo profile", "angle_deg;lift_mm"] + [f"{t:g};{float(H * cycloid(t / 120.0))!r}" for t in a]
    (d / "rise.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    text = to_toml(spec([dwell(60), {"kind": "rise", "angle": 120, "lift": H, "law": "polynomial"}, dwell(60),
                         {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}]))
    text = text.replace('law = "polynomial"', 'law = "table"\ntable_file = "rise.csv"')
    (d / "cam.toml").write_text(text, encoding="utf-8")
    monkeypatch.chdir(tmp_path)          # not the spec's folder
    s = load_spec(d / "cam.toml")
    assert s.motion[1].table_file is None and len(s.motion[1].table) == len(a)
    assert s.motion[1].table[5] == (15.0, H * cycloid(15.0 / 120.0))
    again = load_spec(to_toml(s))           # the points are in the spec: no file needed
    assert again == s


@pytest.mark.parametrize("content, where", [
    (None, "file not found"),
    ("0, 0\n30, 1, 2\n", "rise.csv:2: expected 2 columns"),
    ("0, 0\n30, abc\n", "rise.csv:2: not a number"),
])
def test_table_file_errors_name_the_field_and_line(tmp_path, content, where):
    if content is not None:
        (tmp_path / "rise.csv").write_text(content, encoding="utf-8")
    text = to_toml(spec(table_motion([[0.0, 0.0], [120.0, H]])))
    text = text.replace("table = [[0.0, 0.0], [120.0, 10.0]]", 'table_file = "rise.csv"')
    (tmp_path / "cam.toml").write_text(text, encoding="utf-8")
    with pytest.raises(SpecError) as exc:
        load_spec(tmp_path / "cam.toml")
    assert exc.value.field == "motion[1].table_file" and where in exc.value.rule


def test_table_start_takes_a_segment_out_of_a_whole_cycle():
    """One table of a whole cycle (absolute angles 0 … 360°) serves the rise (table_start = 60) and the
    return (table_start = 240): each fits its own rows."""
    cyc = [[float(t), float(H * cycloid((t - 60) / 120.0)) if 60 <= t <= 180 else
            (H if 180 < t < 240 else float(H * (1 - cycloid((t - 240) / 120.0))) if t >= 240 else 0.0)]
           for t in np.arange(0.0, 360.0 + 1e-9, 2.0)]
    prog = program([dwell(60), {"kind": "rise", "angle": 120, "lift": H, "law": "table", "table": cyc, "table_start": 60.0},
                    dwell(60), {"kind": "return", "angle": 120, "lift": H, "law": "table", "table": cyc,
                                "table_start": 240.0}])
    assert prog.infos[1]["points"] == 61 and prog.infos[3]["points"] == 61
    th = np.radians(np.arange(0.0, 360.0, 2.0))
    assert np.max(np.abs(prog.s(th) - np.array(cyc)[:-1, 1])) < 1e-2


# ---- bad input: the field and the rule --------------------------------------------------------
def _rise(**kw):
    return [dwell(60), {"kind": "rise", "angle": 120, "lift": H, **kw}, dwell(60),
            {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}]


BAD = [
    ("point_outside", _rise(law="polynomial", points=[[130.0, 5.0]]), "motion[1].points[0]", "inside the segment"),
    ("point_at_start", _rise(law="polynomial", points=[[0.0, 0.0]]), "motion[1].points[0]", "inside the segment"),
    ("point_twice", _rise(law="polynomial", points=[[40.0, 3.0], [40.0, 4.0]]), "motion[1].points[1]", "repeats"),
    ("point_not_pair", _rise(law="polynomial", points=[[40.0]]), "motion[1].points[0]", "[angle, lift] pair"),
    ("birkhoff_gap", _rise(law="polynomial", start_continuity=0, end_continuity=0, start_jerk=1.0),
     "motion[1].start_jerk", "do not determine a polynomial"),
    ("too_many_points", _rise(law="polynomial", points=[[4.0 * i, 0.08 * i] for i in range(1, 29)]),
     "motion[1].points[27]", "degree"),
    ("below_zero", _rise(law="polynomial", start_velocity=-20.0), "motion[1].start_velocity", "s must stay ≥ 0"),
    ("below_zero_points", _rise(law="polynomial", points=[[30.0, -1.0]]), "motion[1].points", "s must stay ≥ 0"),
    ("blend_on_polynomial", _rise(law="polynomial", start_blend=10.0), "motion[1].start_blend",
     'applies to law = "constant_velocity" only'),
    ("velocity_on_cruise", _rise(law="constant_velocity", start_velocity=1.0), "motion[1].start_velocity",
     'applies to law = "polynomial" or "table" only'),
    ("points_on_cycloidal", _rise(law="cycloidal", points=[[30.0, 1.0]]), "motion[1].points", "applies to"),
    ("blends_too_long", _rise(law="constant_velocity", start_blend=60.0, end_blend=60.0), "motion[1].end_blend",
     "must be less than the segment's angle"),
    ("blend_zero", _rise(law="constant_velocity", start_blend=0.0), "motion[1].start_blend", "must be ≥ 0.018"),
    # a blend is a span too: shorter than the finest junction spacing, no pitch curve resolves it (a
    # 1e-12° blend once sent pitch.tolerance's search through every M up to 20000, then named pitch.tolerance)
    ("blend_below_minimum", _rise(law="constant_velocity", end_blend=1e-12), "motion[1].end_blend",
     "must be ≥ 0.018 (360°/20000: the finest junction spacing of the pitch curve; a shorter span can lie between "
     "two junctions), got 1e-12"),
    ("blend_without_continuity", _rise(law="constant_velocity", start_blend=20.0, start_continuity=0),
     "motion[1].start_continuity", "a blend needs continuity ≥ 1"),
    ("continuity_4", _rise(law="polynomial", end_continuity=4), "motion[1].end_continuity", "must be ≤ 3"),
    ("table_missing", _rise(law="table"), "motion[1].table", "is required"),
    ("table_outside", _rise(law="table", table=[[0.0, 0.0], [130.0, H]]), "motion[1].table[1]", "outside the segment"),
    ("table_order", _rise(law="table", table=[[0.0, 0.0], [120.0, H]], order=3), "motion[1].order", "order ≥ 4"),
    ("table_not_increasing", _rise(law="table", table=[[0.0, 0.0], [60.0, 5.0], [50.0, 4.0], [120.0, H]]),
     "motion[1].table[2]", "angles must increase"),
    ("table_and_file", _rise(law="table", table=[[0.0, 0.0]], table_file="x.csv"), "motion[1].table_file",
     "exclusive"),
    ("min_continuity_0", None, "checks.min_continuity", "must be ≥ 1"),
]


@pytest.mark.parametrize("name, motion, fld, words", BAD, ids=[b[0] for b in BAD])
def test_bad_input_names_the_field(name, motion, fld, words):
    with pytest.raises(SpecError) as exc:
        if motion is None:
            spec(_rise(law="polynomial"), checks={"min_continuity": 0})
        else:
            spec(motion)
    assert exc.value.field == fld, str(exc.value)
    assert words in exc.value.rule, str(exc.value)


def test_matching_each_other_in_a_cycle_is_named():
    """Two polynomials whose jerk each takes from the other's free end: neither can be solved first."""
    motion = [{"kind": "rise", "angle": 180, "lift": H, "law": "polynomial", "start_continuity": 3},
              {"kind": "return", "angle": 180, "lift": H, "law": "polynomial", "start_continuity": 3}]
    with pytest.raises(SpecError) as exc:
        spec(motion)
    assert exc.value.field in ("motion[0].start_jerk", "motion[1].start_jerk")
    assert "waits for this segment's" in exc.value.rule


def test_toml_round_trip_of_every_new_field():
    s = spec([dwell(40), {"kind": "rise", "angle": 100, "lift": 6.0, "law": "polynomial", "points": [[50.0, 3.5]],
                          "end_velocity": 2.5, "end_acceleration": 0.0, "start_continuity": 3},
              {"kind": "rise", "angle": 80, "lift": 4.0, "law": "constant_velocity", "end_blend": 20.0,
               "end_continuity": 3},
              {"kind": "return", "angle": 140, "lift": 10.0, "law": "table", "table_tolerance": 0.01, "order": 6,
               "table": [[float(t), 10.0 * (1 - cycloid(t / 140.0))] for t in np.arange(0, 141, 5.0)]}],
             checks={"min_continuity": 2})
    text = to_toml(s)
    assert "points = [[50.0, 3.5]]" in text and "table = [[0.0, 10.0], [5.0, " in text
    assert load_spec(text) == s


def test_the_documented_table_example():
    """docs/examples/table_cam.toml: its CSV (relative to it) is fitted within its tolerance by the
    numbers docs/motion.md quotes, every junction C2, every check passing."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    s = load_spec(root / "docs" / "examples" / "table_cam.toml")
    prog = MotionProgram.from_spec(s)
    info = prog.infos[1]
    assert (info["points"], info["spans"]) == (121, 13) and info["max_error"] <= 1e-3
    assert [j.order for j in prog.junctions()] == [2, 2, 2, 2]
    assert run_checks(s).passed


def test_the_packaging_example():
    from cam_workbench.generators.spec.examples import example_spec

    s = example_spec("packaging")
    prog = MotionProgram.from_spec(s)
    assert prog.infos[2]["velocity"] == pytest.approx(22.0 / math.radians(120.0), rel=1e-12)
    assert [j.order for j in prog.junctions()] == [2] * 6
    assert run_checks(s).passed
