"""The motion laws' characteristic values (generators.motion.characteristics) against closed forms
derived here from each law's own definition, against the published tables, and checked as true
maxima with hypothesis."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.characteristics import LawCharacteristics, law_characteristics, peak_abs
from cam_workbench.generators.motion.laws import LAW_FUNCTIONS, evaluate_law

LAWS = sorted(LAW_FUNCTIONS)
PI = math.pi


def _closed_forms() -> dict[str, dict[str, float]]:
    """C_v, C_a, C_j, Q and their places x, derived by hand (u = x(1 − x) for the polynomials,
    whose f' and f'' are functions of u and of 1 − 2x = √(1 − 4u))."""
    out = {}
    # cycloidal: f' = 1 − cos 2πx, f'' = 2π sin 2πx, f''' = 4π² cos 2πx.
    # f'f'' = 2π(1 − cos a) sin a, a = 2πx; d/da = 1 + cos a − 2cos²a = 0 → cos a = −1/2, a = 2π/3.
    out["cycloidal"] = dict(C_v=2.0, x_v=0.5, C_a=2 * PI, x_a=0.25, C_j=4 * PI**2, x_j=0.0,
                            Q=2 * PI * 1.5 * math.sqrt(3) / 2, x_Q=1 / 3)
    # harmonic: f' = (π/2) sin πx, f'' = (π²/2) cos πx (jumps from 0 at the dwell: C_j infinite),
    # inside |f'''| = (π³/2)|sin πx| ≤ π³/2; f'f'' = (π³/8) sin 2πx.
    out["harmonic"] = dict(C_v=PI / 2, x_v=0.5, C_a=PI**2 / 2, x_a=0.0, C_j=math.inf, x_j=0.0,
                           jerk_inside=PI**3 / 2, Q=PI**3 / 8, x_Q=0.25)
    # 3-4-5: f' = 30u², f'' = 60u(1 − 2x), f''' = 60(1 − 6u).
    # f'': d/dx ∝ (1 − 2x)² − 2u = 1 − 6u = 0 → u = 1/6, 1 − 2x = 1/√3: C_a = 10/√3.
    # f''' is largest at u = 0: 60.  f'f'' = 1800u³(1 − 2x): d/dx ∝ 3(1 − 4u) − 2u → u = 3/14.
    u = 3 / 14
    out["poly345"] = dict(C_v=30 / 16, x_v=0.5, C_a=10 / math.sqrt(3), x_a=(1 - 1 / math.sqrt(3)) / 2,
                          C_j=60.0, x_j=0.0, Q=1800 * u**3 / math.sqrt(7), x_Q=(1 - 1 / math.sqrt(7)) / 2)
    # 4-5-6-7: f' = 140u³, f'' = 420u²(1 − 2x), f''' = 840u(1 − 5u).
    # f'': d/dx ∝ 2(1 − 4u) − 2u → u = 1/5, 1 − 2x = 1/√5: C_a = 420/25/√5 = 84√5/25.
    # f''' over u ∈ [0, ¼]: 42 at u = 1/10, −52.5 at u = ¼ (x = ½): C_j = 52.5.
    # f'f'' = 58800u⁵(1 − 2x): d/dx ∝ 5(1 − 4u) − 2u → u = 5/22, 1 − 2x = 1/√11.
    u = 5 / 22
    out["poly4567"] = dict(C_v=140 / 64, x_v=0.5, C_a=84 * math.sqrt(5) / 25, x_a=(1 - 1 / math.sqrt(5)) / 2,
                           C_j=52.5, x_j=0.5, Q=58800 * u**5 / math.sqrt(11), x_Q=(1 - 1 / math.sqrt(11)) / 2)
    # modified sine (Rothbart ch. 3; Norton §3): f'' = A sin 4πx on [0, ⅛], A cos φ on [⅛, ⅞] with
    # φ = 4π(x − ⅛)/3 ∈ [0, π].  Integrating: f' = A/(4π)·(1 − cos 4πx), then A/(4π)·(1 + 3 sin φ).
    # f(1) = 2∫₀^½ f' = A/(4π)·[2(⅛ − 1/(4π)) + 2(⅜ + 9/(4π))] = A(π + 4)/(4π²) = 1.
    a = 4 * PI**2 / (PI + 4)
    # C_v at φ = π/2: A/π.  C_a = A (f'' = A at x = ⅛).  C_j = 4πA at x = 0 (inside, ≤ 4πA/3).
    # f'f'' = A²/(4π)(1 + 3 sin φ) cos φ: d/dφ = 3 − sin φ − 6 sin²φ = 0 → sin φ = (√73 − 1)/12
    # (on [0, ⅛] the product rises to A²/(4π), below this).
    s = (math.sqrt(73) - 1) / 12
    out["modified_sine"] = dict(C_v=a / PI, x_v=0.5, C_a=a, x_a=0.125, C_j=4 * PI * a, x_j=0.0,
                                Q=a**2 / (4 * PI) * (1 + 3 * s) * math.sqrt(1 - s * s),
                                x_Q=0.125 + 3 * math.asin(s) / (4 * PI))
    # modified trapezoid: f'' = A sin 4πx on [0, ⅛], A on [⅛, ⅜], A cos φ on [⅜, ⅝] with
    # φ = 4π(x − ⅜) ∈ [0, π], then the mirror image.  f' = A/(4π)(1 − cos 4πx), A/(4π) + A(x − ⅛),
    # A/(4π)(1 + π + sin φ).  f(1) = 1 gives A(2 + π)/(8π) = 1.
    a = 8 * PI / (PI + 2)
    # C_v at φ = π/2: A(2 + π)/(4π) = 2.  C_a = A on the plateau from x = ⅛.  C_j = 4πA at 0.
    # f'f'' = A²/(4π)(1 + π + sin φ) cos φ: d/dφ = 1 − (1 + π) sin φ − 2 sin²φ = 0.
    s = (math.sqrt((1 + PI) ** 2 + 8) - (1 + PI)) / 4
    out["modified_trapezoid"] = dict(C_v=2.0, x_v=0.5, C_a=a, x_a=0.125, C_j=4 * PI * a, x_j=0.0,
                                     Q=a**2 / (4 * PI) * (1 + PI + s) * math.sqrt(1 - s * s),
                                     x_Q=0.375 + math.asin(s) / (4 * PI))
    for name, d in out.items():
        d.setdefault("jerk_inside", d["C_j"])
        d["torque_index"] = d["C_v"] * d["C_a"]
    return out


CLOSED = _closed_forms()
#: the laws' own evaluation rounding near a maximum, relative (measured: up to 5e-15 for the
#: 4-5-6-7 polynomial's jerk, whose terms cancel): "no point exceeds" is to this tolerance
ROUNDING = 1e-14

#: Published characteristic values (3 significant digits and more as printed).
#: C_v and C_a: Norton, *Design of Machinery*, Table 8-3 (the table tests/test_laws.py cites).
#: Modified sine C_v 1.76, C_a 5.53, C_j 69.47: MechDesigner, "Motion-Law: Modified Sinusoid"
#: (http://mechdesigner.support/motion-cam-law-modified-sinusoid.htm), which also gives the jerk at
#: the crossover, −23.15 (test_modified_sine_crossover_jerk_as_published).
#: C_j and Q (the (V·A)max column) of the others: the trade's tables as commonly quoted
#: (Chen, *Mechanics and Design of Cam Mechanisms*, Pergamon 1982; Rothbart, *Cam Design
#: Handbook*, McGraw-Hill 2004) — these were not re-read from the printed page for this test.
PUBLISHED = {
    "cycloidal": dict(C_v=2.00, C_a=6.28, C_j=39.5, Q=8.16),
    "harmonic": dict(C_v=1.57, C_a=4.93, Q=3.88),
    "modified_sine": dict(C_v=1.76, C_a=5.53, C_j=69.47, Q=5.46),
    "modified_trapezoid": dict(C_v=2.00, C_a=4.89, C_j=61.43, Q=8.09),
    "poly345": dict(C_v=1.875, C_a=5.77, C_j=60.0, Q=6.69),
    "poly4567": dict(C_v=2.19, C_a=7.51, C_j=52.5),
}


@pytest.mark.parametrize("law", LAWS)
def test_values_are_the_closed_forms(law):
    c = law_characteristics(law)
    ref = CLOSED[law]
    for key in ("C_v", "C_a", "C_j", "jerk_inside", "torque_index", "Q"):
        assert getattr(c, key) == pytest.approx(ref[key], rel=1e-13, abs=0), (law, key)
    for key in ("x_v", "x_a", "x_Q"):
        assert getattr(c, key) == pytest.approx(ref[key], abs=1e-12), (law, key)
    # the jerk's place is refined by golden section only (no 4th derivative)
    assert c.x_j == pytest.approx(ref["x_j"], abs=1e-7), law


@pytest.mark.parametrize("law", LAWS)
def test_values_agree_with_the_published_tables(law):
    c = law_characteristics(law)
    for key, pub in PUBLISHED[law].items():
        # within half a unit of the table's third significant digit
        half_unit = 0.5 * 10 ** (math.floor(math.log10(abs(pub))) - 2)
        assert abs(getattr(c, key) - pub) <= half_unit, (law, key, getattr(c, key), pub)


def test_modified_sine_crossover_jerk_as_published():
    """MechDesigner, "Modified-Sinusoid Motion-Law" (Motion-Law: Modified Sinusoid,
    http://mechdesigner.support/motion-cam-law-modified-sinusoid.htm): "Jerk at Cross-over,
    Coefficient: Cj(co) -23.15".  Derived here: on [⅛, ⅞] f″ = A cos φ, φ = 4π(x − ⅛)/3, so
    f‴ = −(4π/3)·A sin φ, at x = ½ (φ = π/2) −4πA/3 with A = 4π²/(π + 4): −23.155, the page's
    digits truncated; it is the law's most negative jerk (C_j_min)."""
    a = 4 * PI**2 / (PI + 4)
    c = law_characteristics("modified_sine")
    crossover = float(evaluate_law("modified_sine", np.array([0.5]))[3][0])
    assert crossover == pytest.approx(-4 * PI * a / 3, rel=1e-13)
    assert c.C_j_min == pytest.approx(crossover, rel=1e-12)
    assert -23.16 < crossover <= -23.15


@pytest.mark.parametrize("law", LAWS)
def test_signed_extremes(law):
    """C_a_max, C_a_min, C_j_max, C_j_min bound f″ and f‴ on a dense grid and are reached (to
    the grid's resolution); C_a is the larger of |C_a_max|, |C_a_min|; the rest-to-rest laws are
    point-symmetric, so C_a_min = −C_a_max."""
    c = law_characteristics(law)
    x = np.linspace(0.0, 1.0, 200_001)
    _, _, a, j = evaluate_law(law, x)
    tol = ROUNDING * c.C_a
    assert a.max() <= c.C_a_max + tol and a.min() >= c.C_a_min - tol
    assert a.max() >= c.C_a_max - 1e-6 * c.C_a and a.min() <= c.C_a_min + 1e-6 * c.C_a
    assert max(c.C_a_max, -c.C_a_min) == pytest.approx(c.C_a, rel=1e-14)
    assert c.C_a_min == pytest.approx(-c.C_a_max, rel=1e-12)
    assert j.max() <= c.C_j_max + ROUNDING * c.jerk_inside and j.min() >= c.C_j_min - ROUNDING * c.jerk_inside
    assert j.max() >= c.C_j_max - 1e-3 * c.jerk_inside and j.min() <= c.C_j_min + 1e-3 * c.jerk_inside


def test_harmonic_jerk_is_infinite_and_its_summary_says_so():
    c = law_characteristics("harmonic")
    assert c.C_j == math.inf and c.x_j == 0.0
    s = c.summary()
    assert s["C_j"] is None and s["C_j_note"].startswith("infinite: the acceleration jumps at the ends")
    json.dumps(s, allow_nan=False)


@pytest.mark.parametrize("law", LAWS)
def test_summary_is_plain(law):
    s = law_characteristics(law).summary()
    assert set(s) >= {"law", "C_v", "x_v", "C_a", "x_a", "C_j", "x_j", "torque_index", "Q", "x_Q"}
    assert all(type(v) in (str, float) or v is None for v in s.values()), s
    assert ("C_j_note" in s) == (law == "harmonic")
    json.dumps(s, allow_nan=False)


def test_cached_and_frozen():
    c = law_characteristics("cycloidal")
    assert law_characteristics("cycloidal") is c
    assert isinstance(c, LawCharacteristics)
    with pytest.raises(AttributeError):
        c.C_v = 3.0  # type: ignore[misc]


def test_unknown_law_is_refused():
    with pytest.raises(SpecError) as err:
        law_characteristics("parabolic")
    assert err.value.field == "law"


@pytest.mark.parametrize("law", LAWS)
def test_maxima_are_reached_where_reported(law):
    c = law_characteristics(law)
    _, v, _, _ = (float(q[0]) for q in evaluate_law(law, np.array([c.x_v])))
    assert abs(v) == pytest.approx(c.C_v, rel=1e-15)
    _, _, a, _ = (float(q[0]) for q in evaluate_law(law, np.array([c.x_a])))
    assert abs(a) == pytest.approx(c.C_a, rel=1e-15)
    _, v, a, _ = (float(q[0]) for q in evaluate_law(law, np.array([c.x_Q])))
    assert abs(v * a) == pytest.approx(c.Q, rel=1e-15)
    if math.isfinite(c.C_j):  # else x_j is the end where f'' jumps
        _, _, _, j = (float(q[0]) for q in evaluate_law(law, np.array([c.x_j])))
        assert abs(j) == pytest.approx(c.C_j, rel=1e-14)


@pytest.mark.parametrize("law", LAWS)
def test_no_dense_grid_point_exceeds_the_maxima(law):
    c = law_characteristics(law)
    x = np.linspace(0.0, 1.0, 1_000_001)
    f, v, a, j = evaluate_law(law, x)
    tol = 1 + ROUNDING
    assert np.abs(v).max() <= c.C_v * tol
    assert np.abs(a).max() <= c.C_a * tol
    assert np.abs(j).max() <= c.jerk_inside * tol
    assert np.abs(v * a).max() <= c.Q * tol
    # and the grid comes within its resolution of them
    assert np.abs(v * a).max() >= c.Q * (1 - 1e-9)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(LAWS), st.lists(st.floats(0.0, 1.0), min_size=1, max_size=64),
       st.floats(-1e-4, 1e-4))
def test_hypothesis_maxima_are_true_maxima(law, xs, offset):
    c = law_characteristics(law)
    # random places, and places near every reported maximum
    near = np.clip(np.array([c.x_v, c.x_a, c.x_j, c.x_Q]) + offset, 0.0, 1.0)
    x = np.concatenate([np.array(xs), near])
    _, v, a, j = evaluate_law(law, x)
    tol = 1 + ROUNDING
    assert np.all(np.abs(v) <= c.C_v * tol)
    assert np.all(np.abs(a) <= c.C_a * tol)
    assert np.all(np.abs(j) <= c.jerk_inside * tol) and c.jerk_inside <= c.C_j
    assert np.all(np.abs(v * a) <= c.Q * tol)


@pytest.mark.parametrize("law", LAWS)
def test_ends(law):
    f = evaluate_law(law, np.array([0.0, 1.0]))[0]
    assert f[0] == pytest.approx(0.0, abs=1e-15) and f[1] == pytest.approx(1.0, abs=1e-14)


def test_peak_abs_on_known_functions():
    # sin(πx)·eˣ: the maximum where tan πx = −π (derivative given: polished to ~1e-15)
    x_star = (PI - math.atan(PI)) / PI
    val, x = peak_abs(lambda t: np.sin(PI * t) * np.exp(t),
                      lambda t: (PI * np.cos(PI * t) + np.sin(PI * t)) * np.exp(t))
    assert x == pytest.approx(x_star, abs=1e-14)
    assert val == pytest.approx(math.sin(PI * x_star) * math.exp(x_star), rel=1e-15)
    # a kink inside and the largest value at an end
    val, x = peak_abs(lambda t: t - 0.3)
    assert (val, x) == (pytest.approx(0.7, rel=1e-15), 1.0)
    # a narrow peak between grid points, no derivative: the value to rounding, the place to ~1e-8
    c = 0.123456789
    val, x = peak_abs(lambda t: 1.0 / (1.0 + ((t - c) * 1e4) ** 2))
    assert val == pytest.approx(1.0, rel=1e-14) and x == pytest.approx(c, abs=1e-8)
